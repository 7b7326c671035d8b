// Radau IIA of order 5 (Radau5): its coefficients against their defining identities, a stiff
// linear problem against its closed form, the classical order 5 on a smooth problem, Van der Pol
// at mu = 1000 against the asymptotic period, the dense output and an event on it, and the
// failures (non-finite derivative, a Newton iteration that cannot converge) as IntegrationError.
#define BOOST_TEST_MODULE runtime_radau5
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "eomc/runtime/events.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/stepper/radau5.hpp"

namespace rt = eomc::runtime;

namespace {

// y' = -lambda (y - cos t) - sin t, y(0) = 0: y = cos t - exp(-lambda t) (a fast transient onto the
// slow solution cos t; Curtiss and Hirschfelder's example of stiffness, [HW] Sect. IV.1).
struct Prothero {
  double lambda = 1000.0;
  void operator()(double t, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = -lambda * (x[0] - std::cos(t)) - std::sin(t);
  }
  void jacobian(double, const rt::State<double>&, Eigen::MatrixXd& J) const { J(0, 0) = -lambda; }
  static double exact(double t, double lambda) { return std::cos(t) - std::exp(-lambda * t); }
};

// x' = A x with A = P diag(-1, -1e6) P^{-1}, P = [[1, 1], [1, -1]]: eigenvalues -1 and -1e6.
// A = [[a, b], [b, a]] with a = (-1 - 1e6)/2, b = (-1 + 1e6)/2; x(t) = P diag(e^{-t}, e^{-1e6 t}) P^{-1} x0.
template <bool WithJacobian>
struct Linear2 {
  static constexpr double a = (-1.0 - 1e6) / 2, b = (-1.0 + 1e6) / 2;
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = a * x[0] + b * x[1];
    dxdt[1] = b * x[0] + a * x[1];
  }
  static rt::State<double> exact(double t, const rt::State<double>& x0) {
    const double s = (x0[0] + x0[1]) / 2 * std::exp(-t), d = (x0[0] - x0[1]) / 2 * std::exp(-1e6 * t);
    return {s + d, s - d};
  }
};
template <>
struct Linear2<true> : Linear2<false> {
  void jacobian(double, const rt::State<double>&, Eigen::MatrixXd& J) const { J << a, b, b, a; }
};

// y' = t y (1 - y), y(0) = 1/2: y = 1/(1 + exp(-t^2/2)); smooth, nonlinear, non-autonomous.
struct Logistic {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = t * x[0] * (S(1) - x[0]);
  }
  template <class S>
  void jacobian(S t, const rt::State<S>& x, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) const {
    J(0, 0) = t * (S(1) - S(2) * x[0]);
  }
};

// Van der Pol, x'' - mu (1 - x^2) x' + x = 0 in the state (x, x').
struct VanDerPol {
  double mu = 1000.0;
  void operator()(double, const rt::State<double>& x, rt::State<double>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = mu * (1.0 - x[0] * x[0]) * x[1] - x[0];
  }
  void jacobian(double, const rt::State<double>& x, Eigen::MatrixXd& J) const {
    J << 0.0, 1.0, -2.0 * mu * x[0] * x[1] - 1.0, mu * (1.0 - x[0] * x[0]);
  }
};

auto no_observer = [](double, const rt::State<double>&) {};

// The tolerance Radau5 controls its order-3 error estimate with (radau5.f's map, see radau5.hpp):
// rtol' = 0.1 rtol^{2/3}. Global errors are bounded by a small multiple of it.
double controlled_tolerance(double tol) { return 0.1 * std::pow(tol, 2.0 / 3.0); }

}  // namespace

using Scalars = boost::mpl::list<double, long double>;

