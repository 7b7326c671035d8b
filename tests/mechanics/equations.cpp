// Lagrange's equations of the bundled scenes against closed forms, through the library:
//   the seed example (Mei 1988, (1.1.36) first line), dropping effects, singular mass matrices,
//   the Jacobi integral, and the relative equilibria of the bead on the spinning hoop.
// Symbolic facts are exact (`expand().is_zero()`); where a trig identity is needed the
// expression is evaluated at random points with a bound of a few ulps times the size of the
// terms that cancel.
#define BOOST_TEST_MODULE mechanics_equations
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <ginac/ginac.h>

#include "mechanics/derive.hpp"
#include "mechanics/kinematics/operators.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

using GiNaC::ex;
using eomc::InputError;
using eomc::model::Effect;
using eomc::model::Model;

namespace {

Model bundled(const std::string& name) {
    return eomc::model::build_model(
        eomc::scene::parse_scene_file(std::string(EOMC_SOURCE_DIR) + "/scenes/" + name + ".toml"));
}

Model from_string(const std::string& toml) {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, "<test>"));
}

const GiNaC::symbol& parameter(const Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    BOOST_FAIL("no parameter " << name);
    return model.parameters.front().symbol;
}

double parameter_value(const Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.value;
    BOOST_FAIL("no parameter " << name);
    return 0;
}

ex effect_value(const eomc::mechanics::Equation& eq, Effect e) {
    for (const auto& term : eq.effects)
        if (term.effect == e) return term.value;
    return 0;  // not kept
}

bool kept(const eomc::mechanics::Equation& eq, Effect e) {
    for (const auto& term : eq.effects)
        if (term.effect == e) return true;
    return false;
}

double to_double(const ex& e) {
    const ex v = e.evalf();
    BOOST_REQUIRE_MESSAGE(GiNaC::is_a<GiNaC::numeric>(v), "not a number: " << v);
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

// Expects an InputError whose message contains every fragment.
template <class F>
void expect_input_error(F&& f, std::initializer_list<std::string> fragments) {
    try {
        f();
        BOOST_ERROR("no InputError");
    } catch (const InputError& e) {
        const std::string message = e.what();
        BOOST_TEST_INFO("message: " << message);
        for (const auto& fragment : fragments) BOOST_TEST(message.find(fragment) != std::string::npos);
    }
}

const std::string disk_tube_ball_head = R"toml(
[scene]
name = "disk_tube_ball_variant"

[parameters]
M = 2.0
m = 0.5
r = 0.3
Omega = 3.0

[coordinates]
q = { initial = 0.1, rate = 0.0 }

[carrier]
motion = "prescribed"
angular_velocity = ["0", "Omega", "0"]
pole_velocity = ["0", "0", "0"]

[[body]]
name = "ball"
mass = "m"
position = ["q", "0", "0"]
)toml";

}  // namespace

// (1.1.36), first line, with V1 = 0: m (q̈ − q Ω²) = 0. The centrifugal effect is −m Ω² q; the
// tube is along x' and ω along y', so the Coriolis force 2m ω × ṙ' is along z' (carried by the
// tube wall, the third line of (1.1.36)) and the Euler and translation terms vanish (Ω constant,
// pole at rest).
BOOST_AUTO_TEST_CASE(seed_example_disk_tube_ball) {
    const Model model = bundled("disk_tube_ball");
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.equations.size(), 1u);
    const auto& eq = eqs.equations[0];
    const auto& c = model.coordinates[0];
    const ex m = parameter(model, "m"), Omega = parameter(model, "Omega");
    BOOST_TEST_INFO("lhs - rhs = " << (eq.lhs - eq.rhs).expand());
    BOOST_TEST((eq.lhs - eq.rhs - m * (c.q_ddot - Omega * Omega * c.q)).expand().is_zero());
    BOOST_TEST((effect_value(eq, Effect::centrifugal) + m * Omega * Omega * c.q).expand().is_zero());
    BOOST_TEST((effect_value(eq, Effect::relative) - m * c.q_ddot).expand().is_zero());
    for (Effect e : {Effect::coriolis, Effect::euler, Effect::translation}) {
        BOOST_TEST_INFO(eomc::model::name(e));
        BOOST_TEST(kept(eq, e));
        BOOST_TEST(effect_value(eq, e).expand().is_zero());
    }
    BOOST_TEST((eqs.mass_matrix(0, 0) - m).expand().is_zero());
    BOOST_TEST((eqs.forcing[0] - m * Omega * Omega * c.q).expand().is_zero());
}

