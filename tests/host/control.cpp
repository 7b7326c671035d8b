// Programs realised by controls end to end (issue 17; Mei ch. 3; Galiullin, Inverse Problems of
// Dynamics, 1981): scenes with [[program]] rows derived, emitted, compiled and run through eomc
// simulate. Erugin's residual law against its closed form on two different systems (a particle
// held on a circle, a double pendulum on a configuration program), the pendulum's energy program
// H(t) = 30 − 7.81 e^{−t}, and the stop at the last good state where Ā M⁻¹ D becomes singular.
//
// Tolerances: dopri5 at rtol 1e-10, atol 1e-12 keeps each step's local error below ~1e-10 of the
// state (|x| ≲ 10 here); over the few hundred steps of these runs, with the law contracting the
// residual's own error, the global error of ω = f(q) (|∂f/∂q| ≲ 3) stays below 1e-8. The numbers are
// the issue's, checked with mpmath.
#define BOOST_TEST_MODULE simulate_control
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <string>

#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/program/erugin.hpp"
#include "host/simulate.hpp"

#include "control_scenes.hpp"
#include "simulation.hpp"

namespace {

constexpr double tolerance = 1e-8;

eomc::host::SimulationResult run(const std::string& toml, double t_end) {
    auto request = test_support::simulation_request(test_support::kernel_of(toml), t_end);
    return eomc::host::simulate(request);
}

std::string circle(const std::string& law) {
    return R"toml([scene]
name = "held_on_circle"
[parameters]
g = 9.81
[coordinates]
x = { initial = 1.1, rate = 0.0 }
y = { initial = 0.0, rate = 1.0 }
[lagrangian]
T = "(x_dot^2 + y_dot^2)/2"
V = "g*y"
[[program]]
name = "circle"
constraint = "x^2 + y^2 - 1"
erugin = )toml" + law + "\n";
}

std::string double_pendulum(const std::string& law) {
    return R"toml([scene]
name = "double_pendulum_program"
[parameters]
g = 9.81
[coordinates]
th1 = { initial = 0.51, rate = 0.0 }
th2 = { initial = 0.2, rate = 0.7 }
[lagrangian]
T = "th1_dot^2 + th2_dot^2/2 + th1_dot*th2_dot*cos(th1 - th2)"
V = "-2*g*cos(th1) - g*cos(th2)"
[[program]]
name = "upper"
constraint = "th1 - 3/10"
erugin = )toml" + law + "\n";
}

// The attitude slew of scenes/attitude_slew.toml, turned by `angle` (a constant, or a function of t)
// with Omega = 0.5, program i's torque about body axis order[i].
std::string attitude_slew_scene(const std::string& angle, const std::array<std::size_t, 3>& order) {
    return test_support::attitude_scene("attitude_slew", "slew = 1.0\nOmega = 0.5\n", test_support::slew_rows(angle), order);
}

}  // namespace

// ω0 = 0.21, ω̇0 = 0, α = 1, β = 2: ω(1) = 0.0316206166806364, ω(3) = −0.000480793741620832.
BOOST_AUTO_TEST_CASE(erugin_law_on_a_particle_held_on_a_circle) {
    BOOST_TEST(eomc::runtime::program::erugin_configuration(1.0, 2.0, 0.21, 0.0, 1.0) == 0.0316206166806364,
               boost::test_tools::tolerance(1e-14));
    BOOST_TEST(eomc::runtime::program::erugin_configuration(2.0, 2.0, 0.21, 0.0, 1.0) == 0.085261228439066,
               boost::test_tools::tolerance(1e-14));
    const auto one = run(circle("{ alpha = 1, beta = 2 }"), 1.0);
    BOOST_TEST(std::abs(one.value("program_circle") - 0.0316206166806364) < tolerance, one.value("program_circle"));
    BOOST_TEST(one.programs.at(0).max_departure < tolerance);
    const auto three = run(circle("{ alpha = 1, beta = 2 }"), 3.0);
    BOOST_TEST(std::abs(three.value("program_circle") + 0.000480793741620832) < tolerance);
    const auto critical = run(circle("{ alpha = 2, beta = 2 }"), 1.0);
    BOOST_TEST(std::abs(critical.value("program_circle") - 0.085261228439066) < tolerance);
}

