// The float128 scalar: arithmetic, limits and every function against 40-digit values (from
// GiNaC's ginsh, Digits = 40), and every runtime stepper run in float128 to errors a double run
// cannot reach (double's epsilon is 2.2e-16), with its convergence order intact down there.
#define BOOST_TEST_MODULE runtime_float128
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "eomc/runtime/float128.hpp"
#include "eomc/runtime/runtime.hpp"

namespace rt = eomc::runtime;
using rt::float128;
using S = float128;

namespace {

const S eps = std::numeric_limits<S>::epsilon();

S parse(const std::string& digits) {
  bool ok = false;
  const S v = rt::float128_from_string(digits, &ok);
  BOOST_REQUIRE_MESSAGE(ok, "cannot parse " << digits);
  return v;
}

// |a - b| <= k eps |b|: a correctly rounded libquadmath function is within an ulp or two.
bool close(S a, S b, double k) { return abs(a - b) <= S(k) * eps * abs(b); }

}  // namespace

BOOST_AUTO_TEST_CASE(limits_and_arithmetic) {
  using L = std::numeric_limits<S>;
  static_assert(L::is_specialized && L::digits == 113 && L::radix == 2);
  // Constant expressions: coefficients are computed in float128 at compile time.
  static_assert(S(1) + S(2) == S(3));
  static_assert(S(1) / S(4) == S(0.25));
  static_assert(isinf(L::infinity()) && isnan(L::quiet_NaN()) && isfinite(L::max()));
  BOOST_TEST((S(1) + eps != S(1)));
  BOOST_TEST((S(1) + eps / S(2) == S(1)));  // ties to even
  BOOST_TEST(static_cast<double>(eps) == std::ldexp(1.0, -112));
  BOOST_TEST(static_cast<double>(L::min()) == 0.0);  // 2^-16382 underflows double
  BOOST_TEST((L::max() * S(2) == L::infinity()));
  BOOST_TEST((L::denorm_min() / S(2) == S(0)));
  BOOST_TEST((L::denorm_min() > S(0)));
  BOOST_TEST((L::lowest() == -L::max()));
  // Mixed with double and int through the implicit conversion; explicit conversion back.
  const S x = S(3) * 0.5 + 1;
  BOOST_TEST(static_cast<double>(x) == 2.5);
  BOOST_TEST((2 < x && x <= 2.5 && x != 3.0 && -x < 0));
  S y = x;
  y += 1;
  y *= 2;
  y -= 0.5;
  y /= 2;
  BOOST_TEST(static_cast<double>(y) == 3.25);
  // One third is not a double: its float128 rounding differs from the double's by ~1e-17.
  const S third = S(1) / S(3);
  BOOST_TEST(abs(third - S(1.0 / 3.0)) > S(1e-18));
  BOOST_TEST(close(third * S(3), S(1), 1));
  std::ostringstream out;
  out.precision(36);
  out << third;
  BOOST_TEST(out.str() == "0.333333333333333333333333333333333317");
  BOOST_TEST((parse(out.str()) == third));
}

BOOST_AUTO_TEST_CASE(functions_against_40_digit_values) {
  struct Case {
    const char* name;
    std::function<S()> value;
    const char* digits;
  };
  using std::acos;
  using std::asin;
  using std::asinh;
  using std::atan;
  using std::atan2;
  using std::cos;
  using std::cosh;
  using std::exp;
  using std::log;
  using std::pow;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  using std::tan;
  using std::tanh;
  const Case cases[] = {
      {"sqrt(2)", [] { return sqrt(S(2)); }, "1.414213562373095048801688724209698078570"},
      {"4 atan(1)", [] { return S(4) * atan(S(1)); }, "3.141592653589793238462643383279502884197"},
      {"exp(1)", [] { return exp(S(1)); }, "2.718281828459045235360287471352662497757"},
      {"log(10)", [] { return log(S(10)); }, "2.302585092994045684017991454684364207601"},
      {"log(2)", [] { return log(S(2)); }, "0.6931471805599453094172321214581765680755"},
      {"cos(1)", [] { return cos(S(1)); }, "0.5403023058681397174009366074429766037323"},
      {"sin(1)", [] { return sin(S(1)); }, "0.8414709848078965066525023216302989996226"},
      {"tan(1)", [] { return tan(S(1)); }, "1.557407724654902230506974807458360173087"},
      {"tanh(1)", [] { return tanh(S(1)); }, "0.7615941559557648881194582826047935904128"},
      {"cosh(1)", [] { return cosh(S(1)); }, "1.543080634815243778477905620757061682602"},
      {"sinh(1/2)", [] { return sinh(S(1) / S(2)); }, "0.5210953054937473616224256264114915591059"},
      {"atan(1/3)", [] { return atan(S(1) / S(3)); }, "0.3217505543966421934014046143586613190208"},
      {"atan2(1, 3)", [] { return atan2(S(1), S(3)); }, "0.3217505543966421934014046143586613190208"},
      {"asin(1/3)", [] { return asin(S(1) / S(3)); }, "0.3398369094541219370963925133917640663882"},
      {"acos(1/3)", [] { return acos(S(1) / S(3)); }, "1.230959417340774682134929178247987375710"},
      {"asinh(1)", [] { return asinh(S(1)); }, "0.8813735870195430252326093249797923090282"},
      {"pow(2, 1/2)", [] { return pow(S(2), S(0.5)); }, "1.414213562373095048801688724209698078570"},
  };
  for (const Case& c : cases) {
    const S v = c.value(), ref = parse(c.digits);
    // The operand 1/3 carries its own rounding (relative eps/2), amplified by the function's
    // condition number (at most ~1.1 here), hence 4 eps rather than 2.
    BOOST_TEST(close(v, ref, 4), c.name << " = " << rt::to_string(v) << ", expected " << c.digits);
    // The same call for long double agrees to long double precision: the ADL overloads are found.
    BOOST_TEST(std::abs(static_cast<long double>(v) - static_cast<long double>(ref)) <=
                   4 * std::numeric_limits<long double>::epsilon() * std::abs(static_cast<long double>(ref)),
               c.name);
  }
}

