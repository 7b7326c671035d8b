// `eomc linearize` (mechanics/linearize) against known answers: the double pendulum's four
// equilibria in closed form, the bead on the hoop against `eomc equilibria`, the Cartesian pendulum
// (a holonomic row) against the minimal-coordinate pendulum, the rolling disc and Chaplygin's sleigh
// (kinematic rows) against closed forms and SymPy's Linearizer (bench/linearize_sympy.py, its output
// in bench/results/linearize_sympy.txt); the sweep's CSV; refusals.
#define BOOST_TEST_MODULE mechanics_linearize
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>

#include "host/linearize_sweep.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/linearize/linearize.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "support/diagnostic.hpp"

#include "command.hpp"
#include "scenes.hpp"

using namespace eomc;
using mechanics::LinearStability;
using mechanics::OperatingPointKind;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

struct Case {
    model::Model model;
    mechanics::Equations equations;
    Case(model::Model m) : model(std::move(m)), equations(mechanics::derive(model)) {}
};

// The linearisation at the scene's values with `set` (name, value) applied.
mechanics::Linearization linearise(const Case& c, OperatingPointKind about,
                                   const std::vector<std::pair<std::string, double>>& set = {}) {
    host::LinearizeInputs in = host::scene_inputs(c.model);
    for (const auto& [name, value] : set) host::set_input(c.model, in, name, value, SourcePos{"test"});
    for (const auto& [name, value] : model::initial_overrides(c.model, set)) host::set_input(c.model, in, name, value, {});
    const mechanics::Linearizer linearizer(c.model, c.equations);
    return linearizer.linearize(in.parameters, about, in.q, in.u, SourcePos{"test"});
}

// A's entries come from LU solves with M of condition ≤ 7 here and sums of a few products, each to a
// few ulp of ‖A‖; a simple, well-separated eigenvalue moves by its condition number (≤ 10 here) times
// the backward error ε‖A‖ of the eigensolver. 1000 ε ‖A‖ bounds both with room, and still fails for
// any wrong entry (the smallest entries here are about 0.3).
double eigen_tolerance(const mechanics::Linearization& lin) { return 1000 * eps * (1.0 + lin.A.norm()); }

// The eigenvalues, checked one by one against `expected` in the listed order (real part decreasing,
// then imaginary part decreasing), and every mode against A v = λ v.
void check_spectrum(const mechanics::Linearization& lin, const std::vector<std::complex<double>>& expected) {
    BOOST_REQUIRE_EQUAL(lin.eigenvalues.size(), expected.size());
    const double tol = eigen_tolerance(lin);
    for (std::size_t j = 0; j < expected.size(); ++j) {
        BOOST_TEST_CONTEXT("eigenvalue " << j << ": " << lin.eigenvalues[j] << " expected " << expected[j]) {
            BOOST_TEST(std::abs(lin.eigenvalues[j] - expected[j]) <= tol);
            const Eigen::VectorXcd v = lin.modes.col(Eigen::Index(j));
            BOOST_TEST((lin.A.cast<std::complex<double>>() * v - lin.eigenvalues[j] * v).norm() <= tol * v.norm());
        }
    }
}

std::complex<double> re(double x) { return {x, 0.0}; }
std::complex<double> im(double y) { return {0.0, y}; }

}  // namespace

