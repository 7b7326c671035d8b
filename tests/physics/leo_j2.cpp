// The bundled orbit scene leo_j2 (a = 7000 km, e = 0.01, i = 50°, J2 only; Cowell: Cartesian
// x, y, z) against what is known of it:
//   * the initial state is the runtime's conversion of the scene's elements;
//   * H0 − R and h_z = x ẏ − y ẋ are conserved (R is time-independent and axisymmetric), within
//     the bound derived from every accepted step's local error (physics_support.hpp);
//   * the node and the perigee drift at the first-order mean rates (Mei 1988, ch. 2),
//     Ω̇ = −(3/2) n J2 (Re/p)² cos i and ω̇ = (3/4) n J2 (Re/p)² (5 cos² i − 1);
//   * with J3 as well (leo_j2_j3, generated at build time), the eccentricity vector circles the
//     frozen eccentricity e_f = −(J3/(2 J2)) (Re/p) sin i at ω = 90°.
#define BOOST_TEST_MODULE physics_leo_j2
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <eomc/runtime/orbit/orbital_elements.hpp>

#include "leo_j2.hpp"
#include "leo_j2_j3.hpp"
#include "physics_support.hpp"

using Model = eomc::models::LeoJ2;
namespace rt = eomc::runtime;

namespace {

// The scene's elements; its angles are degrees, converted as the parser does.
constexpr double degree = 3.14159265358979323846 / 180.0;
const rt::ClassicalElements<double> scene_elements{7000.0, 0.01, 50.0 * degree, 0.0, 0.0, 0.0};

// Least-squares slope of y(t).
double slope(const std::vector<double>& t, const std::vector<double>& y) {
    double mt = 0, my = 0;
    for (std::size_t k = 0; k < t.size(); ++k) mt += t[k], my += y[k];
    mt /= double(t.size());
    my /= double(t.size());
    double num = 0, den = 0;
    for (std::size_t k = 0; k < t.size(); ++k) num += (t[k] - mt) * (y[k] - my), den += (t[k] - mt) * (t[k] - mt);
    return num / den;
}

// An angle sequence made continuous (no 2π jumps between neighbouring samples).
std::vector<double> unwrapped(std::vector<double> a) {
    const double two_pi = 2 * std::numbers::pi;
    for (std::size_t k = 1; k < a.size(); ++k) a[k] -= two_pi * std::round((a[k] - a[k - 1]) / two_pi);
    return a;
}

}  // namespace

BOOST_AUTO_TEST_CASE(initial_state_is_the_runtime_conversion_of_the_elements) {
    const Model::Parameters p{};
    const auto x = rt::cartesian_from_classical(scene_elements, p.mu);
    for (int i = 0; i < 6; ++i) {
        BOOST_TEST_INFO(Model::state_names[std::size_t(i)]);
        // The header prints 17 significant digits: the same double.
        BOOST_TEST(Model::initial_state[std::size_t(i)] == x[std::size_t(i)]);
    }
}

BOOST_AUTO_TEST_CASE(energy_and_polar_angular_momentum_are_conserved) {
    using S = double;
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const auto energy = [&](const std::vector<S>& s) { return Model::energy(S(0), s.data(), sys.p); };
    const auto h_z = [&](const std::vector<S>& s) { return Model::h_z(S(0), s.data(), sys.p); };
    const S e0 = energy(x), h0 = h_z(x);
    // The invariant is H0 − R: check it against its definition once, at the start.
    const S r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const S v2 = x[3] * x[3] + x[4] * x[4] + x[5] * x[5];
    const S R = -sys.p.mu * sys.p.J2 * sys.p.Re * sys.p.Re / (2 * r * r * r) * (3 * x[2] * x[2] / (r * r) - 1);
    BOOST_TEST(std::abs(e0 - (v2 / 2 - sys.p.mu / r - R)) <= 64 * std::numeric_limits<S>::epsilon() * sys.p.mu / r);
    BOOST_TEST(std::abs(h0 - (x[0] * x[4] - x[1] * x[3])) <= 8 * std::numeric_limits<S>::epsilon() * std::abs(h0));

    S worst_e = 0, worst_h = 0;
    rt::Dopri5<S> stepper;
    const rt::Tolerances tol{1e-11, 1e-11};
    const S t_end = 86400;  // one day, about 15 revolutions
    const auto steps = phys::run(stepper, sys, x, S(0), t_end, tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        worst_e = std::max(worst_e, std::abs(energy(st.x_new) - e0));
        worst_h = std::max(worst_h, std::abs(h_z(st.x_new) - h0));
    });
    // Largest terms: μ/r ≈ 57 km²/s² in the energy, r v ≈ 5.3e4 km²/s in h_z.
    const S bound_e = phys::invariant_drift_bound<S>(steps, energy, sys.p.mu / 6000);
    const S bound_h = phys::invariant_drift_bound<S>(steps, h_z, 7100 * 7.7);
    BOOST_TEST_MESSAGE("one day, " << steps.size() << " steps: |E - E0| " << worst_e << " (bound " << bound_e
                                   << ", relative " << worst_e / std::abs(e0) << "), |h_z - h_z0| " << worst_h
                                   << " (bound " << bound_h << ", relative " << worst_h / std::abs(h0) << ")");
    BOOST_TEST(worst_e <= bound_e);
    BOOST_TEST(worst_h <= bound_h);
}

