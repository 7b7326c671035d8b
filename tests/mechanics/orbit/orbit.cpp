// Orbit scenes ([orbit], the perturbation library in [effects]) through the whole pipeline:
// scene errors at file:line:column, the invariants the generator proves (and those it must
// not), the printed disturbing function, and simulations against known answers: the custom R
// of J2 against the library's J2, Hamilton's equations against Lagrange's, the first-order drag
// decay of a circular orbit, the re-entry stop, and the Jacobi-like constant of a third body on
// a circular orbit.
#define BOOST_TEST_MODULE orbit
#include <boost/test/unit_test.hpp>

#include <sys/wait.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace fs = std::filesystem;
using eomc::InputError;
using eomc::host::SimulationRequest;
using eomc::host::SimulationResult;

namespace {

const std::string cache_dir = EOMC_BINARY_DIR "/test-cache";

// An orbit scene: the parameters, the [orbit] table's lines and the [effects] table as given.
std::string orbit_scene(const std::string& name, const std::string& parameters, const std::string& effects,
                        const std::string& initial = "elements = { a = 7000.0, e = 0.01, i = 50.0 }") {
    return "[scene]\nname = \"" + name + "\"\n[parameters]\nmu = 398600.4418\nRe = 6378.137\n" + parameters +
           "[orbit]\ncentral_body = { mu = \"mu\", radius = \"Re\" }\n" + initial + "\n" + effects;
}

const std::string j2_parameters = "J2 = 1.08262668e-3\n";
// J2 disturbing function (Vallado, Fundamentals of Astrodynamics and Applications, eq. 8-19):
// R = −(μ J2 Re²/(2 r³))(3 z²/r² − 1).
const std::string j2_by_hand = "-mu*J2*Re^2/(2*(x^2+y^2+z^2)^(3/2))*(3*z^2/(x^2+y^2+z^2) - 1)";

eomc::model::Model model_of(const std::string& toml) {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, "orbit.toml"));
}

// The error a scene raises, as "line:column: message".
std::string error_of(const std::string& toml) {
    try {
        const auto model = model_of(toml);
        (void)eomc::mechanics::derive(model);
    } catch (const InputError& e) {
        return std::to_string(e.where().line) + ":" + std::to_string(e.where().column) + ": " + e.message();
    }
    return "no error";
}

std::vector<std::string> invariant_names(const std::string& toml) {
    const auto model = model_of(toml);
    std::vector<std::string> names;
    for (const auto& inv : eomc::mechanics::derive(model).invariants) names.push_back(inv.name);
    return names;
}

struct Kernel {
    std::string header, struct_name;
};

Kernel generate(const std::string& toml, bool hamiltonian = false) {
    const auto scene = eomc::scene::parse_scene_string(toml, "orbit.toml");
    const auto model = eomc::model::build_model(scene);
    const auto equations = eomc::mechanics::derive(model);
    if (hamiltonian) {
        const auto canonical = eomc::mechanics::canonical_equations(model, equations);
        return {eomc::codegen::emit_header(eomc::codegen::lower(model, canonical.form), {EOMC_VERSION}),
                eomc::scene::struct_name(scene.name)};
    }
    return {eomc::codegen::emit_header(eomc::codegen::lower(model, equations), {EOMC_VERSION}),
            eomc::scene::struct_name(scene.name)};
}

SimulationRequest request(const Kernel& k, double t_end, double rtol, double atol) {
    SimulationRequest r;
    r.header_text = k.header;
    r.struct_name = k.struct_name;
    r.t_end = t_end;
    r.integrator = "dop853";
    r.rtol = rtol;
    r.atol = atol;
    r.cache_dir = cache_dir;
    r.progress = false;
    return r;
}

std::vector<std::vector<double>> read_csv(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);  // header
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream ss(line);
        std::string cell;
        // Numbers only: an event column's name (the last column of orbit CSVs) is left out.
        while (std::getline(ss, cell, ','))
            if (!cell.empty() && (std::isdigit(static_cast<unsigned char>(cell[0])) || cell[0] == '-' || cell[0] == '+' ||
                                  cell[0] == '.'))
                row.push_back(std::stod(cell));
        rows.push_back(row);
    }
    return rows;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