// The tableau in closed form is Radau IIA's: c = row sums of A, the last row is b (stiffly
// accurate), the quadrature conditions sum b c^{k-1} = 1/k for k <= 5, and T, T^{-1} transform
// A^{-1} to [[gamma, 0, 0], [0, alpha, -beta], [0, beta, alpha]] (radau5.f's T has 20 digits: the
// identities hold to a few ulps of long double, to 1e-18 relative at worst).
BOOST_AUTO_TEST_CASE_TEMPLATE(tableau_identities, S, Scalars) {
  using std::abs;
  using std::pow;
  const auto& tab = rt::Radau5<S>::tableau();
  const S eps = std::numeric_limits<S>::epsilon();
  const S c[3] = {tab.c1, tab.c2, S(1)};
  for (int i = 0; i < 3; ++i) BOOST_TEST(abs(tab.a[i][0] + tab.a[i][1] + tab.a[i][2] - c[i]) <= S(8) * eps);
  for (int k = 1; k <= 5; ++k) {
    S q = S(0);
    for (int j = 0; j < 3; ++j) q += tab.a[2][j] * pow(c[j], S(k - 1));
    BOOST_TEST(abs(q - S(1) / S(k)) <= S(16) * eps);
  }
  Eigen::Matrix<S, 3, 3> A, T, TI, Lambda;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      A(i, j) = tab.a[i][j];
      T(i, j) = tab.T[i][j];
      TI(i, j) = tab.TI[i][j];
    }
  Lambda << tab.gamma, 0, 0, 0, tab.alpha, -tab.beta, 0, tab.beta, tab.alpha;
  const S digits20 = std::max(S(1e-19), S(64) * eps);
  BOOST_TEST((TI * T - Eigen::Matrix<S, 3, 3>::Identity()).cwiseAbs().maxCoeff() <= S(10) * digits20);
  BOOST_TEST((TI * A.inverse() * T - Lambda).cwiseAbs().maxCoeff() <= S(100) * digits20);
}

// The stiff transient: lambda = 1e3 and 1e6, y(t) = cos t - exp(-lambda t) on [0, 10]. The problem
// contracts (lambda > 0), so the global error stays at the local level: at most 10 times the
// controlled tolerance at every step end; and the step count does not grow with lambda, where an
// explicit method would need |h lambda| <= 3.3: 3e3 and 3e6 steps.
BOOST_AUTO_TEST_CASE(stiff_transient_follows_its_closed_form) {
  for (const double lambda : {1e3, 1e6})
    for (const double tol : {1e-6, 1e-9}) {
      Prothero sys{lambda};
      rt::Radau5<double> st;
      rt::State<double> x{0.0};
      double worst = 0;
      const rt::Stats stats = rt::integrate_adaptive(st, sys, x, 0.0, 10.0, 0.0, rt::Tolerances{tol, tol},
                                                     [&](double t, const rt::State<double>& xs) {
                                                       worst = std::max(worst, std::abs(xs[0] - Prothero::exact(t, lambda)));
                                                     });
      BOOST_TEST_MESSAGE("lambda " << lambda << " tol " << tol << ": " << stats.accepted << " steps, "
                                   << stats.rejected << " rejected, worst error " << worst);
      BOOST_TEST(worst <= 10 * controlled_tolerance(tol));
      BOOST_TEST(stats.accepted <= 400u);
      BOOST_TEST((st.jacobian_source() == rt::Radau5<double>::JacobianSource::symbolic));
    }
}

// The 2 x 2 system with eigenvalues -1 and -1e6, with the symbolic Jacobian and with forward
// differences: both reach the closed form to the tolerance; differences cost 2 calls per Jacobian.
BOOST_AUTO_TEST_CASE(stiff_linear_system_symbolic_and_finite_difference_jacobian) {
  const rt::State<double> x0{1.0, 0.0};
  const double tol = 1e-8;
  auto run = [&](auto sys, auto expected_source) {
    rt::Radau5<double> st;
    rt::State<double> x = x0;
    const rt::Stats stats = rt::integrate_adaptive(st, sys, x, 0.0, 5.0, 0.0, rt::Tolerances{tol, tol}, no_observer);
    const rt::State<double> ref = Linear2<false>::exact(5.0, x0);
    const double err = std::max(std::abs(x[0] - ref[0]), std::abs(x[1] - ref[1]));
    BOOST_TEST_MESSAGE("error " << err << ", " << stats.accepted << " steps, " << st.jacobian_evals() << " Jacobians, "
                                << st.lu_decompositions() << " LU, " << stats.rhs_evals << " calls");
    BOOST_TEST(err <= 10 * controlled_tolerance(tol));
    BOOST_TEST(stats.accepted <= 200u);
    BOOST_TEST((st.jacobian_source() == expected_source));
    return st.jacobian_evals();
  };
  run(Linear2<true>{}, rt::Radau5<double>::JacobianSource::symbolic);
  run(Linear2<false>{}, rt::Radau5<double>::JacobianSource::finite_difference);
}

