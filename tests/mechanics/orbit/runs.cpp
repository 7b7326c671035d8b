// Every orbit formulation integrated through `eomc simulate` and compared with Cowell's:
//   * leo_j2 over a day: gauss, lagrange, delaunay, equinoctial and encke end where Cowell does;
//   * an eccentric orbit decaying under drag: each re-enters when Cowell's does;
//   * mean: a, e, i stay exactly constant, the angles advance at J2's first-order secular rates
//     (Kozai 1959), and its orbit stays within the first-order theory's error of Cowell's over ten days;
//   * e = 0.999 over many revolutions: the classical elements stay put and the position is the
//     two-body propagator's.
//
// The bound for "ends where Cowell does" comes from the runs themselves. Each formulation F
// is run at τ = 1e-9 and at τ/1000 (rtol = atol = τ, dop853). Its global error at τ/1000 is
// smaller than at τ by about (1/1000)^(8/9) (an eighth-order method's error per unit
// tolerance), so |x_F(τ) − x_F(τ/1000)| estimates its error at τ and is ≥ 100× its error at
// τ/1000. Two correct formulations of the same motion must then agree at τ/1000 within the sum
// of their error estimates at τ. A formulation with a wrong term (a sign, a factor, a
// missing effect) differs by the size of that term's effect over the run — kilometres for J2
// over a day, seconds in re-entry time for drag — far above these millimetre and millisecond
// estimates.
#define BOOST_TEST_MODULE orbit_runs
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <tuple>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/command.hpp"

namespace fs = std::filesystem;
using test_support::run_eomc;

namespace {

const std::string scenes = EOMC_SOURCE_DIR "/scenes/";
const std::string test_scenes = EOMC_SOURCE_DIR "/tests/mechanics/orbit/scenes/";

using Row = std::map<std::string, double>;

// The first and the last CSV row of a run, by column name.
std::pair<Row, Row> first_and_last_rows(const fs::path& csv) {
    std::ifstream in(csv);
    std::string header, line, first, last;
    std::getline(in, header);
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        if (first.empty()) first = line;
        last = line;
    }
    auto parse = [&](const std::string& text) {
        Row row;
        std::stringstream names(header), values(text);
        for (std::string name, value; std::getline(names, name, ',');) {
            std::getline(values, value, ',');
            if (name != "event") row[name] = std::stod(value);
        }
        return row;
    };
    return {parse(first), parse(last)};
}

struct Run {
    double t = 0;
    double x = 0, y = 0, z = 0;  // the final Cartesian position (the state's or the outputs')
    Row start, row;              // the first and the last CSV rows
};

std::string number(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

// `eomc simulate` of the scene in one formulation at rtol = atol = tol; the final CSV row.
Run simulate(const std::string& scene, const std::string& formulation, double tol, const std::string& extra = "") {
    const std::string name = fs::path(scene).stem().string() + "_" + formulation + "_" + number(tol);
    const fs::path dir = test_support::scratch("orbit_runs", name);
    const auto r = run_eomc("simulate '" + scene + "' --orbit-formulation " + formulation + " --rtol " + number(tol) +
                                " --atol " + number(tol) + " --output '" + (dir / "run.csv").string() +
                                "' --cache-dir '" EOMC_BINARY_DIR "/test-cache' " + extra,
                            dir);
    BOOST_REQUIRE_MESSAGE(r.status == 0, r.err);
    Run run;
    std::tie(run.start, run.row) = first_and_last_rows(dir / "run.csv");
    run.t = run.row.at("t");
    run.x = run.row.at("x");
    run.y = run.row.at("y");
    run.z = run.row.at("z");
    return run;
}

}  // namespace

double distance(const Run& a, const Run& b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }

constexpr double loose = 1e-9, tight = 1e-12;

BOOST_AUTO_TEST_CASE(element_formulations_end_where_cowell_does) {
    const std::string scene = scenes + "leo_j2.toml";
    const Run cowell = simulate(scene, "cowell", tight), cowell_loose = simulate(scene, "cowell", loose);
    const double cowell_error = distance(cowell, cowell_loose);
    for (const char* f : {"gauss", "lagrange", "delaunay", "equinoctial", "encke"}) {
        const Run run = simulate(scene, f, tight), run_loose = simulate(scene, f, loose);
        const double bound = distance(run, run_loose) + cowell_error;
        BOOST_TEST_MESSAGE(f << ": " << distance(run, cowell) << " km from Cowell after a day; bound " << bound);
        BOOST_TEST_INFO(f);
        BOOST_TEST(run.t == 86400.0);
        BOOST_TEST(distance(run, cowell) <= bound);
    }
}

