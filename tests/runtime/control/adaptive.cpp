// Adaptive Dopri5: tolerance proportionality on the harmonic oscillator and the Kepler problem,
// and exact accounting of steps and system calls.
#define BOOST_TEST_MODULE runtime_adaptive
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;

namespace {

// q'' = -q from (1, 0): after one period 2*pi the state returns to (1, 0).
struct Oscillator {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
  template <class S>
  static rt::State<S> initial() { return {S(1), S(0)}; }
};

// Kepler problem, mu = 1, semi-major axis 1, eccentricity 0.5, started at pericentre:
// r = a(1-e) = 0.5, speed sqrt(mu (1+e)/(a (1-e))) = sqrt(3). The period is 2*pi, after which the
// exact solution is the initial state again.
struct Kepler {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    using std::sqrt;
    const S r2 = x[0] * x[0] + x[1] * x[1];
    const S r3 = r2 * sqrt(r2);
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = -x[0] / r3;
    dxdt[3] = -x[1] / r3;
  }
  template <class S>
  static rt::State<S> initial() {
    using std::sqrt;
    return {S(0.5), S(0), S(0), sqrt(S(3))};
  }
};

using Scalars = boost::mpl::list<double, long double>;

struct Run {
  double error;
  rt::Stats stats;
};

template <class S, class Problem>
Run one_period(double tol, S h0) {
  using std::abs;
  rt::Dopri5<S> stepper;
  Problem sys;
  const rt::State<S> x0 = Problem::template initial<S>();
  rt::State<S> x = x0;
  const S period = S(2) * std::numbers::pi_v<S>;
  std::size_t observed = 0;
  S last_t = S(-1);
  const rt::Stats st = rt::integrate_adaptive(stepper, sys, x, S(0), period, h0, rt::Tolerances{tol, tol},
                                              [&](S t, const rt::State<S>&) {
                                                BOOST_CHECK(t > last_t);
                                                last_t = t;
                                                ++observed;
                                              });
  BOOST_TEST(last_t == period);  // lands exactly on t1
  BOOST_TEST(observed == st.accepted + 1);
  // Exact accounting: one call for f(t0), six per attempt (FSAL: stage 7 of an accepted step is
  // stage 1 of the next, and a rejected attempt keeps its stage 1), one for the starting-step probe
  // when h0 is chosen automatically.
  BOOST_TEST(st.rhs_evals == 1 + 6 * (st.accepted + st.rejected) + (h0 > S(0) ? 0 : 1));
  BOOST_TEST(stepper.rhs_evals() == st.rhs_evals - (h0 > S(0) ? 0 : 1));
  S e = 0;
  for (std::size_t i = 0; i < x.size(); ++i) e = std::max(e, abs(x[i] - x0[i]));
  return {static_cast<double>(e), st};
}