// ---------------------------------------------------------------------------------------------
// Steppers. The harmonic oscillator x'' = -x from (1, 0) over [0, 1]: exact (cos t, -sin t).
// ---------------------------------------------------------------------------------------------
namespace {

struct Oscillator {
  void operator()(S, const rt::State<S>& x, rt::State<S>& dxdt) const {
    dxdt[0] = x[1];
    dxdt[1] = -x[0];
  }
};

struct Acceleration {  // the splitting methods' system: q'' = -q
  void operator()(S, const rt::State<S>& q, rt::State<S>& a) const { a[0] = -q[0]; }
};

S error_at(const rt::State<S>& x, S t) {
  using std::cos;
  using std::sin;
  const S e0 = abs(x[0] - cos(t)), e1 = abs(x[1] + sin(t));
  return e0 > e1 ? e0 : e1;
}

template <class Stepper, class Sys>
S fixed_error(int steps) {
  Stepper stepper;
  Sys sys;
  rt::State<S> x{S(1), S(0)};
  const rt::Stats st = rt::integrate_fixed(stepper, sys, x, S(0), S(1), S(1) / S(steps), [](S, const rt::State<S>&) {});
  BOOST_REQUIRE_EQUAL(st.accepted, static_cast<std::size_t>(steps));
  return error_at(x, S(1));
}

// Errors at n and 2n steps: the observed order log2(e_n / e_2n) is the method's within 0.25 (the
// next term of the error expansion moves it by O(h), h <= 1/128 here), and e_2n is below `below`,
// a level double arithmetic cannot reach (its rounding alone is ~1e-16 per step).
template <class Stepper, class Sys>
void check_order(const char* name, int order, int n, double below) {
  const S e1 = fixed_error<Stepper, Sys>(n), e2 = fixed_error<Stepper, Sys>(2 * n);
  using std::log2;
  const double p = static_cast<double>(log2(e1 / e2));
  BOOST_TEST_MESSAGE(name << ": error " << rt::to_string(e1, 4) << " at " << n << " steps, " << rt::to_string(e2, 4)
                          << " at " << 2 * n << ", observed order " << p);
  BOOST_TEST(std::abs(p - order) <= 0.25, name << ": observed order " << p << ", expected " << order);
  BOOST_TEST((e2 < S(below)), name << ": error " << rt::to_string(e2, 4) << " not below " << below);
}

}  // namespace

BOOST_AUTO_TEST_CASE(fixed_step_methods_converge_beyond_double) {
  check_order<rt::Rk4<S>, Oscillator>("rk4", 4, 16384, 1e-20);
  check_order<rt::Gl4<S>, Oscillator>("gl4", 4, 8192, 1e-19);
  check_order<rt::Gl6<S>, Oscillator>("gl6", 6, 512, 1e-22);
  check_order<rt::Gl8<S>, Oscillator>("gl8", 8, 128, 1e-25);
  check_order<rt::Dopri5<S>, Oscillator>("dopri5 (fixed step)", 5, 2048, 1e-20);
  // With the coefficients rounded to long double (1e-19 relative) this would stall near 1e-20:
  // 30-digit coefficients are read in float128 (coefficients.hpp).
  check_order<rt::Dop853<S>, Oscillator>("dop853 (fixed step)", 8, 128, 1e-25);
  // Verlet is second order: 1e-8 at 2048 steps; the order is the check here.
  check_order<rt::Verlet<S>, Acceleration>("verlet", 2, 1024, 1e-7);
  check_order<rt::Yoshida6<S>, Acceleration>("yoshida6", 6, 1024, 1e-21);
  check_order<rt::KahanLi8<S>, Acceleration>("kahanli8", 8, 128, 1e-23);
}

