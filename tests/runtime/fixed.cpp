// integrate_fixed: step placement, exact landing, observer calls, counting, argument checks.
#define BOOST_TEST_MODULE runtime_fixed
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <vector>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;

namespace {

struct Oscillator {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(lands_exactly_and_observes_every_step) {
  rt::Rk4<double> rk4;
  Oscillator sys;
  rt::State<double> x{1.0, 0.0};
  std::vector<double> seen;
  // 1 / 0.3 = 3.33...: three full steps and a shortened one.
  rt::Stats st = rt::integrate_fixed(rk4, sys, x, 0.0, 1.0, 0.3, [&](double t, const rt::State<double>&) { seen.push_back(t); });
  BOOST_TEST(seen == (std::vector<double>{0.0, 0.3, 0.6, 0.8999999999999999, 1.0}), boost::test_tools::per_element());
  BOOST_TEST(st.accepted == 4u);
  BOOST_TEST(st.rhs_evals == 16u);
  BOOST_TEST(st.rejected == 0u);
  // 0.1 * 10 is not 1 in floating point arithmetic, but no sliver step is taken: exactly ten steps.
  seen.clear();
  x = {1.0, 0.0};
  st = rt::integrate_fixed(rk4, sys, x, 0.0, 1.0, 0.1, [&](double t, const rt::State<double>&) { seen.push_back(t); });
  BOOST_TEST(st.accepted == 10u);
  BOOST_TEST(seen.back() == 1.0);
  BOOST_TEST(seen[3] == 3 * 0.1);  // t0 + k h, not accumulated
}

BOOST_AUTO_TEST_CASE(backward_and_dopri5_fixed) {
  rt::Dopri5<double> dp;
  Oscillator sys;
  rt::State<double> x{std::cos(1.0), -std::sin(1.0)};
  std::vector<double> seen;
  const rt::Stats st = rt::integrate_fixed(dp, sys, x, 1.0, 0.0, -0.125, [&](double t, const rt::State<double>&) { seen.push_back(t); });
  BOOST_TEST(seen.back() == 0.0);
  BOOST_TEST(st.accepted == 8u);
  BOOST_TEST(st.rhs_evals == 1u + 6u * 8u);  // FSAL across fixed steps too
  // Global error of the fifth-order method with h = 1/8 over a unit interval: ~h^5/|C| ~ 1e-7.
  BOOST_TEST(std::abs(x[0] - 1.0) < 1e-7);
  BOOST_TEST(std::abs(x[1]) < 1e-7);
}

BOOST_AUTO_TEST_CASE(invalid_step_rejected) {
  rt::Rk4<double> rk4;
  Oscillator sys;
  rt::State<double> x{1.0, 0.0};
  auto obs = [](double, const rt::State<double>&) {};
  BOOST_CHECK_THROW(rt::integrate_fixed(rk4, sys, x, 0.0, 1.0, 0.0, obs), std::invalid_argument);
  BOOST_CHECK_THROW(rt::integrate_fixed(rk4, sys, x, 0.0, 1.0, -0.1, obs), std::invalid_argument);
  // t0 == t1: only the initial observation.
  int calls = 0;
  const rt::Stats st = rt::integrate_fixed(rk4, sys, x, 2.0, 2.0, 0.1, [&](double, const rt::State<double>&) { ++calls; });
  BOOST_TEST(calls == 1);
  BOOST_TEST(st.accepted == 0u);
}