fs::path fresh_dir(const std::string& name) {
    const fs::path dir = fs::path(EOMC_BINARY_DIR) / "orbit-scratch" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

const double mu_earth = 398600.4418, re_earth = 6378.137;

// Semi-major axis from a Cartesian state (vis-viva).
double semi_major_axis(const double* x, double mu) {
    const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double v2 = x[3] * x[3] + x[4] * x[4] + x[5] * x[5];
    return 1.0 / (2.0 / r - v2 / mu);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scene errors: each at the offending place, with a suggestion where one is close.

BOOST_AUTO_TEST_CASE(effect_names_are_checked_and_kept_apart_from_the_carrier_effects) {
    BOOST_TEST(error_of(orbit_scene("s", j2_parameters, "[effects]\nkeep = [\"J22\"]\n")) ==
               "11:9: unknown effect 'J22' in effects.keep; did you mean 'J2'?");
    BOOST_TEST(error_of(orbit_scene("s", j2_parameters, "[effects]\nkeep = [\"J2\", \"coriolis\"]\n")) ==
               "11:15: 'coriolis' in effects.keep is an inertial effect of a [carrier] scene; an [orbit] scene keeps "
               "perturbations: J2, J3, J4, drag, third_body");
    const std::string carrier = "[scene]\nname = \"c\"\n[coordinates]\nq = {}\n[carrier]\nangular_velocity = [\"0\", \"1\", "
                                "\"0\"]\n[[body]]\nname = \"b\"\nmass = 1\nposition = [\"q\", \"0\", \"0\"]\n[effects]\n"
                                "keep = [\"J2\"]\n";
    BOOST_TEST(error_of(carrier) == "12:9: 'J2' in effects.keep is a perturbation of an [orbit] scene; this scene keeps "
                                    "inertial effects of its carrier: relative, translation, euler, centrifugal, coriolis");
    BOOST_TEST(error_of(orbit_scene("s", j2_parameters, "[effects]\nkeep = [\"J2\", \"J2\"]\n")) ==
               "11:15: effect 'J2' appears twice in effects.keep (first at line 11, column 9)");
}

BOOST_AUTO_TEST_CASE(a_missing_effect_parameter_is_named_at_the_effect) {
    BOOST_TEST(error_of(orbit_scene("s", "", "[effects]\nkeep = [\"J2\"]\n")) ==
               "10:9: effect 'J2' needs the parameter 'J2' (the zonal coefficient J2), which [parameters] does not "
               "declare (the effect reads: J2)");
    const std::string drag = "rho0 = 1e-11\nh0 = 300\nH = 50\nomega = 0\n";
    BOOST_TEST(error_of(orbit_scene("s", drag, "[effects]\nkeep = [\"drag\"]\n")) ==
               "14:9: effect 'drag' needs the parameter 'CdA_m' (the ballistic coefficient Cd*A/m, m^2/kg), which "
               "[parameters] does not declare (the effect reads: rho0, h0, H, CdA_m, omega)");
    BOOST_TEST(error_of(orbit_scene("s", "mu3 = 1\na3 = 1e5\n", "[effects]\nkeep = [\"third_body\"]\n")) ==
               "12:9: effect 'third_body' needs the parameter 'i3' (the inclination of its orbit to the x-y plane, "
               "radians), which [parameters] does not declare (the effect reads: mu3, a3, i3)");
}

BOOST_AUTO_TEST_CASE(orbit_tables_are_checked) {
    // Every formulation is built now; typos get a suggestion.
    BOOST_TEST(error_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 0.0 }\nformulation = \"cowel\"")) ==
               "9:15: unknown orbit formulation 'cowel'; did you mean 'cowell'?");
    BOOST_TEST(error_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 1.5 }")) ==
               "8:18: 'orbit.elements.a' = 7000.0 does not fit e = 1.5: an ellipse (e < 1) has a > 0, a hyperbola "
               "(e > 1) a < 0");
    BOOST_TEST(error_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 0.1, i = 200 }")) ==
               "8:39: 'orbit.elements.i' is an inclination in degrees, 0 to 180; got 200");
    BOOST_TEST(error_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 0.1 }\nstate = { r = [7000, 0, 0], v = "
                                                 "[0, 7.5, 0] }")) ==
               "9:9: [orbit] gives both 'elements' and 'state'; give one initial orbit");
    BOOST_TEST(error_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 0.1 }\n[coordinates]\nq = {}")) ==
               "9:1: [coordinates] cannot be combined with [orbit]: an orbit scene's coordinates are the inertial x, "
               "y, z of the orbiting body");
    BOOST_TEST(error_of(orbit_scene("s", "x = 1\n", "")) ==
               "6:1: parameter 'x' has the name of a coordinate of the orbit scene (x, y, z)");
    // A disturbing function is a potential: it may not depend on the velocity.
    BOOST_TEST(error_of(orbit_scene("s", "", "[effects.custom]\ndisturbing_function = \"x_dot\"\n")).find(
                   "10:24:") == 0);
}

