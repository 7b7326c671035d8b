// [[program]] rows through the library (Mei, ch. 3; Galiullin, Inverse Problems of Dynamics, 1981):
// λ and Q_c = D λ in closed form against the known answers, compared as GiNaC expressions (normal()
// of the difference) or, where trigonometric identities are involved, at exact rational points
// with CLN's exact arithmetic, so every comparison is exact and a wrong sign or factor fails.
#define BOOST_TEST_MODULE mechanics_control
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "host/simulate/program_stiffness.hpp"
#include "mechanics/control/control.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "support/diagnostic.hpp"

#include "control_scenes.hpp"
#include "scenes.hpp"

using GiNaC::ex;
using eomc::InputError;
using eomc::model::Model;

namespace {

Model from_string(const std::string& toml) { return test_support::model_of(toml, "p.toml"); }

const GiNaC::symbol& symbol_named(const Model& model, const std::string& name) {
    for (const auto& p : model.parameters)
        if (p.name == name) return p.symbol;
    for (const auto& c : model.coordinates) {
        if (c.name == name) return c.q;
        if (c.name + "_dot" == name) return c.q_dot;
    }
    BOOST_FAIL("no symbol " << name);
    return model.t;
}

eomc::mechanics::Realisation realised(const Model& model) {
    const auto eqs = eomc::mechanics::derive(model);
    return eomc::mechanics::realise(model, eqs);
}

// The first line:column of an InputError.
std::string where(const std::string& toml) {
    try {
        from_string(toml);
    } catch (const InputError& e) {
        return std::to_string(e.where().line) + ":" + std::to_string(e.where().column) + " " + e.message();
    }
    return "accepted";
}

const std::string particle_plane = R"toml(
[scene]
name = "plane"
[parameters]
m = 1.0
g = 9.81
R = 1.0
v0 = 3.0
[coordinates]
x = { initial = 0.0, rate = 3.0 }
y = { initial = -1.0, rate = 0.0 }
[lagrangian]
T = "m*(x_dot^2 + y_dot^2)/2"
V = "m*g*y"
)toml";

}  // namespace

// Newton's inverse-square law from a radial control realising the conics r(1 + e cos φ) = p
// (Mei §3.1; Galiullin ch. 1): on the program (ω = ω̇ = 0) with the area integral h = r²φ̇ (the
// radial control has no moment, so h is conserved), λ = −h²/(p r²).
BOOST_AUTO_TEST_CASE(radial_control_realising_conics_is_newtons_law) {
    const Model model = from_string(R"toml(
[scene]
name = "conic"
[parameters]
p = 1.3
e = 0.4
[coordinates]
r = { initial = 1.0, rate = 0.0 }
phi = { initial = 0.0, rate = 1.0 }
[lagrangian]
T = "(r_dot^2 + r^2*phi_dot^2)/2"
V = "0"
[[program]]
name = "conic"
constraint = "r*(1 + e*cos(phi)) - p"
control = { r = "1" }
)toml");
    const auto r = realised(model);
    BOOST_REQUIRE(r.lambda);
    const auto &rr = symbol_named(model, "r"), &phi = symbol_named(model, "phi"), &rd = symbol_named(model, "r_dot"),
               &phid = symbol_named(model, "phi_dot"), &p = symbol_named(model, "p"), &e = symbol_named(model, "e");
    // On the manifold: p = r(1 + e cos φ) and ṙ = r e sin φ φ̇/(1 + e cos φ) (ω̇ = 0).
    const ex h = rr * rr * phid;
    const ex expected = -h * h / (p * rr * rr);
    const GiNaC::exmap on{{p, rr * (1 + e * GiNaC::cos(phi))},
                          {rd, rr * e * GiNaC::sin(phi) * phid / (1 + e * GiNaC::cos(phi))}};
    const ex difference = GiNaC::normal(((*r.lambda)[0] - expected).subs(on, GiNaC::subs_options::no_pattern));
    BOOST_TEST(difference.is_zero(), difference);
    // Q_c is radial: Q_φ = 0.
    BOOST_TEST((*r.Qc)[1].is_zero());
}