BOOST_AUTO_TEST_CASE(erugin_law_on_a_double_pendulum) {
    const auto one = run(double_pendulum("{ alpha = 1, beta = 2 }"), 1.0);
    BOOST_TEST(std::abs(one.value("program_upper") - 0.0316206166806364) < tolerance, one.value("program_upper"));
    BOOST_TEST(std::abs(one.value("th1") - 0.3 - 0.0316206166806364) < tolerance);
    const auto three = run(double_pendulum("{ alpha = 1, beta = 2 }"), 3.0);
    BOOST_TEST(std::abs(three.value("program_upper") + 0.000480793741620832) < tolerance);
    BOOST_TEST(three.programs.at(0).max_departure < tolerance);
}

const std::string energy_program = R"toml([scene]
name = "pendulum_energy_program"
[parameters]
g = 9.81
h = 30.0
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
)toml";

// From θ̇0 = 8 (H0 = 32 − 9.81 = 22.19), h = 30, κ = 1: H(t) = 30 − 7.81 e^{−t}.
BOOST_AUTO_TEST_CASE(pendulum_energy_program_reaches_its_level) {
    for (double t_end : {1.0, 5.0}) {
        const auto r = run(energy_program, t_end);
        const double H = r.value("theta_dot") * r.value("theta_dot") / 2 - 9.81 * std::cos(r.value("theta"));
        BOOST_TEST(std::abs(H - (30 - 7.81 * std::exp(-t_end))) < tolerance, H);
        BOOST_TEST(r.programs.at(0).max_departure < tolerance);
    }
}

// Braked to a lower level (h = −9.5 below H0 = −7.81, φ > 0): τ = −κφ/θ̇ opposes the motion, so
// θ̇θ̈ ≈ −κφ and θ̇ reaches 0 in finite time while φ > 0, where Ā M⁻¹ D = θ̇ vanishes: the run stops
// there with the reason, at its last good state. (Driven up to a level below the top instead, φ < 0,
// the turning point is approached only asymptotically.)
BOOST_AUTO_TEST_CASE(run_stops_where_the_control_matrix_is_singular) {
    std::string toml = energy_program;
    toml.replace(toml.find("h = 30.0"), 8, "h = -9.5");
    toml.replace(toml.find("rate = 8.0"), 10, "rate = 2.0");
    try {
        run(toml, 10.0);
        BOOST_FAIL("the run went through the singular set of A M^-1 D");
    } catch (const eomc::runtime::IntegrationError& e) {
        BOOST_TEST((e.kind() == eomc::runtime::IntegrationError::Kind::singular_set));
        BOOST_TEST(std::string(e.what()).find("A M^-1 D became singular") != std::string::npos, e.what());
        BOOST_TEST(std::string(e.what()).find("last accepted state") != std::string::npos, e.what());
    }
}

// §3.2 (Mei ch. 3): a free body I = (2, 3, 5) held on its unstable middle axis by torques about
// body axes 1 and 3, programs p = 0 and r = 0 with κ = 2, from ω0 = (0.01, 1, 0.01). Erugin's law
// gives p = r = 0.01 e^{−2t} exactly; the unactuated middle equation B q̇ = (C − A) r p then reads
// q̇ = (3/3) · 1e-4 e^{−4t}, so q(t) = 1 + 1e-4 (1 − e^{−4t})/4: q(1) = 1.00002454210903. The torques
// (closed form from eomc control, by hand from Euler's equations) are M1 = −4p + 2qr, M3 = −10r + pq.
// Without them the body tumbles (the Dzhanibekov flip, scenes/dzhanibekov.toml); run to t = 5 so
// that an uncontrolled drift would show. Tolerance as above: the state is O(1), the run contracts.
BOOST_AUTO_TEST_CASE(rigid_body_held_on_its_middle_axis) {
    for (const std::string formulation : {"euler_poisson", "quaternion"}) {
        const std::string toml = R"toml([scene]
name = "middle_axis_hold"
[rigid_body]
inertia = ["2", "3", "5"]
weight = "0"
formulation = ")toml" + formulation + R"toml("
[rigid_body.initial]
omega = [0.01, 1.0, 0.01]
vertical = [0.0, 0.0, 1.0]
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
        for (double t_end : {1.0, 5.0}) {
            const auto r = run(toml, t_end);
            const double decayed = 0.01 * std::exp(-2 * t_end);
            const double q = 1 + 1e-4 * (1 - std::exp(-4 * t_end)) / 4;
            BOOST_TEST(std::abs(r.value("p") - decayed) < tolerance, formulation << " p = " << r.value("p"));
            BOOST_TEST(std::abs(r.value("r") - decayed) < tolerance, formulation << " r = " << r.value("r"));
            BOOST_TEST(std::abs(r.value("q") - q) < tolerance, formulation << " q = " << r.value("q"));
            if (t_end == 1.0) BOOST_TEST(std::abs(r.value("q") - 1.00002454210903) < tolerance);
            BOOST_TEST(std::abs(r.value("program_hold_p") - decayed) < tolerance);
            // The torques along the run: M1 = −4p + 2qr, M3 = −10r + pq, none about axis 2.
            const double p_ = r.value("p"), q_ = r.value("q"), r_ = r.value("r");
            BOOST_TEST(std::abs(r.value("lambda_hold_p") - (-4 * p_ + 2 * q_ * r_)) < tolerance);
            BOOST_TEST(std::abs(r.value("lambda_hold_r") - (-10 * r_ + p_ * q_)) < tolerance);
            BOOST_TEST(std::abs(r.value("Qc_q")) < 1e-15);
            BOOST_TEST_REQUIRE(r.programs.size() == 2u);
            BOOST_TEST(r.programs[0].max_departure < tolerance);
            BOOST_TEST(r.programs[1].max_departure < tolerance);
        }
    }
}

