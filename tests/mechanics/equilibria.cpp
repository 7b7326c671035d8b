// Relative equilibria and their linear stability (Mei §1.3) against closed forms.
#define BOOST_TEST_MODULE mechanics_equilibria
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "mechanics/derive.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

#include "../support/command.hpp"

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
    BOOST_REQUIRE_EQUAL(found.size(), 4u);  // −θ*, 0, θ*, π on (−π, π]: the top once
    const double theta_star = std::acos(g / (R * omega * omega));
    const double expected[] = {-theta_star, 0.0, theta_star, M_PI};
    for (std::size_t i = 0; i < 4; ++i) BOOST_TEST(std::abs(found[i].q[0] - expected[i]) < tol);

    // Off the bottom: stable, small oscillations at ω sin θ*.
    for (std::size_t i : {0u, 2u}) {
        BOOST_TEST(found[i].verdict == "stable");
        BOOST_TEST(std::abs(largest_imag(found[i]) - omega * std::sin(theta_star)) < tol * omega);
        BOOST_TEST(std::abs(largest_real(found[i])) < tol * omega);
    }
    // The bottom is unstable with growth rate sqrt(ω² − g/R); the top with sqrt(ω² + g/R).
    BOOST_TEST(found[1].verdict == "unstable");
    BOOST_TEST(std::abs(largest_real(found[1]) - std::sqrt(omega * omega - g / R)) < tol * omega);
    BOOST_TEST(found[3].verdict == "unstable");
    BOOST_TEST(std::abs(largest_real(found[3]) - std::sqrt(omega * omega + g / R)) < tol * omega);
}

BOOST_AUTO_TEST_CASE(slow_hoop_keeps_the_bead_at_the_bottom) {
    const double g = 9.81, R = 0.5, omega = 2.0;  // R ω² = 2 < g: only 0 and π
    const auto found = equilibria_of(hoop(omega));
    BOOST_REQUIRE_EQUAL(found.size(), 2u);
    BOOST_TEST(std::abs(found[0].q[0]) < tol);
    BOOST_TEST(found[0].verdict == "stable");
    BOOST_TEST(std::abs(largest_imag(found[0]) - std::sqrt(g / R - omega * omega)) < tol * omega);
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

// ---- Closed forms ----------------------------------------------------------------------------

namespace {

struct Solved {
    model::Model model;
    std::vector<mechanics::Equilibrium> found;
    GiNaC::ex parameter(const std::string& name) const {
        for (const auto& p : model.parameters)
            if (p.name == name) return p.symbol;
        throw std::runtime_error("no parameter " + name);
    }
};

Solved solve(const std::string& toml) {
    Solved s{model::build_model(scene::parse_scene_string(toml, "test.toml")), {}};
    s.found = mechanics::relative_equilibria(s.model, mechanics::derive(s.model));
    return s;
}

// A canonical rational form at every level, function arguments included (acos(x) and acos(y)
// are the same when x and y are): expanded numerator over expanded denominator.
struct NormalEverywhere : GiNaC::map_function {
    GiNaC::ex operator()(const GiNaC::ex& e) override {
        const GiNaC::ex nd = e.map(*this).normal().numer_denom();
        return nd.op(0).expand() / nd.op(1).expand();
    }
};

bool same(const GiNaC::ex& a, const GiNaC::ex& b) {
    NormalEverywhere normal;
    return normal(a - b).is_zero();
}

}  // namespace

// The bead: f(θ) = m R sin θ (R ω² cos θ − g), so θ = 0, ±π and cos θ* = g/(R ω²); M = m R²
// and λ² = f'(θ)/M is ω² − g/R at the bottom, ω² + g/R at the top and g²/(R ω²)² · ω² − ω²
// = −ω² sin² θ* off the bottom (the frequency ω sin θ* of the numeric test above).
BOOST_AUTO_TEST_CASE(hoop_equilibria_in_closed_form) {
    const Solved s = solve(hoop(6.0));
    const GiNaC::ex g = s.parameter("g"), R = s.parameter("R"), w = s.parameter("omega");
    BOOST_REQUIRE_EQUAL(s.found.size(), 4u);
    const GiNaC::ex star = GiNaC::acos(g / (R * w * w));
    const GiNaC::ex expected[] = {-star, 0, star, GiNaC::Pi};
    const GiNaC::ex lambda2[] = {g * g / (R * R * w * w) - w * w, w * w - g / R, g * g / (R * R * w * w) - w * w,
                                 w * w + g / R};
    for (std::size_t i = 0; i < 4; ++i) {
        BOOST_REQUIRE_EQUAL(s.found[i].exact.size(), 1u);
        BOOST_TEST(same(s.found[i].exact[0], expected[i]), "θ " << s.found[i].exact[0]);
        BOOST_REQUIRE(s.found[i].lambda_squared.has_value());
        BOOST_TEST(same(*s.found[i].lambda_squared, lambda2[i]), "λ² " << *s.found[i].lambda_squared);
    }
    // Slow hoop: cos θ* = g/(R ω²) > 1 has no real root; the two left are still exact.
    const Solved slow = solve(hoop(2.0));
    BOOST_REQUIRE_EQUAL(slow.found.size(), 2u);
    for (const auto& e : slow.found) BOOST_TEST(e.exact.size() == 1u);
}

// Two coupled coordinates: a spring-loaded slider (stiffness k, natural length l) at distance
// r along a rod swinging at θ in the plane of a frame spinning at Ω about the vertical. At
// rest f_θ = m r sin θ (r Ω² cos θ − g) and f_r = m Ω² r sin² θ + m g cos θ − k (r − l).
// The factor r Ω² cos θ − g gives r = g/(Ω² cos θ), and then f_r = 0 reduces to
// cos θ* = g (k − m Ω²)/(k l Ω²); sin θ = 0 gives r = l ± m g/k (hanging down, standing up).
std::string slider(double Omega) {
    return R"toml([scene]
name = "slider"
[parameters]
m = 1.0
k = 30.0
l = 0.5
g = 9.81
Omega = )toml" + std::to_string(Omega) + R"toml(
[coordinates]
r = { initial = 0.5 }
theta = {}
[carrier]
angular_velocity = ["0", "0", "Omega"]
[[body]]
name = "p"
mass = "m"
position = ["r*sin(theta)", "0", "-r*cos(theta)"]
[forces]
potential = "-m*g*r*cos(theta) + k*(r-l)^2/2"
)toml";
}