// Meshchersky's constant speed 3 on a vertical circle R = 1 (g = 9.81, m = 1), both programs ideal:
// the force is m v²/R + m g = 18.81 at the bottom and |m v²/R − m g| = 0.81 at the top.
BOOST_AUTO_TEST_CASE(meshchersky_constant_speed_on_a_vertical_circle) {
    const Model model = from_string(particle_plane + R"toml(
[[program]]
name = "circle"
constraint = "x^2 + y^2 - R^2"
[[program]]
name = "speed"
constraint = "(x_dot^2 + y_dot^2 - v0^2)/2"
)toml");
    const auto r = realised(model);
    BOOST_REQUIRE(r.Qc);
    const auto force = [&](double x, double y, double xd, double yd) {
        GiNaC::exmap at = model.parameter_defaults();
        at[symbol_named(model, "x")] = x;
        at[symbol_named(model, "y")] = y;
        at[symbol_named(model, "x_dot")] = xd;
        at[symbol_named(model, "y_dot")] = yd;
        const double fx = GiNaC::ex_to<GiNaC::numeric>((*r.Qc)[0].subs(at).evalf()).to_double();
        const double fy = GiNaC::ex_to<GiNaC::numeric>((*r.Qc)[1].subs(at).evalf()).to_double();
        return std::hypot(fx, fy);
    };
    // The defaults are doubles (9.81): the closed form is exact in them, the evaluation rounds
    // once per operation, so a few ulps of 18.81.
    BOOST_TEST(force(0, -1, 3, 0) == 18.81, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(force(0, 1, -3, 0) == 0.81, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(r.singular.size() >= 1u);  // Ā M⁻¹ D = [[4r², 2 q·q̇], [2 q·q̇, |q̇|²]]: singular at rest
}

// The programmed regular precession of a symmetric body (A = 2, C = 1, θ = 30°, φ̇ = 0.5,
// ψ̇ = 10) in Euler angles (ZXZ: φ precession, θ nutation, ψ spin; ω₃ = ψ̇ + φ̇ cos θ,
// T = A(θ̇² + φ̇² sin²θ)/2 + C(ψ̇ + φ̇ cos θ)²/2, no gravity): Lagrange's θ equation gives
// Q_θ = φ̇ sin θ (C ω₃ − A φ̇ cos θ) = 5/2 − √3/16; the cyclic angles need no torque.
BOOST_AUTO_TEST_CASE(programmed_regular_precession_needs_only_a_nutation_torque) {
    const Model model = from_string(R"toml(
[scene]
name = "precession"
[parameters]
A = 2
C = 1
[coordinates]
phi = { initial = 0.0, rate = 0.5 }
theta = { initial = 0.5235987755982988, rate = 0.0 }
psi = { initial = 0.0, rate = 10.0 }
[lagrangian]
T = "A*(theta_dot^2 + phi_dot^2*sin(theta)^2)/2 + C*(psi_dot + phi_dot*cos(theta))^2/2"
V = "0"
[[program]]
name = "nutation"
constraint = "theta - Pi/6"
[[program]]
name = "precession"
constraint = "phi_dot - 1/2"
[[program]]
name = "spin"
constraint = "psi_dot - 10"
)toml");
    const auto r = realised(model);
    BOOST_REQUIRE(r.Qc);
    GiNaC::exmap at{{symbol_named(model, "A"), 2},          {symbol_named(model, "C"), 1},
                    {symbol_named(model, "theta"), GiNaC::Pi / 6}, {symbol_named(model, "theta_dot"), 0},
                    {symbol_named(model, "phi_dot"), GiNaC::numeric(1, 2)}, {symbol_named(model, "psi_dot"), 10}};
    const ex expected = GiNaC::numeric(5, 2) - GiNaC::sqrt(ex(3)) / 16;
    BOOST_TEST(GiNaC::normal(((*r.Qc)[1].subs(at) - expected).expand()).is_zero(), (*r.Qc)[1].subs(at));
    BOOST_TEST((*r.Qc)[0].subs(at).is_zero(), (*r.Qc)[0].subs(at));
    BOOST_TEST((*r.Qc)[2].subs(at).is_zero(), (*r.Qc)[2].subs(at));
    const double value = GiNaC::ex_to<GiNaC::numeric>(expected.evalf()).to_double();
    BOOST_TEST(value == 2.39174682452695, boost::test_tools::tolerance(1e-14));
}

// A two-link arm in a horizontal plane (point masses m1 at the elbow, m2 at the tip; θ2 the elbow
// angle relative to the first link) on θ1 = Ωt, θ2 = const, one torque per joint: τ1 = 0 and
// τ2 = m2 l1 l2 Ω² sin θ2 (∂T/∂θ2 = −m2 l1 l2 θ̇1(θ̇1 + θ̇2) sin θ2, every other term vanishes).
BOOST_AUTO_TEST_CASE(two_link_arm_computed_torque) {
    const Model model = from_string(R"toml(
[scene]
name = "arm"
[parameters]
m1 = 1.0
m2 = 0.7
l1 = 1.0
l2 = 0.8
Omega = 2.0
c2 = 0.6
[coordinates]
theta1 = { initial = 0.0, rate = 2.0 }
theta2 = { initial = 0.6, rate = 0.0 }
[lagrangian]
T = "m1*l1^2*theta1_dot^2/2 + m2*(l1^2*theta1_dot^2 + l2^2*(theta1_dot + theta2_dot)^2 + 2*l1*l2*theta1_dot*(theta1_dot + theta2_dot)*cos(theta2))/2"
V = "0"
[[program]]
name = "shoulder"
constraint = "theta1 - Omega*t"
control = ["theta1"]
[[program]]
name = "elbow"
constraint = "theta2 - c2"
control = ["theta2"]
)toml");
    const auto r = realised(model);
    BOOST_REQUIRE(r.lambda);
    const auto& th2 = symbol_named(model, "theta2");
    const GiNaC::exmap on{{symbol_named(model, "theta1_dot"), symbol_named(model, "Omega")},
                          {symbol_named(model, "theta2_dot"), 0}};
    const ex tau1 = GiNaC::normal((*r.lambda)[0].subs(on));
    const ex tau2 = GiNaC::normal((*r.lambda)[1].subs(on) - symbol_named(model, "m2") * symbol_named(model, "l1") *
                                                              symbol_named(model, "l2") *
                                                              GiNaC::pow(symbol_named(model, "Omega"), 2) * GiNaC::sin(th2));
    BOOST_TEST(tau1.is_zero(), tau1);
    BOOST_TEST(tau2.is_zero(), tau2);
    BOOST_TEST(r.singular.empty());  // Ā M⁻¹ D = M⁻¹: regular everywhere
}

// A pendulum's energy program H = θ̇²/2 − g cos θ = h with one torque and φ̇ + κφ = 0: Ā M⁻¹ D = θ̇
// (singular where θ̇ = 0, the only factor) and τ = −κ (H − h)/θ̇ (the gravity terms cancel).
BOOST_AUTO_TEST_CASE(pendulum_energy_program_singular_at_rest) {
    const Model model = from_string(R"toml(
[scene]
name = "energy"
[parameters]
g = 9.81
h = 30
[coordinates]
theta = { initial = 0.0, rate = 8.0 }
[lagrangian]
T = "theta_dot^2/2"
V = "-g*cos(theta)"
[[program]]
name = "energy"
constraint = "theta_dot^2/2 - g*cos(theta) - h"
erugin = { kappa = 1 }
control = ["theta"]
)toml");
    const auto r = realised(model);
    BOOST_REQUIRE(r.lambda);
    const auto& thd = symbol_named(model, "theta_dot");
    BOOST_REQUIRE_EQUAL(r.singular.size(), 1u);
    BOOST_TEST((r.singular[0] - thd).is_zero(), r.singular[0]);
    const ex H = thd * thd / 2 - symbol_named(model, "g") * GiNaC::cos(symbol_named(model, "theta"));
    const ex difference = GiNaC::normal((*r.lambda)[0] + (H - symbol_named(model, "h")) / thd);
    BOOST_TEST(difference.is_zero(), difference);
}

BOOST_AUTO_TEST_CASE(refusals_name_the_place) {
    const auto program = [](const std::string& body) { return particle_plane + "[[program]]\n" + body; };
    // An unknown coordinate in the control, with its nearest name.
    const std::string unknown = where(program("name = \"c\"\nconstraint = \"x - t\"\ncontrol = { z = \"1\" }\n"));
    BOOST_TEST(unknown.rfind("18:13", 0) == 0, unknown);
    BOOST_TEST(unknown.find("unknown coordinate 'z'") != std::string::npos, unknown);
    const std::string actuated = where(program("name = \"c\"\nconstraint = \"x - t\"\ncontrol = [\"xx\"]\n"));
    BOOST_TEST(actuated.rfind("18:13", 0) == 0, actuated);
    BOOST_TEST(actuated.find("did you mean 'x'") != std::string::npos, actuated);
    // kappa with a configuration program, alpha/beta with a phase one.
    const std::string kappa = where(program("name = \"c\"\nconstraint = \"x - t\"\nerugin = { kappa = 1 }\n"));
    BOOST_TEST(kappa.rfind("18:10", 0) == 0, kappa);
    BOOST_TEST(kappa.find("not kappa") != std::string::npos, kappa);
    const std::string ab = where(program("name = \"c\"\nconstraint = \"x_dot - 1\"\nerugin = { alpha = 1, beta = 2 }\n"));
    BOOST_TEST(ab.rfind("18:10", 0) == 0, ab);
    BOOST_TEST(ab.find("not alpha and beta") != std::string::npos, ab);
    // Non-positive gains, at the value.
    const std::string gain = where(program("name = \"c\"\nconstraint = \"x - t\"\nerugin = { alpha = 0, beta = 2 }\n"));
    BOOST_TEST(gain.rfind("18:20", 0) == 0, gain);
    BOOST_TEST(gain.find("must be positive") != std::string::npos, gain);
    // Names are checked identifiers.
    const std::string name = where(program("name = \"c d\"\nconstraint = \"x - t\"\n"));
    BOOST_TEST(name.rfind("16:8", 0) == 0, name);
    // Underactuated: a program on x steered through y alone.
    const std::string under = where(program("name = \"c\"\nconstraint = \"x - t\"\ncontrol = [\"y\"]\n"));
    BOOST_TEST(under.find("accepted") == 0, under);  // the model accepts it; derive refuses
    const Model model = from_string(program("name = \"c\"\nconstraint = \"x - t\"\ncontrol = [\"y\"]\n"));
    try {
        eomc::mechanics::derive(model);
        BOOST_FAIL("an underactuated program was accepted");
    } catch (const InputError& e) {
        BOOST_TEST(e.where().line == 18);
        BOOST_TEST(e.message().find("underactuated") != std::string::npos, e.what());
    }
}

// §3.2: a free body I = (A, B, C) = (2, 3, 5) held on its unstable middle axis by torques about body
// axes 1 and 3, programs p = 0 and r = 0 with φ̇ + κφ = 0, κ = 2. By hand from Euler's equations
// (Mei ch. 5) with ṗ = −κp, ṙ = −κr imposed: M1 = A ṗ − (B − C) q r = −4p + 2qr,
// M3 = C ṙ − (A − B) p q = −10r + pq. Compared exactly (normal() of the difference).
const std::string middle_axis_programs = R"toml(
[[program]]
name = "hold_p"
constraint = "p"
erugin = { kappa = 2.0 }
control = { moment = [1, 0, 0] }
[[program]]
name = "hold_r"
constraint = "r"
erugin = { kappa = 2.0 }
control = { moment = [0, 0, 1] }
)toml";

std::string middle_axis(const std::string& formulation, const std::string& programs = middle_axis_programs) {
    return R"toml([scene]
name = "middle_axis_hold"
[rigid_body]
inertia = ["2", "3", "5"]
weight = "0"
formulation = ")toml" + formulation + R"toml("
[rigid_body.initial]
omega = [0.01, 1.0, 0.01]
vertical = [0.0, 0.0, 1.0]
)toml" + programs;
}

