// A long run: 10⁴ orbits of the bundled Kepler orbit (polar, μ = 1, a = 1, e = 0.5) with the
// sixth-order Gauss–Legendre method Gl6 at a fixed step h = T/200 (2·10⁶ steps).
//
// Gl6 is symplectic and symmetric, so by backward error analysis (Hairer–Lubich–Wanner,
// Geometric Numerical Integration, IX.8 and X.3) the energy error E(x_n) − E(x_0) = O(h⁶) stays
// bounded, oscillating with the orbit, over exponentially long times: there is no secular drift.
// The energy error sampled over the first 10 % of the run (10³ orbits, 2·10⁵ steps, every phase of
// the orbit visited many times) therefore already shows its full range, and the last 10 % may not
// exceed it by more than
//   * 25 % (the method's error oscillation is sampled at slightly different phases as the
//     numerical orbit precesses; it is the same oscillation), plus
//   * the round-off random walk: compensated summation leaves a few ulps of the state per step,
//     uncorrelated from step to step, so E walks by ≲ 4 ε (μ/r_p) √N after N steps (4σ of a walk
//     with ε|∇E|·|x| per step, |∇E|·|x| ≤ 2μ/r_p).
// The criterion can fail: RK4 (not symplectic) at the same step drifts secularly and is checked to
// fail it, by orders of magnitude.
#define BOOST_TEST_MODULE stability_long_run
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <vector>

#include "kepler_orbit.hpp"
#include "physics_support.hpp"

namespace rt = eomc::runtime;
using Model = eomc::models::KeplerOrbit;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
constexpr double e = 0.5, mu = 1, a = 1;
constexpr long orbits = 10000, per_orbit = 200;

struct Windows {
    double first = 0, last = 0, all = 0;  // max |E − E0| over the first 10 %, the last 10 %, the whole run
    double mean_first = 0, mean_last = 0;
    std::size_t steps = 0;
    double seconds = 0;
};

template <class Stepper>
Windows run(Stepper& stepper) {
    const double r_p = a * (1 - e), L = std::sqrt(mu * a * (1 - e * e));
    const double T = 2 * std::numbers::pi * std::sqrt(a * a * a / mu);
    rt::State<double> x{r_p, 0, 0, L / (r_p * r_p)};
    phys::KernelSystem<Model, double> sys;
    const double E0 = Model::energy(0.0, x.data(), sys.p);
    const double t1 = orbits * T, h = T / per_orbit;
    Windows w;
    std::size_t n_first = 0, n_last = 0;
    const auto start = std::chrono::steady_clock::now();
    rt::integrate_fixed(stepper, sys, x, 0.0, t1, h, [&](double t, const rt::State<double>& xs) {
        const double dE = Model::energy(t, xs.data(), sys.p) - E0;
        const double d = std::abs(dE);
        w.all = std::max(w.all, d);
        if (t <= 0.1 * t1) { w.first = std::max(w.first, d); w.mean_first += dE; ++n_first; }
        if (t >= 0.9 * t1) { w.last = std::max(w.last, d); w.mean_last += dE; ++n_last; }
        ++w.steps;
    });
    w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    w.mean_first /= double(n_first);
    w.mean_last /= double(n_last);
    return w;
}

double walk(std::size_t steps) { return 4 * eps * (mu / (a * (1 - e))) * std::sqrt(double(steps)); }

}  // namespace

BOOST_AUTO_TEST_CASE(gl6_energy_bounded_without_drift) {
    rt::Gl6<double> stepper;
    const Windows w = run(stepper);
    const double bound = 1.25 * w.first + walk(w.steps);
    BOOST_TEST_MESSAGE("Gl6, " << orbits << " orbits, " << w.steps << " steps in " << w.seconds << " s: max |dE| first 10% "
                               << w.first << ", last 10% " << w.last << ", whole run " << w.all << " (bound " << bound
                               << "); mean dE first " << w.mean_first << ", last " << w.mean_last);
    BOOST_TEST(w.last <= bound);
    BOOST_TEST(w.all <= bound);
    // No drift of the mean either: the means of two windows of the same bounded oscillation differ
    // by less than its amplitude.
    BOOST_TEST(std::abs(w.mean_last - w.mean_first) <= w.first + walk(w.steps));
    // The step is in the asymptotic regime: the error is small, not merely bounded.
    // (h/τ_p = (T/200)/√(r_p³/μ) ≈ 0.09, so (h/τ_p)⁶ ≈ 5e-7; the energy error may not exceed it times |E|.)
    BOOST_TEST(w.all <= 5e-7 * mu / (2 * a));
}

BOOST_AUTO_TEST_CASE(rk4_fails_the_same_criterion) {
    // The control: a non-symplectic method at the same step drifts, and the criterion sees it.
    rt::Rk4<double> stepper;
    const Windows w = run(stepper);
    const double bound = 1.25 * w.first + walk(w.steps);
    BOOST_TEST_MESSAGE("Rk4 (control): max |dE| first 10% " << w.first << ", last 10% " << w.last << " (Gl6 bound form "
                                                            << bound << ")");
    BOOST_TEST(w.last > 5 * bound);
}
