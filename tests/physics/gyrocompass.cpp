// A gyroscope in a gimbal on a platform turning at Ω about x' (scenes/gyrocompass.toml).
// By hand (T = ½ C (ψ̇ + Ω cos φ)² + ½ A (φ̇² + Ω² sin² φ), the rotor symmetric about its spin
// axis): ψ is cyclic, so the total spin n = ψ̇ + Ω cos φ is constant, and
//   A φ̈ = −(C n Ω − A Ω² cos φ) sin φ,
// the gyrocompass equation: the spin axis oscillates about the platform's rotation axis with
// Ω_s² = (C n Ω − A Ω²)/A for small amplitudes. Checks:
//   * the kernel's φ̈ equals that right-hand side at random states (it is the same function);
//   * n and the Jacobi integral are conserved to the bound derived from the steps' tolerances;
//   * the period at amplitude a is 2π/Ω_s (1 − κ a²) with the Landau–Lifshitz §28 shift
//     κ = −3 a3/(8 Ω_s²), a3 = k1/6 − 2k2/3 (k1 = C n Ω/A, k2 = Ω²; the force is odd in φ, so
//     a2 = 0), agreeing to a relative 10 a² plus the timing error.
#define BOOST_TEST_MODULE physics_gyrocompass
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "gyrocompass.hpp"
#include "physics_support.hpp"

using Model = eomc::models::Gyrocompass;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
enum { phi, psi, phi_dot, psi_dot };

S spin(const std::vector<S>& x) { return x[psi_dot] + P.Omega * std::cos(x[phi]); }
S jacobi(const std::vector<S>& x) { return Model::energy(S(0), x.data(), P); }

}  // namespace

BOOST_AUTO_TEST_CASE(kernel_is_the_gyrocompass_equation) {
    static_assert(Model::separable == false);  // the gyroscopic term depends on ψ̇
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-3, 3);
    for (int k = 0; k < 20; ++k) {
        const std::vector<S> x{u(rng), u(rng), u(rng), 10 * u(rng)};
        std::vector<S> dx(4);
        Model::rhs(S(0), x.data(), dx.data(), P);
        const S n = spin(x);
        const S expected = -(P.C * n * P.Omega - P.A * P.Omega * P.Omega * std::cos(x[phi])) * std::sin(x[phi]) / P.A;
        const S scale = P.C * std::abs(n) * P.Omega / P.A + P.Omega * P.Omega;
        BOOST_TEST(std::abs(dx[phi_dot] - expected) <= 16 * std::numeric_limits<S>::epsilon() * scale);
        // ṅ = ψ̈ − Ω sin φ φ̇ = 0.
        BOOST_TEST(std::abs(dx[psi_dot] - P.Omega * std::sin(x[phi]) * x[phi_dot]) <=
                   16 * std::numeric_limits<S>::epsilon() * P.Omega * std::abs(x[phi_dot]));
    }
}

BOOST_AUTO_TEST_CASE(spin_and_jacobi_integral_are_conserved) {
    const rt::Tolerances tol{1e-11, 1e-13};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x{1.0, 0.0, 0.3, 20.0};  // a large swing, far from the linear regime
    const std::vector<S> x0 = x;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, x, S(0), S(20), tol);
    const S dn = std::abs(spin(x) - spin(x0)), dh = std::abs(jacobi(x) - jacobi(x0));
    const S n_bound = phys::invariant_drift_bound<S>(steps, spin, std::abs(spin(x0)));
    const S h_bound = phys::invariant_drift_bound<S>(steps, jacobi, P.C * x0[psi_dot] * x0[psi_dot]);
    BOOST_TEST_MESSAGE("spin drift " << dn << " (bound " << n_bound << "), Jacobi drift " << dh << " (bound " << h_bound
                                     << ")");
    BOOST_TEST(dn <= n_bound);
    BOOST_TEST(dh <= h_bound);
}

BOOST_AUTO_TEST_CASE(small_oscillations_about_the_rotation_axis) {
    const S n = Model::initial_state[psi_dot] + P.Omega;  // started at φ = a ≈ 0 with ψ̇ = 20: n ≈ 20 + Ω cos a
    const rt::Tolerances tol{1e-12, 1e-14};
    for (double a : {1e-2, 5e-3}) {
        const S n_a = Model::initial_state[psi_dot] + P.Omega * std::cos(a);
        const S k1 = P.C * n_a * P.Omega / P.A, k2 = P.Omega * P.Omega;
        const S W2 = k1 - k2, a3 = k1 / 6 - 2 * k2 / 3, kappa = -3 * a3 / (8 * W2);
        const S T0 = 2 * std::numbers::pi / std::sqrt(W2);
        phys::KernelSystem<Model, S> sys;
        std::vector<S> x{a, 0, 0, Model::initial_state[psi_dot]};
        rt::Dopri5<S> stepper;
        auto maxima = phys::down_crossings<S>([](const std::vector<S>& xs) { return xs[phi_dot]; });
        const int periods = 10;
        phys::run(stepper, sys, x, S(0), S((periods + 0.5) * T0), tol, maxima);
        BOOST_REQUIRE_EQUAL(maxima.times.size(), std::size_t(periods));
        const S shift = maxima.times.back() / periods / T0 - 1;
        const S predicted = -kappa * a * a;
        const S timing = 1e-12 / (W2 * a) / T0;
        BOOST_TEST_MESSAGE("a = " << a << ": T/T0 - 1 = " << shift << ", Landau " << predicted << " (n = " << n << ")");
        BOOST_TEST(std::abs(shift - predicted) <= 10 * a * a * std::abs(predicted) + timing);
    }
}
