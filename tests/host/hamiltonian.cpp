// Hamilton's equations (Mei §1.9) against Lagrange's for the same scene: both kernels are
// generated, compiled and integrated with Dopri5 at rtol = atol = tol = 1e-12, and must give the
// same q(t_end), the same p = ∂L/∂q̇ and the same conserved energy.
//
// The bound, from the method. Dopri5 accepts a step when sqrt((1/n) Σ_i (e_i/sc_i)²) ≤ 1 with
// sc_i = atol + rtol·|x_i| (Hairer, Nørsett & Wanner, Solving ODEs I, §II.4), so each component
// of an accepted step's local error is ≤ √n·tol·(1 + X), X the largest |x_i| along the run (the
// fifth-order solution propagated is more accurate than the estimate; physics_support.hpp). An
// error made at t_k reaches t_end multiplied by the state-transition matrix Φ(t_end, t_k),
// ‖Φ‖∞ ≤ G. Summed over a run's N accepted steps, and over both runs,
//   |q_L − q_H| ≤ δ = (N_L + N_H)·√n·tol·A,   A = (1 + X)·G.
// p = ∂L/∂q̇ at Lagrange's state carries Lagrange's error times ‖∂p/∂(q, q̇)‖∞ ≤ P:
// |p_L − p_H| ≤ (1 + P)·δ, P = 24 (the double pendulum's row, 3 + 2|θ̇2|, is the largest).
//   * Regular motions over t ≤ 10 (the rotating spring, bead_on_hoop, double_pendulum,
//     kepler_orbit): G ≤ 10², X ≤ 11 (the double pendulum's energy bounds its rates: T ≤ 19.4
//     with the mass matrix's smallest eigenvalue ≥ (3 − √5)/2 gives |θ̇| ≤ 10.1), so A = 1.2e3.
//     With N ~ 10³ steps per run and n = 4 that is δ ≈ 5e-6: the 1e-7 asserted before was below
//     its own arithmetic (10³ steps · √4 · 1e-12 · 10² = 2e-7 per run, 4e-7 for the pair).
//   * disk_tube_ball, q̈ = Ω² q from x0 = (0.1, 0), Ω = 3, t_end = 3: Φ(τ) = [[cosh Ωτ,
//     sinh Ωτ/Ω], [Ω sinh Ωτ, cosh Ωτ]], ‖Φ(τ)‖∞ ≤ (1 + Ω) cosh Ωτ and |x(t)| ≤ 0.1·Ω cosh Ωt,
//     so ‖Φ(T, t_k)‖(1 + |x_k|) ≤ (1 + Ω)(1 + 0.1·Ω) cosh ΩT = 5.2 cosh 9: A = 2.2e4.
// A formulation error (a wrong sign or a missing gyroscopic term in p) is O(1) times the
// solution, orders above δ; the runs agree to ~1e-11 in fact.
#define BOOST_TEST_MODULE simulate_hamiltonian
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

#include "simulation.hpp"

namespace {

// A particle on a spring in a frame turning at Ω about z: Coriolis and centrifugal terms
// make p = m(q̇ + ω × r) differ from m q̇, which is what the Legendre transform must get right.
const char* const rotating_spring = R"toml(
[scene]
name = "rotating_spring"
[parameters]
m = 1.3
k = 5.0
Omega = 0.7
[coordinates]
x = { initial = 1.0, rate = 0.1 }
y = { initial = 0.0, rate = 0.4 }
[carrier]
angular_velocity = ["0", "0", "Omega"]
[[body]]
name = "p"
mass = "m"
position = ["x", "y", "0"]
[forces]
potential = "k*(x^2 + y^2)/2"
)toml";

eomc::host::SimulationResult run(const std::string& toml, bool hamiltonian, double t_end) {
    eomc::host::SimulationRequest r =
        test_support::simulation_request(test_support::kernel_of(toml, {.hamiltonian = hamiltonian}), t_end);
    r.rtol = r.atol = 1e-12;
    return eomc::host::simulate(r);
}

// A = (1 + X)·G of the header comment for the regular motions compared here.
constexpr double regular_amplification = 1.2e3;

