// The no-progress checker: blow-up, NaN-producing systems, step budget, non-finite fixed steps.
#define BOOST_TEST_MODULE runtime_checker
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;
using Kind = rt::IntegrationError::Kind;

namespace {

// y' = y^2, y(0) = 1: y = 1/(1 - t), a pole at t = 1.
struct BlowUp {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[0] * x[0];
  }
};

// Three components; the derivative of component 1 is NaN from t = 0.5 on.
struct NanAfterHalf {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = t < S(0.5) ? -x[0] : std::numeric_limits<S>::quiet_NaN();
    dxdt[2] = S(1);
  }
};

struct Oscillator {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
};

auto ignore = [](auto, const auto&) {};

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

using Scalars = boost::mpl::list<double, long double>;

}  // namespace

// How close to t = 1 the integration must stop. Two contributions:
// (1) The numerical solution has its own pole t*, shifted by the global error: u = 1/y solves
//     u' = -1, and a relative error eps_n made in y at time t_n shifts t* by eps_n u(t_n). With error
//     per unit step (see the adaptive tests) eps_n <= h_n * lambda_n * rtol, lambda_n = 2 y_n, so the
//     shifts add up to <= rtol * sum 2 h_n = 2 rtol. (Measured: 1 - t* = 1.7e-11 = 0.17 rtol.)
// (2) y' = y^2 is invariant under t* - t -> l (t* - t), y -> y / l, so near t* the controller takes
//     steps h = c (t* - t) with a constant c ~ rtol^(1/5) ~ 0.01, and gives up when h < 16 eps |t|,
//     i.e. at t* - t < 16 eps / 0.01 = 1600 eps; with a factor 10 for the scatter of c: 16000 eps.
// Bound: |1 - t_stop| < 2 rtol + 16000 eps.
BOOST_AUTO_TEST_CASE_TEMPLATE(blow_up_stops_near_pole, S, Scalars) {
  rt::Dopri5<S> stepper;
  BlowUp sys;
  rt::State<S> x{S(1)};
  try {
    rt::integrate_adaptive(stepper, sys, x, S(0), S(2), S(0), rt::Tolerances{1e-10, 1e-10}, ignore);
    BOOST_FAIL("integration through the pole did not throw");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST_MESSAGE("blow-up: " << e.what() << "; 1 - t = " << 1.0 - e.t());
    BOOST_TEST((e.kind() == Kind::step_underflow || e.kind() == Kind::non_finite));
    const double bound = 2 * 1e-10 + 16000.0 * static_cast<double>(std::numeric_limits<S>::epsilon());
    BOOST_TEST(std::abs(1.0 - e.t()) < bound, "stopped at t = " << e.t());
    BOOST_TEST(e.t() <= 1.0);
    if (e.kind() == Kind::step_underflow) {
      BOOST_TEST(contains(e.what(), "step size collapsed to "));
      BOOST_TEST(contains(e.what(), "(step underflow)"));
    }
    BOOST_TEST(contains(e.what(), "at t = "));
  }
}

// A system that turns NaN is reported as non-finite, naming the component, at the last good time;
// the steps that straddle t = 0.5 are rejected and shrink until they underflow, which the driver
// attributes to the NaN.
BOOST_AUTO_TEST_CASE_TEMPLATE(nan_system_reported_as_non_finite, S, Scalars) {
  rt::Dopri5<S> stepper;
  NanAfterHalf sys;
  rt::State<S> x{S(1), S(0), S(0)};
  try {
    rt::integrate_adaptive(stepper, sys, x, S(0), S(1), S(0), rt::Tolerances{1e-8, 1e-8}, ignore);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST_MESSAGE("nan system: " << e.what());
    BOOST_TEST((e.kind() == Kind::non_finite));
    BOOST_TEST(e.component() == 1u);
    BOOST_TEST(contains(e.what(), "(component 1)"));
    BOOST_TEST(contains(e.what(), "non-finite derivative at t = "));
    // The last accepted time lies below 0.5 by no more than the underflow threshold 16 eps * 0.5
    // (t() is a double, in which a long double 0.5 - 2e-18 reads as 0.5; the message keeps it).
    BOOST_TEST(e.t() <= 0.5);
    BOOST_TEST(!contains(e.what(), "t = 0.5 "));
    BOOST_TEST(e.t() > 0.5 - 1e-13);
  }
}

