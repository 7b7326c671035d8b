// Gauss-Legendre implicit Runge-Kutta methods (Gl4, Gl6, Gl8): tableau, order, symplecticity
// (bounded energy error, exact quadratic invariants), compensated summation, simplified Newton
// against fixed-point iteration, double and long double.
#define BOOST_TEST_MODULE runtime_gauss
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "eomc/runtime/stepper/gauss_legendre.hpp"
#include "eomc/runtime/integrate.hpp"

namespace rt = eomc::runtime;

namespace {

using W = long double;

// q'' = -q, q(0) = 1, q'(0) = 0: q = cos t, p = -sin t. Energy (q^2 + p^2)/2 is quadratic.
struct Oscillator {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
};

// y' = t y (1 - y), y(0) = 1/2: y = 1/(1 + exp(-t^2/2)). Nonlinear and non-autonomous, so the
// stage times c_i and all order conditions matter (the linear oscillator only sees the stability
// function).
struct Logistic {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = t * x[0] * (S(1) - x[0]);
  }
};

// Kepler problem, x = (q1, q2, p1, p2), H = |p|^2/2 - 1/|q|, L = q1 p2 - q2 p1.
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
  static S energy(const rt::State<S>& x) {
    using std::sqrt;
    return (x[2] * x[2] + x[3] * x[3]) / S(2) - S(1) / sqrt(x[0] * x[0] + x[1] * x[1]);
  }
  template <class S>
  static S angular_momentum(const rt::State<S>& x) {
    return x[0] * x[3] - x[1] * x[2];
  }
  // Pericentre start with eccentricity e: a = 1, period 2 pi, H = -1/2, L = sqrt(1 - e^2).
  template <class S>
  static rt::State<S> initial(S e) {
    using std::sqrt;
    return {S(1) - e, S(0), S(0), sqrt((S(1) + e) / (S(1) - e))};
  }
};

// Pendulum q' = p, p' = -sin q with its Jacobian: exercises the simplified Newton path.
struct PendulumWithJacobian {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    using std::sin;
    dxdt[0] = x[1];
    dxdt[1] = -sin(x[0]);
  }
  template <class S>
  void jacobian(S, const rt::State<S>& x, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) const {
    using std::cos;
    J(0, 1) = S(1);
    J(1, 0) = -cos(x[0]);
  }
};

// y' = -lambda y with its Jacobian; h*lambda = 10 makes fixed-point iteration diverge.
struct StiffDecay {
  double lambda = 10.0;
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = -S(lambda) * x[0];
  }
  template <class S>
  void jacobian(S, const rt::State<S>&, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) const {
    J(0, 0) = -S(lambda);
  }
};

template <class S>
constexpr S eps() {
  return std::numeric_limits<S>::epsilon();
}

template <class St>
const char* name() {
  return std::is_same_v<typename St::value_type, double> ? "double" : "long double";
}

template <class S, int N>
using GL = rt::GaussLegendre<S, N>;

auto no_obs = [](auto, const auto&) {};

}  // namespace

static_assert(rt::FixedStepper<rt::Gl4<double>, Oscillator, double>);
static_assert(rt::FixedStepper<rt::Gl8<long double>, Kepler, long double>);
static_assert(rt::HasJacobian<PendulumWithJacobian, double>);
static_assert(!rt::HasJacobian<Oscillator, double>);
static_assert(rt::Gl4<double>::order == 4 && rt::Gl6<double>::order == 6 && rt::Gl8<double>::order == 8);

// ---------------------------------------------------------------------------------------------
// Tableau: closed forms ([HW] Table IV.5.1; the four-point Gauss nodes x = -+sqrt(3/7 -+ (2/7)
// sqrt(6/5)), Abramowitz-Stegun Table 25.4) and the structural identities. Every coefficient is a
// handful of roundings from exact, so 16 eps (absolute; all coefficients are below 1) is ample
// while still catching a single wrong digit in any place above the last four bits.
// ---------------------------------------------------------------------------------------------

using Scalars = boost::mpl::list<double, long double>;