BOOST_AUTO_TEST_CASE(rigid_body_held_on_its_middle_axis_torques_in_closed_form) {
    for (const std::string formulation : {"euler_poisson", "quaternion"}) {
        const Model model = from_string(middle_axis(formulation));
        const auto eqs = eomc::mechanics::derive(model);
        BOOST_TEST_REQUIRE(eqs.programs.size() == 2u);
        BOOST_TEST(!eqs.programs[0].configuration);
        const auto r = eomc::mechanics::realise(model, eqs);
        BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
        const ex &p = model.rigid->omega[0], &q = model.rigid->omega[1], &rr = model.rigid->omega[2];
        const ex l1 = GiNaC::normal((*r.lambda)[0] - (-4 * p + 2 * q * rr));
        const ex l3 = GiNaC::normal((*r.lambda)[1] - (-10 * rr + p * q));
        BOOST_TEST(l1.is_zero(), (*r.lambda)[0]);
        BOOST_TEST(l3.is_zero(), (*r.lambda)[1]);
        // Q_c = D λ: the torque in body axes, none about the middle axis.
        BOOST_TEST(GiNaC::normal((*r.Qc)[0] - (*r.lambda)[0]).is_zero());
        BOOST_TEST((*r.Qc)[1].is_zero(), (*r.Qc)[1]);
        BOOST_TEST(GiNaC::normal((*r.Qc)[2] - (*r.lambda)[1]).is_zero());
        // Ā I⁻¹ D = diag(1/A, 1/C): realisable everywhere.
        BOOST_TEST_REQUIRE(r.determinant.has_value());
        BOOST_TEST(GiNaC::normal(*r.determinant - GiNaC::numeric(1, 10)).is_zero(), *r.determinant);
        BOOST_TEST(r.singular.empty());
    }
}

