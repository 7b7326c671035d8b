// Foucault's pendulum (scene foucault_pendulum: relative motion + Coriolis, Ω exaggerated).
// With ζ = x + i y, ω0² = g/L and Ω_z = Ω sin φ the linearised equations are
//   ζ̈ + 2 i Ω_z ζ̇ + ω0² ζ = 0,
// whose solution from rest at ζ = a is (ω' = √(ω0² + Ω_z²))
//   ζ(t) = e^{−i Ω_z t} (a cos ω't + i (Ω_z a/ω') sin ω't):
// a swing whose plane turns at −Ω_z = −Ω sin φ, with a thin ellipse (minor axis a Ω_z/ω') whose
// points of largest |ζ| lie exactly on the turning plane, at angle −Ω_z t.
//
// What the linearisation leaves out, with θ0 = asin(a/L) the angular amplitude:
//   * the pendulum's nonlinearity: the frequency is ω0 (1 − θ0²/16 + O(θ0⁴)), and x = L sin θ
//     carries harmonics of relative size ≲ θ0²/5 (θ³/6 and the θ0³/192 third harmonic);
//   * Airy's precession of the thin ellipse, (3/8) ω0 a b/L² with b = a Ω_z/ω', i.e. a relative
//     (3/8)(ω0/ω') θ0² of the Foucault rate (in the sense the ellipse is traversed, against it);
//   * the horizontal component Ω cos φ. Its Coriolis force on a swing in a vertical plane lies in
//     that plane and is normal to the velocity (along the string), so it does no work along the
//     swing. Across the swing, in axes (u along the swing, v across) where it has the component
//     α along u (|α| ≤ Ω cos φ; α = 0 at the start, the swing is east-west), it drives
//     v̈ + ω0² v = 2α u u̇/L = −(α a² ω0/L) sin 2ω0t, so v = (α a θ0/(3ω0))(sin 2ω0t − 2 sin ω0t):
//     |v| ≤ (√3/2) a θ0 Ω cos φ/ω0, zero at the turning points (ω0 t = kπ) and without mean, so it
//     does not turn the plane; as α changes with the plane (at the rate Ω_z Ω cos φ) it leaves
//     O(θ0 Ω_z Ω cos φ/ω0²) offsets of the turning points that alternate between the two ends of
//     the swing (seen: ~4e-5 rad), which a fit over many turning points averages out.
// So the plane's turning rate must match −Ω sin φ to a relative θ0² (the Airy term is 3/8 of
// that), and the state the closed form to
//   a θ0² (ω0 t/16 + 1/4 + (3/8)(ω0/ω') Ω_z t) + (√3/2) a θ0 Ω cos φ/ω0.
#define BOOST_TEST_MODULE physics_foucault_pendulum
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include "foucault_pendulum.hpp"
#include "physics_support.hpp"

using Model = eomc::models::FoucaultPendulum;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
const double a = Model::initial_state[0];
const double theta0 = std::asin(a / P.L);
const double omega0 = std::sqrt(P.g / P.L);
const double Omega_z = P.Omega * std::sin(P.phi);
const double omega_prime = std::sqrt(omega0 * omega0 + Omega_z * Omega_z);
const double t_end = 60.0;  // the scene's: ~19 swings, the plane turns by ~2.1 rad

std::complex<double> linear(double t) {
    using namespace std::complex_literals;
    return std::exp(-1i * Omega_z * t) * (a * std::cos(omega_prime * t) + 1i * (Omega_z * a / omega_prime) * std::sin(omega_prime * t));
}

}  // namespace