BOOST_AUTO_TEST_CASE(the_command_line_exits_2_naming_the_place_and_writes_nothing) {
    const fs::path dir = fresh_dir("cli");
    const fs::path scene = dir / "leo.toml";
    std::ofstream(scene) << orbit_scene("leo", "", "[effects]\nkeep = [\"J2\"]\n");
    const fs::path out = dir / "out";
    const std::string command = std::string(EOMC_EXECUTABLE) + " generate " + scene.string() + " -o " + out.string() +
                                " > /dev/null 2> " + (dir / "stderr").string();
    const int raw = std::system(command.c_str());
    BOOST_TEST(WIFEXITED(raw));
    BOOST_TEST(WEXITSTATUS(raw) == 2);
    BOOST_TEST(slurp(dir / "stderr") == scene.string() + ":10:9: error: effect 'J2' needs the parameter 'J2' (the zonal "
                                                         "coefficient J2), which [parameters] does not declare (the "
                                                         "effect reads: J2)\n");
    BOOST_TEST(!fs::exists(out / "leo.hpp"));
}

// ---------------------------------------------------------------------------------------------
// The model and the derivation.

BOOST_AUTO_TEST_CASE(invariants_are_proven_only_where_they_hold) {
    using V = std::vector<std::string>;
    // Zonal harmonics: R is time-independent and axisymmetric.
    BOOST_TEST(invariant_names(orbit_scene("s", j2_parameters + "J3 = -2.5e-6\nJ4 = -1.6e-6\n",
                                           "[effects]\nkeep = [\"J2\", \"J3\", \"J4\"]\n")) == (V{"energy", "h_z"}));
    // A custom R without the symmetry keeps the energy only.
    BOOST_TEST(invariant_names(orbit_scene("s", "", "[effects.custom]\ndisturbing_function = \"1e-6*x*z\"\n")) ==
               (V{"energy"}));
    // Drag does work; a third body moves (R depends on t) and pulls off the axis.
    BOOST_TEST(invariant_names(orbit_scene("s", "rho0 = 1e-11\nh0 = 300\nH = 50\nCdA_m = 0.02\nomega = 7.29e-5\n",
                                           "[effects]\nkeep = [\"drag\"]\n"))
                   .empty());
    BOOST_TEST(invariant_names(orbit_scene("s", "mu3 = 4902.8\na3 = 384400\ni3 = 0.4\n",
                                           "[effects]\nkeep = [\"third_body\"]\n"))
                   .empty());
    // A custom acceleration −k v: it does work and its torque about z is −k h_z, so neither holds.
    BOOST_TEST(invariant_names(orbit_scene("s", "", "[effects.custom]\nacceleration = [\"-1e-9*x_dot\", \"-1e-9*y_dot\", "
                                                    "\"-1e-9*z_dot\"]\n"))
                   .empty());
    // No perturbation: the Kepler problem, energy and h_z.
    BOOST_TEST(invariant_names(orbit_scene("s", "", "")) == (V{"energy", "h_z"}));
}