BOOST_AUTO_TEST_CASE_TEMPLATE(tableau_closed_forms, S, Scalars) {
  using std::abs;
  using std::sqrt;
  const S tol = S(16) * eps<S>();
  {
    const auto& t = rt::Gl4<S>::tableau();
    const S r3 = sqrt(S(3));
    BOOST_TEST(abs(t.c[0] - (S(0.5) - r3 / S(6))) <= tol);
    BOOST_TEST(abs(t.c[1] - (S(0.5) + r3 / S(6))) <= tol);
    BOOST_TEST(abs(t.b[0] - S(0.5)) <= tol);
    BOOST_TEST(abs(t.b[1] - S(0.5)) <= tol);
    BOOST_TEST(abs(t.a[0][0] - S(0.25)) <= tol);
    BOOST_TEST(abs(t.a[0][1] - (S(0.25) - r3 / S(6))) <= tol);
    BOOST_TEST(abs(t.a[1][0] - (S(0.25) + r3 / S(6))) <= tol);
    BOOST_TEST(abs(t.a[1][1] - S(0.25)) <= tol);
  }
  {
    const auto& t = rt::Gl6<S>::tableau();
    const S r15 = sqrt(S(15));
    const S c[3] = {S(0.5) - r15 / S(10), S(0.5), S(0.5) + r15 / S(10)};
    const S b[3] = {S(5) / S(18), S(4) / S(9), S(5) / S(18)};
    const S a[3][3] = {{S(5) / S(36), S(2) / S(9) - r15 / S(15), S(5) / S(36) - r15 / S(30)},
                       {S(5) / S(36) + r15 / S(24), S(2) / S(9), S(5) / S(36) - r15 / S(24)},
                       {S(5) / S(36) + r15 / S(30), S(2) / S(9) + r15 / S(15), S(5) / S(36)}};
    for (int i = 0; i < 3; ++i) {
      BOOST_TEST(abs(t.c[i] - c[i]) <= tol);
      BOOST_TEST(abs(t.b[i] - b[i]) <= tol);
      for (int j = 0; j < 3; ++j) BOOST_TEST(abs(t.a[i][j] - a[i][j]) <= tol, "a" << i << j);
    }
  }
  {
    const auto& t = rt::Gl8<S>::tableau();
    const S s65 = S(2) / S(7) * sqrt(S(6) / S(5));
    const S x[4] = {-sqrt(S(3) / S(7) + s65), -sqrt(S(3) / S(7) - s65), sqrt(S(3) / S(7) - s65),
                    sqrt(S(3) / S(7) + s65)};
    const S r30 = sqrt(S(30));
    const S w[4] = {(S(18) - r30) / S(36), (S(18) + r30) / S(36), (S(18) + r30) / S(36), (S(18) - r30) / S(36)};
    for (int i = 0; i < 4; ++i) {
      BOOST_TEST(abs(t.c[i] - (S(1) + x[i]) / S(2)) <= tol);
      BOOST_TEST(abs(t.b[i] - w[i] / S(2)) <= tol);
    }
  }
}

template <class S, int N>
void check_structure() {
  using std::abs;
  const auto& t = rt::GaussLegendre<S, N>::tableau();
  const S tol = S(16) * eps<S>();
  S bsum = 0;
  for (int i = 0; i < N; ++i) {
    bsum += t.b[i];
    S row = 0;
    for (int j = 0; j < N; ++j) {
      row += t.a[i][j];
      // symplecticity b_i a_ij + b_j a_ji = b_i b_j ([GNI] Theorem VI.4.3)
      BOOST_TEST(abs(t.b[i] * t.a[i][j] + t.b[j] * t.a[j][i] - t.b[i] * t.b[j]) <= tol, "s=" << N << " i=" << i << " j=" << j);
    }
    BOOST_TEST(abs(row - t.c[i]) <= tol);
    BOOST_TEST(abs(t.c[i] + t.c[N - 1 - i] - S(1)) <= tol);  // symmetric nodes
  }
  BOOST_TEST(abs(bsum - S(1)) <= tol);
}

BOOST_AUTO_TEST_CASE_TEMPLATE(tableau_structure, S, Scalars) {
  check_structure<S, 2>();
  check_structure<S, 3>();
  check_structure<S, 4>();
}

