// Unilateral rows beside bilateral ones (issue 16; Mei, Special Topics in Analytical Mechanics,
// §6.6: nonholonomic systems with unilateral holonomic constraints), end to end through eomc
// simulate with both contact drivers: the bundled knife-edge sled hitting a wall (a kinematic
// bilateral row), and a pendulum written in Cartesian coordinates with its rod a holonomic
// bilateral row, against the bundled pendulum_wall in θ. Known answers checked with mpmath.
#define BOOST_TEST_MODULE simulate_contacts_bilateral
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "host/simulate.hpp"

#include "scenes.hpp"
#include "simulation.hpp"

namespace {

eomc::host::SimulationRequest request(const test_support::Kernel& k, double t_end, double rtol = 1e-12) {
    auto r = test_support::simulation_request(k, t_end);
    r.rtol = rtol;
    r.atol = rtol * 1e-2;
    return r;
}

std::vector<const eomc::host::ContactEventReport*> impacts_of(const eomc::host::SimulationResult& result) {
    std::vector<const eomc::host::ContactEventReport*> out;
    for (const auto& e : result.contact_events)
        if (e.kind == "impact") out.push_back(&e);
    return out;
}

const double sqrt3 = std::sqrt(3.0);

// The sled's known answer (scenes/knife_edge_sled_wall.toml): (ẋ, ẏ)⁺ = (√3/2, 1/2), the wall
// impulse 2√3, ΔT = −3/2 by Carnot, φ̇ = 0 throughout.
void check_sled(const eomc::host::SimulationResult& result, const eomc::host::ContactEventReport& impact, double tol) {
    BOOST_TEST(result.value("x_dot") == 0.866025403784439, boost::test_tools::tolerance(tol));
    BOOST_TEST(result.value("y_dot") == 0.5, boost::test_tools::tolerance(tol));
    BOOST_TEST(std::abs(result.value("phi_dot")) <= tol);
    BOOST_TEST(impact.impulse == 3.46410161513775, boost::test_tools::tolerance(tol));
    BOOST_TEST(impact.rate_before == -sqrt3, boost::test_tools::tolerance(tol));
    BOOST_TEST(impact.rate_after == sqrt3 / 2, boost::test_tools::tolerance(tol));
    BOOST_TEST(impact.energy_change == -1.5, boost::test_tools::tolerance(tol));
    BOOST_TEST(impact.carnot == -1.5, boost::test_tools::tolerance(tol));
    // The blade holds after the impact: the velocity lies along the heading.
    const double phi = result.value("phi");
    BOOST_TEST(std::abs(-std::sin(phi) * result.value("x_dot") + std::cos(phi) * result.value("y_dot")) <= tol);
}

}  // namespace

// Event-driven: no force acts, so free flight is linear in t and dopri5 follows it exactly; the
// impact at x = 0.5 − √3 t is located to round-off (t = 0.5/√3) and Newton's law with the blade is
// a closed form (one row). Every number agrees to a few ulp: 1e-13 relative.
BOOST_AUTO_TEST_CASE(knife_edge_sled_hits_a_wall) {
    const auto k = test_support::kernel_of(test_support::bundled_scene("knife_edge_sled_wall"));
    const auto result = eomc::host::simulate(request(k, 1.0));
    const auto impacts = impacts_of(result);
    BOOST_REQUIRE(impacts.size() == 1u);
    BOOST_TEST(impacts[0]->t == 0.5 / sqrt3, boost::test_tools::tolerance(1e-13));
    check_sled(result, *impacts[0], 1e-13);
    BOOST_TEST(result.value("x") == (1.0 - 0.5 / sqrt3) * sqrt3 / 2, boost::test_tools::tolerance(1e-13));
}

