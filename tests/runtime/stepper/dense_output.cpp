// Dense output of Dopri5: order of the continuous extension, and exactness at the step ends.
#define BOOST_TEST_MODULE runtime_dense_output
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;

namespace {

// y' = t y (1 - y) with y = 1/(1 + exp(-t^2/2)); q'' = -q with q = cos t. One nonlinear and
// non-autonomous component, so no error coefficient of the interpolant vanishes by accident.
struct Coupled {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = t * x[0] * (S(1) - x[0]);
    dxdt[1] = x[2];
    dxdt[2] = -x[1];
  }
  template <class S>
  static rt::State<S> exact(S t) {
    using std::cos;
    using std::exp;
    using std::sin;
    return {S(1) / (S(1) + exp(-t * t / S(2))), cos(t), -sin(t)};
  }
};

template <class S>
S max_abs_diff(const rt::State<S>& a, const rt::State<S>& b) {
  using std::abs;
  S m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, abs(a[i] - b[i]));
  return m;
}

using Scalars = boost::mpl::list<double, long double>;

}  // namespace

// One step of size h from the exact state at t0; the interpolant's error at interior points is a
// local error of a fourth-order continuous extension, O(h^5), while the step end is O(h^6). So the
// interior error (max over five theta and all components) must fall by 2^5 per halving of h: the
// observed local order log2(d(h)/d(h/2)) is 5 up to a relative correction O(h) of the next term,
// which halves with h and is below 0.1 from h = 0.1 down (checked on the two finest halvings,
// 0.1 -> 0.05 -> 0.025). Round-off: evaluating the interpolant and the reference costs a few
// roundings of eps*max|x|; every error used must exceed 100 times 4*eps*max|x| (max|x| = 1 here),
// so round-off moves the observed order by less than 0.03. Band: |p_obs - 5| < 0.1.
BOOST_AUTO_TEST_CASE_TEMPLATE(interior_error_is_fifth_order_local, S, Scalars) {
  const S eps = std::numeric_limits<S>::epsilon();
  const S t0 = S(0.3);
  const std::vector<S> thetas{S(0.1), S(0.25), S(0.5), S(0.75), S(0.9)};
  std::vector<S> d, hs;
  for (S h = S(0.4); h > S(0.02); h /= S(2)) {
    rt::Dopri5<S> stepper;
    Coupled sys;
    rt::State<S> x = Coupled::exact(t0), u;
    stepper.do_step(sys, x, t0, h);
    S worst = 0;
    for (const S th : thetas) {
      stepper.calc_state(t0 + th * h, u);
      worst = std::max(worst, max_abs_diff(u, Coupled::exact(t0 + th * h)));
    }
    BOOST_REQUIRE_MESSAGE(worst > S(100) * S(4) * eps, "dense-output error " << double(worst) << " at h=" << double(h) << " is at round-off level");
    d.push_back(worst);
    hs.push_back(h);
  }
  BOOST_REQUIRE_EQUAL(d.size(), 5u);
  for (std::size_t k = 0; k + 1 < d.size(); ++k) {
    const double p = static_cast<double>(std::log2(d[k] / d[k + 1]));
    BOOST_TEST_MESSAGE("dense output " << (sizeof(S) == sizeof(double) ? "double" : "long double") << ": h=" << double(hs[k])
                                       << " err=" << double(d[k]) << " -> " << double(d[k + 1]) << " local order " << p);
    if (k + 3 >= d.size()) BOOST_TEST(std::abs(p - 5.0) < 0.1, "local order of dense output " << p << " at h=" << double(hs[k]));
  }
}

// At theta = 0 the interpolant is exactly the old state; at the step end it is x_old + (x_new -
// x_old) with theta = 1 up to the rounding of t_new = t_old + h: two roundings of size
// eps*max(|x_old|, |x_new|) in the sum, at most 2 ulp in theta times |x_new - x_old| + O(h^2): the
// bound 8*eps*max(|x_old|, |x_new|) covers both.
BOOST_AUTO_TEST_CASE_TEMPLATE(step_ends_are_reproduced, S, Scalars) {
  using std::abs;
  const S eps = std::numeric_limits<S>::epsilon();
  rt::Dopri5<S> stepper;
  Coupled sys;
  S t = S(0.1), h = S(0.05);
  rt::State<S> x = Coupled::exact(t), u;
  int accepted = 0;
  while (accepted < 20) {
    const rt::State<S> x_old = x;
    const S t_old = t;
    if (!stepper.try_step(sys, x, t, h, rt::Tolerances{1e-9, 1e-9})) continue;
    ++accepted;
    BOOST_TEST(stepper.previous_time() == t_old);
    BOOST_TEST(stepper.current_time() == t);
    stepper.calc_state(t_old, u);
    for (std::size_t i = 0; i < u.size(); ++i) BOOST_TEST(u[i] == x_old[i], "component " << i << " at t_old");
    stepper.calc_state(t, u);
    for (std::size_t i = 0; i < u.size(); ++i) {
      const S bound = S(8) * eps * std::max(abs(x_old[i]), abs(x[i]));
      BOOST_TEST(abs(u[i] - x[i]) <= bound, "component " << i << " at t_new: " << double(u[i] - x[i]) << " > " << double(bound));
    }
  }
}

BOOST_AUTO_TEST_CASE(calc_state_before_any_step_throws) {
  rt::Dopri5<double> stepper;
  rt::State<double> u;
  BOOST_CHECK_THROW(stepper.calc_state(0.0, u), std::logic_error);
}

// A rejected attempt must not disturb the dense output of the last accepted step.
BOOST_AUTO_TEST_CASE(rejection_keeps_dense_output) {
  rt::Dopri5<double> stepper;
  Coupled sys;
  double t = 0.0, h = 0.01;
  rt::State<double> x = Coupled::exact(t), before, after;
  BOOST_REQUIRE(stepper.try_step(sys, x, t, h, rt::Tolerances{1e-6, 1e-6}));
  const double mid = 0.5 * (stepper.previous_time() + stepper.current_time());
  stepper.calc_state(mid, before);
  double t_try = t, h_try = 5.0;  // far too large for 1e-14: rejected
  rt::State<double> x_try = x;
  BOOST_REQUIRE(!stepper.try_step(sys, x_try, t_try, h_try, rt::Tolerances{1e-14, 1e-14}));
  BOOST_TEST(t_try == t);
  BOOST_TEST(h_try < 5.0);
  BOOST_TEST(x_try == x);
  stepper.calc_state(mid, after);
  BOOST_TEST(after == before);
}