// ---------------------------------------------------------------------------------------------
// 1. Order. Global error at fixed T against the exact solution, N = 4, 8, 16, ... steps of T/N
// (T exact in binary). Round-off r(N) is estimated as in tests/runtime/order.cpp: the same run in
// long double differs only by round-off, r(N) = |x_S - x_W| + 2 N eps_W max(|x|, 1) (one rounding
// of the update and one eps of a bounded increment per step; both problems are non-expansive).
// The coarsest step is h = 1 (h |df/dx| <= 1, so the fixed-point iteration contracts).
// Only errors e >= 100 r(N) are admissible (round-off moves p_obs by < 0.03). The observed order
// p_obs = log2(e(h)/e(h/2)) of the two finest admissible halvings must be within 0.3 of 2s: the
// leading correction p_obs - p ~ D h / (2 ln 2) halves with h, and 0.3 leaves room for the coarse
// steps Gl8 needs before it reaches round-off (its errors fall by 256 per halving).
// ---------------------------------------------------------------------------------------------

template <class Problem, class S, int N>
rt::State<S> run_to(S t_end, std::size_t steps, rt::State<S> x) {
  rt::GaussLegendre<S, N> st;
  Problem sys;
  const rt::Stats s = rt::integrate_fixed(st, sys, x, S(0), t_end, t_end / S(steps), no_obs);
  BOOST_REQUIRE_EQUAL(s.accepted, steps);
  return x;
}

template <class S, int N, class Problem, class Init, class Exact>
void check_order(const char* problem, W t_end, std::size_t first, Init init, Exact exact) {
  using std::abs;
  std::vector<std::size_t> n;
  std::vector<W> e;
  for (std::size_t steps = first; steps <= (std::size_t(1) << 12); steps *= 2) {
    const rt::State<S> x = run_to<Problem, S, N>(S(t_end), steps, init.template operator()<S>());
    const rt::State<W> xw = run_to<Problem, W, N>(t_end, steps, init.template operator()<W>());
    const rt::State<W> ref = exact(t_end);
    W scale = 1, dsw = 0, err = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      scale = std::max(scale, abs(xw[i]));
      dsw = std::max(dsw, abs(W(x[i]) - xw[i]));
      err = std::max(err, abs(W(x[i]) - ref[i]));
    }
    const W roundoff = dsw + W(2) * W(steps) * eps<W>() * scale;
    if (err < W(100) * roundoff) break;
    n.push_back(steps);
    e.push_back(err);
  }
  BOOST_REQUIRE_MESSAGE(n.size() >= 3, problem << ": fewer than three admissible step counts");
  const std::size_t m = e.size() - 1;
  for (std::size_t k = m - 1; k <= m; ++k) {
    const double p = double(std::log2(e[k - 1] / e[k]));
    BOOST_TEST_MESSAGE(problem << " s=" << N << " " << (std::is_same_v<S, double> ? "double" : "long double") << " N=" << n[k - 1] << "->" << n[k]
                               << " e=" << double(e[k - 1]) << "->" << double(e[k]) << " p_obs=" << p);
    BOOST_TEST(std::abs(p - 2 * N) < 0.3, problem << " s=" << N << ": observed order " << p << " between N=" << n[k - 1] << " and " << n[k]);
  }
}

struct OscInit {
  template <class S>
  rt::State<S> operator()() const { return {S(1), S(0)}; }
};
struct LogInit {
  template <class S>
  rt::State<S> operator()() const { return {S(0.5)}; }
};
const auto osc_exact = [](W t) { return rt::State<W>{std::cos(t), -std::sin(t)}; };
const auto log_exact = [](W t) { return rt::State<W>{W(1) / (W(1) + std::exp(-t * t / W(2)))}; };

template <class S, int N>
void check_orders() {
  check_order<S, N, Oscillator>("oscillator", W(8), 8, OscInit{}, osc_exact);
  check_order<S, N, Logistic>("y'=ty(1-y)", W(3), 4, LogInit{}, log_exact);
}

BOOST_AUTO_TEST_CASE(order_gl4_gl6_double) {
  check_orders<double, 2>();
  check_orders<double, 3>();
}
BOOST_AUTO_TEST_CASE(order_gl4_gl6_gl8_long_double) {
  check_orders<W, 2>();
  check_orders<W, 3>();
  check_orders<W, 4>();
}