// Dependent ideal programs (Udwadia & Kalaba, Analytical Dynamics: A New Approach, 1996, ch. 2):
// the circle written twice, ω₁ = x² + y² − 1 and ω₂ = 2ω₁, both with α = 1, β = 2. Ā = [∇ω₁; 2∇ω₁]
// has rank 1, so the kernel takes the pseudo-inverse path; the motion is Gauss's minimiser under
// the one relation, i.e. the single program's: same trajectory, same Q_c = ∇ω₁ λ. The multipliers
// are the minimum-norm ones with Āᵀ (λ₁, λ₂) = ∇ω₁ λ, (λ₁, λ₂) = λ (1, 2)/5. Tolerance: the two runs
// integrate one ODE with right-hand sides equal to round-off, each within the file's global error
// of the exact motion, so they agree to 2 × tolerance; ω₂ = 2ω₁ follows twice the law.
BOOST_AUTO_TEST_CASE(dependent_ideal_programs_move_as_the_single_one) {
    const std::string law = "{ alpha = 1, beta = 2 }";
    const std::string twice = circle(law) + "[[program]]\nname = \"circle2\"\nconstraint = \"2*(x^2 + y^2 - 1)\"\n"
                                            "erugin = " + law + "\n";
    for (double t_end : {1.0, 3.0}) {
        const auto single = run(circle(law), t_end);
        const auto pair = run(twice, t_end);
        for (const char* name : {"x", "y", "x_dot", "y_dot", "Qc_x", "Qc_y"})
            BOOST_TEST(std::abs(pair.value(name) - single.value(name)) < 2 * tolerance,
                       name << ": " << pair.value(name) << " against " << single.value(name));
        const double lambda = single.value("lambda_circle");
        BOOST_TEST(std::abs(lambda) > 1.0);  // the control is at work (g = 9.81 is held by it)
        BOOST_TEST(std::abs(pair.value("lambda_circle") - lambda / 5) < 2 * tolerance);
        BOOST_TEST(std::abs(pair.value("lambda_circle2") - 2 * lambda / 5) < 2 * tolerance);
        const double expected = eomc::runtime::program::erugin_configuration(1.0, 2.0, 0.21, 0.0, t_end);
        BOOST_TEST(std::abs(pair.value("program_circle") - expected) < tolerance);
        BOOST_TEST(std::abs(pair.value("program_circle2") - 2 * expected) < 2 * tolerance);
        BOOST_TEST_REQUIRE(pair.programs.size() == 2u);
        BOOST_TEST(pair.programs[0].max_departure < tolerance);
        BOOST_TEST(pair.programs[1].max_departure < 2 * tolerance);
    }
}

// The same relation under two different laws (α = 1, β = 2 and α = β = 2): off the circle ω₂ = 2ω₁
// cannot follow both, Ā q̈ = c has no solution, and the scene is refused before anything is emitted.
BOOST_AUTO_TEST_CASE(dependent_programs_with_contradicting_laws_are_refused) {
    const std::string toml = circle("{ alpha = 1, beta = 2 }") +
                             "[[program]]\nname = \"circle2\"\nconstraint = \"2*(x^2 + y^2 - 1)\"\n"
                             "erugin = { alpha = 2, beta = 2 }\n";
    try {
        (void)test_support::kernel_of(toml);
        BOOST_FAIL("contradicting dependent programs were accepted");
    } catch (const std::exception& e) {
        const std::string what = e.what();
        BOOST_TEST(what.find("are dependent") != std::string::npos, what);
        BOOST_TEST(what.find("contradict") != std::string::npos, what);
        BOOST_TEST(what.find("'circle' and 'circle2'") != std::string::npos, what);
    }
}