// M = m l² [[2, c], [c, 1]], K = m g l diag(2 s1, s2), c = cos(θ1 − θ2) = ±1, s_i = cos θ_i:
// det(K − μ M) = 0 gives μ = (g/l)[(s1 + s2) ± √((s1 + s2)² − 2 s1 s2)] and λ² = −μ.
BOOST_AUTO_TEST_CASE(double_pendulum_four_equilibria_in_closed_form) {
    const Case c(test_support::bundled_model("double_pendulum"));
    const double g = 9.81, l = 1.0, pi = std::numbers::pi;
    const double low = std::sqrt(g / l * (2 - std::sqrt(2.0))), high = std::sqrt(g / l * (2 + std::sqrt(2.0)));
    const double mixed = std::sqrt(std::sqrt(2.0) * g / l);
    struct Point { double th1, th2; std::vector<std::complex<double>> expected; LinearStability verdict; };
    const std::vector<Point> points{
        {0, 0, {im(high), im(low), im(-low), im(-high)}, LinearStability::stable_linear},
        {0, pi, {re(mixed), im(mixed), im(-mixed), re(-mixed)}, LinearStability::unstable},
        {pi, 0, {re(mixed), im(mixed), im(-mixed), re(-mixed)}, LinearStability::unstable},
        {pi, pi, {re(high), re(low), re(-low), re(-high)}, LinearStability::unstable},
    };
    for (const Point& p : points) {
        BOOST_TEST_CONTEXT("th1 = " << p.th1 << ", th2 = " << p.th2) {
            const auto lin = linearise(c, OperatingPointKind::initial, {{"th1", p.th1}, {"th2", p.th2}});
            check_spectrum(lin, p.expected);
            BOOST_TEST(int(lin.verdict) == int(p.verdict));
            BOOST_TEST(lin.ignorable.empty());
        }
    }
    // SymPy's Linearizer (bench/results/linearize_sympy.txt) at the bottom, to its 17 digits.
    const auto bottom = linearise(c, OperatingPointKind::initial, {{"th1", 0}, {"th2", 0}});
    BOOST_TEST(std::abs(bottom.eigenvalues[0].imag() - 5.7873512980360946) <= eigen_tolerance(bottom));
    BOOST_TEST(std::abs(bottom.eigenvalues[1].imag() - 2.3971993978640862) <= eigen_tolerance(bottom));
    // `--about equilibrium` from the scene's (1.5, 0.5): Newton's method reaches the bottom.
    const auto found = linearise(c, OperatingPointKind::equilibrium);
    BOOST_TEST(std::abs(found.q[0]) <= 1e-12);
    BOOST_TEST(std::abs(found.q[1]) <= 1e-12);
}

BOOST_AUTO_TEST_CASE(bead_on_hoop_agrees_with_eomc_equilibria) {
    const Case c(test_support::bundled_model("bead_on_hoop"));
    const auto equilibria = mechanics::relative_equilibria(c.model, c.equations);
    BOOST_REQUIRE_EQUAL(equilibria.size(), 4u);
    for (const auto& e : equilibria) {
        BOOST_TEST_CONTEXT("theta = " << e.q[0]) {
            const auto lin = linearise(c, OperatingPointKind::initial, {{"theta", e.q[0]}});
            check_spectrum(lin, e.eigenvalues);
            BOOST_TEST((lin.verdict == LinearStability::unstable) == (e.verdict == "unstable"));
        }
    }
}

// x² + y² = l² as a row: y and y_dot dependent at the bottom, ±i√(g/l) as the pendulum in θ; at the
// top ±√(g/l).
BOOST_AUTO_TEST_CASE(cartesian_pendulum_matches_the_minimal_pendulum) {
    const Case c(test_support::bundled_model("pendulum_cartesian"));
    const double w = std::sqrt(9.81 / 1.2);
    const auto bottom = linearise(c, OperatingPointKind::equilibrium);
    BOOST_TEST(std::abs(bottom.q[0]) <= 1e-12);
    BOOST_TEST(std::abs(bottom.q[1] + 1.2) <= 1e-12);
    BOOST_TEST(bottom.state == (std::vector<std::string>{"x", "x_dot"}), boost::test_tools::per_element());
    BOOST_TEST(bottom.dependent_coordinates == std::vector<std::size_t>{1}, boost::test_tools::per_element());
    BOOST_TEST(bottom.dependent_speeds == std::vector<std::size_t>{1}, boost::test_tools::per_element());
    check_spectrum(bottom, {im(w), im(-w)});
    BOOST_TEST(int(bottom.verdict) == int(LinearStability::stable_linear));
    // The rod's tension m g at the bottom: λ = −N/(2l) (the scene's comment).
    BOOST_TEST(std::abs(bottom.multipliers[0] + 9.81 / 2.4) <= 1e-12);
    const auto top = linearise(c, OperatingPointKind::equilibrium, {{"x", 0.1}, {"y", 1.1}});
    BOOST_TEST(std::abs(top.q[1] - 1.2) <= 1e-12);
    check_spectrum(top, {re(w), re(-w)});
    BOOST_TEST(int(top.verdict) == int(LinearStability::unstable));
}