BOOST_AUTO_TEST_CASE(dropping_the_centrifugal_effect) {
    const Model model = from_string(disk_tube_ball_head + "[effects]\nkeep = [\"relative\", \"coriolis\"]\n");
    const auto eqs = eomc::mechanics::derive(model);
    const auto& eq = eqs.equations[0];
    const ex Omega = parameter(model, "Omega");
    BOOST_TEST(!kept(eq, Effect::centrifugal));
    BOOST_TEST(!kept(eq, Effect::euler));
    BOOST_TEST(!kept(eq, Effect::translation));
    BOOST_TEST(kept(eq, Effect::coriolis));
    BOOST_TEST(!eq.lhs.expand().has(Omega));
    BOOST_TEST(!eqs.forcing[0].expand().has(Omega));
    BOOST_TEST((eq.lhs - parameter(model, "m") * model.coordinates[0].q_ddot).expand().is_zero());
}

// A puck on a turntable spinning at Ω about z': with every effect, m(ẍ − 2Ωẏ − Ω²x) = 0 and
// m(ÿ + 2Ωẋ − Ω²y) = 0; keeping only relative + coriolis leaves m(ẍ − 2Ωẏ), m(ÿ + 2Ωẋ): the
// Coriolis terms (first degree in Ω) stay and nothing of degree 2 in Ω is left.
BOOST_AUTO_TEST_CASE(dropping_centrifugal_keeps_coriolis) {
    const std::string head = R"toml(
[scene]
name = "turntable"

[parameters]
m = 0.3
Omega = 2.0

[coordinates]
x = { initial = 0.1, rate = 0.0 }
y = { initial = 0.0, rate = 0.2 }

[carrier]
motion = "prescribed"
angular_velocity = ["0", "0", "Omega"]
pole_velocity = ["0", "0", "0"]

[[body]]
name = "puck"
mass = "m"
position = ["x", "y", "0"]
)toml";
    const Model full = from_string(head);
    const Model dropped = from_string(head + "[effects]\nkeep = [\"relative\", \"coriolis\"]\n");
    for (const Model* model : {&full, &dropped}) {
        const auto eqs = eomc::mechanics::derive(*model);
        const ex m = parameter(*model, "m"), Omega = parameter(*model, "Omega");
        const auto& X = model->coordinates[0];
        const auto& Y = model->coordinates[1];
        const ex centrifugal = model == &full ? ex(1) : ex(0);
        const ex expected_x = m * (X.q_ddot - 2 * Omega * Y.q_dot - centrifugal * Omega * Omega * X.q);
        const ex expected_y = m * (Y.q_ddot + 2 * Omega * X.q_dot - centrifugal * Omega * Omega * Y.q);
        BOOST_TEST_INFO((model == &full ? "all effects" : "relative + coriolis") << ": " << eqs.equations[0].lhs.expand()
                                                                                << ", " << eqs.equations[1].lhs.expand());
        BOOST_TEST((eqs.equations[0].lhs - eqs.equations[0].rhs - expected_x).expand().is_zero());
        BOOST_TEST((eqs.equations[1].lhs - eqs.equations[1].rhs - expected_y).expand().is_zero());
        if (model == &dropped) {
            for (const auto& eq : eqs.equations) {
                BOOST_TEST(eq.lhs.expand().degree(Omega) == 1);
                BOOST_TEST(!kept(eq, Effect::centrifugal));
            }
            // The Jacobi integral of the kept equations is T_r (Coriolis does no work).
            BOOST_REQUIRE_EQUAL(eqs.invariants.size(), 1u);
            BOOST_TEST((eqs.invariants[0].value - eqs.T_r).expand().is_zero());
        }
    }
}

BOOST_AUTO_TEST_CASE(keeping_effects_without_relative_is_refused) {
    expect_input_error(
        [] { eomc::mechanics::derive(from_string(disk_tube_ball_head + "[effects]\nkeep = [\"centrifugal\", \"coriolis\"]\n")); },
        {"singular", "'q'"});
}

BOOST_AUTO_TEST_CASE(degenerate_kinetic_energy_names_both_coordinates) {
    const std::string toml = R"toml(
[scene]
name = "degenerate"

[parameters]
m = 1.0

[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = 0.0, rate = 0.0 }

[lagrangian]
T = "m*(x_dot + y_dot)^2/2"
V = "0"
)toml";
    expect_input_error([&] { eomc::mechanics::derive(from_string(toml)); }, {"singular", "'x'", "'y'"});
}

// The Jacobi integral h = Σ q̇ ∂L/∂q̇ − L = T_r − T_e + V (T_m = 0 here: ω × r' ⟂ ṙ' on the hoop)
// is reported for a steadily spinning carrier, and not for one whose spin ω = α t accelerates
// (then ∂L/∂t ≠ 0 and h changes at the rate −∂L/∂t: the motor does work).
BOOST_AUTO_TEST_CASE(jacobi_integral_of_the_hoop) {
    const Model model = bundled("bead_on_hoop");
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.invariants.size(), 1u);
    BOOST_TEST(eqs.invariants[0].name == "energy");
    const ex h = eqs.invariants[0].value;
    BOOST_TEST_INFO("h = " << h);
    BOOST_TEST((h - (eqs.T_r - eqs.T_e + eqs.V)).expand().is_zero());
    BOOST_TEST(eqs.T_m.expand().is_zero());
    // And it is conserved: dh/dt = Σ q̇_s (lhs_s − rhs_s), identically in q̈.
    ex power = 0;
    for (std::size_t s = 0; s < eqs.equations.size(); ++s)
        power += model.coordinates[s].q_dot * (eqs.equations[s].lhs - eqs.equations[s].rhs);
    BOOST_TEST((eomc::mechanics::total_derivative(model, h) - power).expand().is_zero());

    std::string accelerating = R"toml(