// The open loop (no erugin: ω̈ = 0). Started on the circle at rest in ω (x = 1, y = 0, ẋ = 0, ẏ = 1:
// ω = ω̇ = 0), the exact motion keeps ω = 0, but nothing pulls it back: ω̈ = 0 holds exactly for the
// controlled vector field at every state, so an error (δω_k, δω̇_k) made by step k persists as
// δω_k + δω̇_k (T − t_k) at T. Each accepted dopri5 step has error norm ≤ 1, RMS_i e_i/(atol + rtol|x_i|)
// ≤ 1, so |e| ≤ √n (atol + rtol X) =: ε with X = 5 ≥ |x_i| (|x|, |y| ≤ 1, speed² ≤ 1 + 2g·1 < 21);
// |∇ω| = 2|(x, y)| = 2 and |∇ω̇| = 2|(ẋ, ẏ, x, y)| ≤ 2·√22 < 10. Hence, with N accepted steps,
//     |ω(T)| ≤ N ε (2 + 10 T),
// and N ∝ T: the bound grows like T² (a velocity-level error δ = N ε 10 / T per unit time, integrated
// twice: δ T²). (The step's estimate, not the true local error, is bounded; the estimate of the
// embedded 4th-order solution overstates the 5th-order step taken, which makes the bound safe.)
// Galiullin's closed loop (α = 1, β = 2, ν = √3) on the same system: an error made at t_k reaches T
// as e^{−(T − t_k)} times at most |δω|(1 + α/ν) + |δω̇|/ν ≤ ε (2·1.58 + 10/1.73) < 9ε, and the sum of
// e^{−(T − t_k)} over steps of density N/T (the factor 2 for non-uniform steps) is ≤ 2(N/T + 1):
// a bound 18 ε (N/T + 1) that does not grow with T, where the open loop's grows like T².
BOOST_AUTO_TEST_CASE(open_loop_residual_drifts_closed_loop_holds_it) {
    const auto scene = [](const std::string& law) {
        std::string toml = circle(law);
        toml.replace(toml.find("initial = 1.1"), 13, "initial = 1.0");
        return toml;
    };
    std::string open = scene("{}");
    open.replace(open.find("erugin = {}"), 11, "");
    const double eps = 2.0 * (1e-12 + 1e-10 * 5.0);  // √n (atol + rtol X), n = 4
    for (double t_end : {5.0, 10.0, 20.0, 40.0}) {
        const auto r = run(open, t_end);
        BOOST_TEST(r.programs.at(0).law == "omega_ddot = 0 (open loop)");
        const double drift = std::abs(r.value("program_circle"));
        const double bound = double(r.steps) * eps * (2 + 10 * t_end);
        BOOST_TEST_MESSAGE("open loop T = " << t_end << ": |omega| = " << drift << ", bound " << bound
                                             << ", steps " << r.steps);
        BOOST_TEST(drift < bound, "T = " << t_end << ": " << drift << " >= " << bound);
        BOOST_TEST(r.programs.at(0).max_abs_residual < bound);
        const auto closed = run(scene("{ alpha = 1, beta = 2 }"), t_end);
        const double held = 18 * eps * (double(closed.steps) / t_end + 1);
        BOOST_TEST_MESSAGE("closed loop T = " << t_end << ": max |omega| = " << closed.programs.at(0).max_abs_residual
                                               << ", bound " << held);
        BOOST_TEST(closed.programs.at(0).max_abs_residual < held);
    }
}