// Upright straight rolling at v (Ω = v/r): the lean obeys θ̈ = (4g/(5r) − 12Ω²/5) θ once the heading
// rate's ψ̇ = −2Ω δθ is put in, so λ² = (4/(5r))(g − 3v²/r): stable for v² > g r/3. The other six
// eigenvalues are zero; x, y, ψ and φ are ignorable. SymPy's numbers: bench/results/linearize_sympy.txt.
BOOST_AUTO_TEST_CASE(rolling_disc_steady_rolling) {
    const Case c(test_support::bundled_model("rolling_disc"));
    const double g = 9.81, r = 0.5;
    struct Speed { double v, sympy; LinearStability verdict; };
    for (const Speed& s : {Speed{0.5, 3.6463680560250635, LinearStability::unstable},
                           Speed{1.2, 1.3682105101189665, LinearStability::unstable},
                           Speed{1.5, 2.4298148077579906, LinearStability::stable_linear}}) {
        BOOST_TEST_CONTEXT("v = " << s.v) {
            // The scene's rates x_dot = "v", phi_dot = "v/r" follow v.
            const auto lin = linearise(c, OperatingPointKind::initial, {{"v", s.v}});
            BOOST_TEST(lin.u[0] == s.v);
            BOOST_TEST(std::abs(lin.u[4] - s.v / r) <= eps * s.v / r);
            const double lambda2 = 4 / (5 * r) * (g - 3 * s.v * s.v / r);
            const double root = std::sqrt(std::abs(lambda2));
            const std::complex<double> top = lambda2 > 0 ? re(root) : im(root);
            std::vector<std::complex<double>> expected{top, 0, 0, 0, 0, 0, 0, -top};
            BOOST_REQUIRE_EQUAL(lin.eigenvalues.size(), 8u);
            const double tol = eigen_tolerance(lin);
            BOOST_TEST(std::abs(lin.eigenvalues.front() - expected.front()) <= tol);
            BOOST_TEST(std::abs(lin.eigenvalues.back() - expected.back()) <= tol);
            BOOST_TEST(std::abs(root - s.sympy) <= tol);
            // The zeros: a double zero of the reduced system's (ψ̇, θ, θ̇, φ̇) block, and x, y, ψ, φ's
            // columns; Jordan chains among them move a zero by up to √(ε‖A‖)·‖A‖^(1/2).
            for (std::size_t j = 1; j + 1 < 8; ++j) BOOST_TEST(std::abs(lin.eigenvalues[j]) <= 8 * std::sqrt(eps) * lin.A.norm());
            BOOST_TEST(int(lin.verdict) == int(s.verdict));
            BOOST_TEST(lin.ignorable == (std::vector<std::size_t>{0, 1, 2, 4}), boost::test_tools::per_element());
            BOOST_TEST(lin.dependent_speeds == (std::vector<std::size_t>{0, 1}), boost::test_tools::per_element());
        }
    }
    // The boundary v² = g r/3, one percent either side.
    const double critical = std::sqrt(g * r / 3);
    for (double f : {0.99, 1.01}) {
        const auto lin = linearise(c, OperatingPointKind::initial, {{"x_dot", f * critical}, {"phi_dot", f * critical / r}});
        BOOST_TEST(int(lin.verdict) == int(f > 1 ? LinearStability::stable_linear : LinearStability::unstable));
    }
}

// Straight sliding at V: v̇ = a ω², ω̇ = −(m a/J) V ω to first order (J = I + m a²): −m a V/J and
// zeros; x, y and the heading are ignorable.
BOOST_AUTO_TEST_CASE(chaplygin_sleigh_straight_motion) {
    const Case c(test_support::bundled_model("chaplygin_sleigh"));
    const double m = 2.0, I = 0.5, a = 0.4, V = 0.3, J = I + m * a * a;
    const auto lin = linearise(c, OperatingPointKind::initial, {{"phi_dot", 0.0}, {"x_dot", V}});
    BOOST_REQUIRE_EQUAL(lin.eigenvalues.size(), 5u);
    BOOST_TEST(std::abs(lin.eigenvalues.back() - re(-m * a * V / J)) <= eigen_tolerance(lin));
    BOOST_TEST(int(lin.verdict) == int(LinearStability::stable_linear));
    BOOST_TEST(lin.ignorable == (std::vector<std::size_t>{0, 1, 2}), boost::test_tools::per_element());
    // The scene's own start turns (φ̇ = 2): v̇ = a ω² ≠ 0, not steady.
    BOOST_CHECK_THROW((void)linearise(c, OperatingPointKind::initial), InputError);
}