// A program holding the vertical: φ = K·γ − k0 (the area), steered by a torque about axis 3. Its
// bias is ∂φ/∂γ · (γ × ω) = Iω · (γ × ω), and Ā I⁻¹ D = ∂φ/∂ω I⁻¹ e3 = γ3: singular where γ3 = 0
// (the torque about body axis 3 is then horizontal and cannot change the vertical momentum).
BOOST_AUTO_TEST_CASE(rigid_body_area_program_singular_where_the_torque_is_horizontal) {
    const Model model = from_string(middle_axis("euler_poisson", R"toml(
[[program]]
name = "area"
constraint = "2*p*gamma1 + 3*q*gamma2 + 5*r*gamma3 - 1"
erugin = { kappa = 1.0 }
control = { moment = [0, 0, 1] }
)toml"));
    const auto r = realised(model);
    BOOST_TEST_REQUIRE(r.determinant.has_value());
    const ex gamma3 = model.rigid->gamma[2];
    BOOST_TEST(GiNaC::normal(*r.determinant - gamma3).is_zero(), *r.determinant);
    BOOST_TEST_REQUIRE(r.singular.size() == 1u);
    BOOST_TEST(GiNaC::normal(r.singular[0] - gamma3).is_zero());
    // A free body's K·γ is an integral (Mei ch. 5), so d/dt(K·γ) = λ γ3 and λ γ3 = −κ φ.
    BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
    const auto& w = model.rigid->omega;
    const auto& g = model.rigid->gamma;
    const ex phi = 2 * w[0] * g[0] + 3 * w[1] * g[1] + 5 * w[2] * g[2] - 1;
    const ex difference = GiNaC::normal((*r.lambda)[0] * gamma3 + phi);
    BOOST_TEST(difference.is_zero(), (*r.lambda)[0]);
}

BOOST_AUTO_TEST_CASE(rigid_body_program_refusals_name_the_place) {
    const auto program = [](const std::string& control, const std::string& constraint = "p") {
        return middle_axis("euler_poisson", "[[program]]\nname = \"c\"\nconstraint = \"" + constraint +
                                                "\"\nerugin = { kappa = 1 }\ncontrol = " + control + "\n");
    };
    // Line 14 holds control = ...; the value starts at column 11 (line 12: the constraint).
    const std::string zero = where(program("{ moment = [0, 0.0, 0] }"));
    BOOST_TEST(zero.rfind("14:22", 0) == 0, zero);
    BOOST_TEST(zero.find("zero vector") != std::string::npos, zero);
    const std::string two = where(program("{ moment = [1, 0] }"));
    BOOST_TEST(two.rfind("14:22", 0) == 0, two);
    BOOST_TEST(two.find("expected 3 components") != std::string::npos, two);
    const std::string other = where(program("{ torque = [1, 0, 0] }"));
    BOOST_TEST(other.rfind("14:", 0) == 0, other);
    BOOST_TEST(other.find("torque") != std::string::npos, other);
    const std::string list = where(program("[\"p\"]"));
    BOOST_TEST(list.rfind("14:11", 0) == 0, list);
    BOOST_TEST(list.find("no coordinates to actuate") != std::string::npos, list);
    const std::string state = where(program("{ moment = [\"q\", 0, 0] }"));
    BOOST_TEST(state.rfind("14:", 0) == 0, state);
    // An attitude program (no rate) is of the configuration space: its law is of second order.
    const std::string attitude = where(program("{ moment = [1, 0, 0] }", "gamma1"));
    BOOST_TEST(attitude.rfind("13:", 0) == 0, attitude);
    BOOST_TEST(attitude.find("configuration space") != std::string::npos, attitude);
    std::string angles = middle_axis("euler_angles");
    angles.replace(angles.find("vertical = [0.0, 0.0, 1.0]"), 26, "vertical = [0.0, 0.6, 0.8]");
    const std::string formulation = where(angles);
    BOOST_TEST(formulation.find("euler_poisson or quaternion") != std::string::npos, formulation);
    // Underactuated: a torque about the middle axis cannot steer p.
    const Model model = from_string(program("{ moment = [0, 1, 0] }"));
    try {
        eomc::mechanics::derive(model);
        BOOST_FAIL("an underactuated program was accepted");
    } catch (const InputError& e) {
        BOOST_TEST(e.where().line == 14);
        BOOST_TEST(e.message().find("underactuated") != std::string::npos, e.what());
    }
}

// The stiffness warning (mechanics::stiffness_warnings). Known boundaries: RK4's stability interval
// on the negative real axis ends at z = −2.7853 (|R(−2.78)| = 0.992, |R(−2.79)| = 1.007), so at
// h = 0.01 the phase program φ̇ + κφ = 0 is stable for κ = 278 and not for κ = 279. For dopri5 the
// step is held near 3.3/|λ|: κ = 10⁶ to t = 10 costs ≈ 3.0·10⁶ steps (warned), κ = 10⁴ ≈ 3·10⁴ (not).
// The Gauss–Legendre methods are A-stable: never a warning.
namespace {
Model speed_program(const std::string& law) {
    return from_string(R"toml([scene]
name = "speed"
[coordinates]
x = { initial = 0.0, rate = 1.0 }
[lagrangian]
T = "x_dot^2/2"
V = "0"
[[program]]
name = "speed"
constraint = "x_dot - 2"
erugin = )toml" + law + "\ncontrol = [\"x\"]\n");
}
}  // namespace

BOOST_AUTO_TEST_CASE(stiffness_warning_at_the_integrators_stability_boundary) {
    // The judgment is the host's (host/simulate/program_stiffness.hpp), on the eigenvalues mechanics gives.
    const auto stiffness_warnings = [](const Model& model, const char* integrator, double step, double t_end) {
        return eomc::host::program_stiffness_warnings(model, *eomc::runtime::find_integrator(integrator), step, t_end);
    };
    BOOST_TEST(stiffness_warnings(speed_program("{ kappa = 278 }"), "rk4", 0.01, 10.0).empty());
    const auto rk4 = stiffness_warnings(speed_program("{ kappa = 279 }"), "rk4", 0.01, 10.0);
    BOOST_TEST_REQUIRE(rk4.size() == 1u);
    BOOST_TEST(rk4[0].find("'speed' with kappa = 279") != std::string::npos, rk4[0]);
    BOOST_TEST(rk4[0].find("rk4") != std::string::npos, rk4[0]);
    BOOST_TEST(rk4[0].find("step below 0.00998") != std::string::npos, rk4[0]);  // 2.785/279
    BOOST_TEST(stiffness_warnings(speed_program("{ kappa = 1e6 }"), "gl4", 0.01, 10.0).empty());
    BOOST_TEST(stiffness_warnings(speed_program("{ kappa = 1e4 }"), "dopri5", 0.01, 10.0).empty());
    const auto adaptive = stiffness_warnings(speed_program("{ kappa = 1e6 }"), "dopri5", 0.01, 10.0);
    BOOST_TEST_REQUIRE(adaptive.size() == 1u);
    BOOST_TEST(adaptive[0].find("about 3.03e+06 steps") != std::string::npos, adaptive[0]);
    // dop853's region reaches ≈ 6.1: the same run costs ≈ 1.6·10⁶ steps, still warned.
    BOOST_TEST(stiffness_warnings(speed_program("{ kappa = 1e6 }"), "dop853", 0.01, 10.0).size() == 1u);
    // Complex eigenvalues: α = 1, β = 200 gives λ = −1 ± 199.997i. RK4's region reaches ±2.83 along
    // the imaginary axis: h = 0.01 puts hλ ≈ −0.01 ± 2.0i inside (|R| = 0.735), h = 0.02 puts it at
    // −0.02 ± 4.0i, outside (|R| = 7.56).
    Model circle = from_string(R"toml([scene]
name = "circle"
[coordinates]
x = { initial = 1.0, rate = 0.0 }
y = { initial = 0.0, rate = 1.0 }
[lagrangian]
T = "(x_dot^2 + y_dot^2)/2"
V = "0"
[[program]]
name = "circle"
constraint = "x^2 + y^2 - 1"
erugin = { alpha = 1, beta = 200 }
)toml");
    BOOST_TEST(stiffness_warnings(circle, "rk4", 0.01, 10.0).empty());
    const auto complex = stiffness_warnings(circle, "rk4", 0.02, 10.0);
    BOOST_TEST_REQUIRE(complex.size() == 1u);
    BOOST_TEST(complex[0].find("alpha = 1, beta = 200") != std::string::npos, complex[0]);
}

// §3.2, an attitude programmed by the error quaternion δq = q_d* ⊗ e (scenes/attitude_slew.toml):
// the rows δ_v = 0 are of the configuration space, reach ω̇ through ė = ½ e ⊗ (0, ω), and
// Ā I⁻¹ D for three body-axis torques has det = δ0 |e|²/(8 A B C): singular only where the error
// is half a turn (δ0 = 0; |e|² = 1 on every state). Torques at rest by hand: with q_d = 1 and e a
// turn θ about body axis 1, δ̈1 = ½ e0 ṗ = −β² sin(θ/2) gives τ1 = −2 A β² tan(θ/2), τ2 = τ3 = 0;
// at e = (4/5, 3/5, 0, 0) (tan(θ/2) = 3/4) and A = 2, β = 2: τ1 = −12. The slew scene's torques at
// its initial state and at a moving one are SymPy's (bench/sympy_control.py, an independent
// derivation of λ = I Ā⁻¹ c − Iω × ω). The exact inputs and GiNaC's floats of the gains leave
// round-off only: relative 1e-12.
namespace {
std::string attitude_scene(const std::string& target) {
    return test_support::attitude_scene(
        "attitude", "slew = 1.0\n",
        target == "identity" ? std::array<std::string, 3>{"e1", "e2", "e3"} : test_support::slew_rows("slew"));
}

// λ at a state of the rigid body (ω, e), the parameters at their defaults.
std::vector<double> torques_at(const Model& model, const eomc::mechanics::Realisation& r, std::array<double, 3> w,
                               std::array<double, 4> e) {
    GiNaC::exmap at = model.parameter_defaults();
    for (std::size_t i = 0; i < 3; ++i) at[model.rigid->omega[i]] = w[i];
    for (std::size_t k = 0; k < 4; ++k) at[(*model.rigid->attitude)[k]] = e[k];
    std::vector<double> out;
    for (const ex& l : *r.lambda) out.push_back(GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(l.subs(at))).to_double());
    return out;
}
}  // namespace

