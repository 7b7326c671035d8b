// The planar double pendulum of the bundled scene (m1 = m2, l1 = l2 = l):
//   * energy T + V (the kernel's `energy`) is conserved over t = 20 on the chaotic scene start
//     to the bound derived from the accepted steps' tolerances (physics_support.hpp);
//   * the normal modes of small oscillations have ω² = (g/l)(2 ∓ √2), with shapes
//     θ2 = ±√2 θ1: checked on the linearisation (the generated Jacobian at rest) to rounding,
//     and by integrating each mode at a small amplitude to O(amplitude²).
#define BOOST_TEST_MODULE physics_double_pendulum
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "double_pendulum.hpp"
#include "physics_support.hpp"

using Model = eomc::models::DoublePendulum;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
const double sqrt2 = std::numbers::sqrt2;
// Slow mode first: ω² = (g/l)(2 − √2), shape (1, √2); fast: (g/l)(2 + √2), shape (1, −√2).
const double mode_omega2[2] = {P.g / P.l1 * (2 - sqrt2), P.g / P.l1 * (2 + sqrt2)};
const double mode_ratio[2] = {sqrt2, -sqrt2};

}  // namespace

BOOST_AUTO_TEST_CASE(parameters_are_the_symmetric_case) {
    BOOST_TEST(P.m1 == P.m2);
    BOOST_TEST(P.l1 == P.l2);
}

BOOST_AUTO_TEST_CASE(energy_is_conserved) {
    const rt::Tolerances tol{1e-10, 1e-12};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const auto energy = [](const std::vector<S>& s) { return Model::energy(S(0), s.data(), P); };
    const S e0 = energy(x);
    S worst = 0;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, x, S(0), S(20), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        worst = std::max(worst, std::abs(energy(st.x_new) - e0));
    });
    // Largest terms of T + V: (m1 + m2) g l1 + m2 g l2 = 3 m g l bounds V, and T is at most that
    // (energy is conserved and V ≥ −3 m g l).
    const S terms = 6 * P.m1 * P.g * P.l1;
    const S bound = phys::invariant_drift_bound<S>(steps, energy, terms);
    BOOST_TEST_MESSAGE("energy over t = 20: max |E - E0| = " << worst << " over " << steps.size() << " steps, bound "
                                                             << bound << " (E0 = " << e0 << ")");
    BOOST_TEST(worst <= bound);
}

// At rest at the bottom the Jacobian is [[0, I], [−M⁻¹K, 0]]; the eigenvalues of M⁻¹K are the
// squared mode frequencies. The entries are computed in a few dozen operations (rounding ≲ 32 ε
// of the largest entry, g/l · 2), and a 2×2 eigenvalue adds a few ε more: 64 ε g/l bounds it.
BOOST_AUTO_TEST_CASE(normal_modes_of_the_linearisation) {
    const std::array<S, 4> rest{0, 0, 0, 0};
    std::array<S, 16> J{};
    Model::jacobian(S(0), rest.data(), J.data(), P);
    Eigen::Matrix2d K;  // −∂q̈/∂q
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) K(i, j) = -J[(2 + i) * 4 + j];
    // Upper blocks: q̇ = q̇; and at rest q̈ does not depend on q̇.
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 4; ++j) BOOST_TEST(J[i * 4 + j] == (j == i + 2 ? 1.0 : 0.0));
    for (int i = 2; i < 4; ++i)
        for (int j = 2; j < 4; ++j) BOOST_TEST(J[i * 4 + j] == 0.0);
    Eigen::EigenSolver<Eigen::Matrix2d> eig(K);
    std::vector<double> w2{eig.eigenvalues()(0).real(), eig.eigenvalues()(1).real()};
    std::sort(w2.begin(), w2.end());
    const double bound = 64 * std::numeric_limits<double>::epsilon() * P.g / P.l1;
    for (int k = 0; k < 2; ++k) {
        BOOST_TEST_INFO("mode " << k << ": omega^2 = " << w2[k] << ", closed form " << mode_omega2[k]);
        BOOST_TEST(std::abs(eig.eigenvalues()(k).imag()) <= bound);
        BOOST_TEST(std::abs(w2[k] - mode_omega2[k]) <= bound);
        // The mode shape (1, ±√2) is an eigenvector: K v = ω² v.
        const Eigen::Vector2d v(1.0, mode_ratio[k]);
        BOOST_TEST((K * v - mode_omega2[k] * v).norm() <= bound * v.norm());
    }
}

// Each mode started from rest at θ1 = A, θ2 = ±√2 A. The nonlinear terms of L relative to the
// quadratic ones are θ²/12 (from cos θ in V) and (θ1 − θ2)²/2 (from cos(θ1 − θ2) in T), at most
// (1 + √2)² A²/2 here; first-order perturbation theory shifts ω by at most that relative size, and
// the other mode, excited at O(A³) by the cubic forces, moves the maxima of θ1 by O(A²) of a
// period too. So |T/T_k − 1| ≤ (1 + √2)² A². The timing error of the integration (tolerance
// 1e-12) is ~1e-12/(ω² A) per maximum, negligible at A = 1e-2.
BOOST_AUTO_TEST_CASE(small_amplitude_mode_periods) {
    const double A = 1e-2;
    const double bound = (1 + sqrt2) * (1 + sqrt2) * A * A;
    for (int k = 0; k < 2; ++k) {
        phys::KernelSystem<Model, S> sys;
        std::vector<S> x{A, mode_ratio[k] * A, 0, 0};
        const double T_k = 2 * std::numbers::pi / std::sqrt(mode_omega2[k]);
        const int periods = 10;
        auto maxima = phys::down_crossings<S>([](const std::vector<S>& s) { return s[2]; });  // θ̇1 ↓ 0
        rt::Dopri5<S> stepper;
        phys::run(stepper, sys, x, S(0), S((periods + 0.5) * T_k), rt::Tolerances{1e-12, 1e-14}, maxima);
        BOOST_REQUIRE_EQUAL(maxima.times.size(), std::size_t(periods));
        const double T = maxima.times.back() / periods;
        // Still in the mode: θ2/θ1 at the last maximum keeps the shape to O(A²).
        const double shape = maxima.states.back()[1] / maxima.states.back()[0];
        BOOST_TEST_MESSAGE("mode " << k << ": T/T_k - 1 = " << T / T_k - 1 << " (bound " << bound << "), theta2/theta1 = "
                                   << shape << " (" << mode_ratio[k] << ")");
        BOOST_TEST(std::abs(T / T_k - 1) <= bound);
        BOOST_TEST(std::abs(shape - mode_ratio[k]) <= bound * std::abs(mode_ratio[k]) * periods);
    }
}
