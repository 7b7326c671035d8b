// The relative-motion split of Lagrange's equations (FORMULAS §1, Mei 1988 §1.1), checked as
// symbolic identities on a carrier whose ω(t) and v_o(t) have all three components non-zero
// and time dependent, with two particles at non-trivial r'(q1, q2):
//   ε_s(T_e) + ε_s(T_m) = translation + euler + centrifugal + coriolis,   ε_s(T_r) = relative,
// and T_e, T_m, T_r are homogeneous of degree 0, 1, 2 in q̇ for a scleronomic r'.
// Every identity is polynomial in sin, cos of the coordinates and of t (no sin² + cos² = 1 is
// needed: both sides come from the same product and chain rules), so `expand().is_zero()` is
// an exact test; a random-point evaluation is reported alongside to make a failure readable.
#define BOOST_TEST_MODULE mechanics_effects
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <map>
#include <random>
#include <string>

#include <ginac/ginac.h>

#include "mechanics/derive.hpp"
#include "mechanics/kinematics/operators.hpp"
#include "mechanics/relative/carried_motion.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

using GiNaC::ex;
using eomc::model::Effect;

namespace {

// Carrier motion with every component a non-trivial function of t; positions mixing
// polynomials and trigonometric functions of both coordinates.
const char* const general_carrier = R"toml(
[scene]
name = "general_carrier"

[parameters]
a = 0.7
b = 1.3
c = 0.4
d = 0.9
m1 = 1.5
m2 = 0.8
l = 0.6

[coordinates]
q1 = { initial = 0.2, rate = 0.1 }
q2 = { initial = 0.5, rate = -0.3 }

[carrier]
motion = "prescribed"
angular_velocity = ["a*t", "b*sin(t)", "c + t^2"]
pole_velocity = ["t", "cos(t)", "d*t^2"]

[[body]]
name = "p1"
mass = "m1"
position = ["l*cos(q1) + q2", "l*sin(q1)*q2", "q2^2"]

[[body]]
name = "p2"
mass = "m2"
position = ["q1*q2", "sin(q2) + cos(q1)", "l*sin(q1 + q2)"]
)toml";

// The same carrier with a rheonomic particle (r' depends on t explicitly): the effect identity
// of FORMULAS §1 does not rely on r' being scleronomic, so it must hold here too.
const char* const rheonomic_carrier = R"toml(
[scene]
name = "rheonomic_carrier"

[parameters]
a = 0.7
b = 1.3
c = 0.4
d = 0.9
m1 = 1.5
l = 0.6

[coordinates]
q1 = { initial = 0.2, rate = 0.1 }
q2 = { initial = 0.5, rate = -0.3 }

[carrier]
motion = "prescribed"
angular_velocity = ["a*t", "b*sin(t)", "c + t^2"]
pole_velocity = ["t", "cos(t)", "d*t^2"]

[[body]]
name = "p1"
mass = "m1"
position = ["l*cos(q1 + t) + q2", "q1*sin(t)", "q2^2 + t*q1"]
)toml";

eomc::model::Model model_of(const char* toml) {
    return eomc::model::build_model(eomc::scene::parse_scene_string(toml, "<test>"));
}

ex effect_value(const eomc::mechanics::Equation& eq, Effect e) {
    for (const auto& term : eq.effects)
        if (term.effect == e) return term.value;
    BOOST_FAIL("effect " << eomc::model::name(e) << " missing from the equation of " << eq.coordinate);
    return 0;
}

// Collects every symbol of an expression (model symbols and any the test introduced).
void collect_symbols(const ex& e, GiNaC::exset& out) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) out.insert(e);
    for (std::size_t i = 0; i < e.nops(); ++i) collect_symbols(e.op(i), out);
}

// Value at a fixed pseudo-random point of every symbol in the expression (only for messages).
double at_random_point(const ex& e) {
    GiNaC::exset symbols;
    collect_symbols(e, symbols);
    std::mt19937 gen(12345);
    std::uniform_real_distribution<double> u(-1.3, 1.7);
    GiNaC::exmap point;
    for (const ex& s : symbols) point[s] = u(gen);
    const ex v = e.subs(point).evalf();
    return GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).real().to_double() : std::nan("");
}

void require_identity(const ex& lhs, const ex& rhs, const std::string& what) {
    const ex difference = (lhs - rhs).expand();
    BOOST_TEST_INFO(what << ": lhs - rhs at a random point = " << at_random_point(lhs - rhs)
                         << " (lhs there = " << at_random_point(lhs) << ")");
    BOOST_TEST(difference.is_zero());
}