BOOST_AUTO_TEST_CASE(the_initial_state_is_given_or_converted_from_degrees) {
    const auto given = model_of(orbit_scene("s", "", "", "state = { r = [7000, 1, 2], v = [0.5, 7.5, 0.25] }"));
    const double expected[] = {7000, 1, 2, 0.5, 7.5, 0.25};
    for (std::size_t k = 0; k < 3; ++k) {
        BOOST_TEST(given.coordinates[k].initial == expected[k]);
        BOOST_TEST(given.coordinates[k].rate == expected[k + 3]);
    }
    // i = 90°, raan = 90°, circular, from the node: r on the y axis, v along z.
    const auto polar = model_of(orbit_scene("s", "", "", "elements = { a = 7000.0, e = 0.0, i = 90.0, raan = 90.0 }"));
    const double v = std::sqrt(mu_earth / 7000.0);
    const double want[] = {0, 7000, 0, 0, 0, v};
    for (std::size_t k = 0; k < 3; ++k) {
        BOOST_TEST_INFO(polar.coordinates[k].name);
        BOOST_TEST(std::abs(polar.coordinates[k].initial - want[k]) <= 1e-9);
        BOOST_TEST(std::abs(polar.coordinates[k].rate - want[k + 3]) <= 1e-12);
    }
}

BOOST_AUTO_TEST_CASE(derive_prints_the_disturbing_function_and_its_gradient_before_the_equations) {
    const auto model = model_of(orbit_scene("s", j2_parameters, "[effects]\nkeep = [\"J2\"]\n"));
    const auto eqs = eomc::mechanics::derive(model);
    std::ostringstream text, json;
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::text, text);
    eomc::report::print_derivation(model, eqs, eomc::report::DerivationFormat::json, json);
    const std::string t = text.str();
    const auto equations = t.find("Lagrange's equations");
    for (const char* piece : {"R_J2 = ", "∂R/∂x = ", "∂R/∂y = ", "∂R/∂z = "}) {
        BOOST_TEST_INFO(piece);
        BOOST_TEST(t.find(piece) < equations);
    }
    BOOST_TEST(json.str().find("\"orbit\": {\"formulation\": \"cowell\"") != std::string::npos);
    // The printed gradient is the force: f_s = −μ q_s/r³ + ∂R/∂q_s (evaluated at a point).
    GiNaC::exmap at;
    const double point[] = {6500.0, -2100.0, 3300.0};
    for (std::size_t k = 0; k < 3; ++k) at[model.coordinates[k].q] = point[k];
    for (const auto& p : model.parameters) at[p.symbol] = p.value;
    const double r = std::sqrt(point[0] * point[0] + point[1] * point[1] + point[2] * point[2]);
    for (std::size_t k = 0; k < 3; ++k) {
        const GiNaC::ex grad = model.orbit->R.diff(model.coordinates[k].q);
        const double f = GiNaC::ex_to<GiNaC::numeric>(eqs.forcing[k].subs(at).evalf()).to_double();
        const double g = GiNaC::ex_to<GiNaC::numeric>(grad.subs(at).evalf()).to_double();
        BOOST_TEST(std::abs(f - (-mu_earth * point[k] / (r * r * r) + g)) <= 1e-15 * mu_earth / (r * r));
    }
}

// ---------------------------------------------------------------------------------------------
// Simulations.

// The same R written by hand gives the same equations and so the same trajectory. The two
// runs integrate identical right-hand sides up to rounding (term order), so they take the same
// steps and differ by rounding amplified by the flow: far below one run's own tolerance budget,
// steps × √6 × (atol + rtol |r|), which bounds each run's accumulated local error.
BOOST_AUTO_TEST_CASE(custom_disturbing_function_reproduces_the_library_j2) {
    const auto library = generate(orbit_scene("lib_j2", j2_parameters, "[effects]\nkeep = [\"J2\"]\n"));
    const auto custom =
        generate(orbit_scene("custom_j2", j2_parameters, "[effects.custom]\ndisturbing_function = \"" + j2_by_hand + "\"\n"));
    const double rtol = 1e-12, atol = 1e-9;
    const SimulationResult a = eomc::host::simulate(request(library, 86400, rtol, atol));
    const SimulationResult b = eomc::host::simulate(request(custom, 86400, rtol, atol));
    const double budget = double(a.steps) * std::sqrt(6.0) * (atol + rtol * 7100);
    double worst = 0;
    for (std::size_t i = 0; i < 6; ++i) worst = std::max(worst, std::abs(a.state[i].second - b.state[i].second));
    BOOST_TEST_MESSAGE("one day: library vs custom J2 differ by " << worst << " km (budget " << budget << ", "
                                                                  << a.steps << " steps)");
    BOOST_TEST(worst <= budget);
    BOOST_TEST(a.invariants.size() == 2u);
    BOOST_TEST(b.invariants.size() == 2u);
}