BOOST_AUTO_TEST_CASE(swing_plane_turns_at_minus_Omega_sin_phi) {
    const rt::Tolerances tol{1e-10, 1e-12};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    rt::Dopri5<S> stepper;
    // Turning points: largest x² + y², where x ẋ + y ẏ crosses zero downwards.
    auto turning = phys::down_crossings<S>([](const std::vector<S>& s) { return s[0] * s[2] + s[1] * s[3]; });
    phys::run(stepper, sys, x, S(0), S(t_end), tol, turning);
    BOOST_REQUIRE_GE(turning.times.size(), 15u);

    // Plane angle at each turning point, continued across the ±π ambiguity of a line's direction.
    std::vector<double> ts{0.0}, psi{0.0};
    for (std::size_t k = 0; k < turning.times.size(); ++k) {
        double p = std::atan2(turning.states[k][1], turning.states[k][0]);
        p += std::numbers::pi * std::round((psi.back() - p) / std::numbers::pi);
        ts.push_back(turning.times[k]);
        psi.push_back(p);
    }
    // Least-squares slope of ψ(t).
    const double n = double(ts.size());
    double st = 0, sp = 0, stt = 0, stp = 0;
    for (std::size_t k = 0; k < ts.size(); ++k) {
        st += ts[k];
        sp += psi[k];
        stt += ts[k] * ts[k];
        stp += ts[k] * psi[k];
    }
    const double slope = (n * stp - st * sp) / (n * stt - st * st);
    const double expected = -P.Omega * std::sin(P.phi);
    const double relative = std::abs(slope / expected - 1);
    const double airy = 0.375 * (omega0 / omega_prime) * theta0 * theta0;
    BOOST_TEST_MESSAGE("plane turns at " << slope << " rad/s over " << turning.times.size()
                                         << " turning points; -Omega sin(phi) = " << expected
                                         << ", relative difference " << relative << " (Airy estimate " << airy
                                         << ", bound theta0^2 = " << theta0 * theta0 << ")");
    BOOST_TEST(relative <= theta0 * theta0);
}

BOOST_AUTO_TEST_CASE(matches_the_linearised_closed_form) {
    const rt::Tolerances tol{1e-10, 1e-12};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    rt::Dopri5<S> stepper;
    double worst_ratio = 0, worst = 0;
    phys::run(stepper, sys, x, S(0), S(t_end), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        const double t = st.t_new;
        const std::complex<double> z(st.x_new[0], st.x_new[1]);
        const double dev = std::abs(z - linear(t));
        const double bound =
            a * theta0 * theta0 * (omega0 * t / 16 + 0.25 + 0.375 * (omega0 / omega_prime) * Omega_z * t) +
            std::sqrt(3.0) / 2 * a * theta0 * P.Omega * std::cos(P.phi) / omega0;
        worst = std::max(worst, dev);
        worst_ratio = std::max(worst_ratio, dev / bound);
        BOOST_TEST_INFO("t = " << t << ": |zeta - zeta_lin| = " << dev << ", bound " << bound);
        BOOST_TEST(dev <= bound);
    });
    BOOST_TEST_MESSAGE("closed form: max |zeta - zeta_lin| = " << worst << ", max deviation/bound = " << worst_ratio);
}

// With only the relative and Coriolis effects kept, the kernel's invariant is h = T_r + V (the
// Coriolis force does no work); it equals ½ m |ṙ'|² − m g √(L² − x² − y²) and is conserved to the
// bound derived from the accepted steps' tolerances (physics_support.hpp).
BOOST_AUTO_TEST_CASE(relative_energy_is_conserved) {
    const rt::Tolerances tol{1e-10, 1e-12};
    const auto energy = [](const std::vector<S>& s) { return Model::energy(S(0), s.data(), P); };
    const auto by_hand = [](const std::vector<S>& s) {
        const double root = std::sqrt(P.L * P.L - s[0] * s[0] - s[1] * s[1]);
        const double z_dot = (s[0] * s[2] + s[1] * s[3]) / root;
        return 0.5 * P.m * (s[2] * s[2] + s[3] * s[3] + z_dot * z_dot) - P.m * P.g * root;
    };
    const double rounding = 64 * std::numeric_limits<double>::epsilon() * P.m * P.g * P.L;
    const std::vector<S> probe{0.7, -1.1, 0.3, 0.45};
    BOOST_TEST(std::abs(energy(probe) - by_hand(probe)) <= rounding);

    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const S e0 = energy(x);
    S worst = 0;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, x, S(0), S(t_end), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        worst = std::max(worst, std::abs(energy(st.x_new) - e0));
    });
    const S bound = phys::invariant_drift_bound<S>(steps, energy, S(P.m * P.g * P.L));
    BOOST_TEST_MESSAGE("T_r + V over t = " << t_end << ": max drift " << worst << ", bound " << bound << " ("
                                           << steps.size() << " steps)");
    BOOST_TEST(worst <= bound);
}