// A moving coordinate that enters the equations: ẍ = ÿ = 0 at the point, but M changes as x moves.
BOOST_AUTO_TEST_CASE(refuses_a_motion_that_is_not_steady) {
    const Case c(test_support::model_of(R"toml([scene]
name = "drifting"
[parameters]
m = 1.0
[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = { initial = 0.0, rate = 0.0 }
[lagrangian]
T = "m*x_dot^2/2 + m*(1 + x^2)*y_dot^2/2"
)toml"));
    try {
        (void)linearise(c, OperatingPointKind::initial);
        BOOST_FAIL("no refusal");
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()).find("x moves at the operating point") != std::string::npos, e.what());
    }
}

// A defective zero (a free particle: x drifts at any speed) on a matrix of known structure, and
// the three verdicts on diagonal spectra.
BOOST_AUTO_TEST_CASE(verdicts_on_known_matrices) {
    mechanics::Linearization lin;
    lin.independent_coordinates = {0};
    lin.A = Eigen::MatrixXd{{0, 1}, {-4, -0.5}};
    mechanics::classify_linearization(lin);
    BOOST_TEST(int(lin.verdict) == int(LinearStability::asymptotically_stable));
    lin.A = Eigen::MatrixXd{{0, 1}, {4, 0}};
    mechanics::classify_linearization(lin);
    BOOST_TEST(int(lin.verdict) == int(LinearStability::unstable));
    // x̂ column zero: x is ignorable and the reduced system (ẋ alone, λ = 0) is stable.
    lin.A = Eigen::MatrixXd{{0, 1}, {0, 0}};
    mechanics::classify_linearization(lin);
    BOOST_TEST(lin.ignorable == std::vector<std::size_t>{0}, boost::test_tools::per_element());
    BOOST_TEST(int(lin.verdict) == int(LinearStability::stable_linear));
    // An oscillator driven at resonance by another, (θ1, u1, θ2, u2): ±i twice, defective (δθ1 grows
    // like t sin t), and neither coordinate ignorable.
    lin.independent_coordinates = {0, 2};
    lin.A = Eigen::MatrixXd{{0, 1, 0, 0}, {-1, 0, 1, 0}, {0, 0, 0, 1}, {0, 0, -1, 0}};
    mechanics::classify_linearization(lin);
    BOOST_TEST(int(lin.verdict) == int(LinearStability::unstable));
}