BOOST_AUTO_TEST_CASE(attitude_program_by_the_error_quaternion) {
    {
        const Model model = from_string(attitude_scene("identity"));
        const auto eqs = eomc::mechanics::derive(model);
        BOOST_TEST_REQUIRE(eqs.programs.size() == 3u);
        for (const auto& p : eqs.programs) BOOST_TEST(p.configuration);
        const auto r = eomc::mechanics::realise(model, eqs);
        BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
        const auto tau = torques_at(model, r, {0, 0, 0}, {0.8, 0.6, 0, 0});
        BOOST_TEST(tau[0] == -12.0, boost::test_tools::tolerance(1e-12));
        BOOST_TEST(std::abs(tau[1]) < 1e-12);
        BOOST_TEST(std::abs(tau[2]) < 1e-12);
        BOOST_TEST_REQUIRE(r.singular.size() == 1u);
        BOOST_TEST((r.singular[0] - (*model.rigid->attitude)[0]).is_zero(), r.singular[0]);
        const ex det = GiNaC::normal(*r.determinant - (*model.rigid->attitude)[0] / 240 *
                                                          (GiNaC::pow((*model.rigid->attitude)[0], 2) +
                                                           GiNaC::pow((*model.rigid->attitude)[1], 2) +
                                                           GiNaC::pow((*model.rigid->attitude)[2], 2) +
                                                           GiNaC::pow((*model.rigid->attitude)[3], 2)));
        BOOST_TEST(det.is_zero(), *r.determinant);
    }
    const Model model = from_string(attitude_scene("slew"));
    const auto r = realised(model);
    BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
    const auto start = torques_at(model, r, {0, 0, 0}, {std::cos(0.3), std::sin(0.3), 0, 0});
    const std::array<double, 3> sympy_start{-4.949379993753972, 4.055787920656258, 21.85209959375162};
    const auto moving = torques_at(model, r, {0.3, -0.2, 0.7}, {0.5, 0.5, -0.5, 0.5});
    const std::array<double, 3> sympy_moving{-5.992614932740240, 23.64, -18.34153733185060};
    for (std::size_t i = 0; i < 3; ++i) {
        BOOST_TEST(start[i] == sympy_start[i], boost::test_tools::tolerance(1e-12));
        BOOST_TEST(moving[i] == sympy_moving[i], boost::test_tools::tolerance(1e-12));
    }
    // Singular where δ0 = cos(slew/2) e0 + sin(slew/2) e3 = 0.
    BOOST_TEST_REQUIRE(r.singular.size() == 1u);
    const auto& e = *model.rigid->attitude;
    const ex slew = symbol_named(model, "slew");
    BOOST_TEST((r.singular[0] - (GiNaC::cos(slew / 2) * e[0] + GiNaC::sin(slew / 2) * e[3])).expand().is_zero(),
               r.singular[0]);
}