// §3.2, an attitude slew by three body-axis torques (scenes/attitude_slew.toml): a free body
// I = (2, 3, 5) at rest, turned 0.6 rad about x (e = (cos 0.3, sin 0.3, 0, 0)), driven to the
// attitude q_d = (cos(θ/2), 0, 0, sin(θ/2)), a turn θ about z, by the vector part of the error
// quaternion δq = q_d* ⊗ e with α = 1, β = 2. The rows are realised exactly, so whatever the
// (nonlinear) kinematics each component follows Erugin's closed form from its own δ(0), δ̇(0):
// constant θ = 1 from rest (δ̇(0) = 0), δ(0) = (cos ½ sin 0.3, −sin ½ sin 0.3, −sin ½ cos 0.3);
// a turning target θ = Ω t (Ω = 0.5), where δ(0) = (sin 0.3, 0, 0) and ∂δ/∂t gives
// δ̇(0) = (0, −Ω/2 sin 0.3, −Ω/2 cos 0.3). At t = 6 the error has decayed by e⁻⁶ and the body
// sits at q_d to that. The tolerance is the file's: the state is O(1) and the law contracts.
// The torques' axes assigned to the programs in turn (err1 by z, err2 by x, err3 by y) realise the
// same motion: D's columns span the same space, so u̇ is the same and only λ is reordered. Then
// Ā M⁻¹ D has its large entries off the diagonal and the run-time LU must exchange rows at more
// than its first step.
BOOST_AUTO_TEST_CASE(attitude_slew_follows_erugins_law_per_component) {
    using eomc::runtime::program::erugin_configuration;
    const double a = std::sin(0.3), b = std::cos(0.3);
    const std::array<double, 3> fixed0{std::cos(0.5) * a, -std::sin(0.5) * a, -std::sin(0.5) * b};
    const std::array<double, 3> turning0{a, 0, 0}, turning_rate0{0, -0.25 * a, -0.25 * b};
    for (const std::array<std::size_t, 3> order : {std::array<std::size_t, 3>{0, 1, 2}, std::array<std::size_t, 3>{2, 0, 1}})
        for (double t_end : {1.0, 3.0, 6.0}) {
            BOOST_TEST_CONTEXT("torque axes " << order[0] << order[1] << order[2] << ", t = " << t_end) {
                const auto fixed = run(attitude_slew_scene("slew", order), t_end);
                const auto turning = run(attitude_slew_scene("Omega*t", order), t_end);
                BOOST_TEST_REQUIRE(fixed.programs.size() == 3u);
                for (std::size_t i = 0; i < 3; ++i) {
                    const std::string name = "program_err" + std::to_string(i + 1);
                    const double want = erugin_configuration(1.0, 2.0, fixed0[i], 0.0, t_end);
                    BOOST_TEST(std::abs(fixed.value(name) - want) < tolerance,
                               name << " = " << fixed.value(name) << ", " << want);
                    const double turn = erugin_configuration(1.0, 2.0, turning0[i], turning_rate0[i], t_end);
                    BOOST_TEST(std::abs(turning.value(name) - turn) < tolerance,
                               name << " = " << turning.value(name) << ", " << turn);
                    BOOST_TEST(fixed.programs[i].max_departure < tolerance);
                    BOOST_TEST(turning.programs[i].max_departure < tolerance);
                }
                if (t_end == 6.0) {
                    // At the target to the decayed error: e = q_d ⊗ δq ≈ q_d (δ0 > 0 throughout), |e − q_d| ≤
                    // |δ_v| + O(|δ_v|²), and each |δ_i(6)| ≤ e⁻⁶ (1 + 1/√3) |δ_i(0)| ≤ 1.8e-3.
                    BOOST_TEST(std::abs(fixed.value("e0") - std::cos(0.5)) < 2e-3);
                    BOOST_TEST(std::abs(fixed.value("e3") - std::sin(0.5)) < 2e-3);
                }
            }
        }
}

// A program beside a [[constraint]] row at run time: the bead kept at speed v0 = 3 on the circle
// x² + y² = 1 (Baumgarte α = 1, β = 2) by the tangential control d = (−y, x), κ = 3 (the scene
// and its closed forms: tests/support/control_scenes.hpp). Along the run the reaction's
// multiplier is μ = m (g y − v0²)/(2R²) and the control λ = m g x/R² at the state reached, both
// rows held to the file's tolerance. μ and λ are affine in the state with slopes ≤ g/2 and g, and
// the state is within the global error of the programmed motion, so they match the closed forms
// to 10 × tolerance.
BOOST_AUTO_TEST_CASE(program_beside_a_constraint_row_at_run_time) {
    const std::string toml = test_support::bead_on_circle_at_constant_speed();
    for (double t_end : {0.4, 1.3}) {
        const auto r = run(toml, t_end);
        const double x = r.value("x"), y = r.value("y");
        BOOST_TEST(std::abs(r.value("lambda_circle") - (9.81 * y - 9.0) / 2) < 10 * tolerance, r.value("lambda_circle"));
        BOOST_TEST(std::abs(r.value("lambda_speed") - 9.81 * x) < 10 * tolerance, r.value("lambda_speed"));
        BOOST_TEST(std::abs(x * x + y * y - 1) < tolerance);
        BOOST_TEST(std::abs(r.value("x_dot") * r.value("x_dot") + r.value("y_dot") * r.value("y_dot") - 9) < tolerance);
        BOOST_TEST_REQUIRE(r.programs.size() == 2u);
        BOOST_TEST(r.programs[0].max_departure < tolerance);
        BOOST_TEST(r.programs[1].max_departure < tolerance);
    }
}