// Moreau–Jean (h = 1e-3): without forces u_free = u_k, and the impact step's LCP is Newton's law
// with the blade eliminated by M̃⁻¹, so the velocities, the impulse and ΔT are the exact ones to
// round-off; only the impact's time is O(h) (the step predicted active: within 2 h).
BOOST_AUTO_TEST_CASE(knife_edge_sled_hits_a_wall_moreau_jean) {
    const auto k = test_support::kernel_of(test_support::bundled_scene("knife_edge_sled_wall"));
    auto r = request(k, 1.0);
    r.contact_method = "moreau_jean";
    r.step = 1e-3;
    const auto result = eomc::host::simulate(r);
    const auto impacts = impacts_of(result);
    BOOST_REQUIRE(impacts.size() == 1u);
    BOOST_TEST(std::abs(impacts[0]->t - 0.5 / sqrt3) <= 2 * r.step);
    check_sled(result, *impacts[0], 1e-12);
}

namespace {

// The pendulum l = 0.5 of scenes/pendulum_wall.toml in the bob's Cartesian coordinates, θ from the
// downward vertical: x = l sin θ, y = −l cos θ, the rod x² + y² = l² a holonomic bilateral row and
// the wall θ ≥ 0 the gap x ≥ 0 (e = 0.6). At the wall x = 0, y = −l: ẋ = l θ̇.
const char* const cartesian_pendulum = R"toml([scene]
name = "pendulum_wall_cartesian"
[parameters]
m = 1.0
l = 0.5
g = 9.81
e = 0.6
[coordinates]
x = { initial = 0.5, rate = 0.0 }
y = { initial = 0.0, rate = 0.0 }
[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"
[[constraint]]
name = "rod"
holonomic = "x^2 + y^2 - l^2"
[[unilateral]]
name = "wall"
gap = "x"
restitution = "e"
)toml";

constexpr double l = 0.5, g = 9.81;

// The amplitude after an impact whose rebound rate is θ̇⁺: l θ̇⁺²/2 = g (1 − cos θ_max).
double amplitude_degrees(double theta_dot_plus) {
    return std::acos(1 - l * theta_dot_plus * theta_dot_plus / (2 * g)) * 180 / M_PI;
}
// The k-th amplitude in closed form: θ̇⁺ = e^k √(2g/l), so 1 − cos θ_k = e^(2k).
double amplitude_closed_form(double e, int k) { return std::acos(1 - std::pow(e, 2 * k)) * 180 / M_PI; }

}  // namespace

