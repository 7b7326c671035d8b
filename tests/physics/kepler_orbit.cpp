// The Kepler orbit of the bundled scene (polar coordinates, μ = 1, a = 1, e = 0.5, from
// pericentre), against the two-body closed forms:
//   * after one period T = 2π √(a³/μ) the state is the pericentre state again (φ advanced by 2π),
//     and at T/2 the orbit is at apocentre r = a(1 + e), φ = π, ṙ = 0;
//   * the energy −μ/(2a) and the angular momentum r² φ̇ = √(μ a (1 − e²)) are conserved.
// State errors are checked against the bound propagated from every accepted step's tolerance
// through the variational equation (physics_support.hpp); Kepler's shear (a period that depends
// on the energy) is what makes that propagation, not the local tolerance alone, the right bound.
// Templated over double and long double; long double runs at a tolerance 1e4 times tighter.
#define BOOST_TEST_MODULE physics_kepler_orbit
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "kepler_orbit.hpp"
#include "physics_support.hpp"

using Model = eomc::models::KeplerOrbit;
namespace rt = eomc::runtime;

namespace {

template <class S>
struct Orbit {
    S mu = 1, a = 1, e = S(1) / 2;
    S r_peri() const { return a * (1 - e); }
    S r_apo() const { return a * (1 + e); }
    S h() const { return std::sqrt(mu * a * (1 - e * e)); }  // r² φ̇
    S period() const { return 2 * std::numbers::pi_v<S> * std::sqrt(a * a * a / mu); }
    S energy() const { return -mu / (2 * a); }
    std::vector<S> pericentre(S phi) const { return {r_peri(), phi, 0, h() / (r_peri() * r_peri())}; }
    std::vector<S> apocentre() const { return {r_apo(), std::numbers::pi_v<S>, 0, h() / (r_apo() * r_apo())}; }
};

template <class S>
rt::Tolerances tolerances() {
    return std::is_same_v<S, double> ? rt::Tolerances{1e-11, 1e-13} : rt::Tolerances{1e-15, 1e-17};
}

// Runs from pericentre to t1 and checks the state against `expected` component by component.
// Returns the largest error.
template <class S>
S check_state_at(S t1, const std::vector<S>& expected) {
    using std::abs;
    const Orbit<S> orbit;
    phys::KernelSystem<Model, S> sys;
    const std::vector<S> x0 = orbit.pericentre(0);
    std::vector<S> x = x0;
    rt::Dopri5<S> stepper;
    const auto tol = tolerances<S>();
    const auto steps = phys::run(stepper, sys, x, S(0), t1, tol);
    const auto bound = phys::propagated_error_bound<Model, S>(steps, x0, S(0), sys.p, tol);
    S worst = 0;
    for (int i = 0; i < 4; ++i) {
        const S err = abs(x[i] - expected[i]);
        worst = std::max(worst, err);
        BOOST_TEST_INFO(Model::state_names[i] << " at t = " << double(t1) << ": |x - exact| = " << double(err)
                                              << ", bound " << double(bound[i]) << " (" << steps.size() << " steps)");
        BOOST_TEST(err <= bound[i]);
    }
    BOOST_TEST_MESSAGE("t = " << double(t1) << ": max error " << double(worst) << ", bounds " << double(bound[0]) << ", "
                              << double(bound[1]) << ", " << double(bound[2]) << ", " << double(bound[3]) << " ("
                              << steps.size() << " steps, rtol " << tol.rtol << ")");
    return worst;
}

}  // namespace

using Scalars = boost::mpl::list<double, long double>;

BOOST_AUTO_TEST_CASE(scene_starts_at_pericentre) {
    const Orbit<double> orbit;
    const Model::Parameters p{};
    BOOST_TEST(p.mu == orbit.mu);
    const auto x0 = orbit.pericentre(0);
    for (int i = 0; i < 4; ++i) {
        BOOST_TEST_INFO(Model::state_names[i]);
        BOOST_TEST(std::abs(Model::initial_state[i] - x0[i]) <= 2 * std::numeric_limits<double>::epsilon() * std::abs(x0[i]));
    }
    // The kernel's invariant is the energy T + V = −μ/(2a) (to the rounding of a few operations).
    BOOST_TEST(std::abs(Model::energy(0.0, x0.data(), p) - orbit.energy()) <= 8 * std::numeric_limits<double>::epsilon());
}

BOOST_AUTO_TEST_CASE_TEMPLATE(returns_to_pericentre_after_one_period, S, Scalars) {
    const Orbit<S> orbit;
    check_state_at<S>(orbit.period(), orbit.pericentre(2 * std::numbers::pi_v<S>));
}

BOOST_AUTO_TEST_CASE_TEMPLATE(apocentre_at_half_period, S, Scalars) {
    const Orbit<S> orbit;
    check_state_at<S>(orbit.period() / 2, orbit.apocentre());
}

BOOST_AUTO_TEST_CASE(long_double_is_more_accurate) {
    const Orbit<double> d;
    const Orbit<long double> ld;
    const double err_d = check_state_at<double>(d.period(), d.pericentre(2 * std::numbers::pi));
    const long double err_ld = check_state_at<long double>(ld.period(), ld.pericentre(2 * std::numbers::pi_v<long double>));
    BOOST_TEST_MESSAGE("one period: double @1e-11 " << err_d << ", long double @1e-15 " << double(err_ld));
    // Tolerance 1e4 tighter: the error must drop by well over 100 (it scales about linearly with
    // the tolerance for an error-per-step controller).
    BOOST_TEST(err_ld < err_d / 100);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(energy_and_angular_momentum_are_conserved, S, Scalars) {
    using std::abs;
    const Orbit<S> orbit;
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x = orbit.pericentre(0);
    const auto energy = [&](const std::vector<S>& s) { return Model::energy(S(0), s.data(), sys.p); };
    const auto momentum = [](const std::vector<S>& s) { return s[0] * s[0] * s[3]; };
    S worst_e = 0, worst_h = 0;
    rt::Dopri5<S> stepper;
    const auto tol = tolerances<S>();
    // Ten periods: the bounds grow with the number of steps, and so would a real drift.
    const auto steps = phys::run(stepper, sys, x, S(0), 10 * orbit.period(), tol,
                                 [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
                                     worst_e = std::max(worst_e, abs(energy(st.x_new) - orbit.energy()));
                                     worst_h = std::max(worst_h, abs(momentum(st.x_new) - orbit.h()));
                                 });
    // Largest terms: ½ r² φ̇² = h²/(2 r_peri²) = 1.5 and μ/r_peri = 2 in the energy; h in r² φ̇.
    const S bound_e = phys::invariant_drift_bound<S>(steps, energy, S(4)) +
                      8 * std::numeric_limits<S>::epsilon();  // rounding of the start state itself
    const S bound_h = phys::invariant_drift_bound<S>(steps, momentum, orbit.h()) +
                      8 * std::numeric_limits<S>::epsilon();
    BOOST_TEST_MESSAGE("ten periods, " << steps.size() << " steps: |E - E0| " << double(worst_e) << " (bound "
                                       << double(bound_e) << "), |h - h0| " << double(worst_h) << " (bound "
                                       << double(bound_h) << ")");
    BOOST_TEST(worst_e <= bound_e);
    BOOST_TEST(worst_h <= bound_h);
}