// §3.3, an underactuated system of rigid bodies: the Acrobot (Spong, "The swing up control problem
// for the Acrobot", IEEE Control Systems 15(1), 1995, eqs. 2–7), two links with the torque at the
// elbow only. Programmed on both angles the two programs ask for two independent accelerations from
// one torque: refused at the second program's control, with the rank. Programmed on the elbow
// alone it is Spong's collocated partial feedback linearisation (ibid., eqs. 10–12): q̈2 = v2 by
// τ = d̄22 v2 + h̄2 + φ̄2, d̄22 = d22 − d21 d12/d11, h̄2 = h2 − d21 h1/d11, φ̄2 = φ2 − d21 φ1/d11, here
// with v2 = c = −2α q̇2 − β² (q2 − c2), every term written from Spong's d, h, φ (not from eomc's M, f).
namespace {
std::string acrobot(const std::string& programs) {
    return R"toml([scene]
name = "acrobot"
[parameters]
m1 = 1.0
m2 = 1.0
l1 = 1.0
lc1 = 0.5
lc2 = 0.5
I1 = 0.083
I2 = 0.33
g = 9.8
c2 = 0.3
[coordinates]
q1 = { initial = 0.1, rate = 0.0 }
q2 = { initial = 0.2, rate = 0.0 }
[lagrangian]
T = "((m1*lc1^2 + m2*(l1^2 + lc2^2 + 2*l1*lc2*cos(q2)) + I1 + I2)*q1_dot^2 + 2*(m2*(lc2^2 + l1*lc2*cos(q2)) + I2)*q1_dot*q2_dot + (m2*lc2^2 + I2)*q2_dot^2)/2"
V = "-(m1*lc1 + m2*l1)*g*cos(q1) - m2*lc2*g*cos(q1 + q2)"
)toml" + programs;
}
}  // namespace

