// The encke formulation of orbit scenes: the deviation δ = r − ρ from a reference Kepler ellipse,
// rectified when it grows. Checked here: the equations against Cowell's at random states (the
// derivation), pure Kepler motion (δ stays exactly zero and the output is the runtime's two-body
// propagator), one day of J2 against Cowell, the rectification (when it happens and that the
// motion goes through it unchanged), the drag re-entry time against Cowell, the refusal of a
// hyperbolic start, and `eomc derive`.
#define BOOST_TEST_MODULE encke
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../support/command.hpp"
#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "eomc/runtime/orbit/kepler.hpp"
#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/orbit/encke.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace fs = std::filesystem;
using eomc::host::SimulationRequest;
using eomc::host::SimulationResult;

namespace {

const std::string cache_dir = EOMC_BINARY_DIR "/test-cache";
const double eps = std::numeric_limits<double>::epsilon();
const double mu_earth = 398600.4418;

std::string orbit_scene(const std::string& name, const std::string& parameters, const std::string& effects,
                        const std::string& orbit_lines) {
    return "[scene]\nname = \"" + name + "\"\n[parameters]\nmu = 398600.4418\nRe = 6378.137\n" + parameters +
           "[orbit]\ncentral_body = { mu = \"mu\", radius = \"Re\" }\n" + orbit_lines + "\n" + effects;
}

// A bundled scene in the given formulation (the scene's name gains _<formulation> unless it is its own).
eomc::scene::Scene bundled(const std::string& file, const std::string& formulation) {
    auto scene = eomc::scene::parse_scene_file(EOMC_SOURCE_DIR "/scenes/" + file);
    eomc::scene::set_orbit_formulation(scene, formulation, eomc::SourcePos{"test"});
    return scene;
}

struct Kernel {
    std::string header, struct_name;
    std::vector<double> initial;  // the model's Cartesian initial state (the scene's)
};

Kernel generate(const eomc::scene::Scene& scene) {
    const auto model = eomc::model::build_model(scene);
    const auto equations = eomc::mechanics::derive(model);
    Kernel k{eomc::codegen::emit_header(eomc::codegen::lower(model, equations), {EOMC_VERSION}),
             eomc::scene::struct_name(scene.name), {}};
    for (const auto& c : model.coordinates) k.initial.push_back(c.initial);
    for (const auto& c : model.coordinates) k.initial.push_back(c.rate);
    return k;
}

Kernel generate(const std::string& toml) { return generate(eomc::scene::parse_scene_string(toml, "encke.toml")); }

SimulationRequest request(const Kernel& k, double t_end, double rtol, double atol, const fs::path& csv) {
    SimulationRequest r;
    r.header_text = k.header;
    r.struct_name = k.struct_name;
    r.t_end = t_end;
    r.integrator = "dop853";
    r.rtol = rtol;
    r.atol = atol;
    r.cache_dir = cache_dir;
    r.progress = false;
    r.csv_path = csv.string();
    return r;
}

// A trajectory CSV by column name; the event column (text) is read as NaN.
struct Csv {
    std::vector<std::string> names;
    std::vector<std::vector<double>> rows;
    std::size_t column(const std::string& name) const {
        const auto it = std::find(names.begin(), names.end(), name);
        BOOST_REQUIRE_MESSAGE(it != names.end(), "no column " << name);
        return std::size_t(it - names.begin());
    }
    // Three or six consecutive columns from `first`.
    std::vector<double> block(std::size_t row, const std::string& first, std::size_t count) const {
        const std::size_t c = column(first);
        return std::vector<double>(rows[row].begin() + std::ptrdiff_t(c), rows[row].begin() + std::ptrdiff_t(c + count));
    }
};

Csv read_csv(const fs::path& p) {
    std::ifstream in(p);
    Csv csv;
    std::string line, cell;
    std::getline(in, line);
    for (std::stringstream ss(line); std::getline(ss, cell, ',');) csv.names.push_back(cell);
    while (std::getline(in, line)) {
        std::vector<double> row;
        std::stringstream ss(line);
        while (std::getline(ss, cell, ',')) {
            try {
                row.push_back(std::stod(cell));
            } catch (const std::exception&) {
                row.push_back(std::numeric_limits<double>::quiet_NaN());
            }
        }
        row.resize(csv.names.size(), std::numeric_limits<double>::quiet_NaN());
        csv.rows.push_back(row);
    }
    return csv;
}

double norm3(const std::vector<double>& v, std::size_t from = 0) {
    return std::sqrt(v[from] * v[from] + v[from + 1] * v[from + 1] + v[from + 2] * v[from + 2]);
}

// The controller's guarantee per accepted step: the weighted RMS of the error estimate over the
// N state components is ≤ 1, so each component's error is ≤ √N (atol + rtol |y|). A run's
// position error is bounded, as in tests/mechanics/orbit/orbit.cpp, by the local bounds of the six
// Cartesian (or deviation) components summed over the steps, each mapped 1:1 into position — a
// derived, not a tight, bound (the Kepler shear grows an along-track error only about linearly
// over the spans here), and an O(1) mistake in the equations moves the orbit by kilometres.
double step_sum_bound(std::size_t steps, std::size_t n_state, double rtol, double atol, double y_max) {
    return double(steps) * std::sqrt(double(n_state)) * 6 * (atol + rtol * y_max);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// The derivation: δ̈ + ρ̈ (ρ̈ = −μ ρ/ρ³, the reference being a Kepler orbit) is Cowell's
// acceleration at r = ρ + δ, ṙ = ρ̇ + δ̇, at random states, with J2, J3, drag and a custom
// time-dependent R (every kind of term the library has). Both sides are evaluated from their
// GiNaC expressions in double precision; the Encke side subtracts nearly equal accelerations
// only through f(q), so it agrees to the rounding of the terms, |μ/r²| ≈ 1e-2 km/s² times a few
// hundred ulps.
BOOST_AUTO_TEST_CASE(encke_equations_are_cowells_minus_the_reference_orbit) {
    const std::string scene = orbit_scene(
        "derive", "J2 = 1.08262668e-3\nJ3 = -2.53e-6\nrho0 = 5.464e-10\nh0 = 180.0\nH = 29.74\nCdA_m = 0.022\nomega = 7.29e-5\n",
        "[effects]\nkeep = [\"J2\", \"J3\", \"drag\"]\n[effects.custom]\ndisturbing_function = \"1e-9*x*z*sin(t/1000)\"\n",
        "elements = { a = 7200.0, e = 0.05, i = 40.0, raan = 20.0, argp = 60.0, mean_anomaly = 100.0 }\nformulation = "
        "\"encke\"");
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(scene, "derive.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    const auto form = eomc::mechanics::first_order_form(model, eqs);
    BOOST_REQUIRE(form.rectification.has_value());
    BOOST_REQUIRE(form.state.size() == 14u);
    BOOST_TEST(form.state[0].name == "dx");
    BOOST_TEST(form.state[13].name == "rectifications");
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    double worst = 0;
    for (int trial = 0; trial < 20; ++trial) {
        GiNaC::exmap at;
        for (const auto& p : model.parameters) at[p.symbol] = p.value;
        const double t = 3000 * (1 + u(rng));
        at[model.t] = t;
        // Deviations up to 100 km and 0.1 km/s, references around the initial one.
        const double scale[14] = {100, 100, 100, 0.1, 0.1, 0.1, 500, 50, 0.02, 0.1, 0.1, 0.1, 1, 0};
        for (std::size_t k = 0; k < 14; ++k) at[form.state[k].symbol] = form.state[k].initial + scale[k] * u(rng);
        auto value = [&](const GiNaC::ex& e) { return GiNaC::ex_to<GiNaC::numeric>(e.subs(at).evalf()).to_double(); };
        std::vector<double> rho(7);
        for (std::size_t k = 0; k < 7; ++k) rho[k] = value(form.rectification->reference[k]);
        const double mu = rho[6], rho_n = norm3(rho);
        GiNaC::exmap cartesian = at;
        for (std::size_t j = 0; j < 3; ++j) {
            cartesian[model.coordinates[j].q] = rho[j] + value(form.state[j].symbol);
            cartesian[model.coordinates[j].q_dot] = rho[3 + j] + value(form.state[3 + j].symbol);
        }
        for (std::size_t j = 0; j < 3; ++j) {
            const double encke = value(form.explicit_rates[3 + j].second) - mu * rho[j] / (rho_n * rho_n * rho_n);
            const double cowell = GiNaC::ex_to<GiNaC::numeric>(eqs.forcing[j].subs(cartesian).evalf()).to_double();
            worst = std::max(worst, std::abs(encke - cowell) / (mu / (rho_n * rho_n)));
        }
        for (std::size_t k = 0; k < 3; ++k) BOOST_TEST(form.explicit_rates[k].second == form.state[3 + k].symbol);
        for (std::size_t k = 6; k < 14; ++k) BOOST_TEST(form.explicit_rates[k].second.is_zero());
    }
    BOOST_TEST_MESSAGE("Encke's δ̈ + ρ̈ vs Cowell's r̈: worst difference " << worst << " of μ/r²");
    BOOST_TEST(worst <= 256 * eps);
    // f(q) is (1 + q)^(3/2) − 1, formed without the cancellation at small q.
    for (const double q : {-0.3, -1e-3, 1e-8, 0.02, 0.5}) {
        const double f = GiNaC::ex_to<GiNaC::numeric>(eomc::mechanics::encke_f(GiNaC::numeric(q)).evalf()).to_double();
        const double direct = std::expm1(1.5 * std::log1p(q));
        BOOST_TEST(std::abs(f - direct) <= 4 * eps * std::abs(direct), "q = " << q);
    }
}

// ---------------------------------------------------------------------------------------------
// Pure Kepler motion: δ̈ = −(μ/ρ³)(δ + f(q) r) is exactly 0 at δ = δ̇ = 0 (q = 0, f = 0), so δ
// stays exactly zero, nothing is rectified, and the outputs are the reference ellipse itself.
// Against the runtime's universal-variable propagator from the scene's initial state, over ten
// periods of an e = 0.3 orbit: both map t to the orbit through a mean motion computed from
// rounded data. Vis-viva 1/a = 2/r − v²/μ carries ≤ (2a/r)(2.5 ulp) + (a v²/μ)(3 ulp) + 1 ulp ≤
// 14 ulp at e = 0.3 (2a/r ≤ 2/(1 − e), a v²/μ ≤ (1 + e)/(1 − e)), so n ≈ √(μ/a³) carries ≤ 21 + 2
// ulp: ≤ 46 ulp of phase per radian of n t between the two, plus a few ulp of |M| in the
// reduction; a phase error moves the position by |∂r/∂M| = |v|/n ≤ a √((1 + e)/(1 − e)). The
// element conversions and the rotation add ≤ 64 ulp of r_max = a (1 + e).
BOOST_AUTO_TEST_CASE(pure_kepler_keeps_delta_zero_and_matches_the_two_body_propagator) {
    const double a = 12000, e = 0.3;
    const Kernel k = generate(orbit_scene(
        "kepler_encke", "", "",
        "elements = { a = 12000.0, e = 0.3, i = 50.0, raan = 30.0, argp = 40.0, mean_anomaly = 10.0 }\nformulation = "
        "\"encke\""));
    const double n = std::sqrt(mu_earth / (a * a * a)), period = 2 * std::numbers::pi / n;
    const fs::path dir = test_support::scratch("encke-scratch", "kepler");
    const SimulationResult r = eomc::host::simulate(request(k, 10 * period, 1e-12, 1e-9, dir / "run.csv"));
    BOOST_TEST(r.value("rectifications") == 0.0);
    const Csv csv = read_csv(dir / "run.csv");
    BOOST_REQUIRE(csv.rows.size() > 10u);
    std::array<double, 6> x0{};
    std::copy(k.initial.begin(), k.initial.end(), x0.begin());
    double worst = 0, worst_ratio = 0;
    for (std::size_t row = 0; row < csv.rows.size(); ++row) {
        const double t = csv.rows[row][0];
        const auto delta = csv.block(row, "dx", 6);
        for (double d : delta) BOOST_TEST(d == 0.0);
        const auto out = csv.block(row, "x", 6);
        const auto expected = eomc::runtime::propagate_kepler(x0, t, mu_earth);
        double diff = 0;
        for (std::size_t i = 0; i < 3; ++i) diff = std::max(diff, std::abs(out[i] - expected[i]));
        const double bound = (46 * n * t + 8 * std::numbers::pi) * eps * a * std::sqrt((1 + e) / (1 - e)) +
                             64 * eps * a * (1 + e);
        worst = std::max(worst, diff);
        worst_ratio = std::max(worst_ratio, diff / bound);
        BOOST_TEST(diff <= bound, "t = " << t);
    }
    BOOST_TEST_MESSAGE("ten periods of pure Kepler motion (" << r.steps << " steps): δ ≡ 0, output vs propagate_kepler "
                                                             << worst << " km, at most " << worst_ratio
                                                             << " of the bound");
}

// ---------------------------------------------------------------------------------------------
// One day of the bundled LEO J2 scene: encke against cowell, at the scene's tolerances.
BOOST_AUTO_TEST_CASE(leo_j2_in_encke_agrees_with_cowell_over_a_day) {
    const auto cowell_scene = bundled("leo_j2.toml", "cowell");
    const auto encke_scene = bundled("leo_j2.toml", "encke");
    const double rtol = cowell_scene.simulate.rtol, atol = cowell_scene.simulate.atol, t_end = 86400;
    const fs::path dir = test_support::scratch("encke-scratch", "leo_j2");
    const SimulationResult c = eomc::host::simulate(request(generate(cowell_scene), t_end, rtol, atol, dir / "cowell.csv"));
    const SimulationResult e = eomc::host::simulate(request(generate(encke_scene), t_end, rtol, atol, dir / "encke.csv"));
    // The largest deviation components the encke run saw (its steps' |y|), the largest radius
    // of either (a(1 + e) = 7070 km plus J2's few km).
    const Csv csv = read_csv(dir / "encke.csv");
    double y_max = 0;
    for (std::size_t row = 0; row < csv.rows.size(); ++row)
        for (double d : csv.block(row, "dx", 6)) y_max = std::max(y_max, std::abs(d));
    const double r_max = 7100;
    const double bound = step_sum_bound(c.steps, 6, rtol, atol, r_max) + step_sum_bound(e.steps, 14, rtol, atol, y_max);
    double worst = 0;
    for (const char* name : {"x", "y", "z"}) worst = std::max(worst, std::abs(c.value(name) - e.value(name)));
    BOOST_TEST_MESSAGE("one day of J2: cowell (" << c.steps << " steps) and encke (" << e.steps << " steps, "
                                                 << e.value("rectifications") << " rectifications) differ by " << worst
                                                 << " km (bound " << bound << ")");
    BOOST_TEST(worst <= bound);
    // The invariants carried over from the Cowell equations, evaluated in the total state: equal
    // at t = 0 up to the round trip of the scene's state through the elements (a few ulp of r
    // and v; the energy's terms are ~2 |E|, h_z's ~|h_z|).
    BOOST_REQUIRE_MESSAGE(e.invariants.size() == c.invariants.size(),
                          e.invariants.size() << " invariants in encke, " << c.invariants.size() << " in cowell");
    for (std::size_t i = 0; i < c.invariants.size(); ++i) {
        BOOST_TEST(e.invariants[i].name == c.invariants[i].name);
        BOOST_TEST(std::abs(e.invariants[i].initial - c.invariants[i].initial) <=
                   64 * eps * std::abs(c.invariants[i].initial));
    }
}

// ---------------------------------------------------------------------------------------------
// Rectification over the same day. The CSV rows are the states the integration goes on from,
// after project(): no row has |δ| above rectify |ρ|, and a row one rectification further than the
// one before has its own time as the reference epoch and δ of that one step's growth; every other
// row keeps the reference. The kernel itself (loaded as the simulation loads it) then shows that
// project() leaves the motion where it was: the total state r = ρ + δ, ṙ = ρ̇ + δ̇ changes by the
// rounding of its three sums, ≤ 4 ulp of |r| (|ṙ|), and the new δ is the round trip r, ṙ →
// elements → ρ, ρ̇, within 256 ulp of |r| (|ṙ|): the split of ω + M is ill-conditioned as 1/e,
// e ≈ 0.01 here, but only the sum enters ρ.
BOOST_AUTO_TEST_CASE(rectification_keeps_delta_small_and_the_motion_continuous) {
    const auto scene = bundled("leo_j2.toml", "encke");
    const double ratio = 1e-2;  // the default [orbit] rectify
    BOOST_REQUIRE(scene.orbit->rectify == ratio);
    const Kernel k = generate(scene);
    const fs::path dir = test_support::scratch("encke-scratch", "rectify");
    const SimulationResult r = eomc::host::simulate(request(k, 86400, 1e-12, 1e-9, dir / "run.csv"));
    const Csv csv = read_csv(dir / "run.csv");
    const std::size_t count = csv.column("rectifications"), ref_t = csv.column("ref_t");
    std::vector<std::size_t> triggers;  // the rows just rectified
    double max_ratio = 0, max_after = 0;
    for (std::size_t row = 0; row < csv.rows.size(); ++row) {
        const auto delta = csv.block(row, "dx", 3), out = csv.block(row, "x", 3);
        const std::vector<double> rho{out[0] - delta[0], out[1] - delta[1], out[2] - delta[2]};
        const double ratio_here = norm3(delta) / norm3(rho);
        max_ratio = std::max(max_ratio, ratio_here);
        BOOST_TEST(ratio_here <= ratio, "row " << row);
        if (row == 0) continue;
        const auto& prev = csv.rows[row - 1];
        const bool rectified = csv.rows[row][count] == prev[count] + 1;
        BOOST_TEST((rectified || csv.rows[row][count] == prev[count]), "row " << row);
        if (rectified) {
            triggers.push_back(row);
            BOOST_TEST(csv.rows[row][ref_t] == csv.rows[row][0]);
            // Just after a rectification δ has only that step's growth, ≈ ½ |∇R| h² ≈ 0.2 km at
            // J2's 1e-5 km/s² and h ≈ 200 s: far below the threshold that a reset that did not
            // re-express δ would leave.
            max_after = std::max(max_after, ratio_here);
        } else {
            BOOST_TEST(csv.rows[row][ref_t] == prev[ref_t]);
        }
    }
    BOOST_TEST_MESSAGE("one day of J2 in encke: " << triggers.size() << " rectifications, max |δ|/|ρ| " << max_ratio
                                                  << " (threshold " << ratio << "), just after a rectification "
                                                  << max_after);
    BOOST_TEST(triggers.size() >= 2u);
    BOOST_TEST(r.value("rectifications") == double(triggers.size()));
    BOOST_TEST(max_after < ratio / 10);

    const auto lib = eomc::host::KernelLibrary::load(k.header, k.struct_name, cache_dir);
    BOOST_TEST(lib.projects());
    const auto parameters = lib.make_parameters(lib.parameter_defaults());
    const std::size_t n = lib.state_names().size();
    double worst_jump = 0, worst_delta = 0;
    for (std::size_t row : triggers) {
        // The state before the rectification, pushed past the threshold: the same total r, ṙ with
        // the reference epoch a quarter orbit earlier, so that δ = r − ρ is of the size of r.
        const double t = csv.rows[row - 1][0];
        std::vector<double> x(csv.rows[row - 1].begin() + 1, csv.rows[row - 1].begin() + 1 + std::ptrdiff_t(n));
        std::vector<double> total(6), rho(6), before(6), after(6);
        lib.outputs(t, x.data(), total.data(), parameters);
        x[ref_t - 1] -= 1500.0;
        std::vector<double> reference = x;
        for (std::size_t i = 0; i < 6; ++i) reference[i] = 0.0;
        lib.outputs(t, reference.data(), rho.data(), parameters);
        for (std::size_t i = 0; i < 6; ++i) x[i] = total[i] - rho[i];
        lib.outputs(t, x.data(), before.data(), parameters);
        const double count_before = x[count - 1];
        lib.project(t, x.data(), parameters);
        lib.outputs(t, x.data(), after.data(), parameters);
        BOOST_TEST(x[count - 1] == count_before + 1);
        BOOST_TEST(x[ref_t - 1] == t);
        for (std::size_t i = 0; i < 6; ++i) {
            const double size = i < 3 ? norm3(before) : norm3(before, 3);
            worst_jump = std::max(worst_jump, std::abs(after[i] - before[i]) / (eps * size));
            worst_delta = std::max(worst_delta, std::abs(x[i]) / (eps * size));
            BOOST_TEST(std::abs(after[i] - before[i]) <= 4 * eps * size, "row " << row << " component " << i);
            BOOST_TEST(std::abs(x[i]) <= 256 * eps * size, "row " << row << " component " << i);
        }
        // Below the threshold project() changes nothing.
        std::vector<double> again = x;
        lib.project(t, again.data(), parameters);
        BOOST_TEST(again == x);
    }
    BOOST_TEST_MESSAGE("across the rectifications the total state moved by ≤ " << worst_jump
                                                                              << " ulp, the new δ is ≤ " << worst_delta
                                                                              << " ulp");
}

// ---------------------------------------------------------------------------------------------
// The bundled drag scene re-enters at the same time in both formulations. The crossing r = Re is
// located to a few ulps of t on each run's dense output, so the two times differ by the runs'
// position difference at the crossing over the radial speed there, plus those ulps; the position
// difference is bounded as in the J2 day (the encke run's own deviations set its scale).
BOOST_AUTO_TEST_CASE(drag_reenters_at_the_same_time_as_cowell) {
    const auto cowell_scene = bundled("leo_drag.toml", "cowell");
    const auto encke_scene = bundled("leo_drag.toml", "encke");
    const double rtol = cowell_scene.simulate.rtol, atol = cowell_scene.simulate.atol;
    const double t_end = cowell_scene.simulate.t_end;
    const fs::path dir = test_support::scratch("encke-scratch", "drag");
    const SimulationResult c = eomc::host::simulate(request(generate(cowell_scene), t_end, rtol, atol, dir / "cowell.csv"));
    const SimulationResult e = eomc::host::simulate(request(generate(encke_scene), t_end, rtol, atol, dir / "encke.csv"));
    BOOST_REQUIRE(c.stopped_by == "re_entry");
    BOOST_REQUIRE(e.stopped_by == "re_entry");
    const Csv csv = read_csv(dir / "encke.csv");
    double y_max = 0;
    for (std::size_t row = 0; row < csv.rows.size(); ++row)
        for (double d : csv.block(row, "dx", 6)) y_max = std::max(y_max, std::abs(d));
    const double r_max = 6628.137 * 1.001;  // circular at 250 km, only sinking
    const double dr = step_sum_bound(c.steps, 6, rtol, atol, r_max) + step_sum_bound(e.steps, 14, rtol, atol, y_max);
    std::vector<double> x;
    for (const char* name : {"x", "y", "z", "x_dot", "y_dot", "z_dot"}) x.push_back(c.value(name));
    const double radial_speed = std::abs(x[0] * x[3] + x[1] * x[4] + x[2] * x[5]) / norm3(x);
    const double bound = dr / radial_speed + 8 * eps * c.t;
    BOOST_TEST_MESSAGE("re-entry after " << c.t / 86400 << " days: cowell (" << c.steps << " steps) at " << c.t
                                         << " s, encke (" << e.steps << " steps, " << e.value("rectifications")
                                         << " rectifications) at " << e.t << " s; differ by " << std::abs(c.t - e.t)
                                         << " s (bound " << bound << " s: " << dr << " km at " << radial_speed
                                         << " km/s)");
    BOOST_TEST(std::abs(c.t - e.t) <= bound);
    BOOST_TEST(e.value("rectifications") > 0.0);
    // The event is located in the total state: the encke run ends on the surface too.
    std::vector<double> r_end;
    for (const char* name : {"x", "y", "z"}) r_end.push_back(e.value(name));
    BOOST_TEST(std::abs(norm3(r_end) - 6378.137) <= 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Errors: a hyperbolic (or parabolic) start has no Kepler ellipse to refer to, refused at the
// formulation key (the scene's, or the command line's); so are [orbit] rectify outside (0, 1)
// and --variational.
BOOST_AUTO_TEST_CASE(a_hyperbolic_start_and_bad_settings_are_refused_at_their_place) {
    const fs::path dir = test_support::scratch("encke-scratch", "errors");
    auto write = [&](const std::string& name, const std::string& text) {
        const fs::path p = dir / name;
        std::ofstream(p) << text;
        return p;
    };
    const fs::path hyperbola = write(
        "hyperbola.toml", orbit_scene("hyperbola", "", "", "state = { r = [7000.0, 0.0, 0.0], v = [0.0, 11.0, 0.0] }\n"
                                                           "formulation = \"encke\""));
    auto run = test_support::run_eomc("generate " + hyperbola.string() + " -o " + (dir / "out").string(), dir);
    BOOST_TEST(run.status == 2);
    BOOST_TEST(run.err.find(hyperbola.string() + ":9:15: ") != std::string::npos, run.err);
    BOOST_TEST(run.err.find("the encke formulation needs an elliptic initial orbit") != std::string::npos, run.err);
    BOOST_TEST(run.err.find("a hyperbola") != std::string::npos, run.err);
    BOOST_TEST(!fs::exists(dir / "out"));

    // The same scene in cowell is fine; asking for encke on the command line is refused there.
    const fs::path cowell = write("cowell.toml", orbit_scene("cowell", "", "",
                                                             "state = { r = [7000.0, 0.0, 0.0], v = [0.0, 11.0, 0.0] }"));
    run = test_support::run_eomc("derive " + cowell.string(), dir);
    BOOST_TEST(run.status == 0, run.err);
    run = test_support::run_eomc("derive " + cowell.string() + " --orbit-formulation encke", dir);
    BOOST_TEST(run.status == 2);
    BOOST_TEST(run.err.find("--orbit-formulation encke") != std::string::npos, run.err);
    BOOST_TEST(run.err.find("elliptic initial orbit") != std::string::npos, run.err);

    const fs::path bad_ratio = write("ratio.toml", orbit_scene("ratio", "", "",
                                                               "elements = { a = 7000.0, e = 0.0 }\nrectify = 1.5"));
    run = test_support::run_eomc("derive " + bad_ratio.string(), dir);
    BOOST_TEST(run.status == 2);
    BOOST_TEST(run.err.find(bad_ratio.string() + ":9:11: ") != std::string::npos, run.err);
    BOOST_TEST(run.err.find("must lie in (0, 1), got 1.5") != std::string::npos, run.err);

    run = test_support::run_eomc(
        "generate " + std::string(EOMC_SOURCE_DIR) + "/scenes/leo_j2.toml --orbit-formulation encke --variational -o " +
            (dir / "out").string(),
        dir);
    BOOST_TEST(run.status == 2);
    BOOST_TEST(run.err.find("--variational cannot follow the encke formulation's rectifications") != std::string::npos,
               run.err);
}

// ---------------------------------------------------------------------------------------------
// `eomc derive` of an encke scene: the disturbing function and its partials (as for every orbit
// scene), then Encke's equation with f(q) and the reference orbit, in text, LaTeX and JSON.
BOOST_AUTO_TEST_CASE(derive_prints_the_encke_equation) {
    const fs::path dir = test_support::scratch("encke-scratch", "derive");
    const std::string scene = std::string(EOMC_SOURCE_DIR) + "/scenes/leo_j2.toml --orbit-formulation encke";
    auto text = test_support::run_eomc("derive " + scene, dir);
    BOOST_TEST(text.status == 0, text.err);
    for (const char* piece : {"Orbit (encke)", "R_J2 = ", "∂R/∂x = ", "Formulation encke (Battin §9.3)",
                              "δ̈ = −(μ/ρ³)(δ + f(q) r) + ∇R(r) + a(r, ṙ)", "q = δ·(δ − 2r)/r²", "f(q) = (1 + q)^(3/2) − 1 = ",
                              "E = kepler_E(M + n (t − t_ref), e)", "|δ| > 0.01 |ρ|"})
        BOOST_TEST(text.out.find(piece) != std::string::npos, piece);
    auto latex = test_support::run_eomc("derive " + scene + " --format latex", dir);
    BOOST_TEST(latex.status == 0, latex.err);
    BOOST_TEST(latex.out.find("\\subsection*{Encke's formulation}") != std::string::npos);
    BOOST_TEST(latex.out.find("f(q) = (1 + q)^{3/2} - 1 = ") != std::string::npos);
    auto json = test_support::run_eomc("derive " + scene + " --format json", dir);
    BOOST_TEST(json.status == 0, json.err);
    BOOST_TEST(json.out.find("\"formulation\": \"encke\"") != std::string::npos);
    BOOST_TEST(json.out.find("\"encke\": {\"equation\": ") != std::string::npos);
    BOOST_TEST(json.out.find("\"rectify\": 0.01}") != std::string::npos);
    // The summary lists the Cartesian outputs after the state.
    auto sim = test_support::run_eomc("simulate " + scene + " --t-end 600 --cache-dir " + cache_dir, dir);
    BOOST_TEST(sim.status == 0, sim.err);
    BOOST_TEST(sim.out.find("outputs\n  x ") != std::string::npos, sim.out);
}