// Hamilton's equations of H = H0 − R (p = q̇ here) against Lagrange's: the same motion.
BOOST_AUTO_TEST_CASE(hamiltonian_formulation_gives_the_same_motion) {
    const std::string scene = orbit_scene("leo_h", j2_parameters, "[effects]\nkeep = [\"J2\"]\n");
    const double rtol = 1e-12, atol = 1e-9;
    const SimulationResult l = eomc::host::simulate(request(generate(scene), 86400, rtol, atol));
    const SimulationResult h = eomc::host::simulate(request(generate(scene, true), 86400, rtol, atol));
    const double budget = double(l.steps + h.steps) * std::sqrt(6.0) * (atol + rtol * 7100);
    double worst = 0;
    for (std::size_t i = 0; i < 6; ++i) worst = std::max(worst, std::abs(l.state[i].second - h.state[i].second));
    BOOST_TEST_MESSAGE("one day: Lagrange vs Hamilton differ by " << worst << " (budget " << budget << ")");
    BOOST_TEST(worst <= budget);
    BOOST_TEST(h.state[3].first == "p_x");
}

// Drag on a circular orbit, non-rotating atmosphere: to first order in the drag the orbit stays
// circular and da/dt = −ρ(a) (Cd A/m) √(μ a) (ρ B in 1/m, times 1000 m/km). That law, with
// ρ(a) = ρ0 exp(−(a − Re − h0)/H), is integrated here by RK4 (exact to far below the check) and
// compared with a from the simulated final state. Neglected: the eccentricity the drag itself
// induces (it changes ρ along the orbit by e a/H and the mean rate by O(e² a²/H²)) and the
// second order in the drag, of relative size Δa/a ≈ 3e-4 per unit of the O(1) coefficient
// that the first-order average leaves out; 1e-4 of the decay is the tolerance (measured: ~1e-6),
// and a factor error (2, 1000, a sign) misses it by orders of magnitude.
BOOST_AUTO_TEST_CASE(drag_decays_a_circular_orbit_at_the_first_order_rate) {
    const double rho0 = 5.464e-10, h0 = 180, H = 29.74, B = 0.022, a0 = re_earth + 300;
    const std::string parameters = "rho0 = 5.464e-10\nh0 = 180.0\nH = 29.74\nCdA_m = 0.022\nomega = 0.0\n";
    const auto kernel = generate(orbit_scene("decay", parameters, "[effects]\nkeep = [\"drag\"]\n",
                                             "elements = { a = " + std::to_string(a0) + ", e = 0.0, i = 30.0 }"));
    const double t_end = 2 * 86400.0;
    const SimulationResult r = eomc::host::simulate(request(kernel, t_end, 1e-12, 1e-10));
    BOOST_TEST(r.stopped_by.empty());
    double x[6];
    for (std::size_t i = 0; i < 6; ++i) x[i] = r.state[i].second;
    const double a_sim = semi_major_axis(x, mu_earth);
    auto rate = [&](double a) { return -rho0 * std::exp(-(a - re_earth - h0) / H) * B * 1000 * std::sqrt(mu_earth * a); };
    double a = a0;
    const int n = 2000;
    const double dt = t_end / n;
    for (int k = 0; k < n; ++k) {
        const double k1 = rate(a), k2 = rate(a + dt / 2 * k1), k3 = rate(a + dt / 2 * k2), k4 = rate(a + dt * k3);
        a += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    const double decay_sim = a0 - a_sim, decay_theory = a0 - a;
    BOOST_TEST_MESSAGE("two days at 300 km: a decayed by " << decay_sim << " km, first-order theory " << decay_theory
                                                           << " km, relative difference "
                                                           << decay_sim / decay_theory - 1);
    BOOST_TEST(decay_theory > 1.0);  // the check is not vacuous: about 1 km/day at 300 km
    BOOST_TEST(std::abs(decay_sim / decay_theory - 1) <= 1e-4);
}

// The bundled leo_drag scene re-enters: the orbit's terminal event re_entry (r − radius crossing
// downwards) stops the run at the surface, the summary says so, and the CSV ends on that finite
// state, the crossing located to round-off on the step's dense output.
BOOST_AUTO_TEST_CASE(re_entry_stops_the_run_at_the_surface) {
    const auto scene = eomc::scene::parse_scene_file(EOMC_SOURCE_DIR "/scenes/leo_drag.toml");
    const auto model = eomc::model::build_model(scene);
    const Kernel kernel{eomc::codegen::emit_header(eomc::codegen::lower(model, eomc::mechanics::derive(model)),
                                                   {EOMC_VERSION}),
                        eomc::scene::struct_name(scene.name)};
    const fs::path dir = fresh_dir("reentry");
    SimulationRequest req = request(kernel, scene.simulate.t_end, scene.simulate.rtol, scene.simulate.atol);
    req.csv_path = (dir / "drag.csv").string();
    const SimulationResult r = eomc::host::simulate(req);
    BOOST_TEST(r.stopped_by == "re_entry");
    BOOST_TEST(r.t < scene.simulate.t_end);
    BOOST_TEST(r.t > 86400.0);  // 250 km with this atmosphere lasts days, not hours
    double x[6];
    for (std::size_t i = 0; i < 6; ++i) {
        x[i] = r.state[i].second;
        BOOST_TEST(std::isfinite(x[i]));
    }
    const double altitude = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) - re_earth;
    BOOST_TEST_MESSAGE("re-entered at t = " << r.t << " s; final altitude " << altitude << " km");
    BOOST_TEST(std::abs(altitude) <= 1e-6);
    const auto rows = read_csv(dir / "drag.csv");
    BOOST_TEST(rows.back()[0] == r.t);
    for (std::size_t i = 0; i < 6; ++i) BOOST_TEST(rows.back()[i + 1] == x[i]);
    std::ostringstream summary;
    eomc::host::print_summary(r, "text", summary);
    BOOST_TEST(summary.str().find("stopped by the terminal event 're_entry'") != std::string::npos);
}