BOOST_AUTO_TEST_CASE(acrobot_underactuated_refused_collocated_accepted) {
    const Model both = from_string(acrobot(R"toml([[program]]
name = "shoulder"
constraint = "q1"
erugin = { alpha = 1, beta = 2 }
control = ["q2"]
[[program]]
name = "elbow"
constraint = "q2 - c2"
erugin = { alpha = 1, beta = 2 }
control = ["q2"]
)toml"));
    try {
        eomc::mechanics::derive(both);
        BOOST_FAIL("two programs on one torque were accepted");
    } catch (const InputError& e) {
        // The elbow's control = [...] is the scene's line 28, its value at column 11.
        BOOST_TEST(e.where().line == 28);
        BOOST_TEST(e.where().column == 11);
        const std::string m = e.message();
        BOOST_TEST(m.find("ask for 2 independent accelerations but the controls act in 1 direction (on q2)") !=
                       std::string::npos,
                   m);
        BOOST_TEST(m.find("rank 1 < 2") != std::string::npos, m);
        BOOST_TEST(m.find("underactuated") != std::string::npos, m);
    }
    const Model elbow = from_string(acrobot(R"toml([[program]]
name = "elbow"
constraint = "q2 - c2"
erugin = { alpha = 1, beta = 2 }
control = ["q2"]
)toml"));
    const auto r = realised(elbow);
    BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
    const auto s = [&](const char* n) { return ex(symbol_named(elbow, n)); };
    const ex q1 = s("q1"), q2 = s("q2"), u1 = s("q1_dot"), u2 = s("q2_dot"), m1 = s("m1"), m2 = s("m2"), l1 = s("l1"),
             lc1 = s("lc1"), lc2 = s("lc2"), I1 = s("I1"), I2 = s("I2"), g = s("g");
    const ex d11 = m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * cos(q2)) + I1 + I2;
    const ex d12 = m2 * (lc2 * lc2 + l1 * lc2 * cos(q2)) + I2, d22 = m2 * lc2 * lc2 + I2;
    const ex h1 = -m2 * l1 * lc2 * sin(q2) * u2 * u2 - 2 * m2 * l1 * lc2 * sin(q2) * u2 * u1;
    const ex h2 = m2 * l1 * lc2 * sin(q2) * u1 * u1;
    const ex phi1 = (m1 * lc1 + m2 * l1) * g * sin(q1) + m2 * lc2 * g * sin(q1 + q2);
    const ex phi2 = m2 * lc2 * g * sin(q1 + q2);
    const ex v2 = -2 * u2 - 4 * (q2 - s("c2"));
    const ex spong = (d22 - d12 * d12 / d11) * v2 + h2 - d12 * h1 / d11 + phi2 - d12 * phi1 / d11;
    // Compared at rational points of the state, evaluated to doubles: round-off only.
    for (const auto& point : {std::array<int, 4>{1, 2, 3, -1}, std::array<int, 4>{-2, 5, -1, 4}}) {
        const GiNaC::exmap at{{q1, GiNaC::numeric(point[0], 7)}, {q2, GiNaC::numeric(point[1], 9)},
                              {u1, GiNaC::numeric(point[2], 5)}, {u2, GiNaC::numeric(point[3], 3)}};
        const double got = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf((*r.lambda)[0].subs(at).subs(elbow.parameter_defaults()))).to_double();
        const double want = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(spong.subs(at).subs(elbow.parameter_defaults()))).to_double();
        BOOST_TEST(got == want, boost::test_tools::tolerance(1e-12));
    }
    BOOST_TEST(r.singular.empty(), r.singular.size());  // Ā M⁻¹ D = d11/det M: a principal minor, > 0
}