// Thirty days sampled every 10 minutes; the osculating node and perigee are fitted by straight
// lines and their slopes compared with the first-order mean rates, evaluated at the time-averaged
// osculating a, e, i (the averages of the short-period terms of a, e, i vanish to first order
// in J2, so these are the mean elements up to O(J2²) and O(J2 e²)).
// Neglected: the O(J2²) secular rates, relative size J2 (Re/p)² times coefficients of order one
// (Brouwer 1959, eqs. for the second-order secular terms: 3/2…5/2 at i = 50°), so the first-order
// rate is right to 3 J2 (Re/p)² ≈ 2.7e-3 relative; the short-period terms (amplitude ~J2 (Re/a)²
// rad in Ω, ~J2 (Re/a)²/e in ω) average out of a fit over ~430 revolutions to well below that.
BOOST_AUTO_TEST_CASE(node_and_perigee_drift_at_the_mean_j2_rates) {
    using S = double;
    phys::KernelSystem<Model, S> sys;
    const auto& p = sys.p;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const S day = 86400, t_end = 30 * day, dt = 600;
    std::vector<S> times;
    for (S t = 0; t <= t_end + 0.5; t += dt) times.push_back(t);
    std::vector<S> raan, argp, a, e, inc;
    rt::Dop853<S> stepper;
    rt::integrate_times(stepper, sys, x, times, S(0), rt::Tolerances{1e-12, 1e-9}, [&](S, const rt::State<S>& xs) {
        const auto el = rt::classical_from_cartesian(rt::CartesianState<S>{xs[0], xs[1], xs[2], xs[3], xs[4], xs[5]}, p.mu);
        raan.push_back(el.raan);
        argp.push_back(el.argp);
        a.push_back(el.a);
        e.push_back(el.e);
        inc.push_back(el.i);
    });
    auto mean = [](const std::vector<S>& v) {
        S s = 0;
        for (S q : v) s += q;
        return s / S(v.size());
    };
    const S am = mean(a), em = mean(e), im = mean(inc);
    const S n = std::sqrt(p.mu / (am * am * am)), pp = am * (1 - em * em);
    const S k = p.J2 * (p.Re / pp) * (p.Re / pp);
    const S raan_rate = -1.5 * n * k * std::cos(im);
    const S argp_rate = 0.75 * n * k * (5 * std::cos(im) * std::cos(im) - 1);
    const S raan_fit = slope(times, unwrapped(raan)), argp_fit = slope(times, unwrapped(argp));
    const S tolerance = 3 * k;
    BOOST_TEST_MESSAGE("30 days, mean a " << am << " km, e " << em << ", i " << im / degree << " deg");
    BOOST_TEST_MESSAGE("RAAN rate: fitted " << raan_fit * day / degree << " deg/day, theory " << raan_rate * day / degree
                                            << " deg/day, relative difference " << raan_fit / raan_rate - 1
                                            << " (tolerance " << tolerance << ")");
    BOOST_TEST_MESSAGE("argp rate: fitted " << argp_fit * day / degree << " deg/day, theory " << argp_rate * day / degree
                                            << " deg/day, relative difference " << argp_fit / argp_rate - 1
                                            << " (tolerance " << tolerance << ")");
    BOOST_TEST(std::abs(raan_fit / raan_rate - 1) <= tolerance);
    BOOST_TEST(std::abs(argp_fit / argp_rate - 1) <= tolerance);
}

