// Motion on the rotating Earth (seed §2.3): the bundled scenes falling_particle (Coriolis only)
// and projectile_rotating_earth (Coriolis, centrifugal and the pole's acceleration), against
// exact solutions written here from r̈ = g − 2 ω × ṙ − ω × (ω × r) − ω × (ω × r_o) in the local
// frame (x east, y north, z up; ω = Ω (0, cos φ, sin φ); r_o = (0, 0, Re)), not from the
// generator's output. The global error is held to the bound propagated from the accepted steps'
// tolerances (physics_support.hpp).
#define BOOST_TEST_MODULE physics_rotating_earth
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "damped_particle.hpp"
#include "falling_particle.hpp"
#include "physics_support.hpp"
#include "projectile_rotating_earth.hpp"

namespace rt = eomc::runtime;
using Vec = Eigen::Vector3d;

namespace {

Vec earth_rate(double Omega, double phi) { return Omega * Vec(0, std::cos(phi), std::sin(phi)); }

// Coriolis only, v̇ = g − a × v with a = 2ω, from rest at r0. With g = g∥ + g⊥ about â and
// v_p = (g × a)/|a|² (the drift where −a × v_p + g⊥ = 0), the velocity is g∥ t + v_p minus v_p
// turned by −|a| t about â, and integrating once more (â × v_p = g⊥/A)
//   r(t) = r0 + g∥ t²/2 + v_p (t − sin(At)/A) + g⊥ (1 − cos(At))/A²,  A = |a|.
// At the Earth's rate At ~ 7e-4, so both brackets are written as their series in x = At,
//   t − sin(x)/A = t (x²/3! − x⁴/5! + …),  (1 − cos x)/A² = t² (1/2! − x²/4! + …),
// which keeps every digit (the plain forms lose 7 to cancellation).
Vec coriolis_fall(const Vec& r0, const Vec& g, const Vec& omega, double t) {
    const Vec a = 2 * omega;
    const double A = a.norm(), x = A * t;
    const Vec axis = a / A;
    const Vec g_par = g.dot(axis) * axis, g_perp = g - g_par;
    const Vec v_p = g.cross(a) / (A * A);
    double sine_part = 0, cosine_part = 0, term_s = 1.0 / 6, term_c = 0.5;  // x^(2k)/(2k+3)!, x^(2k)/(2k+2)!
    for (int k = 0; k < 12; ++k) {
        sine_part += (k % 2 ? -term_s : term_s) * std::pow(x, 2 * k);
        cosine_part += (k % 2 ? -term_c : term_c) * std::pow(x, 2 * k);
        term_s /= double((2 * k + 4) * (2 * k + 5));
        term_c /= double((2 * k + 3) * (2 * k + 4));
    }
    return r0 + g_par * t * t / 2 + v_p * (t * x * x * sine_part) + g_perp * (t * t * cosine_part);
}

// Every effect (and a linear drag −k ṙ): ż = A z + b with z = (r, ṙ) is linear with constant coefficients, so
// z(t) = exp(t B) (z0, 1) with B = [[A, b], [0, 0]] (Eigen's Padé-scaling-squaring exponential,
// accurate to a few ulps of the norm of exp(tB) here).
Eigen::Matrix<double, 6, 1> full_motion(const Eigen::Matrix<double, 6, 1>& z0, const Vec& g, const Vec& omega,
                                        const Vec& r_o, double t, bool centrifugal = true, double k = 0) {
    Eigen::Matrix3d W;  // W v = ω × v
    W << 0, -omega.z(), omega.y(), omega.z(), 0, -omega.x(), -omega.y(), omega.x(), 0;
    Eigen::Matrix<double, 7, 7> B = Eigen::Matrix<double, 7, 7>::Zero();
    B.block<3, 3>(0, 3).setIdentity();
    if (centrifugal) B.block<3, 3>(3, 0) = -W * W;
    B.block<3, 3>(3, 3) = -2 * W - k * Eigen::Matrix3d::Identity();
    B.block<3, 1>(3, 6) = g - omega.cross(omega.cross(r_o));
    Eigen::Matrix<double, 7, 1> z;
    z << z0, 1;
    const Eigen::Matrix<double, 7, 1> zt = (t * B).exp() * z;
    return zt.head<6>();
}

}  // namespace

BOOST_AUTO_TEST_CASE(falling_particle_lands_east_as_the_closed_form_says) {
    using Model = eomc::models::FallingParticle;
    const rt::Tolerances tol{1e-12, 1e-12};
    phys::KernelSystem<Model, double> sys;
    const Model::Parameters& P = sys.p;
    std::vector<double> x0(Model::initial_state.begin(), Model::initial_state.end()), x = x0;
    const double t1 = 4.5;
    rt::Dopri5<double> stepper;
    const auto steps = phys::run(stepper, sys, x, 0.0, t1, tol);
    const auto bound = phys::propagated_error_bound<Model, double>(steps, x0, 0.0, P, tol);
    const Vec exact = coriolis_fall(Vec(x0[0], x0[1], x0[2]), Vec(0, 0, -P.g), earth_rate(P.Omega, P.phi), t1);
    for (int i = 0; i < 3; ++i) {
        BOOST_TEST_INFO("component " << i << ": " << x[std::size_t(i)] << " vs " << exact(i) << ", bound " << bound[std::size_t(i)]);
        BOOST_TEST(std::abs(x[std::size_t(i)] - exact(i)) <= bound[std::size_t(i)]);
    }
    // Gauss and Laplace's first-order eastward deflection (1/3) Ω g t³ cos φ. The exact one is
    // v_p (t − sin(At)/A) = (1/3) Ω g t³ cos φ (1 − (At)²/20 + …), so they agree to (At)²/20
    // relative (4e-7 here); the southward deflection is O(Ω²) (here ~1e-9 m).
    const double east = P.Omega * P.g * t1 * t1 * t1 * std::cos(P.phi) / 3;
    const double A = 2 * P.Omega;
    BOOST_TEST(std::abs(x[0] - east) <= east * (A * t1) * (A * t1) / 20 * 1.01 + bound[0]);
    BOOST_TEST(x[0] > 0.015);  // 1.57 cm east at 45° from 100 m
}