// Fixed steps on the logistic problem: the error at t = 1 falls as h^5 (Radau IIA, s = 3: classical
// order 2s - 1 = 5, [HW] Sect. IV.5). Log-log slope over h = 1/4 .. 1/32 within 5 +- 0.3.
BOOST_AUTO_TEST_CASE_TEMPLATE(fixed_step_order_is_five, S, Scalars) {
  using std::exp;
  using std::log;
  const S exact = S(1) / (S(1) + exp(S(-0.5)));
  std::vector<S> errors;
  for (int N : {4, 8, 16, 32}) {
    Logistic sys;
    rt::Radau5<S> st;
    rt::State<S> x{S(0.5)};
    rt::integrate_fixed(st, sys, x, S(0), S(1), S(1) / S(N), [](S, const rt::State<S>&) {});
    errors.push_back(std::abs(x[0] - exact));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const S slope = log(errors[i - 1] / errors[i]) / log(S(2));
    BOOST_TEST_MESSAGE("error " << static_cast<double>(errors[i]) << " slope " << static_cast<double>(slope));
    BOOST_TEST(std::abs(static_cast<double>(slope) - 5.0) <= 0.3);
  }
}

// Van der Pol at mu = 1000 from (2, 0) over [0, 3000]: the period between two downward zero
// crossings of x (located on the dense output) against the asymptotic period
// T = (3 - 2 ln 2) mu + 3 a mu^{-1/3} + O(mu^{-1} ln mu), a = 2.338107 the first zero of -Ai
// (Dorodnitsyn 1947; J. Grasman, Asymptotic Methods for Relaxation Oscillations and
// Applications, Springer 1987). The neglected -(2/3) mu^{-1} ln mu and O(1/mu) terms are about
// 0.01 at mu = 1000. The runs at rtol = atol = 1e-6 and 1e-8 agree with one at 1e-10 to the
// looser one's accuracy: a relative error rtol' per unit time accumulates to rtol' T over a period.
BOOST_AUTO_TEST_CASE(van_der_pol_mu_1000_period) {
  const double mu = 1000.0;
  const double airy = 2.338107410459767;
  const double asymptotic = (3.0 - 2.0 * std::log(2.0)) * mu + 3.0 * airy * std::cbrt(1.0 / mu);
  std::vector<double> periods;
  for (const double tol : {1e-6, 1e-8, 1e-10}) {
    VanDerPol sys{mu};
    rt::Radau5<double> st;
    rt::State<double> x{2.0, 0.0};
    rt::EventLocator<double> locator({{rt::EventDirection::down}});
    auto g = [](double, const rt::State<double>& xs, rt::State<double>& out) { out[0] = xs[0]; };
    std::vector<double> crossings;
    const auto out = rt::integrate_adaptive_events(st, sys, x, 0.0, 3000.0, 0.0, rt::Tolerances{tol, tol}, locator, g,
                                                   no_observer,
                                                   [&](const rt::EventHit<double>& hit) { crossings.push_back(hit.t); });
    BOOST_TEST_REQUIRE(crossings.size() == 2u);
    periods.push_back(crossings[1] - crossings[0]);
    BOOST_TEST_MESSAGE("tol " << tol << ": T = " << periods.back() << " (asymptotic " << asymptotic << "), "
                              << out.stats.accepted << " steps, " << out.stats.rejected << " rejected, "
                              << out.stats.rhs_evals << " calls, " << st.jacobian_evals() << " Jacobians, "
                              << st.lu_decompositions() << " LU");
  }
  BOOST_TEST(std::abs(periods[2] - asymptotic) <= 0.02);
  BOOST_TEST_MESSAGE(std::setprecision(12) << "periods " << periods[0] << " " << periods[1] << " " << periods[2]);
  BOOST_TEST(std::abs(periods[0] - periods[2]) <= controlled_tolerance(1e-6) * asymptotic);
  BOOST_TEST(std::abs(periods[1] - periods[2]) <= controlled_tolerance(1e-8) * asymptotic);
}

// Dense output: the collocation polynomial's error is O(h^4) uniformly over a step (stage order 3,
// [HW] Sect. IV.5). Fixed steps h = 1/4 .. 1/32 on the logistic problem, the worst error at 7
// interior points of every step falls as h^4: slope 4 +- 0.5 (at the step ends it is the order-5
// solution's).
BOOST_AUTO_TEST_CASE(dense_output_order_four) {
  auto exact = [](double t) { return 1.0 / (1.0 + std::exp(-t * t / 2)); };
  std::vector<double> errors;
  for (int N : {4, 8, 16, 32}) {
    Logistic sys;
    rt::Radau5<double> st;
    rt::State<double> x{0.5}, u;
    double worst = 0;
    for (int k = 0; k < N; ++k) {
      const double t = double(k) / N, h = 1.0 / N;
      st.do_step(sys, x, t, h);
      for (int j = 1; j < 8; ++j) {
        st.calc_state(t + h * j / 8, u);
        worst = std::max(worst, std::abs(u[0] - exact(t + h * j / 8)));
      }
    }
    errors.push_back(worst);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double slope = std::log2(errors[i - 1] / errors[i]);
    BOOST_TEST_MESSAGE("dense output error " << errors[i] << " slope " << slope);
    BOOST_TEST(std::abs(slope - 4.0) <= 0.5);
  }
}