// A scene that starts at or below the surface is refused where its initial state is given.
BOOST_AUTO_TEST_CASE(an_orbit_starting_underground_is_refused) {
    const std::string text = orbit_scene("under", "", "", "state = { r = [6000.0, 0.0, 0.0], v = [0.0, 7.5, 0.0] }");
    BOOST_CHECK_EXCEPTION(eomc::model::build_model(eomc::scene::parse_scene_string(text, "under.toml")),
                          eomc::InputError, [](const eomc::InputError& e) {
                              return std::string(e.what()).find("at or below the central body's surface") !=
                                     std::string::npos;
                          });

}

// A third body on a circular orbit of rate n3 about the axis k3 = (0, −sin i3, cos i3): R(t, r)
// is invariant under rotation about k3 combined with a time shift, so the Jacobi-like
// C = |v|²/2 − μ/r − R − n3 k3·(r × v) is conserved while H0 − R is not. Checked from the CSV
// rows, with R written here independently of the generator. Bound: each accepted step's local
// error moves C by at most |∇C|·√6·(atol + rtol |x|), summed over the steps.
BOOST_AUTO_TEST_CASE(third_body_conserves_the_jacobi_like_constant) {
    const double mu3 = 4902.8, a3 = 384400.0, i3 = 0.4;
    const auto kernel = generate(orbit_scene("geo_moon", "mu3 = 4902.8\na3 = 384400.0\ni3 = 0.4\n",
                                             "[effects]\nkeep = [\"third_body\"]\n",
                                             "elements = { a = 42164.0, e = 0.1, i = 10.0, raan = 30.0 }"));
    const fs::path dir = fresh_dir("third_body");
    const double rtol = 1e-13, atol = 1e-12;
    SimulationRequest req = request(kernel, 10 * 86400.0, rtol, atol);
    req.csv_path = (dir / "moon.csv").string();
    const SimulationResult r = eomc::host::simulate(req);
    BOOST_TEST(r.invariants.empty());  // neither H0 − R nor h_z is claimed
    const double n3 = std::sqrt((mu_earth + mu3) / (a3 * a3 * a3));
    const double k3[] = {0.0, -std::sin(i3), std::cos(i3)};
    auto R = [&](double t, const double* x) {
        const double u = n3 * t;
        const double r3[] = {a3 * std::cos(u), a3 * std::cos(i3) * std::sin(u), a3 * std::sin(i3) * std::sin(u)};
        const double d = std::sqrt((r3[0] - x[0]) * (r3[0] - x[0]) + (r3[1] - x[1]) * (r3[1] - x[1]) +
                                   (r3[2] - x[2]) * (r3[2] - x[2]));
        return mu3 * (1 / d - (x[0] * r3[0] + x[1] * r3[1] + x[2] * r3[2]) / (a3 * a3 * a3));
    };
    auto energy = [&](const double* x) {
        return (x[3] * x[3] + x[4] * x[4] + x[5] * x[5]) / 2 - mu_earth / std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    };
    auto jacobi = [&](double t, const double* x) {
        const double h[] = {x[1] * x[5] - x[2] * x[4], x[2] * x[3] - x[0] * x[5], x[0] * x[4] - x[1] * x[3]};
        return energy(x) - R(t, x) - n3 * (k3[0] * h[0] + k3[1] * h[1] + k3[2] * h[2]);
    };
    const auto rows = read_csv(dir / "moon.csv");
    BOOST_REQUIRE(rows.size() > 10u);
    const double c0 = jacobi(rows[0][0], &rows[0][1]), e0 = energy(&rows[0][1]) - R(0, &rows[0][1]);
    double drift_c = 0, drift_e = 0, bound = 0;
    const double eps = std::numeric_limits<double>::epsilon();
    for (std::size_t k = 1; k < rows.size(); ++k) {
        const double t = rows[k][0];
        const double* x = &rows[k][1];
        drift_c = std::max(drift_c, std::abs(jacobi(t, x) - c0));
        drift_e = std::max(drift_e, std::abs(energy(x) - R(t, x) - e0));
        // This step's local error bound per component (as the controller accepted it) times
        // |∂C/∂x_i| (central differences).
        for (std::size_t i = 0; i < 6; ++i) {
            const double big = std::max(std::abs(rows[k - 1][i + 1]), std::abs(x[i]));
            double xp[6], xm[6];
            std::copy(x, x + 6, xp);
            std::copy(x, x + 6, xm);
            const double dx = 1e-6 * (1 + std::abs(x[i]));
            xp[i] += dx;
            xm[i] -= dx;
            const double grad = (jacobi(t, xp) - jacobi(t, xm)) / (2 * dx);
            bound += std::abs(grad) * (std::sqrt(6.0) * (atol + rtol * big) + 4 * eps * big);
        }
    }
    bound += 64 * eps * 2 * std::abs(c0);  // rounding of evaluating C twice (terms of size |C|)
    BOOST_TEST_MESSAGE("ten days near GEO with the Moon: C drifts " << drift_c << " (bound " << bound
                                                                     << "), H0 - R drifts " << drift_e);
    BOOST_TEST(drift_c <= bound);
    BOOST_TEST(drift_e > 100 * bound);  // the time dependence is real: H0 − R alone is not conserved
}