BOOST_AUTO_TEST_CASE(coupled_coordinates_eliminated_in_closed_form) {
    const Solved s = solve(slider(5.0));
    const GiNaC::ex m = s.parameter("m"), k = s.parameter("k"), l = s.parameter("l"), g = s.parameter("g"),
                    W = s.parameter("Omega");
    const GiNaC::ex cos_star = g * (k - m * W * W) / (k * l * W * W);
    const GiNaC::ex off_axis_r = g / (W * W * cos_star);
    // π (standing up), 0 (hanging), ±θ*: four on (−π, π], all in closed form.
    BOOST_REQUIRE_EQUAL(s.found.size(), 4u);
    int hanging = 0, standing = 0, off_axis = 0;
    for (const auto& e : s.found) {
        BOOST_REQUIRE_EQUAL(e.exact.size(), 2u);
        const GiNaC::ex r = e.exact[0], theta = e.exact[1];
        if (same(theta, 0)) {
            ++hanging;
            BOOST_TEST(same(r, l + m * g / k), r);
        } else if (same(GiNaC::cos(theta), -1)) {
            ++standing;
            BOOST_TEST(same(r, l - m * g / k), r);
        } else {
            ++off_axis;
            BOOST_TEST((same(theta, GiNaC::acos(cos_star)) || same(theta, -GiNaC::acos(cos_star))), theta);
            BOOST_TEST(same(r, off_axis_r), r);
        }
        // The numbers are the closed forms evaluated: r g/(Ω² cos θ*) = 3.0000 at these values.
        GiNaC::exmap values;
        for (const auto& p : s.model.parameters) values[p.symbol] = p.value;
        for (std::size_t c = 0; c < 2; ++c)
            BOOST_TEST(std::abs(GiNaC::ex_to<GiNaC::numeric>(e.exact[c].subs(values).evalf()).to_double() - e.q[c]) < tol);
    }
    BOOST_TEST(hanging == 1);
    BOOST_TEST(standing == 1);
    BOOST_TEST(off_axis == 2);
}

