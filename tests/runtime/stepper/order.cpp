// Accuracy-order tests, templated over every fixed-step method and over double / long double
// (the odeint habit: the global error at a fixed end time must scale as h^p).
#define BOOST_TEST_MODULE runtime_order
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;

namespace {

// q'' = -q, q(0) = 1, q'(0) = 0:  q = cos t, q' = -sin t.
struct Oscillator {
  template <class S>
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
  template <class S>
  static rt::State<S> initial() { return {S(1), S(0)}; }
  template <class S>
  static rt::State<S> exact(S t) {
    using std::cos;
    using std::sin;
    return {cos(t), -sin(t)};
  }
  static constexpr long double t_end = 3.0L;
};

// y' = t y (1 - y), y(0) = 1/2:  y = 1/(1 + exp(-t^2/2)), a logistic equation with a growing rate.
// Nonlinear and non-autonomous, so it exercises the order conditions of every tree and the stage
// times c_i, which the linear oscillator does not. (Problems such as y' = -2ty^2 were tried and
// discarded: Dopri5's small leading error constant makes them reach the asymptotic regime only
// at errors below double-precision round-off.) It contracts (df/dy = t(1-2y) <= 0 for y >= 1/2),
// so round-off is not amplified.
struct Logistic {
  template <class S>
  void operator()(S t, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = t * x[0] * (S(1) - x[0]);
  }
  template <class S>
  static rt::State<S> initial() { return {S(0.5)}; }
  template <class S>
  static rt::State<S> exact(S t) {
    using std::exp;
    return {S(1) / (S(1) + exp(-t * t / S(2)))};
  }
  static constexpr long double t_end = 2.0L;
};

template <class Stepper, class W>
struct Rebind;
template <template <class> class Stepper, class S, class W>
struct Rebind<Stepper<S>, W> {
  using type = Stepper<W>;
};

// Final state after N fixed steps of t_end/N (exact in binary, so every precision takes the same steps).
template <class Stepper, class Problem>
rt::State<typename Stepper::value_type> final_state(std::size_t n_steps) {
  using S = typename Stepper::value_type;
  Stepper stepper;
  Problem sys;
  rt::State<S> x = Problem::template initial<S>();
  const S t_end = S(Problem::t_end);
  const rt::Stats st = rt::integrate_fixed(stepper, sys, x, S(0), t_end, t_end / S(n_steps), [](S, const rt::State<S>&) {});
  BOOST_REQUIRE_EQUAL(st.accepted, n_steps);
  return x;
}

template <class A, class B>
long double max_abs_diff(const rt::State<A>& a, const rt::State<B>& b) {
  long double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(static_cast<long double>(a[i]) - static_cast<long double>(b[i])));
  return m;
}

// Integrates with N = 4, 8, 16, ... steps while the error stays truncation-dominated, then checks
// the observed order p_obs = log2(e(h)/e(h/2)) of the two finest admissible halvings.
//
// Round-off r(N) of a run in precision S: the same run in the widest precision W = long double
// differs from it only by round-off (same steps, same formulas), so r(N) = |x_S - x_W| + r_W(N),
// and r_W(N) <= 2*N*eps_W*max|x|: per step the update x + h*sum(b_i k_i) rounds once (eps/2 |x|)
// and the increment, at most |x| for these steps, carries about one eps relative error; both
// problems are non-expansive, so the contributions add up at most linearly. (For S = long double the
// first term is zero and the bound alone is used.) Only errors e >= 100 r(N) are admissible; then
// round-off moves p_obs by at most log2(1.01/0.99) < 0.03.
// Truncation: e(h) = C h^p (1 + D h + ...) gives p_obs - p ~ D h / (2 ln 2), halving with every
// halving of h; on these problems the finest admissible pairs have |D h| small enough that this is
// below 0.07. Hence the band |p_obs - p| < 0.1.
template <class Stepper, class Problem>
void check_order(const char* problem) {
  using S = typename Stepper::value_type;
  using W = long double;
  using Wide = typename Rebind<Stepper, W>::type;
  const W eps_w = std::numeric_limits<W>::epsilon();
  std::vector<std::size_t> n;
  std::vector<W> e;
  for (std::size_t steps = 4; steps <= (std::size_t(1) << 14); steps *= 2) {
    const rt::State<S> x = final_state<Stepper, Problem>(steps);
    const rt::State<W> xw = final_state<Wide, Problem>(steps);
    const rt::State<W> ref = Problem::template exact<W>(W(Problem::t_end));
    W scale = 0;
    for (const W v : xw) scale = std::max(scale, std::abs(v));
    const W roundoff = max_abs_diff(x, xw) + W(2) * W(steps) * eps_w * std::max(scale, W(1));
    const W err = max_abs_diff(x, ref);
    if (err < W(100) * roundoff) break;
    n.push_back(steps);
    e.push_back(err);
  }
  BOOST_REQUIRE_MESSAGE(n.size() >= 3, problem << ": fewer than three admissible step counts");
  std::vector<double> p_obs;
  for (std::size_t k = 0; k + 1 < e.size(); ++k) p_obs.push_back(static_cast<double>(std::log2(e[k] / e[k + 1])));
  const std::size_t m = p_obs.size();
  BOOST_TEST_MESSAGE(problem << (std::is_same_v<S, double> ? " double" : " long double") << " p=" << Stepper::order << " N=" << n[m - 2] << ".." << n[m] << " e=" << double(e[m - 2])
                             << ".." << double(e[m]) << " p_obs=" << p_obs[m - 2] << ", " << p_obs[m - 1]);
  for (std::size_t k = m - 2; k < m; ++k)
    BOOST_TEST(std::abs(p_obs[k] - Stepper::order) < 0.1,
               problem << ": observed order " << p_obs[k] << " between N=" << n[k] << " and N=" << n[k + 1]
                       << " (errors " << double(e[k]) << ", " << double(e[k + 1]) << "), expected " << Stepper::order);
}

using Steppers = boost::mpl::list<rt::Rk4<double>, rt::Rk4<long double>, rt::Dopri5<double>, rt::Dopri5<long double>>;

}  // namespace

BOOST_AUTO_TEST_CASE_TEMPLATE(order_harmonic_oscillator, Stepper, Steppers) {
  check_order<Stepper, Oscillator>("oscillator");
}

BOOST_AUTO_TEST_CASE_TEMPLATE(order_nonlinear_nonautonomous, Stepper, Steppers) {
  check_order<Stepper, Logistic>("y'=ty(1-y)");
}