// ---------------------------------------------------------------------------------------------
// 2. Symplecticity: no drift over 1000 orbits.
//
// Quadratic invariants (angular momentum of Kepler; the oscillator's energy) are conserved exactly
// by Gauss methods ([GNI] Theorem IV.2.1), so what remains is round-off. Per step, the stage
// values Y = x + Z carry a rounding of eps|x|, so the stage derivatives err by L_f eps |x| (L_f a
// bound on |df/dx|), the increment h sum b_i K_i by h (L_f |x| + |f|) eps, and the invariant I by
// |grad I| times that; the stored x adds a non-accumulating eps|x| per component (the rest goes
// into the compensation). Round-to-nearest errors are unbiased, so the accumulated part is a
// random walk: |I_n - I_0| <= eps (3 sigma sqrt(n) + 2 |grad I| |x|) with
// sigma = h (L_f X + F) G, X >= |x|, F >= |f|, G >= |grad I| (3 sigma: a random walk stays within
// three standard deviations of its end-point spread over the whole run with probability > 0.99).
//  * Kepler e = 0.5 (a = 1): r >= 1/2, |p| <= sqrt(3), so X = G = 2 (|grad L| = |x|),
//    L_f <= 2/r^3 = 16, F <= sqrt(|p|^2 + 1/r^4) <= 4.4;
//  * oscillator: X = G = F = L_f = 1 (|x|^2 = 2H = 1).
//
// Energy of Kepler is not quadratic: its error is O(h^p), oscillating with the orbit (backward
// error analysis: H is conserved up to h^p times a bounded function of the phase on the modified
// orbit). No secular growth: the maximum over the last 10% of the run must be within 10% of the
// maximum over the first 10%. Steps per orbit N + 0.618 (not an integer), so within a 100-orbit
// window the step grid samples the pericentre passage at many phases and both maxima are within a
// percent of the same envelope; the truncation error is asserted to dwarf the round-off walk
// (>= 100 times its bound, so the walk moves the ratio by at most 2% of the 10% margin).
// ---------------------------------------------------------------------------------------------

template <class S, int N>
void check_kepler(double steps_per_orbit) {
  using std::abs;
  using std::sqrt;
  const S e = S(0.5);
  const S pi = S(3.141592653589793238462643383279502884L);
  const S period = S(2) * pi;
  const S t_end = S(1000) * period;
  const S h = period / S(steps_per_orbit);
  Kepler sys;
  rt::State<S> x = Kepler::initial<S>(e);
  const S H0 = Kepler::energy(x), L0 = Kepler::angular_momentum(x);
  S first = 0, last = 0, dl = 0;
  rt::GaussLegendre<S, N> st;
  const rt::Stats stats = rt::integrate_fixed(st, sys, x, S(0), t_end, h, [&](S t, const rt::State<S>& y) {
    const S dh = abs(Kepler::energy(y) - H0);
    if (t <= t_end / S(10)) first = std::max(first, dh);
    if (t >= t_end * S(0.9)) last = std::max(last, dh);
    dl = std::max(dl, abs(Kepler::angular_momentum(y) - L0));
  });
  const S n = S(stats.accepted);
  const S X = 2, G = 2, Lf = 16, F = S(4.4);
  const S sigma = h * (Lf * X + F) * G;
  const S bound = eps<S>() * (S(3) * sigma * sqrt(n) + S(2) * G * X);
  BOOST_TEST_MESSAGE("kepler s=" << N << " " << (std::is_same_v<S, double> ? "double" : "long double") << " steps=" << stats.accepted
                                 << " evals/step=" << double(stats.rhs_evals) / double(stats.accepted) << " |dH| first10%=" << double(first)
                                 << " last10%=" << double(last) << " ratio=" << double(last / first) << " |dL|max=" << double(dl)
                                 << " (" << double(dl / (eps<S>() * sqrt(n))) << " eps sqrt(n); bound " << double(bound) << ")");
  BOOST_TEST(first >= S(100) * bound);  // round-off then moves the ratio by <= 2%
  BOOST_TEST(last <= S(1.1) * first);
  BOOST_TEST(last >= first / S(1.1));
  BOOST_TEST(dl <= bound);
}

BOOST_AUTO_TEST_CASE(kepler_1000_orbits_double) {
  check_kepler<double, 2>(100.618);
  check_kepler<double, 3>(60.618);
  check_kepler<double, 4>(40.618);
}
BOOST_AUTO_TEST_CASE(kepler_1000_orbits_long_double) {
  check_kepler<W, 2>(100.618);
  check_kepler<W, 4>(30.618);
}