// What the global error should be. Dopri5 controls the error per step of the fourth-order
// embedded solution but propagates the fifth-order one (local extrapolation); Dormand and Prince
// chose the pair so that the fifth-order truncation constants are smaller than the embedded
// fourth-order ones, so the true local error of a step is at most h*lambda times its estimate
// (lambda the local frequency), i.e. the controller acts like error per unit step. Then
//   oscillator (lambda = 1, flow a rotation: amplification <= sqrt(2) in the max norm, weights
//   sc <= 2): global error <= sqrt(2) * 2*pi * 2 * tol = 17.8 tol, so C = 20.
//   Kepler: a perturbation d of the state at some time changes the energy by <= (|v| + 1/r^2) d
//   <= (sqrt(3) + 4) d, the semi-major axis by twice that, the phase accumulated until the end of
//   the period by <= 3*pi times that (dn/da = -3/2, at most one period 2*pi), and a phase error moves
//   the final pericentre state by <= 4 (|acceleration| there) per radian: amplification
//   <= 4 * 3*pi * 2 * 5.73 = 432. The per-period sum of true local errors is the oscillator's
//   measured level (about 2 tol), giving C = 1000 (measured: 107 to 222).
// Tolerance proportionality: h ~ tol^(1/5) from the fourth-order estimate and a fifth-order
// propagated error give err ~ tol^(5/5): the exponent fitted over the whole range of tolerances
// (8 decades) must be 1 within 0.1 (err/tol may drift by a factor 10^0.8 = 6 over the range;
// observed: <= 2.1); every tenfold-hundredfold step in tol must decrease the error, by a factor
// 100^e with e in [0.75, 1.25] (a few-step run at tol = 1e-4 is far from asymptotic).
template <class S, class Problem>
void check_proportionality(const char* name, double C, const std::vector<double>& tols) {
  std::vector<double> errs;
  for (std::size_t k = 0; k < tols.size(); ++k) {
    const Run auto_h0 = one_period<S, Problem>(tols[k], S(0));
    const Run given_h0 = one_period<S, Problem>(tols[k], S(1e-3));
    BOOST_TEST_MESSAGE(name << (sizeof(S) == sizeof(double) ? " double" : " long double") << " tol=" << tols[k]
                            << " err=" << auto_h0.error << " err/tol=" << auto_h0.error / tols[k]
                            << " accepted=" << auto_h0.stats.accepted << " rejected=" << auto_h0.stats.rejected
                            << " rhs=" << auto_h0.stats.rhs_evals);
    BOOST_TEST(auto_h0.error < C * tols[k], name << " tol=" << tols[k] << ": error " << auto_h0.error);
    BOOST_TEST(given_h0.error < C * tols[k], name << " tol=" << tols[k] << " (h0=1e-3): error " << given_h0.error);
    if (k > 0) {
      const double e = std::log(errs.back() / auto_h0.error) / std::log(tols[k - 1] / tols[k]);
      BOOST_TEST(auto_h0.error < errs.back());
      BOOST_TEST((e > 0.75 && e < 1.25), name << ": error exponent " << e << " from tol " << tols[k - 1] << " to " << tols[k]);
    }
    errs.push_back(auto_h0.error);
  }
  const double e_all = std::log(errs.front() / errs.back()) / std::log(tols.front() / tols.back());
  BOOST_TEST_MESSAGE(name << ": tolerance exponent over the range " << e_all);
  BOOST_TEST(std::abs(e_all - 1.0) < 0.1, name << ": tolerance exponent " << e_all);
}

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(oscillator_error_proportional_to_tolerance, S, Scalars) {
  check_proportionality<S, Oscillator>("oscillator", 20.0, {1e-4, 1e-6, 1e-8, 1e-10, 1e-12});
}

BOOST_AUTO_TEST_CASE_TEMPLATE(kepler_error_proportional_to_tolerance, S, Scalars) {
  check_proportionality<S, Kepler>("kepler e=0.5", 1000.0, {1e-4, 1e-6, 1e-8, 1e-10, 1e-12});
}

// Integrating backwards over the same period returns to the start as well.
BOOST_AUTO_TEST_CASE(backward_integration) {
  rt::Dopri5<double> stepper;
  Kepler sys;
  rt::State<double> x = Kepler::initial<double>();
  const double period = 2 * std::numbers::pi;
  double last = 1.0;
  const rt::Stats st = rt::integrate_adaptive(stepper, sys, x, period, 0.0, 0.0, rt::Tolerances{1e-10, 1e-10},
                                              [&](double t, const rt::State<double>&) {
                                                BOOST_CHECK(t < last || t == period);
                                                last = t;
                                              });
  BOOST_TEST(last == 0.0);
  BOOST_TEST(st.accepted > 10u);
  const rt::State<double> x0 = Kepler::initial<double>();
  for (std::size_t i = 0; i < x.size(); ++i) BOOST_TEST(std::abs(x[i] - x0[i]) < 1000 * 1e-10);
}

