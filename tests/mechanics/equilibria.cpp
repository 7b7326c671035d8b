// Relative equilibria and their linear stability (Mei §1.3) against closed forms.
#define BOOST_TEST_MODULE mechanics_equilibria
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "mechanics/equilibria.hpp"
#include "mechanics/lagrange.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

using namespace eomc;

namespace {

std::vector<mechanics::Equilibrium> equilibria_of(const std::string& toml) {
    const model::Model model = model::build_model(scene::parse_scene_string(toml, "test.toml"));
    return mechanics::relative_equilibria(model, mechanics::derive(model));
}

std::string hoop(double omega) {
    return R"toml([scene]
name = "hoop"
[parameters]
m = 0.1
R = 0.5
g = 9.81
omega = )toml" + std::to_string(omega) + R"toml(
[coordinates]
theta = {}
[carrier]
angular_velocity = ["0", "0", "omega"]
[[body]]
name = "bead"
mass = "m"
position = ["R*sin(theta)", "0", "-R*cos(theta)"]
[forces]
potential = "-m*g*R*cos(theta)"
)toml";
}

// Newton converges quadratically to a root of f(θ) whose scale is m g R ~ 0.5: the roots
// are exact to a few ulp of θ; eigenvalues come from a 2×2 (or 4×4) eigensolver whose
// backward error is a few ulp of the largest eigenvalue. 1e-9 leaves room for both.
constexpr double tol = 1e-9;

double largest_real(const mechanics::Equilibrium& e) {
    double r = -1e300;
    for (const auto& l : e.eigenvalues) r = std::max(r, l.real());
    return r;
}

double largest_imag(const mechanics::Equilibrium& e) {
    double r = 0;
    for (const auto& l : e.eigenvalues) r = std::max(r, l.imag());
    return r;
}

}  // namespace

BOOST_AUTO_TEST_CASE(fast_hoop_has_the_bead_off_the_bottom) {
    const double g = 9.81, R = 0.5, omega = 6.0;  // R ω² = 18 > g
    const auto found = equilibria_of(hoop(omega));
    BOOST_REQUIRE_EQUAL(found.size(), 5u);  // −π, −θ*, 0, θ*, π on [−π, π]
    const double theta_star = std::acos(g / (R * omega * omega));
    const double expected[] = {-M_PI, -theta_star, 0.0, theta_star, M_PI};
    for (std::size_t i = 0; i < 5; ++i) BOOST_TEST(std::abs(found[i].q[0] - expected[i]) < tol);

    // Off the bottom: stable, small oscillations at ω sin θ*.
    for (std::size_t i : {1u, 3u}) {
        BOOST_TEST(found[i].verdict == "stable");
        BOOST_TEST(std::abs(largest_imag(found[i]) - omega * std::sin(theta_star)) < tol * omega);
        BOOST_TEST(std::abs(largest_real(found[i])) < tol * omega);
    }
    // The bottom is unstable with growth rate sqrt(ω² − g/R); the top with sqrt(ω² + g/R).
    BOOST_TEST(found[2].verdict == "unstable");
    BOOST_TEST(std::abs(largest_real(found[2]) - std::sqrt(omega * omega - g / R)) < tol * omega);
    BOOST_TEST(found[0].verdict == "unstable");
    BOOST_TEST(std::abs(largest_real(found[0]) - std::sqrt(omega * omega + g / R)) < tol * omega);
}

BOOST_AUTO_TEST_CASE(slow_hoop_keeps_the_bead_at_the_bottom) {
    const double g = 9.81, R = 0.5, omega = 2.0;  // R ω² = 2 < g: only 0 and ±π
    const auto found = equilibria_of(hoop(omega));
    BOOST_REQUIRE_EQUAL(found.size(), 3u);
    BOOST_TEST(std::abs(found[1].q[0]) < tol);
    BOOST_TEST(found[1].verdict == "stable");
    BOOST_TEST(std::abs(largest_imag(found[1]) - std::sqrt(g / R - omega * omega)) < tol * omega);
}

// A particle in a saddle potential ½ m a (x² − y²) fixed in a frame spinning at Ω:
// linearised, λ² = −Ω² ± a. For Ω² > a both stiffnesses a − Ω², −a − Ω² are negative
// (the stiffness matrix is negative definite), yet the Coriolis coupling makes every
// eigenvalue imaginary: gyroscopic stabilisation, frequencies sqrt(Ω² ∓ a). For Ω² < a
// one stiffness is positive, one negative: no gyroscopic coupling can save it.
std::string saddle(double Omega) {
    return R"toml([scene]
name = "saddle"
[parameters]
m = 1.0
a = 1.0
Omega = )toml" + std::to_string(Omega) + R"toml(
[coordinates]
x = {}
y = {}
[carrier]
angular_velocity = ["0", "0", "Omega"]
[[body]]
name = "p"
mass = "m"
position = ["x", "y", "0"]
[forces]
potential = "m*a*(x^2 - y^2)/2"
)toml";
}

BOOST_AUTO_TEST_CASE(rotating_saddle_is_gyroscopically_stabilised) {
    const double a = 1.0, Omega = 2.0;
    const auto found = equilibria_of(saddle(Omega));
    BOOST_REQUIRE_EQUAL(found.size(), 1u);
    BOOST_TEST(found[0].verdict == "gyroscopically stabilised");
    std::vector<double> frequencies;
    for (const auto& l : found[0].eigenvalues) {
        BOOST_TEST(std::abs(l.real()) < tol * Omega);
        if (l.imag() > 0) frequencies.push_back(l.imag());
    }
    std::sort(frequencies.begin(), frequencies.end());
    BOOST_REQUIRE_EQUAL(frequencies.size(), 2u);
    BOOST_TEST(std::abs(frequencies[0] - std::sqrt(Omega * Omega - a)) < tol * Omega);
    BOOST_TEST(std::abs(frequencies[1] - std::sqrt(Omega * Omega + a)) < tol * Omega);

    const auto slow = equilibria_of(saddle(0.5));
    BOOST_REQUIRE_EQUAL(slow.size(), 1u);
    BOOST_TEST(slow[0].verdict == "unstable");
    BOOST_TEST(std::abs(largest_real(slow[0]) - std::sqrt(a - 0.25)) < tol);
}

BOOST_AUTO_TEST_CASE(an_unsteady_carrier_has_no_relative_equilibria) {
    std::string spun_up = hoop(6.0);
    spun_up.replace(spun_up.find("\"omega\"]"), 8, "\"omega*t\"]");
    BOOST_CHECK_THROW(equilibria_of(spun_up), InputError);
}
