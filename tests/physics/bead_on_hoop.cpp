// Bead on a hoop spinning at ω about its vertical diameter: θ̈ = sin θ (ω² cos θ − g/R).
//   * The Jacobi integral h = T_r − T_e + V (the kernel's `energy`) is conserved over t = 100 to
//     the bound derived from the accepted steps' tolerances (physics_support.hpp).
//   * Started at the relative equilibrium cos θ* = g/(R ω²) with θ̇ = 0 it stays there.
//   * Small oscillations about θ* have period 2π/(ω sin θ*), up to the amplitude-dependent
//     shift of a weakly nonlinear oscillator (Landau & Lifshitz, Mechanics §28).
#define BOOST_TEST_MODULE physics_bead_on_hoop
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "bead_on_hoop.hpp"
#include "physics_support.hpp"

using Model = eomc::models::BeadOnHoop;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
const double cos_star = P.g / (P.R * P.omega * P.omega);
const double theta_star = std::acos(cos_star);
const double sin_star = std::sin(theta_star);
const double Omega_small = P.omega * sin_star;  // small-oscillation frequency about θ*

S jacobi(const std::vector<S>& x) { return Model::energy(S(0), x.data(), P); }

}  // namespace

BOOST_AUTO_TEST_CASE(jacobi_integral_is_conserved) {
    const rt::Tolerances tol{1e-10, 1e-12};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const S h0 = jacobi(x);
    rt::Dopri5<S> stepper;
    S worst = 0;
    const auto steps = phys::run(stepper, sys, x, S(0), S(100), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        worst = std::max(worst, std::abs(jacobi(st.x_new) - h0));
    });
    // Largest term of h: ½ m R² θ̇², m g R, ½ m R² ω² — all ≤ m R² ω² + m g R here.
    const S terms = P.m * P.R * P.R * P.omega * P.omega + P.m * P.g * P.R;
    const S bound = phys::invariant_drift_bound<S>(steps, jacobi, terms);
    BOOST_TEST_MESSAGE("Jacobi integral: max |h - h0| = " << worst << " over " << steps.size() << " steps, bound "
                                                          << bound << " (h0 = " << h0 << ")");
    BOOST_TEST(worst <= bound);
    // The motion is a real oscillation through θ* (not a trivially constant state).
    BOOST_TEST(std::abs(x[0] - Model::initial_state[0]) + std::abs(x[1]) > 1e-3);
}

// The kernel's acceleration at θ* is zero up to rounding, |θ̈(θ*)| ≤ a_r := 8ε(ω² + g/R) (a few
// operations on terms of size ω² and g/R). A constant residual acceleration a_r displaces a
// stable oscillator of frequency Ω by at most 2 a_r/Ω². The integrator adds at most its
// propagated local errors; for a state that barely moves these are ≤ √n·(atol + rtol|θ*|) per
// step, and the linear oscillation about θ* does not amplify them (|Φ| ≤ max(1, Ω, 1/Ω)).
BOOST_AUTO_TEST_CASE(relative_equilibrium_stays_put) {
    const rt::Tolerances tol{1e-10, 1e-12};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x{theta_star, 0};
    std::vector<S> dx(2);
    sys(0, x, dx);
    const double a_r = 8 * std::numeric_limits<double>::epsilon() * (P.omega * P.omega + P.g / P.R);
    BOOST_TEST_INFO("theta_ddot at theta* = " << dx[1]);
    BOOST_TEST(std::abs(dx[1]) <= a_r);
    rt::Dopri5<S> stepper;
    S worst = 0;
    const auto steps = phys::run(stepper, sys, x, S(0), S(100), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        worst = std::max(worst, std::abs(st.x_new[0] - theta_star));
    });
    const double amplification = std::max({1.0, Omega_small, 1 / Omega_small});
    const double bound = 2 * a_r / (Omega_small * Omega_small) +
                         amplification * steps.size() * std::sqrt(2.0) * (tol.atol + tol.rtol * theta_star);
    BOOST_TEST_MESSAGE("equilibrium: max |theta - theta*| = " << worst << " over " << steps.size() << " steps, bound "
                                                              << bound);
    BOOST_TEST(worst <= bound);
}

// Period of small oscillations started at θ* + A from rest. Expanding θ̈ = F(θ) about θ*,
//   δ̈ = −Ω² δ + a2 δ² + a3 δ³,   Ω² = ω² s²,  a2 = F''/2 = −(3/2) ω² s c,  a3 = F'''/6 = ω² (4s² − 3c²)/6,
// (s, c = sin θ*, cos θ*), and Landau–Lifshitz §28 gives the frequency ω(b) = Ω (1 + κ b²) with
// κ = −3 a3/(8Ω²) − 5 a2²/(12 Ω⁴), b the amplitude of the first harmonic; the second-order
// solution has δ(0) = b − α b²/(3Ω²), α = −a2, so b = A + α A²/(3Ω²) + O(A³). Hence
//   T/T0 − 1 = −κ b² + O(A⁴) = −κ A² (1 + 2αA/(3Ω²)) + O(A⁴),   T0 = 2π/(ω sin θ*).
// Checks: |T/T0 − 1| ≤ 2|κ| A² (matches T0 to O(A²)), and the measured shift agrees with the
// Landau prediction to a relative 10 A² (the neglected O(A⁴) over the O(A²) term, with a
// coefficient ≤ 10 for these O(1) Taylor coefficients) plus the timing error.
BOOST_AUTO_TEST_CASE(small_oscillation_period_about_theta_star) {
    const double w2 = P.omega * P.omega, s = sin_star, c = cos_star, W2 = Omega_small * Omega_small;
    const double a2 = -1.5 * w2 * s * c, a3 = w2 * (4 * s * s - 3 * c * c) / 6, alpha = -a2;
    const double kappa = -3 * a3 / (8 * W2) - 5 * a2 * a2 / (12 * W2 * W2);
    const double T0 = 2 * std::numbers::pi / Omega_small;
    const rt::Tolerances tol{1e-12, 1e-14};
    for (double A : {1e-2, 5e-3}) {
        phys::KernelSystem<Model, S> sys;
        std::vector<S> x{theta_star + A, 0};
        rt::Dopri5<S> stepper;
        // Maxima of θ: θ̇ crosses zero downwards. t = 0 is a maximum too.
        auto maxima = phys::down_crossings<S>([](const std::vector<S>& xs) { return xs[1]; });
        const int periods = 10;
        phys::run(stepper, sys, x, S(0), S((periods + 0.5) * T0), tol, maxima);
        BOOST_REQUIRE_EQUAL(maxima.times.size(), std::size_t(periods));
        const double T = maxima.times.back() / periods;
        const double shift = T / T0 - 1;
        const double predicted = -kappa * A * A * (1 + 2 * alpha * A / (3 * W2));
        // Timing: each maximum is located to ~|δθ̇|/|θ̈| with δθ̇ ≲ 1e-12 (tolerance) and |θ̈| = Ω² A.
        const double timing = 1e-12 / (W2 * A) / T0;
        BOOST_TEST_MESSAGE("A = " << A << ": T/T0 - 1 = " << shift << ", Landau " << predicted << ", O(A^2) bound "
                                  << 2 * std::abs(kappa) * A * A);
        BOOST_TEST(std::abs(shift) <= 2 * std::abs(kappa) * A * A);
        BOOST_TEST(std::abs(shift - predicted) <= 10 * A * A * std::abs(predicted) + timing);
    }
}