BOOST_AUTO_TEST_CASE(equinoctial_elements_stay_accurate_on_a_circular_equatorial_orbit) {
    // geo_equinoctial: e = 0, i = 0, J2 and the Moon for 30 days, where the classical elements
    // are undefined (and refused). The equinoctial run ends where Cowell's does.
    const std::string scene = scenes + "geo_equinoctial.toml";
    const Run cowell = simulate(scene, "cowell", tight), cowell_loose = simulate(scene, "cowell", loose);
    const Run run = simulate(scene, "equinoctial", tight), run_loose = simulate(scene, "equinoctial", loose);
    const double bound = distance(run, run_loose) + distance(cowell, cowell_loose);
    BOOST_TEST_MESSAGE("equinoctial: " << distance(run, cowell) << " km from Cowell after 30 days; bound " << bound);
    BOOST_TEST(distance(run, cowell) <= bound);
    const fs::path dir = test_support::scratch("orbit_runs", "geo_gauss");
    const auto refused = run_eomc("generate '" + scene + "' --orbit-formulation gauss -o .", dir);
    BOOST_TEST(refused.status == 2);
    BOOST_TEST(refused.err.find("elements are singular for this orbit (circular, e = 0)") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(element_formulations_reenter_when_cowell_does) {
    const std::string scene = test_scenes + "decay_eccentric.toml";
    const Run cowell = simulate(scene, "cowell", tight), cowell_loose = simulate(scene, "cowell", loose);
    BOOST_REQUIRE(cowell.t < 2592000.0);  // stopped by re_entry, not at t_end
    // Each run ends on the event, located on the dense output to rounding: its time carries
    // the integration error only.
    const double cowell_error = std::abs(cowell.t - cowell_loose.t);
    for (const char* f : {"gauss", "lagrange", "delaunay", "equinoctial", "encke"}) {
        const Run run = simulate(scene, f, tight), run_loose = simulate(scene, f, loose);
        const double bound = std::abs(run.t - run_loose.t) + cowell_error;
        BOOST_TEST_MESSAGE(f << ": re-entry at " << run.t << " s, " << run.t - cowell.t << " s from Cowell's; bound "
                             << bound);
        BOOST_TEST_INFO(f);
        BOOST_TEST(std::abs(run.t - cowell.t) <= bound);
        // At the surface: r = Re.
        BOOST_TEST(std::hypot(run.x, run.y, run.z) == 6378.137, boost::test_tools::tolerance(1e-9));
    }
}

BOOST_AUTO_TEST_CASE(mean_elements_drift_at_the_secular_rates) {
    const std::string scene = scenes + "leo_j2.toml";
    const double T = 864000;  // ten days
    const Run mean = simulate(scene, "mean", tight, "--t-end " + number(T));
    const double a = mean.start.at("a"), e = mean.start.at("e"), i = mean.start.at("i");
    // Under J2 alone a, e and i have no secular rate: the integration keeps them bit for bit.
    BOOST_TEST(mean.row.at("a") == a);
    BOOST_TEST(mean.row.at("e") == e);
    BOOST_TEST(mean.row.at("i") == i);
    // The angles advance linearly at Kozai's (1959) secular rates. Integrating a constant rate, dop853's
    // only error is rounding: a few ulps of the angle per step, over a few dozen steps.
    const double mu = 398600.4418, Re = 6378.137, J2 = 1.08262668e-3;
    const double eta = std::sqrt(1 - e * e), p = a * eta * eta, n = std::sqrt(mu / (a * a * a));
    const double k2 = J2 * (Re / p) * (Re / p), ci = std::cos(i);
    const double rates[] = {-1.5 * n * k2 * ci, 0.75 * n * k2 * (5 * ci * ci - 1), n * (1 + 0.75 * k2 * eta * (3 * ci * ci - 1))};
    const char* names[] = {"raan", "argp", "mean_anomaly"};
    for (int k = 0; k < 3; ++k) {
        BOOST_TEST_INFO(names[k]);
        const double expected = mean.start.at(names[k]) + rates[k] * T;
        BOOST_TEST(std::abs(mean.row.at(names[k]) - expected) <= 1e-12 * (std::abs(expected) + 1));
    }
    // Against Cowell: the first-order theory leaves out the short-period terms, whose size in
    // position is J2 Re²/p = 6.3 km times factors of order one in each direction (Kozai 1959),
    // and its secular rates are wrong at second order, J2² n t a ≈ 8 km over these ten days.
    // 10 J2 Re²/p holds both; without the mean semi-major axis (the first-order correction of the
    // initial a) the along-track error would grow by 1.5 (δa/a) n t a ≈ 8000 km instead.
    const Run cowell = simulate(scene, "cowell", tight, "--t-end " + number(T));
    const double gap = distance(mean, cowell), bound = 10 * J2 * Re * Re / p;
    BOOST_TEST_MESSAGE("mean vs Cowell after ten days: " << gap << " km; bound " << bound << " km");
    BOOST_TEST(gap <= bound);
}

BOOST_AUTO_TEST_CASE(nearly_parabolic_orbit_over_many_revolutions) {
    // e = 0.999 (periapsis 7000 km, apoapsis 14 million km), no perturbation, 100 revolutions
    // of the kernel's own orbit (T from its initial elements): every element but M stays
    // constant and M advances by n t, so the body is back at periapsis, where it started. The
    // error is M's rounding: a few dozen steps of a few ulps of M(T) = 200π, plus n T's own
    // rounding, δM ≤ 64 ulp(200π); near periapsis δE = δM/(1 − e) and the position moves by
    // |dX/dE| δE ≤ √2 a η δE. (Cowell and the equinoctial elements integrate the periapsis
    // passages themselves; at rtol 1e-12 they end thousands of km away: bench/RESULTS.md.)
    const fs::path dir = test_support::scratch("orbit_runs", "e0999");
    const double mu = 398600.4418, e = 0.999;
    const std::string scene = (dir / "e0999.toml").string();
    std::ofstream(scene) << "[scene]\nname = \"e0999\"\n[parameters]\nmu = 398600.4418\nRe = 6378.137\n"
                            "[orbit]\ncentral_body = { mu = \"mu\", radius = \"Re\" }\n"
                            "elements = { a = 7.0e6, e = 0.999, i = 30.0, raan = 20.0, argp = 10.0 }\n";
    const double dM = 64 * std::numeric_limits<double>::epsilon() * 200 * std::numbers::pi;
    for (const char* f : {"lagrange", "gauss", "delaunay"}) {
        const Row start = simulate(scene, f, tight, "--t-end 1").start;
        const double a = std::string(f) == "delaunay" ? start.at("L") * start.at("L") / mu : start.at("a");
        const double T = 100 * (2 * std::numbers::pi / std::sqrt(mu / (a * a * a)));
        const double bound = std::sqrt(2.0) * a * std::sqrt(1 - e * e) * dM / (1 - e);
        const Run run = simulate(scene, f, tight, "--t-end " + number(T));
        const double moved = std::hypot(run.x - run.start.at("x"), run.y - run.start.at("y"), run.z - run.start.at("z"));
        BOOST_TEST_MESSAGE(f << ": " << moved << " km from the start after 100 revolutions; bound " << bound);
        BOOST_TEST_INFO(f);
        BOOST_TEST(run.t == T);
        BOOST_TEST(moved <= bound);
    }
}

BOOST_AUTO_TEST_CASE(a_start_moved_below_the_surface_is_refused) {
    // re_entry is a downward crossing and cannot see a start already inside the body: a --set
    // that puts it there is refused before the run, in any formulation.
    const fs::path dir = test_support::scratch("orbit_runs", "below");
    for (const std::string& args : {std::string("--set x=6000"), std::string("--orbit-formulation gauss --set a=6300"),
                                    std::string("--set Re=7000")}) {
        const auto r = run_eomc("simulate '" + scenes + "leo_j2.toml' " + args + " --t-end 10 --cache-dir '" EOMC_BINARY_DIR
                                "/test-cache'",
                                dir);
        BOOST_TEST_INFO(args);
        BOOST_TEST(r.status == 2);
        // A moved state is refused against the kernel's re_entry; a moved radius already when the
        // scene is checked again with the values --set gives (as the scene's own radius would be).
        BOOST_TEST((r.err.find("--set: error: the initial state of leo_j2") == 0 ||
                    r.err.find("--set Re=7000: error: the orbit starts at r = 6930 km") == 0),
                   r.err);
        BOOST_TEST(r.err.find("below the central body's surface") != std::string::npos);
    }
}

BOOST_AUTO_TEST_CASE(hamiltonian_orbit_kernel_carries_h_z) {
    // Hamilton's equations of leo_j2 in (x, y, z, p_x, p_y, p_z) keep the Lagrangian side's
    // integrals: H and h_z = x p_y − y p_x. Each accepted step changes h_z by at most
    // |∇h_z|·|local error| ≤ (|p_x| + |p_y| + |x| + |y|) √6 (atol + rtol max|x_i|) (the dop853
    // acceptance test bounds every component by √n times its scale), summed over the steps.
    const fs::path dir = test_support::scratch("orbit_runs", "hamiltonian");
    const auto r = run_eomc("simulate '" + scenes + "leo_j2.toml' --hamiltonian --summary text --cache-dir '" EOMC_BINARY_DIR
                            "/test-cache'",
                            dir);
    BOOST_REQUIRE_MESSAGE(r.status == 0, r.err);
    std::istringstream out(r.out);
    double h0 = 0, drift = -1, steps = 0;
    for (std::string line; std::getline(out, line);) {
        std::istringstream words(line);
        std::string first;
        words >> first;
        if (first == "h_z") words >> h0 >> drift;
        if (first == "steps") words >> steps;
    }
    BOOST_REQUIRE(drift >= 0);
    const double rtol = 1e-12, atol = 1e-9, r_max = 7000 * 1.02, v_max = 7.6;  // leo_j2: a = 7000 km, e = 0.01
    const double per_step = (2 * v_max + 2 * r_max) * std::sqrt(6.0) * (atol + rtol * r_max);
    BOOST_TEST_MESSAGE("h_z = " << h0 << ", drift " << drift << " over " << steps << " steps; bound " << steps * per_step);
    BOOST_TEST(drift <= steps * per_step);
}