template <class S, int N>
void check_oscillator_energy(bool compensated, std::size_t steps, S h, S& rms, S& maxdev) {
  using std::abs;
  using std::sqrt;
  Oscillator sys;
  rt::GaussLegendreOptions opt;
  opt.compensated = compensated;
  rt::GaussLegendre<S, N> st(opt);
  rt::State<S> x{S(1), S(0)};
  const S H0 = S(0.5);
  S sum2 = 0;
  maxdev = 0;
  rt::integrate_fixed(st, sys, x, S(0), S(steps) * h, h, [&](S, const rt::State<S>& y) {
    const S d = (y[0] * y[0] + y[1] * y[1]) / S(2) - H0;
    sum2 += d * d;
    maxdev = std::max(maxdev, abs(d));
  });
  rms = sqrt(sum2 / S(steps + 1));
}

// Oscillator over 1000 periods: energy (quadratic) conserved to the round-off bound above.
BOOST_AUTO_TEST_CASE_TEMPLATE(oscillator_energy_roundoff, S, Scalars) {
  using std::sqrt;
  const S pi = S(3.141592653589793238462643383279502884L);
  const std::size_t steps = 1000 * 50;
  const S h = S(2) * pi / S(50);
  S rms, maxdev;
  check_oscillator_energy<S, 2>(true, steps, h, rms, maxdev);
  const S bound = eps<S>() * (S(3) * h * S(2) * sqrt(S(steps)) + S(2));
  BOOST_TEST_MESSAGE("oscillator Gl4 " << (std::is_same_v<S, double> ? "double" : "long double") << " max|dH|=" << double(maxdev)
                                       << " bound " << double(bound));
  BOOST_TEST(maxdev <= bound);
  check_oscillator_energy<S, 4>(true, steps, h, rms, maxdev);
  BOOST_TEST_MESSAGE("oscillator Gl8 max|dH|=" << double(maxdev));
  BOOST_TEST(maxdev <= bound);
}

// ---------------------------------------------------------------------------------------------
// 3. Compensated vs plain summation, oscillator (its energy is conserved exactly by the method, so
// its error is pure round-off), 10^6 steps of h = 2 pi / 628.318... (~0.01). Plain summation
// rounds x_{n+1} = x_n + inc once per step: a random walk with per-step energy error of standard
// deviation about eps |x|^2 / sqrt(6) ~ 0.4 eps (two components, uniform rounding error of +-ulp/2).
// Compensated summation carries that rounding forward, leaving the stage round-off of the
// derivation above, sigma <= h (L_f X + F) G eps = 2 h eps ~ 0.02 eps. Predicted RMS ratio
// ~ 0.4 / 0.02 = 20 (Brouwer's law with a constant smaller by ~h); measured 67 (double) and 129
// (long double). We assert 10: half the prediction, for the spread of a random walk's RMS between
// two realisations.
// ---------------------------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE_TEMPLATE(compensated_summation_beats_plain, S, Scalars) {
  const S pi = S(3.141592653589793238462643383279502884L);
  const std::size_t steps = 1000000;
  const S h = S(2) * pi / S(628.318);
  S rms_c, max_c, rms_p, max_p;
  check_oscillator_energy<S, 2>(true, steps, h, rms_c, max_c);
  check_oscillator_energy<S, 2>(false, steps, h, rms_p, max_p);
  BOOST_TEST_MESSAGE("oscillator 1e6 steps " << (std::is_same_v<S, double> ? "double" : "long double") << ": plain rms=" << double(rms_p)
                                             << " max=" << double(max_p) << "  compensated rms=" << double(rms_c) << " max=" << double(max_c)
                                             << "  rms ratio=" << double(rms_p / rms_c));
  BOOST_TEST(rms_p >= S(10) * rms_c);
  BOOST_TEST(max_p >= S(10) * max_c);
}