// ---------------------------------------------------------------------------------------------
// The equinoctial formulation against Cowell's on the same scene.

namespace {

// Final Cartesian state of a run: the state itself (Cowell) or the kernel's outputs, the last
// CSV row's last six columns (equinoctial).
std::vector<double> final_cartesian(const std::string& toml, const std::string& name, double t_end, double rtol,
                                    double atol, std::size_t& steps) {
    const fs::path dir = fresh_dir(name);
    SimulationRequest req = request(generate(toml), t_end, rtol, atol);
    req.csv_path = (dir / "run.csv").string();
    const SimulationResult r = eomc::host::simulate(req);
    steps = r.steps;
    const auto rows = read_csv(dir / "run.csv");
    BOOST_REQUIRE(!rows.empty());
    const auto& last = rows.back();
    BOOST_REQUIRE(last.size() >= 7u);
    if (r.state[0].first == "x") return std::vector<double>(last.begin() + 1, last.begin() + 7);
    return std::vector<double>(last.end() - 6, last.end());
}

// Both runs integrate the same motion; each one's local errors are bounded by the controller,
// √6 (atol + rtol |y|) per step and component. Mapped to the position: a Cartesian component
// error as it is; an element error through |∂r/∂p| = r/p ≤ 1/(1 − e) ≤ 2 and |∂r/∂(f, g, h, k,
// L)| ≤ 2r. Summed linearly over the steps — a derived, not a tight, bound (the Kepler shear
// grows an along-track error only about linearly over a day). An O(1) mistake in a Gauss
// equation moves the orbit by kilometres.
void check_same_motion(const std::string& cowell, const std::string& equinoctial, const std::string& what, double r_max) {
    const double rtol = 1e-12, atol = 1e-10, t_end = 86400;
    std::size_t steps_c = 0, steps_e = 0;
    const auto c = final_cartesian(cowell, "cowell_" + what, t_end, rtol, atol, steps_c);
    const auto e = final_cartesian(equinoctial, "equinoctial_" + what, t_end, rtol, atol, steps_e);
    const double L_max = 2 * std::numbers::pi * (t_end / 5000 + 2);  // about one revolution per 5000 s or more
    // Cowell: each of the 6 components at most atol + rtol r_max (velocities are smaller), 1:1 in
    // position. Equinoctial: p at most atol + rtol r_max, through r/p ≤ 2; f, g, h, k (≤ 1) and L
    // (≤ L_max) through ≤ 2 r_max each.
    const double per_step_c = std::sqrt(6.0) * 6 * (atol + rtol * r_max);
    const double per_step_e = std::sqrt(6.0) * ((atol + rtol * r_max) * 2 + 4 * (atol + rtol) * 2 * r_max +
                                                (atol + rtol * L_max) * 2 * r_max);
    const double bound = double(steps_c) * per_step_c + double(steps_e) * per_step_e;
    double worst = 0;
    for (std::size_t i = 0; i < 3; ++i) worst = std::max(worst, std::abs(c[i] - e[i]));
    BOOST_TEST_MESSAGE(what << ": Cowell (" << steps_c << " steps) and equinoctial (" << steps_e
                            << " steps) positions differ by " << worst << " km after one day (bound " << bound << ")");
    BOOST_TEST(worst <= bound);
    for (double v : e) BOOST_TEST(std::isfinite(v));
}

std::string with_formulation(std::string toml, const std::string& name, const std::string& formulation) {
    toml.replace(toml.find("name = \"orb\""), 12, "name = \"" + name + "\"");
    const auto at = toml.find("[effects]");
    return toml.substr(0, at) + "formulation = \"" + formulation + "\"\n" + toml.substr(at);
}

}  // namespace