// J3's long-period effect. For small e the mean-element equations (Lagrange's, Mei 1988, ch. 2, with
// the averaged R_2 and R_3) in k = e cos ω, h = e sin ω are
//   dk/dt = −A − ω̇₂ h,  dh/dt = ω̇₂ k,  A = (3/2) n J3 (Re/p)³ sin i (1 − (5/4) sin² i),
//   ω̇₂ = 3 n J2 (Re/p)² (1 − (5/4) sin² i),
// a circle about (0, e_f), e_f = −A/ω̇₂ = −(J3/(2 J2)) (Re/p) sin i: positive for the Earth
// (J3 < 0), the frozen orbits at ω = 90°. The osculating (k, h), sampled every 10 minutes over
// 100 days (one turn of ω takes 93 days), is fitted with a circle (algebraic least squares).
// Neglected: O(J2) relative corrections to both rates (second-order secular terms and the
// first-order short-period terms, which average out of the fit only to that order), and O(e²)
// terms, e ≤ 0.011 (so p = a(1 − e²) is taken as a); the centre is e_f to about 1e-3 relative,
// and the check allows 1e-2.
BOOST_AUTO_TEST_CASE(j3_eccentricity_circles_the_frozen_eccentricity) {
    using K = eomc::models::LeoJ2J3;
    using S = double;
    phys::KernelSystem<K, S> sys;
    const auto& p = sys.p;
    std::vector<S> x(K::initial_state.begin(), K::initial_state.end());
    const S day = 86400, t_end = 100 * day, dt = 600;
    std::vector<S> times;
    for (S t = 0; t <= t_end + 0.5; t += dt) times.push_back(t);
    std::vector<S> k, h, a, inc;
    rt::Dop853<S> stepper;
    rt::integrate_times(stepper, sys, x, times, S(0), rt::Tolerances{1e-12, 1e-9}, [&](S, const rt::State<S>& xs) {
        const auto el = rt::classical_from_cartesian(rt::CartesianState<S>{xs[0], xs[1], xs[2], xs[3], xs[4], xs[5]}, p.mu);
        k.push_back(el.e * std::cos(el.argp));
        h.push_back(el.e * std::sin(el.argp));
        a.push_back(el.a);
        inc.push_back(el.i);
    });
    // Circle k² + h² + D k + E h + F = 0 by linear least squares; centre (−D/2, −E/2).
    Eigen::MatrixXd A(k.size(), 3);
    Eigen::VectorXd b(k.size());
    for (std::size_t j = 0; j < k.size(); ++j) {
        A(Eigen::Index(j), 0) = k[j];
        A(Eigen::Index(j), 1) = h[j];
        A(Eigen::Index(j), 2) = 1;
        b(Eigen::Index(j)) = -(k[j] * k[j] + h[j] * h[j]);
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
    const S k_c = -c(0) / 2, h_c = -c(1) / 2, radius = std::sqrt(k_c * k_c + h_c * h_c - c(2));
    S am = 0, im = 0;
    for (std::size_t j = 0; j < a.size(); ++j) am += a[j], im += inc[j];
    am /= S(a.size());
    im /= S(inc.size());
    const S e_f = -(p.J3 / (2 * p.J2)) * (p.Re / am) * std::sin(im);
    BOOST_TEST_MESSAGE("J3: eccentricity circle centre (" << k_c << ", " << h_c << "), radius " << radius
                                                           << "; frozen eccentricity theory (0, " << e_f
                                                           << "), relative difference " << h_c / e_f - 1);
    BOOST_TEST(e_f > 0);
    BOOST_TEST(std::abs(h_c / e_f - 1) <= 1e-2);
    BOOST_TEST(std::abs(k_c) <= 1e-2 * e_f);
}