// Composition coefficients in float128: the Kahan-Li weights are given to 26 decimals, so the 15
// of them sum to 1 within 15 * 0.5e-26; Yoshida's w0 = 1 - 2 (w1 + w2 + w3) holds to the 36th
// decimal of its digits (0.5e-35 each, times 1 + 2 * 3).
BOOST_AUTO_TEST_CASE(composition_coefficients_in_float128) {
  using rt::detail::coefficient;
  S sum = S(0);
  for (const auto& g : rt::KahanLi8Coefficients::gamma) sum += coefficient<S>(g);
  BOOST_TEST((abs(sum - S(1)) <= S(7.5e-26)), "Kahan-Li sum - 1 = " << rt::to_string(sum - S(1), 4));
  using Y = rt::Yoshida6Coefficients;
  const S w0 = coefficient<S>(Y::w0), w = coefficient<S>(Y::w1) + coefficient<S>(Y::w2) + coefficient<S>(Y::w3);
  BOOST_TEST((abs(w0 - (S(1) - S(2) * w)) <= S(3.5e-35) + S(4) * eps), rt::to_string(w0 - (S(1) - S(2) * w), 4));
}

// DOP853 adaptive in float128 on the oscillator over 10 time units at rtol = atol = 1e-28. The
// oscillator does not amplify errors (its flow is a rotation), so the global error is at most the
// sum of the local errors; each is held to err <= 1, i.e. about sc = atol + rtol |x| <= 2e-28 per
// component, by the controller. Bound: accepted steps * 2e-28, which must itself be below 1e-25.
BOOST_AUTO_TEST_CASE(dop853_adaptive_reaches_1e_25) {
  for (double tol : {1e-22, 1e-28}) {
    rt::Dop853<S> stepper;
    Oscillator sys;
    rt::State<S> x{S(1), S(0)};
    const rt::Stats st = rt::integrate_adaptive(stepper, sys, x, S(0), S(10), S(0), rt::Tolerances{tol, tol},
                                                [](S, const rt::State<S>&) {});
    const S err = error_at(x, S(10));
    const double bound = static_cast<double>(st.accepted) * 2 * tol;
    BOOST_TEST_MESSAGE("dop853 float128 tol " << tol << ": error " << rt::to_string(err, 4) << ", " << st.accepted
                                              << " steps, bound " << bound);
    BOOST_TEST((err <= S(bound)), "tol " << tol << ": error " << rt::to_string(err, 4) << " above " << bound);
    if (tol == 1e-28) BOOST_TEST((err <= S(1e-25)), "error " << rt::to_string(err, 4));
  }
}

// The same adaptive run with Dopri5, and Gauss-Legendre with the Newton solver (Eigen's LU over
// float128): compile, run, and keep their accuracy.
BOOST_AUTO_TEST_CASE(dopri5_adaptive_and_gauss_newton) {
  rt::Dopri5<S> dopri5;
  Oscillator sys;
  rt::State<S> x{S(1), S(0)};
  const rt::Stats st = rt::integrate_adaptive(dopri5, sys, x, S(0), S(1), S(0), rt::Tolerances{1e-24, 1e-24},
                                              [](S, const rt::State<S>&) {});
  BOOST_TEST((error_at(x, S(1)) <= S(static_cast<double>(st.accepted) * 2e-24)), rt::to_string(error_at(x, S(1)), 4));

  struct WithJacobian : Oscillator {
    void jacobian(S, const rt::State<S>&, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) const {
      J(0, 1) = S(1);
      J(1, 0) = S(-1);
    }
  } newton_sys;
  rt::GaussLegendreOptions options;
  options.solver = rt::GaussLegendreOptions::Solver::newton;
  rt::Gl8<S> gl8(options);
  rt::State<S> y{S(1), S(0)};
  rt::integrate_fixed(gl8, newton_sys, y, S(0), S(1), S(1) / S(256), [](S, const rt::State<S>&) {});
  BOOST_TEST(gl8.jacobian_evals() == 256u);
  BOOST_TEST((error_at(y, S(1)) < S(1e-25)), rt::to_string(error_at(y, S(1)), 4));
}