// ½ Σ m |w|² for one vector per particle, computed here independently of the library.
using Vec = std::array<ex, 3>;
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
ex dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }

}  // namespace

BOOST_AUTO_TEST_CASE(coriolis_and_friends_are_the_euler_operator_of_T_e_plus_T_m) {
    for (const char* scene : {general_carrier, rheonomic_carrier}) {
        const auto model = model_of(scene);
        const auto eqs = eomc::mechanics::derive(model);
        BOOST_REQUIRE(eqs.from_particles && eqs.has_carrier);
        BOOST_REQUIRE_EQUAL(eqs.equations.size(), model.coordinates.size());
        for (std::size_t s = 0; s < model.coordinates.size(); ++s) {
            const auto& eq = eqs.equations[s];
            BOOST_REQUIRE_EQUAL(eq.effects.size(), 5u);  // all effects kept by default
            const ex carrier_side = effect_value(eq, Effect::translation) + effect_value(eq, Effect::euler) +
                                    effect_value(eq, Effect::centrifugal) + effect_value(eq, Effect::coriolis);
            const ex by_operator = eomc::mechanics::euler_operator(model, eqs.T_e, s) +
                                   eomc::mechanics::euler_operator(model, eqs.T_m, s);
            require_identity(by_operator, carrier_side,
                             model.name + ", eps_" + model.coordinates[s].name + "(T_e + T_m)");
            require_identity(eomc::mechanics::euler_operator(model, eqs.T_r, s),
                             effect_value(eq, Effect::relative),
                             model.name + ", eps_" + model.coordinates[s].name + "(T_r)");
            // The inertial side is the sum of the kept effects, and all of it is ε_s(T).
            require_identity(eq.lhs, eomc::mechanics::euler_operator(model, eqs.T, s),
                             model.name + ", lhs vs eps(T)");
        }
    }
}

BOOST_AUTO_TEST_CASE(kinetic_energy_parts_match_an_independent_computation_and_their_degrees) {
    const auto model = model_of(general_carrier);
    const auto eqs = eomc::mechanics::derive(model);
    const auto& omega = model.carrier->angular_velocity;
    const auto& v_o = model.carrier->pole_velocity;

    // T_e = ½ Σ m |v_o + ω × r'|², T_m = Σ m (v_o + ω × r')·ṙ', T_r = ½ Σ m |ṙ'|² (FORMULAS §1).
    ex T_e = 0, T_m = 0, T_r = 0;
    for (const auto& p : model.particles) {
        Vec r_dot{0, 0, 0};
        for (int i = 0; i < 3; ++i)
            for (const auto& c : model.coordinates) r_dot[i] += p.position[i].diff(c.q) * c.q_dot;
        const Vec transport = add(v_o, cross(omega, p.position));
        T_e += p.mass * dot(transport, transport) / 2;
        T_m += p.mass * dot(transport, r_dot);
        T_r += p.mass * dot(r_dot, r_dot) / 2;
    }
    require_identity(eqs.T_e, T_e, "T_e");
    require_identity(eqs.T_m, T_m, "T_m");
    require_identity(eqs.T_r, T_r, "T_r");
    require_identity(eqs.T, T_e + T_m + T_r, "T");
    const auto split = eomc::mechanics::split_kinetic_energy(model);
    require_identity(split.T_e, T_e, "split T_e");
    require_identity(split.T_m, T_m, "split T_m");
    require_identity(split.T_r, T_r, "split T_r");

    // Homogeneity: F(λ q̇) = λ^k F(q̇) with k = 0, 1, 2.
    const GiNaC::symbol lambda("lambda");
    GiNaC::exmap scale;
    for (const auto& c : model.coordinates) scale[c.q_dot] = lambda * c.q_dot;
    require_identity(eqs.T_e.subs(scale), eqs.T_e, "T_e degree 0");
    require_identity(eqs.T_m.subs(scale), lambda * eqs.T_m, "T_m degree 1");
    require_identity(eqs.T_r.subs(scale), lambda * lambda * eqs.T_r, "T_r degree 2");
    // And none of them is zero (a vacuous split would pass the three lines above).
    for (const ex* part : {&eqs.T_e, &eqs.T_m, &eqs.T_r}) BOOST_TEST(!part->expand().is_zero());
}