void compare(const std::string& toml, double t_end, double amplification = regular_amplification) {
    const auto lagrange = run(toml, false, t_end);
    const auto hamilton = run(toml, true, t_end);
    const double tol = 1e-12, P = 24;
    const double n = double(std::max(lagrange.state.size(), hamilton.state.size()));
    const double delta = double(lagrange.steps + hamilton.steps) * std::sqrt(n) * tol * amplification;
    BOOST_TEST_MESSAGE(lagrange.scene_name << ": " << lagrange.steps << " + " << hamilton.steps << " steps, δ = " << delta);
    const auto model = test_support::model_of(toml);
    const auto eqs = eomc::mechanics::derive(model);
    const auto canonical = eomc::mechanics::canonical_equations(model, eqs);
    GiNaC::exmap at_end{{model.t, t_end}};
    for (const auto& p : model.parameters) at_end[p.symbol] = p.value;
    for (const auto& c : model.coordinates) {
        BOOST_TEST(std::abs(lagrange.value(c.name) - hamilton.value(c.name)) <= delta, lagrange.scene_name << " " << c.name);
        at_end[c.q] = lagrange.value(c.name);
        at_end[c.q_dot] = lagrange.value(c.name + "_dot");
    }
    for (std::size_t s = 0; s < model.coordinates.size(); ++s) {
        const double p = GiNaC::ex_to<GiNaC::numeric>(canonical.momentum[s].subs(at_end).evalf()).to_double();
        BOOST_TEST(std::abs(p - hamilton.value("p_" + model.coordinates[s].name)) <= (1 + P) * delta,
                   lagrange.scene_name << " p_" << model.coordinates[s].name);
    }
    // The energy, then the momenta of cyclic coordinates (kepler_orbit's φ), in both formulations.
    BOOST_REQUIRE_GE(lagrange.invariants.size(), 1u);
    BOOST_REQUIRE_EQUAL(hamilton.invariants.size(), lagrange.invariants.size());
    // h(q, q̇) and H(q, p) are the same function on corresponding states (and so is each momentum).
    for (std::size_t i = 0; i < lagrange.invariants.size(); ++i) {
        BOOST_TEST(lagrange.invariants[i].name == hamilton.invariants[i].name);
        BOOST_TEST(std::abs(lagrange.invariants[i].initial - hamilton.invariants[i].initial) <=
                   1e-12 * (1 + std::abs(lagrange.invariants[i].initial)));
        BOOST_TEST(hamilton.invariants[i].max_abs_drift <= 1e-8 * (1 + std::abs(hamilton.invariants[i].initial)));
    }
}

}  // namespace

BOOST_AUTO_TEST_CASE(same_trajectory_in_a_rotating_frame) { compare(rotating_spring, 10.0); }

BOOST_AUTO_TEST_CASE(same_trajectory_for_the_bundled_scenes) {
    for (const char* scene : {"bead_on_hoop", "double_pendulum", "kepler_orbit"})
        compare(test_support::bundled_scene(scene), 3.0);
    // Exponential growth at Ω = 3 (the header comment's second case).
    compare(test_support::bundled_scene("disk_tube_ball"), 3.0, 5.2 * std::cosh(9.0));
}

BOOST_AUTO_TEST_CASE(refusals_name_the_reason) {
    const std::string dropped = std::string(rotating_spring) + "[effects]\nkeep = [\"relative\", \"coriolis\"]\n";
    const auto model = test_support::model_of(dropped);
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_CHECK_EXCEPTION(eomc::mechanics::canonical_equations(model, eqs), eomc::InputError,
                          [](const eomc::InputError& e) { return std::string(e.what()).find("[effects]") != std::string::npos; });
    // T = x_dot^4: the velocity Hessian depends on the velocity; no quadratic Legendre transform.
    const char* quartic = R"toml(
[scene]
name = "quartic"
[coordinates]
x = { initial = 1.0, rate = 0.5 }
[lagrangian]
T = "x_dot^4/12 + x_dot^2/2"
V = "x^2/2"
)toml";
    const auto m2 = test_support::model_of(quartic);
    const auto e2 = eomc::mechanics::derive(m2);
    BOOST_CHECK_EXCEPTION(eomc::mechanics::canonical_equations(m2, e2), eomc::InputError,
                          [](const eomc::InputError& e) { return std::string(e.what()).find("quadratic") != std::string::npos; });
}