BOOST_AUTO_TEST_CASE(equinoctial_matches_cowell_with_j2_j3_and_an_acceleration) {
    // J2, J3 and a small along-track push (a custom acceleration), on an inclined eccentric orbit.
    const std::string scene =
        orbit_scene("orb", j2_parameters + "J3 = -2.53265649e-6\n",
                    "[effects]\nkeep = [\"J2\", \"J3\"]\n[effects.custom]\nacceleration = [\"1e-8*x_dot\", "
                    "\"1e-8*y_dot\", \"1e-8*z_dot\"]\n",
                    "elements = { a = 8000.0, e = 0.1, i = 63.0, raan = 40.0, argp = 20.0, mean_anomaly = 10.0 }");
    check_same_motion(with_formulation(scene, "orb_c", "cowell"), with_formulation(scene, "orb_e", "equinoctial"),
                      "inclined", 8000 * 1.1);
}

// e = 0 and i = 0: the classical angles are undefined, the equinoctial elements are not (f = g
// = h = k = 0); J2 keeps the orbit equatorial and circular in shape while it speeds it up.
BOOST_AUTO_TEST_CASE(equinoctial_is_regular_at_zero_eccentricity_and_inclination) {
    const std::string scene = orbit_scene("orb", j2_parameters, "[effects]\nkeep = [\"J2\"]\n",
                                          "elements = { a = 7000.0, e = 0.0, i = 0.0 }");
    check_same_motion(with_formulation(scene, "eq0_c", "cowell"), with_formulation(scene, "eq0_e", "equinoctial"),
                      "equatorial circular", 7000 * 1.01);
}

BOOST_AUTO_TEST_CASE(equinoctial_state_names_must_be_free) {
    BOOST_TEST(error_of(orbit_scene("s", "h = 1\n", "", "elements = { a = 7000.0, e = 0.0 }\nformulation = \"equinoctial\"")) ==
               "10:15: the equinoctial formulation's state has an element 'h', which names a parameter of this scene; "
               "rename the parameter");
}