// A program beside a [[constraint]] row: the bead held on a vertical circle and kept at constant
// speed (tests/support/control_scenes.hpp, with the closed forms μ = m (g y − v0²)/(2R²) and
// λ = m g x/R²). The reaction μ ∇f and the control λ d are solved together; at x = 3/5, y = 4/5,
// (ẋ, ẏ) = v0 (−4/5, 3/5): λ = 5.886, μ = −0.576. Exact rationals in, GiNaC's floats of the gains:
// round-off only. A "project" stabilisation has no counterpart in the controlled kernel: refused at
// its place.
BOOST_AUTO_TEST_CASE(program_beside_a_constraint_row_solved_together) {
    const std::string scene = test_support::bead_on_circle_at_constant_speed();
    const Model model = from_string(scene);
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_TEST_REQUIRE(eqs.programs.size() == 2u);
    BOOST_TEST(eqs.programs[0].name() == "circle");
    const auto r = eomc::mechanics::realise(model, eqs);
    BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
    GiNaC::exmap at = model.parameter_defaults();
    at[symbol_named(model, "x")] = GiNaC::numeric(3, 5);
    at[symbol_named(model, "y")] = GiNaC::numeric(4, 5);
    at[symbol_named(model, "x_dot")] = GiNaC::numeric(-12, 5);
    at[symbol_named(model, "y_dot")] = GiNaC::numeric(9, 5);
    const auto value = [&](const ex& e) { return GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf(e.subs(at))).to_double(); };
    BOOST_TEST(value((*r.lambda)[0]) == -0.576, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(value((*r.lambda)[1]) == 5.886, boost::test_tools::tolerance(1e-12));
    // Q_c = μ ∇f + λ d = −0.576 (6/5, 8/5) + 5.886 (−4/5, 3/5).
    BOOST_TEST(value((*r.Qc)[0]) == -0.576 * 1.2 - 5.886 * 0.8, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(value((*r.Qc)[1]) == -0.576 * 1.6 + 5.886 * 0.6, boost::test_tools::tolerance(1e-12));
    std::string projected = scene;
    projected.replace(projected.find("stabilize = { alpha = 1, beta = 2 }"), 35, "stabilize = \"project\"");
    const std::string refused = where(projected);
    BOOST_TEST(refused.rfind("17:13", 0) == 0, refused);
    BOOST_TEST(refused.find("give stabilize = { alpha = ..., beta = ... }") != std::string::npos, refused);
}

// An attitude program in the Euler–Poisson formulation, on the vertical alone: ω = γ3 − 4/5 (the
// tilt of body axis 3), torque about body axis 1, α = 1, β = 2. With γ̇ = γ × ω the row's rate is
// γ̇3 = γ1 q − γ2 p, so Ā = (−γ2, γ1, 0) and Ā I⁻¹ D = −γ2/A: singular where γ2 = 0 (the torque's
// axis then lies in the vertical plane of axis 3 and cannot tilt it). At rest the bias and Euler's
// terms vanish and −(γ2/A) λ = −β² (γ3 − 4/5), so λ = A β² (γ3 − 4/5)/γ2: at γ = (2/7, 3/7, 6/7),
// λ = 2·4·(6/7 − 4/5)/(3/7) = 16/15.
BOOST_AUTO_TEST_CASE(tilt_program_on_the_vertical) {
    const Model model = from_string(middle_axis("euler_poisson", R"toml([[program]]
name = "tilt"
constraint = "gamma3 - 4/5"
erugin = { alpha = 1, beta = 2 }
control = { moment = [1, 0, 0] }
)toml"));
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_TEST_REQUIRE(eqs.programs.size() == 1u);
    BOOST_TEST(eqs.programs[0].configuration);
    const auto r = eomc::mechanics::realise(model, eqs);
    BOOST_TEST_REQUIRE(r.lambda.has_value(), r.why_not);
    BOOST_TEST_REQUIRE(r.singular.size() == 1u);
    BOOST_TEST((r.singular[0] - model.rigid->gamma[1]).is_zero(), r.singular[0]);
    GiNaC::exmap at;
    for (std::size_t i = 0; i < 3; ++i) at[model.rigid->omega[i]] = 0;
    at[model.rigid->gamma[0]] = GiNaC::numeric(2, 7);
    at[model.rigid->gamma[1]] = GiNaC::numeric(3, 7);
    at[model.rigid->gamma[2]] = GiNaC::numeric(6, 7);
    const double lambda = GiNaC::ex_to<GiNaC::numeric>(GiNaC::evalf((*r.lambda)[0].subs(at))).to_double();
    BOOST_TEST(lambda == 16.0 / 15.0, boost::test_tools::tolerance(1e-12));
}