// NaN already at t0: reported immediately, at t0.
BOOST_AUTO_TEST_CASE(nan_at_start) {
  rt::Dopri5<double> stepper;
  NanAfterHalf sys;
  rt::State<double> x{1.0, 0.0, 0.0};
  try {
    rt::integrate_adaptive(stepper, sys, x, 0.75, 1.0, 0.0, rt::Tolerances{}, ignore);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST((e.kind() == Kind::non_finite));
    BOOST_TEST(e.t() == 0.75);
    BOOST_TEST(std::string(e.what()) == "non-finite derivative at t = 0.75 (component 1)");
  }
  rt::State<double> bad{1.0, std::numeric_limits<double>::infinity(), 0.0};
  try {
    rt::integrate_adaptive(stepper, sys, bad, 0.0, 1.0, 0.0, rt::Tolerances{}, ignore);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST(std::string(e.what()) == "non-finite state at t = 0 (component 1)");
  }
}

// 100 attempts cannot cover ten periods at rtol 1e-10 (that takes ~700 steps).
BOOST_AUTO_TEST_CASE(step_budget) {
  rt::Dopri5<double> stepper;
  Oscillator sys;
  rt::State<double> x{1.0, 0.0};
  rt::Limits limits;
  limits.max_steps = 100;
  std::size_t observed = 0;
  try {
    rt::integrate_adaptive(stepper, sys, x, 0.0, 20 * std::acos(-1.0), 0.0, rt::Tolerances{1e-10, 1e-10},
                           [&](double, const rt::State<double>&) { ++observed; }, limits);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST((e.kind() == Kind::step_budget));
    BOOST_TEST(e.t() > 0.0);
    BOOST_TEST(std::string(e.what()) == "step budget of 100 steps exhausted at t = " + rt::IntegrationError::format(e.t()));
    BOOST_TEST(observed <= 101u);  // t0 plus at most 100 accepted steps
  }
  // The fixed-step driver obeys the same budget.
  rt::Rk4<double> rk4;
  x = {1.0, 0.0};
  limits.max_steps = 10;
  try {
    rt::integrate_fixed(rk4, sys, x, 0.0, 1.0, 0.01, ignore, limits);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST((e.kind() == Kind::step_budget));
    BOOST_TEST(std::abs(e.t() - 0.1) < 1e-15);
  }
}

// Fixed steps cannot be rejected, so non-finite values show up in the state: y' = y^2 with h = 0.25
// overflows within a few steps past the pole's neighbourhood; and a NaN system poisons the state.
BOOST_AUTO_TEST_CASE_TEMPLATE(fixed_detects_non_finite, S, Scalars) {
  rt::Rk4<S> rk4;
  BlowUp blow;
  rt::State<S> y{S(1)};
  try {
    rt::integrate_fixed(rk4, blow, y, S(0), S(2), S(0.25), ignore);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST_MESSAGE("fixed blow-up: " << e.what());
    BOOST_TEST((e.kind() == Kind::non_finite));
    BOOST_TEST(e.component() == 0u);
    BOOST_TEST(contains(e.what(), "non-finite state at t = "));
  }
  NanAfterHalf nan_sys;
  rt::State<S> x{S(1), S(0), S(0)};
  try {
    rt::integrate_fixed(rk4, nan_sys, x, S(0), S(1), S(0.125), ignore);
    BOOST_FAIL("no error");
  } catch (const rt::IntegrationError& e) {
    BOOST_TEST((e.kind() == Kind::non_finite));
    BOOST_TEST(e.t() == 0.5);  // the step [0.375, 0.5] evaluates f at t = 0.5
    BOOST_TEST(std::string(e.what()) == "non-finite state at t = 0.5 (component 1)");
  }
}

BOOST_AUTO_TEST_CASE(underflow_message_format) {
  const auto e = rt::IntegrationError::step_underflow(1.2345, 3.1e-17);
  BOOST_TEST(std::string(e.what()) == "step size collapsed to 3.1e-17 at t = 1.2345 (step underflow)");
  BOOST_TEST((e.kind() == Kind::step_underflow));
  BOOST_TEST(e.component() == rt::IntegrationError::no_component);
}
