// integrate_times: the observer is called exactly at the requested times, with dense-output
// values that match the closed form to the tolerance.
#define BOOST_TEST_MODULE runtime_integrate_times
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;

namespace {

// q'' = -q, q = cos t; and y' = -2 t y^2, y = 1/(1 + t^2).
struct Coupled {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
    dxdt[2] = S(-2) * t * x[2] * x[2];
  }
  template <class S>
  static rt::State<S> exact(S t) {
    using std::cos;
    using std::sin;
    return {cos(t), -sin(t), S(1) / (S(1) + t * t)};
  }
};

using Scalars = boost::mpl::list<double, long double>;

}  // namespace

// Over [0, 10] at rtol = atol = 1e-10 the global error of the step ends is below ~20 tol (see the
// adaptive tests); the dense output adds its own O(h^5) local error, which the controller keeps at
// the level of the step's error estimate (the interpolant is fourth order, like the estimate). So
// every output value must match the closed form to C*tol with the same C = 20 used for the
// oscillator step ends.
BOOST_AUTO_TEST_CASE_TEMPLATE(observer_called_exactly_at_times, S, Scalars) {
  using std::abs;
  const double tol = 1e-10;
  std::vector<S> times;
  for (int i = 0; i <= 1000; ++i) times.push_back(S(i) / S(100));  // 0, 0.01, ..., 10
  times.insert(times.begin() + 500, times[500]);                   // a repeated time is observed twice
  rt::Dopri5<S> stepper;
  Coupled sys;
  rt::State<S> x = Coupled::exact(S(0));
  std::vector<S> seen;
  double worst = 0;
  const rt::Stats st = rt::integrate_times(stepper, sys, x, times, S(0), rt::Tolerances{tol, tol},
                                           [&](S t, const rt::State<S>& xt) {
                                             seen.push_back(t);
                                             const rt::State<S> ref = Coupled::exact(t);
                                             for (std::size_t i = 0; i < xt.size(); ++i)
                                               worst = std::max(worst, static_cast<double>(abs(xt[i] - ref[i])));
                                           });
  BOOST_TEST_MESSAGE("integrate_times: worst error " << worst << " accepted " << st.accepted << " rejected " << st.rejected);
  BOOST_TEST(seen == times, boost::test_tools::per_element());
  BOOST_TEST(worst < 20 * tol);
  // Steps are not shortened to hit output times: far fewer steps than output times.
  BOOST_TEST(st.accepted < times.size() / 4);
  BOOST_TEST(st.rhs_evals == 2 + 6 * (st.accepted + st.rejected));
  // x ends at times.back() exactly as a step end.
  const rt::State<S> ref = Coupled::exact(S(10));
  for (std::size_t i = 0; i < x.size(); ++i) BOOST_TEST(abs(x[i] - ref[i]) < S(20 * tol));
}

BOOST_AUTO_TEST_CASE(edge_cases) {
  rt::Dopri5<double> stepper;
  Coupled sys;
  std::vector<double> seen;
  auto obs = [&](double t, const rt::State<double>&) { seen.push_back(t); };
  rt::State<double> x = Coupled::exact(0.0);
  // Empty: nothing happens.
  rt::Stats st = rt::integrate_times(stepper, sys, x, std::vector<double>{}, 0.0, rt::Tolerances{}, obs);
  BOOST_TEST(seen.empty());
  BOOST_TEST(st.rhs_evals == 0u);
  // A single time: observed once, no step.
  st = rt::integrate_times(stepper, sys, x, std::vector<double>{0.0}, 0.0, rt::Tolerances{}, obs);
  BOOST_TEST(seen == std::vector<double>{0.0});
  BOOST_TEST(st.accepted == 0u);
  // Backwards in time.
  seen.clear();
  x = Coupled::exact(2.0);
  const std::vector<double> back{2.0, 1.5, 1.0, 0.25, 0.0};
  rt::integrate_times(stepper, sys, x, back, 0.0, rt::Tolerances{1e-10, 1e-10}, obs);
  BOOST_TEST(seen == back, boost::test_tools::per_element());
  const rt::State<double> ref = Coupled::exact(0.0);
  for (std::size_t i = 0; i < x.size(); ++i) BOOST_TEST(std::abs(x[i] - ref[i]) < 20e-10);
  // Not monotone: rejected before any work.
  BOOST_CHECK_THROW(rt::integrate_times(stepper, sys, x, std::vector<double>{0.0, 1.0, 0.5}, 0.0, rt::Tolerances{}, obs),
                    std::invalid_argument);
}