[scene]
name = "accelerating_hoop"

[parameters]
m = 0.1
R = 0.5
g = 9.81
alpha = 2.0

[coordinates]
theta = { initial = 0.3, rate = 0.0 }

[carrier]
motion = "prescribed"
angular_velocity = ["0", "0", "alpha*t"]
pole_velocity = ["0", "0", "0"]

[[body]]
name = "bead"
mass = "m"
position = ["R*sin(theta)", "0", "-R*cos(theta)"]

[forces]
potential = "m*g*(-R*cos(theta))"
)toml";
    const auto spun_up = eomc::mechanics::derive(from_string(accelerating));
    BOOST_TEST(spun_up.invariants.empty());
    // The Euler effect m (ω̇ × r')·e_θ is zero here (ω̇ ∥ z', e_θ in the x'z' plane, r' in it too:
    // ω̇ × r' is along y'), so the equation differs from the steady hoop only through ω(t)² — yet
    // h is not conserved, which is what matters.
}

BOOST_AUTO_TEST_CASE(energy_of_the_double_pendulum_is_T_plus_V) {
    const Model model = bundled("double_pendulum");
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_REQUIRE_EQUAL(eqs.invariants.size(), 1u);
    BOOST_TEST(eqs.invariants[0].name == "energy");
    BOOST_TEST((eqs.invariants[0].value - (eqs.T + eqs.V)).expand().is_zero());
    BOOST_TEST(!eqs.from_particles);
}

// Bead on the hoop: M θ̈ = f(θ, θ̇) with M = m R², f = m R² ω² sin θ cos θ − m g R sin θ.
// Relative equilibria (f = 0 at θ̇ = 0): θ = 0, θ = π and cos θ* = g/(R ω²). Linearising,
// δ̈ = (∂f/∂θ / M) δ, so the squared frequency is −(∂f/∂θ)/M: ω² sin² θ* = ω² − g²/(R² ω²) at θ*
// and g/R − ω² at the bottom (negative for the defaults, R ω² = 18 > g: unstable).
BOOST_AUTO_TEST_CASE(relative_equilibria_of_the_bead_on_the_hoop) {
    const Model model = bundled("bead_on_hoop");
    const auto eqs = eomc::mechanics::derive(model);
    const auto& c = model.coordinates[0];
    const ex m = parameter(model, "m"), R = parameter(model, "R"), g = parameter(model, "g"),
             omega = parameter(model, "omega");
    const ex f = eqs.forcing[0], M = eqs.mass_matrix(0, 0);
    // No velocity dependence: T_m = 0 and the Coriolis force is normal to the hoop.
    BOOST_TEST(!f.expand().has(c.q_dot));

    const ex f_rest = f.subs(c.q_dot == 0);
    const ex theta_star = GiNaC::acos(g / (R * omega * omega));
    for (const ex& theta : {ex(0), ex(GiNaC::Pi), theta_star}) {
        BOOST_TEST_INFO("theta = " << theta << ", f = " << f_rest.subs(c.q == theta).expand());
        BOOST_TEST(f_rest.subs(c.q == theta).expand().normal().is_zero());
    }

    const ex stiffness = -f_rest.diff(c.q) / M;  // squared frequency of small oscillations
    const ex at_star = stiffness.subs(c.q == theta_star);
    const ex expected_star = omega * omega - g * g / (R * R * omega * omega);
    BOOST_TEST_INFO("at theta*: " << at_star.normal());
    BOOST_TEST((at_star - expected_star).normal().is_zero());
    const ex at_bottom = stiffness.subs(c.q == 0);
    BOOST_TEST((at_bottom - (g / R - omega * omega)).normal().is_zero());

    // And numerically with the scene's defaults: θ* exists and the bottom is unstable.
    GiNaC::exmap defaults;
    for (const auto& p : model.parameters) defaults[p.symbol] = p.value;
    const double w = parameter_value(model, "omega"), RR = parameter_value(model, "R"),
                 gg = parameter_value(model, "g");
    BOOST_TEST(gg / (RR * w * w) < 1.0);
    BOOST_TEST(to_double(at_bottom.subs(defaults)) < 0.0);
    const double s_star = std::sqrt(1.0 - std::pow(gg / (RR * w * w), 2));
    // Both sides are a few operations from the same inputs: 16 ulps of ω² bounds the rounding.
    BOOST_TEST(std::abs(to_double(at_star.subs(defaults)) - w * w * s_star * s_star) <=
               16 * std::numeric_limits<double>::epsilon() * w * w);
    (void)m;
}