// FSAL is reused only at the exact end point of the last step: a state edited between steps (an
// impulse) gets a fresh derivative, which costs exactly one extra system call.
BOOST_AUTO_TEST_CASE(fsal_not_reused_after_state_edit) {
  rt::Dopri5<double> stepper;
  Oscillator sys;
  rt::State<double> x{1.0, 0.0};
  double t = 0.0, h = 0.1;
  const rt::Tolerances tol{1e-8, 1e-8};
  while (!stepper.try_step(sys, x, t, h, tol)) {
  }
  const std::size_t before = stepper.rhs_evals();
  while (!stepper.try_step(sys, x, t, h, tol)) {
  }
  BOOST_TEST(stepper.rhs_evals() % 6 == before % 6);  // FSAL: multiples of 6 only
  const std::size_t mid = stepper.rhs_evals();
  x[1] = -x[1];  // impulse
  rt::State<double> expected(2);
  sys(t, x, expected);
  const rt::State<double>& f = stepper.prepare(sys, x, t);
  BOOST_TEST(stepper.rhs_evals() == mid + 1);
  BOOST_TEST(f == expected);
}

BOOST_AUTO_TEST_CASE(invalid_tolerances_rejected) {
  rt::Dopri5<double> stepper;
  Oscillator sys;
  rt::State<double> x{1.0, 0.0};
  auto obs = [](double, const rt::State<double>&) {};
  BOOST_CHECK_THROW(rt::integrate_adaptive(stepper, sys, x, 0.0, 1.0, 0.0, rt::Tolerances{0.0, 0.0}, obs), std::invalid_argument);
  BOOST_CHECK_THROW(rt::integrate_adaptive(stepper, sys, x, 0.0, 1.0, 0.0, rt::Tolerances{-1e-6, 1e-6}, obs), std::invalid_argument);
}

namespace {

// A unit vector turning at rate 1 in the plane, ẋ = J x. Its norm is conserved by the flow but
// not by Dopri5, which (not being symplectic) lets it drift by about the local error per step.
struct Turning {
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = -x[1];
    dxdt[1] = x[0];
  }
};
// The same with project(t, x): the state back on the unit circle after every accepted step.
struct TurningOnCircle : Turning {
  std::size_t projections = 0;
  double last_t = -1.0;
  bool times_increase = true;  // each projection at a later time than the one before
  void project(double t, rt::State<double>& x) {
    const double norm = std::hypot(x[0], x[1]);
    x[0] /= norm, x[1] /= norm;
    times_increase = times_increase && t > last_t;
    last_t = t;
    ++projections;
  }
};

}  // namespace

// The drivers call project() once per accepted step, after the observer, and the edited state
// restarts Dopri5's first-same-as-last derivative (one extra call per step). At rtol 1e-5 over
// 100 turns the plain run's norm drifts by ~1e-4 (hundreds of steps, a few 1e-7 each); the
// projected run ends on the circle to the rounding of one division, 2 ulp.
BOOST_AUTO_TEST_CASE(projection_after_every_accepted_step) {
  const rt::Tolerances tol{1e-5, 1e-5};
  const double t1 = 200 * std::numbers::pi;
  Turning plain;
  rt::State<double> x{1.0, 0.0};
  rt::Dopri5<double> a;
  const rt::Stats free_run = rt::integrate_adaptive(a, plain, x, 0.0, t1, 0.0, tol, [](double, const rt::State<double>&) {});
  const double drift = std::abs(std::hypot(x[0], x[1]) - 1);

  TurningOnCircle projected;
  rt::State<double> y{1.0, 0.0};
  rt::Dopri5<double> b;
  const rt::Stats run = rt::integrate_adaptive(b, projected, y, 0.0, t1, 0.0, tol, [](double, const rt::State<double>&) {});
  BOOST_TEST_MESSAGE("norm drift " << drift << " plain, " << std::abs(std::hypot(y[0], y[1]) - 1) << " projected");
  BOOST_TEST(drift > 1e-6);
  BOOST_TEST(std::abs(std::hypot(y[0], y[1]) - 1) <= 2 * std::numeric_limits<double>::epsilon());
  BOOST_TEST(projected.projections == run.accepted);
  // Called with each step's end time: the last one is t1 itself.
  BOOST_TEST(projected.times_increase);
  BOOST_TEST(projected.last_t == t1);
  // Six stages per attempt, the first derivative and the initial-step estimate, and one restart
  // per projected step but the last (nothing follows it).
  BOOST_TEST(run.rhs_evals == 6 * (run.accepted + run.rejected) + 2 + (run.accepted - 1));
  BOOST_TEST(free_run.rhs_evals == 6 * (free_run.accepted + free_run.rejected) + 2);
}