// The same motion in θ and in (x, y) with the rod: the impacts at the same times, ẋ = l θ̇ before
// and after each, and the amplitudes 1 − cos θ_k = e^(2k) (mpmath: the first impact at
// 0.41857927447728 with |θ̇⁻| = √(2g/l); issue 16's amplitudes 59.336170257614°, 40.5446170970667°,
// 28.0727232800295° are this law's for e = 0.7, checked below; the scene has e = 0.6). Both runs locate each
// impact on dopri5's dense output at rtol 1e-12 (atol 1e-14): the time carries the global error of
// the smooth phase, about rtol per step over a few dozen steps per swing, so 1e-9 in t and in
// θ̇ (relative) bounds each of the first three impacts in either run; the amplitudes follow from
// θ̇⁺ with dθ_max/dθ̇⁺ = l θ̇⁺/(g sin θ_max) = O(0.5 s): 1e-7°.
BOOST_AUTO_TEST_CASE(cartesian_pendulum_against_a_wall_matches_theta) {
    const auto polar = eomc::host::simulate(
        request(test_support::kernel_of(test_support::bundled_scene("pendulum_wall")), 2.0));
    const auto cartesian = eomc::host::simulate(request(test_support::kernel_of(cartesian_pendulum), 2.0));
    const auto a = impacts_of(polar), b = impacts_of(cartesian);
    BOOST_REQUIRE(a.size() >= 3u);
    BOOST_REQUIRE(b.size() == a.size());
    BOOST_TEST(a[0]->t == 0.41857927447728, boost::test_tools::tolerance(1e-9));
    BOOST_TEST(-a[0]->rate_before == std::sqrt(2 * g / l), boost::test_tools::tolerance(1e-9));
    const double amplitudes_e07[] = {59.336170257614, 40.5446170970667, 28.0727232800295};
    for (int i = 0; i < 3; ++i) BOOST_TEST(std::abs(amplitude_closed_form(0.7, i + 1) - amplitudes_e07[i]) <= 1e-11);
    for (std::size_t i = 0; i < a.size(); ++i) {
        BOOST_TEST_MESSAGE("impact " << i + 1 << ": θ at " << a[i]->t << ", (x, y) at " << b[i]->t << ", difference "
                                     << b[i]->t - a[i]->t);
        BOOST_TEST(std::abs(b[i]->t - a[i]->t) <= 1e-9);
        BOOST_TEST(b[i]->rate_before == l * a[i]->rate_before, boost::test_tools::tolerance(1e-9));
        BOOST_TEST(b[i]->rate_after == l * a[i]->rate_after, boost::test_tools::tolerance(1e-9));
        // Carnot with the rod held: ΔT = −((1 − e)/(1 + e)) ½ m Δẋ² (ẏ = 0 at the wall).
        BOOST_TEST(b[i]->carnot == b[i]->energy_change, boost::test_tools::tolerance(1e-9));
        const double expected = amplitude_closed_form(0.6, int(i) + 1);
        BOOST_TEST(std::abs(amplitude_degrees(a[i]->rate_after) - expected) <= 1e-7);
        BOOST_TEST(std::abs(amplitude_degrees(b[i]->rate_after / l) - expected) <= 1e-7);
    }
    // On the rod at the end, positions and velocities (the projection after every step).
    const double x = cartesian.value("x"), y = cartesian.value("y");
    BOOST_TEST(std::abs(x * x + y * y - l * l) <= 1e-14);
    BOOST_TEST(std::abs(x * cartesian.value("x_dot") + y * cartesian.value("y_dot")) <= 1e-13);
    BOOST_TEST(x == l * std::sin(polar.value("theta")), boost::test_tools::tolerance(1e-8));
}

// Moreau–Jean (h = 1e-3) on the Cartesian pendulum: the rod is held at every step (the bilateral
// row eliminated in the LCP, the state projected after it), and the first impact falls within the
// O(h) of the scheme of the exact time (the step predicted active, at most two steps late), with
// ẋ⁻ to O(h) (it is read at the impact step's start, up to two steps early: g h over |ẋ⁻| ≈ 1.6, 2%)
// and Newton's law ẋ⁺ = −e ẋ⁻ up to the velocity projection after the step: the rod's normal
// turns by h |u|/l over it, which changes u by about h |u|²/l along the normal, whose x-component
// is x/l ≈ h |u|/l: h² |u|³/l² ≈ 3e-5, 2e-5 of ẋ⁺; bound 5e-5.
BOOST_AUTO_TEST_CASE(cartesian_pendulum_against_a_wall_moreau_jean) {
    auto r = request(test_support::kernel_of(cartesian_pendulum), 1.0);
    r.contact_method = "moreau_jean";
    r.step = 1e-3;
    const auto result = eomc::host::simulate(r);
    const auto impacts = impacts_of(result);
    BOOST_REQUIRE(!impacts.empty());
    BOOST_TEST(std::abs(impacts[0]->t - 0.41857927447728) <= 2 * r.step);
    BOOST_TEST(impacts[0]->rate_before == -l * std::sqrt(2 * g / l), boost::test_tools::tolerance(0.02));
    BOOST_TEST(impacts[0]->rate_after == -0.6 * impacts[0]->rate_before, boost::test_tools::tolerance(5e-5));
    const double x = result.value("x"), y = result.value("y");
    BOOST_TEST(std::abs(x * x + y * y - l * l) <= 1e-14);
    BOOST_TEST(std::abs(x * result.value("x_dot") + y * result.value("y_dot")) <= 1e-13);
}