// A coordinate absent from the equations at rest (the rotor's spin angle ψ of the gyrocompass,
// cyclic) makes every equilibrium a family in it; the search runs over the others. At rest
// f_φ = (A − C) Ω² sin φ cos φ (platform rate Ω about x', rotor moments C about its axis, A
// across), so φ = 0, ±π/2, ±π. About φ = 0 the stiffness (C − A) Ω² is positive. About φ = π/2
// it is negative, yet the gyroscopic coupling G = C Ω sin φ with ψ̇ (ψ̇ = G φ/C, C being ψ's
// inertia) adds −G²/C: M_φ φ̈ = ((C − A) − C) Ω² φ = −A Ω² φ, stable at Ω √(A/M_φ) = 1 here.
BOOST_AUTO_TEST_CASE(cyclic_coordinate_is_free_and_couples_gyroscopically) {
    const std::string scene = R"toml([scene]
name = "gyro"
[parameters]
m = 1.0
A = 1.0
C = 2.0
Omega = 1.0
[coordinates]
phi = {}
psi = {}
[carrier]
angular_velocity = ["Omega", "0", "0"]
[[body]]
name = "rotor"
mass = "m"
position = ["0", "0", "0"]
inertia = ["C", "A", "A"]
orientation = ["z:phi", "x:psi"]
)toml";
    const auto found = equilibria_of(scene);
    BOOST_REQUIRE_EQUAL(found.size(), 4u);
    const double expected[] = {-M_PI / 2, 0, M_PI / 2, M_PI};
    for (std::size_t i = 0; i < 4; ++i) {
        BOOST_TEST(std::abs(found[i].q[0] - expected[i]) < tol);
        BOOST_TEST(!found[i].free[0]);
        BOOST_TEST(found[i].free[1]);
        BOOST_TEST(std::abs(largest_imag(found[i]) - 1.0) < tol);
        BOOST_TEST(std::abs(largest_real(found[i])) < tol);
    }
    BOOST_TEST(found[1].verdict == "stable");
    BOOST_TEST(found[2].verdict == "gyroscopically stabilised");
}

// ---- Angles: one point of the circle, one equilibrium --------------------------------------------

// The double pendulum's angles enter its equations only through sin and cos of θ1, θ2 and
// θ1 − θ2: each is periodic, and its four equilibria (each link down or up) are reported once,
// in (−π, π], not as the nine points of {−π, 0, π}² of the search range.
BOOST_AUTO_TEST_CASE(angles_report_each_point_of_the_circle_once) {
    const model::Model model =
        model::build_model(scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) + "/scenes/double_pendulum.toml"));
    const auto found = mechanics::relative_equilibria(model, mechanics::derive(model));
    BOOST_REQUIRE_EQUAL(found.size(), 4u);
    const double expected[4][2] = {{0, 0}, {0, M_PI}, {M_PI, 0}, {M_PI, M_PI}};
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t k = 0; k < 2; ++k) BOOST_TEST(std::abs(found[i].q[k] - expected[i][k]) < tol);
    // Only the bottom (both links down) is stable.
    BOOST_TEST(found[0].verdict == "stable");
    for (std::size_t i = 1; i < 4; ++i) BOOST_TEST(found[i].verdict == "unstable");
}

// ---- Singular points and orbit scenes ---------------------------------------------------------

// A point mass about a centre with a J2-like r⁻³ term, in three coordinates: the grid of
// Newton starts has its middle point on the centre (to round-off), where the steps shrink
// with |q| while f ~ q/r⁵ is enormous. The centre is where the equations are singular, not an
// equilibrium, and there is no other point at rest.
BOOST_AUTO_TEST_CASE(the_centre_of_an_attraction_is_not_an_equilibrium) {
    const auto found = equilibria_of(R"toml([scene]
name = "attractor"
[parameters]
m = 1.0
k = 1.0
j = 0.1
[coordinates]
x = { initial = 1.0 }
y = {}
z = {}
[[body]]
name = "p"
mass = "m"
position = ["x", "y", "z"]
[forces]
potential = "-k/sqrt(x^2+y^2+z^2) - k*j/(x^2+y^2+z^2)^(3/2)"
)toml");
    BOOST_TEST(found.size() == 0u);
}

BOOST_AUTO_TEST_CASE(equilibria_of_an_orbit_scene_is_refused_with_exit_2) {
    namespace fs = std::filesystem;
    const fs::path dir = test_support::scratch("equilibria-scratch", "orbit");
    for (const char* name : {"leo_j2", "leo_drag", "geo_equinoctial"}) {
        BOOST_TEST_CONTEXT(name) {
            const std::string path = (fs::path(EOMC_SOURCE_DIR) / "scenes" / (std::string(name) + ".toml")).string();
            const auto r = test_support::run_eomc("equilibria " + path, dir);
            BOOST_TEST(r.status == 2, r.err);
            BOOST_TEST(r.out.empty(), r.out);
            BOOST_TEST(r.err.find(path + ": error: '" + name + "' is an orbit scene ([orbit]): `eomc equilibria` finds "
                                  "the relative equilibria of bodies carried by a steadily moving carrier") == 0u,
                       r.err);
        }
    }
    // The library refuses it the same way, before any search.
    const model::Model leo = model::build_model(scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) + "/scenes/leo_j2.toml"));
    BOOST_CHECK_THROW(mechanics::relative_equilibria(leo, mechanics::derive(leo)), InputError);
}