// The zero of y = cos t - e^{-1000 t} (pi/2, to far below round-off) located on the dense output:
// |dy/dt| = 1 there, so the event time is off by the dense output's own error at pi/2 (to first
// order; Brent's root solve adds a few ulps), and that error is the collocation polynomial's,
// below 10 rtol' at this tolerance.
BOOST_AUTO_TEST_CASE(event_located_on_the_dense_output) {
  const double tol = 1e-9;
  Prothero sys{1000.0};
  rt::Radau5<double> st;
  rt::State<double> y{0.0};
  rt::EventLocator<double> locator({{rt::EventDirection::down, true}});
  auto g = [](double, const rt::State<double>& xs, rt::State<double>& out) { out[0] = xs[0]; };
  const auto out = rt::integrate_adaptive_events(st, sys, y, 0.0, 3.0, 0.0, rt::Tolerances{tol, tol}, locator, g,
                                                 no_observer, [](const rt::EventHit<double>&) {});
  BOOST_TEST_REQUIRE(out.stopped);
  rt::State<double> u;
  st.calc_state(std::numbers::pi / 2, u);  // the step holding the event
  const double event_error = out.t - std::numbers::pi / 2, dense_error = u[0];
  BOOST_TEST_MESSAGE("event error " << event_error << ", dense output at pi/2 " << dense_error);
  // y(t_e) = 0 on the dense output and y'(pi/2) = -1: t_e - pi/2 = u(pi/2) + O(u^2).
  BOOST_TEST(std::abs(event_error - dense_error) <= 1e-3 * std::abs(dense_error) + 1e-14);
  BOOST_TEST(std::abs(event_error) <= 10 * controlled_tolerance(tol));
}

// A derivative that turns NaN past t = 1: the steps collapse onto t = 1 and the driver reports the
// non-finite derivative with its component. y' = y^2, y(0) = 1 blows up at t = 1: the steps
// collapse at the pole (an implicit step may land just past it) and the run ends in IntegrationError.
BOOST_AUTO_TEST_CASE(failures_are_integration_errors) {
  auto nan_past_one = [](double t, const rt::State<double>& x, rt::State<double>& dxdt) {
    dxdt[0] = -x[0];
    dxdt[1] = t > 1.0 ? std::numeric_limits<double>::quiet_NaN() : -x[1];
  };
  {
    rt::Radau5<double> st;
    rt::State<double> x{1.0, 1.0};
    try {
      rt::integrate_adaptive(st, nan_past_one, x, 0.0, 2.0, 0.0, rt::Tolerances{1e-8, 1e-8}, no_observer);
      BOOST_FAIL("no IntegrationError");
    } catch (const rt::IntegrationError& e) {
      BOOST_TEST_MESSAGE(e.what());
      BOOST_TEST((e.kind() == rt::IntegrationError::Kind::non_finite));
      BOOST_TEST(e.component() == 1u);
      BOOST_TEST(std::abs(e.t() - 1.0) <= 1e-9);
    }
  }
  {
    auto blow_up = [](double, const rt::State<double>& x, rt::State<double>& dxdt) { dxdt[0] = x[0] * x[0]; };
    rt::Radau5<double> st;
    rt::State<double> x{1.0};
    try {
      rt::integrate_adaptive(st, blow_up, x, 0.0, 2.0, 0.0, rt::Tolerances{1e-8, 1e-8}, no_observer);
      BOOST_FAIL("no IntegrationError");
    } catch (const rt::IntegrationError& e) {
      BOOST_TEST_MESSAGE(e.what());
      BOOST_TEST((e.kind() == rt::IntegrationError::Kind::step_underflow));
      BOOST_TEST(std::abs(e.t() - 1.0) <= 1e-6);
    }
  }
  {
    rt::Radau5<double> st;
    rt::State<double> x{1.0, 1.0};
    BOOST_CHECK_THROW(st.do_step(nan_past_one, x, 1.0, 0.5), rt::IntegrationError);
  }
}