// ---------------------------------------------------------------------------------------------
// 4. Simplified Newton (system with jacobian) and fixed-point iteration solve the same stage
// equations, each to round-off, so they differ per step by a few ulps of the stage values: the
// stage noise of the derivation above, at most 2 h (L_f X + F) eps per step with c = 2 for two
// independent solves, here X = |(q, p)| <= 1.1 (q(0) = 1, p(0) = 0, energy 1 - cos 1), L_f = F = 1.1.
// The pendulum's linearised flow grows a perturbation at most like 1 + t |omega'(E)| |grad E|
// <= 1 + T (libration below amplitude 1 changes the period by < 7%), so summing worst-case
// (not random-walk) over n steps: |x_N - y_N| <= 2 n h (L_f X + F) eps (1 + T), T = 10.
// ---------------------------------------------------------------------------------------------

template <class S, int N>
void check_newton_vs_fixed_point() {
  using std::abs;
  PendulumWithJacobian sys;
  const S T = 10, h = S(1) / S(8);
  const std::size_t n = 80;
  rt::GaussLegendreOptions fp, nw;
  fp.solver = rt::GaussLegendreOptions::Solver::fixed_point;
  nw.solver = rt::GaussLegendreOptions::Solver::newton;
  rt::GaussLegendre<S, N> a(fp), b(nw);
  rt::State<S> x{S(1), S(0)}, y{S(1), S(0)};
  rt::integrate_fixed(a, sys, x, S(0), T, h, no_obs);
  rt::integrate_fixed(b, sys, y, S(0), T, h, no_obs);
  const S d = std::max(abs(x[0] - y[0]), abs(x[1] - y[1]));
  const S bound = S(2) * S(n) * h * (S(1.1) * S(1.1) + S(1.1)) * eps<S>() * (S(1) + T);
  BOOST_TEST_MESSAGE("newton vs fixed point s=" << N << " " << (std::is_same_v<S, double> ? "double" : "long double") << ": |diff|=" << double(d)
                                                << " (" << double(d / eps<S>()) << " eps, bound " << double(bound / eps<S>()) << " eps)"
                                                << " iterations/step fp=" << double(a.iterations()) / n << " newton=" << double(b.iterations()) / n);
  BOOST_TEST(d <= bound);
  BOOST_TEST(b.jacobian_evals() == n);
  BOOST_TEST(a.jacobian_evals() == 0u);
  BOOST_TEST(b.iterations() < a.iterations());
}

BOOST_AUTO_TEST_CASE_TEMPLATE(newton_matches_fixed_point, S, Scalars) {
  check_newton_vs_fixed_point<S, 2>();
  check_newton_vs_fixed_point<S, 3>();
  check_newton_vs_fixed_point<S, 4>();
}

// Fixed-point iteration cannot converge for h |df/dx| = 10 (its iteration matrix has spectral radius
// h lambda rho(A) > 1); it must throw, not return garbage. Simplified Newton with the exact Jacobian
// of a linear system converges at once and reproduces the stability function of Gl4,
// R(z) = (1 + z/2 + z^2/12) / (1 - z/2 + z^2/12), to a few ulps.
BOOST_AUTO_TEST_CASE_TEMPLATE(divergent_fixed_point_throws_newton_converges, S, Scalars) {
  using std::abs;
  StiffDecay sys;
  rt::GaussLegendreOptions fp;
  fp.solver = rt::GaussLegendreOptions::Solver::fixed_point;
  rt::Gl4<S> a(fp);
  rt::State<S> x{S(1)};
  BOOST_CHECK_THROW(a.do_step(sys, x, S(0), S(1)), rt::StageIterationError);
  BOOST_CHECK_THROW(a.do_step(sys, x, S(0), S(1)), rt::IntegrationError);
  rt::Gl4<S> b;  // automatic: Newton, since StiffDecay has a Jacobian
  rt::State<S> y{S(1)};
  b.do_step(sys, y, S(0), S(1));
  const S z = -10;
  const S r = (S(1) + z / S(2) + z * z / S(12)) / (S(1) - z / S(2) + z * z / S(12));
  BOOST_TEST(abs(y[0] - r) <= S(16) * eps<S>());
  BOOST_TEST(b.jacobian_evals() == 1u);
  // Newton on a system without a Jacobian is a usage error.
  rt::GaussLegendreOptions nw;
  nw.solver = rt::GaussLegendreOptions::Solver::newton;
  rt::Gl4<S> c(nw);
  Oscillator osc;
  rt::State<S> u{S(1), S(0)};
  BOOST_CHECK_THROW(c.do_step(osc, u, S(0), S(0.1)), std::invalid_argument);
}