// `sweep --linearize` over g: im_1 = √(g/l) in the CSV; `eomc linearize` in JSON; exit 2 on a bad name.
BOOST_AUTO_TEST_CASE(command_line) {
    const auto dir = test_support::scratch("mechanics_linearize", "command_line");
    const std::string scene = std::string(EOMC_SOURCE_DIR) + "/scenes/pendulum_cartesian.toml";
    auto r = test_support::run_eomc("sweep " + scene + " --grid g=1:9:3 --linearize -o " + (dir / "s.csv").string(), dir);
    BOOST_REQUIRE_EQUAL(r.status, 0);
    const std::string csv = test_support::slurp(dir / "s.csv");
    BOOST_TEST(csv.rfind("point,g,verdict,re_1,im_1,re_2,im_2\n", 0) == 0u, csv);
    std::istringstream lines(csv);
    std::string line;
    std::getline(lines, line);
    for (double g : {1.0, 5.0, 9.0}) {
        std::getline(lines, line);
        std::vector<std::string> cells;
        for (std::istringstream cell(line); std::getline(cell, line, ',');) cells.push_back(line);
        BOOST_REQUIRE_EQUAL(cells.size(), 7u);
        BOOST_TEST(cells[2] == "stable in the linear approximation");
        BOOST_TEST(std::abs(std::stod(cells[4]) - std::sqrt(g / 1.2)) <= 1e-12 * std::sqrt(g / 1.2));
    }
    r = test_support::run_eomc("linearize " + scene + " --format json", dir);
    BOOST_REQUIRE_EQUAL(r.status, 0);
    BOOST_TEST(r.out.find("\"verdict\": \"stable in the linear approximation\"") != std::string::npos, r.out);
    BOOST_TEST(r.out.find("\"dependent_coordinates\": [\"y\"]") != std::string::npos, r.out);
    test_support::write_file(dir / "l.json", r.out);
    BOOST_TEST(std::system(("python3 -m json.tool " + (dir / "l.json").string() + " > /dev/null").c_str()) == 0);
    r = test_support::run_eomc("linearize " + scene + " --set speed=2", dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--set speed=2: error: 'speed' is neither") != std::string::npos, r.err);
    r = test_support::run_eomc("linearize " + scene + " --about initial", dir);
    BOOST_TEST(r.status == 2);
    BOOST_TEST(r.err.find("--about initial: error: the operating point is not an equilibrium") != std::string::npos, r.err);
}

// Initial values given as expressions of the parameters ([coordinates] rate = "v/r"): recomputed at
// the values --set, --grid or --vary give, unless the override names the initial value itself.
BOOST_AUTO_TEST_CASE(initial_values_follow_their_parameters) {
    const model::Model disc = test_support::bundled_model("rolling_disc");
    BOOST_TEST(disc.coordinates[0].rate == 1.5);
    BOOST_TEST(disc.coordinates[4].rate == 3.0);
    using Pairs = std::vector<std::pair<std::string, double>>;
    BOOST_TEST(model::initial_overrides(disc, {}).empty());
    BOOST_TEST((model::initial_overrides(disc, {{"v", 2.0}}) == Pairs{{"x_dot", 2.0}, {"phi_dot", 4.0}}));
    BOOST_TEST((model::initial_overrides(disc, {{"v", 2.0}, {"x_dot", 1.0}}) == Pairs{{"phi_dot", 4.0}}));
    BOOST_TEST((model::initial_overrides(disc, {{"r", 0.25}}) == Pairs{{"x_dot", 1.5}, {"phi_dot", 6.0}}));
    // Only parameters may appear: a coordinate is refused at its place in the scene.
    try {
        (void)test_support::model_of(R"toml([scene]
name = "bad"
[parameters]
v = 1.0
[coordinates]
x = { initial = 0.0, rate = "v*y" }
y = {}
[lagrangian]
T = "x_dot^2/2 + y_dot^2/2"
)toml");
        BOOST_FAIL("no refusal");
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()).find("test.toml:6:32: error:") == 0u, e.what());
    }
}

// The same through the command line: a linearisation sweep over v crosses v² = g r/3 (the verdict
// changes between v = 1.2 and 1.4), and a run with --set v=2 starts at x_dot = 2, phi_dot = 4.
BOOST_AUTO_TEST_CASE(sweeping_the_forward_speed) {
    const auto dir = test_support::scratch("mechanics_linearize", "sweeping_the_forward_speed");
    const std::string scene = std::string(EOMC_SOURCE_DIR) + "/scenes/rolling_disc.toml";
    auto r = test_support::run_eomc("sweep " + scene + " --grid v=1.2:1.4:2 --linearize --about initial -o " +
                                        (dir / "s.csv").string(), dir);
    BOOST_REQUIRE_EQUAL(r.status, 0);
    std::istringstream lines(test_support::slurp(dir / "s.csv"));
    std::string line;
    std::getline(lines, line);
    const double g = 9.81, radius = 0.5;
    for (double v : {1.2, 1.4}) {
        std::getline(lines, line);
        std::vector<std::string> cells;
        for (std::istringstream cell(line); std::getline(cell, line, ',');) cells.push_back(line);
        BOOST_REQUIRE_EQUAL(cells.size(), 19u);  // point, v, verdict, 8 eigenvalues
        const double lambda2 = 4 / (5 * radius) * (g - 3 * v * v / radius);
        BOOST_TEST(cells[2] == (lambda2 > 0 ? "unstable" : "stable in the linear approximation"));
        // ‖A‖ ≈ 20 here: 1000 ε ‖A‖ (eigen_tolerance) is below 1e-11.
        BOOST_TEST(std::abs(std::stod(cells[lambda2 > 0 ? 3 : 4]) - std::sqrt(std::abs(lambda2))) <= 1e-11);
    }
    r = test_support::run_eomc("simulate " + scene + " --set v=2 --t-end 0.01 --cache-dir " + (dir / "cache").string() +
                                   " --output " + (dir / "d.csv").string(),
                               dir);
    BOOST_REQUIRE_EQUAL(r.status, 0);
    const std::string run = test_support::slurp(dir / "d.csv");
    BOOST_TEST(run.find("\n0,0,0,0,0,0,2,0,0,0,4,") != std::string::npos, run);
}