BOOST_AUTO_TEST_CASE(projectile_with_every_effect_follows_the_matrix_exponential) {
    using Model = eomc::models::ProjectileRotatingEarth;
    const rt::Tolerances tol{1e-12, 1e-12};
    phys::KernelSystem<Model, double> sys;
    const Model::Parameters& P = sys.p;
    std::vector<double> x0(Model::initial_state.begin(), Model::initial_state.end()), x = x0;
    const double t1 = 60.0;
    rt::Dopri5<double> stepper;
    const auto steps = phys::run(stepper, sys, x, 0.0, t1, tol);
    const auto bound = phys::propagated_error_bound<Model, double>(steps, x0, 0.0, P, tol);
    Eigen::Matrix<double, 6, 1> z0;
    for (int i = 0; i < 6; ++i) z0(i) = x0[std::size_t(i)];
    const auto exact = full_motion(z0, Vec(0, 0, -P.g), earth_rate(P.Omega, P.phi), Vec(0, 0, P.Re), t1);
    // The exponential's own error: a few ulps of |exp(tB)| |(z0, 1)| ~ 1e4 (the pole term
    // Ω² Re t²/2 is ~30 m): 64 ε times that.
    const double reference = 64 * std::numeric_limits<double>::epsilon() * 1e4;
    for (int i = 0; i < 6; ++i) {
        BOOST_TEST_INFO("component " << i << ": " << x[std::size_t(i)] << " vs " << exact(i) << ", bound "
                                     << bound[std::size_t(i)]);
        BOOST_TEST(std::abs(x[std::size_t(i)] - exact(i)) <= bound[std::size_t(i)] + reference);
    }
    // The effects are resolved: the exact motion departs from the plain parabola r0 + v0 t +
    // g t²/2 by metres east (Coriolis) and north (the pole's acceleration, Ω² Re sin φ cos φ
    // ≈ 1.7 cm/s² southward, and the centrifugal term), orders above the bound, so a missing or
    // wrong-signed term cannot hide in it.
    for (int i : {0, 1}) {
        const double parabola = x0[std::size_t(i)] + x0[std::size_t(i + 3)] * t1;
        BOOST_TEST_INFO("component " << i << ": departure " << exact(i) - parabola);
        BOOST_TEST(std::abs(exact(i) - parabola) > 1e6 * (bound[std::size_t(i)] + reference));
    }
}

// Seed §2.4: the fall through a resisting medium. Coriolis and drag only (so r_o plays no part
// and there is no centrifugal term), the same exponential with B's velocity block −2W − k I.
// The vertical speed tends to g/k (49.05 m/s) as 1 − e^{−kt}, which the exact solution shows.
BOOST_AUTO_TEST_CASE(damped_fall_follows_the_matrix_exponential) {
    using Model = eomc::models::DampedParticle;
    const rt::Tolerances tol{1e-12, 1e-12};
    phys::KernelSystem<Model, double> sys;
    const Model::Parameters& P = sys.p;
    std::vector<double> x0(Model::initial_state.begin(), Model::initial_state.end()), x = x0;
    const double t1 = 25.0;
    rt::Dopri5<double> stepper;
    const auto steps = phys::run(stepper, sys, x, 0.0, t1, tol);
    const auto bound = phys::propagated_error_bound<Model, double>(steps, x0, 0.0, P, tol);
    Eigen::Matrix<double, 6, 1> z0;
    for (int i = 0; i < 6; ++i) z0(i) = x0[std::size_t(i)];
    const auto exact = full_motion(z0, Vec(0, 0, -P.g), earth_rate(P.Omega, P.phi), Vec::Zero(), t1, false, P.k);
    const double reference = 64 * std::numeric_limits<double>::epsilon() * 1e3;  // |z| ≤ 1000 m
    for (int i = 0; i < 6; ++i) {
        BOOST_TEST_INFO("component " << i << ": " << x[std::size_t(i)] << " vs " << exact(i) << ", bound "
                                     << bound[std::size_t(i)]);
        BOOST_TEST(std::abs(x[std::size_t(i)] - exact(i)) <= bound[std::size_t(i)] + reference);
    }
    // The vertical speed without the Coriolis force is (g/k)(e^{−kt} − 1). The east speed obeys
    // ẍ = −k ẋ + 2Ω(ẏ sin φ − ż cos φ), so it stays below the steady 2Ω cos φ (g/k)/k (plus
    // O(Ω²)), and it feeds back into z̈ through +2Ω cos φ ẋ, moving ż by at most 2Ω cos φ/k times
    // that: 4 Ω² cos² φ g/k³ = 1.3e-5 m/s. (The drag-free deflection would grow without bound.)
    const double plain = P.g / P.k * (std::exp(-P.k * t1) - 1);
    const double c = std::cos(P.phi);
    BOOST_TEST(std::abs(x[5] - plain) <= 4 * P.Omega * P.Omega * c * c * P.g / (P.k * P.k * P.k) * 1.01);
    BOOST_TEST(x[3] <= 2 * P.Omega * c * P.g / (P.k * P.k) * 1.01);
    BOOST_TEST(x[0] > 0);  // drifted east
}
