#pragma once

// Kepler's equation and the two-body propagator (Mei, ch. 2, perturbation theory).
//
//   elliptic     E - e sin E = M,          0 <= e < 1    eccentric_from_mean
//   hyperbolic   e sinh H - H = M,         e > 1         hyperbolic_from_mean
//   universal    sqrt(mu) dt = r0 U1(chi) + (r0.v0/sqrt(mu)) U2(chi) + U3(chi), any conic
//                                                         solve_universal_kepler, propagate_kepler
// and the true <-> eccentric (hyperbolic) <-> mean anomaly conversions.
//
// References:
//   [Markley] F. L. Markley, Kepler equation solver, Celest. Mech. Dyn. Astron. 63 (1995) 101-111:
//     the cubic starter and the fifth-order correction.
//   [Vallado] D. A. Vallado, Fundamentals of Astrodynamics and Applications, 4th ed. (2013):
//     Ch. 2 (Kepler's equation, anomalies), Algorithm 8 (KEPLER: universal variables, f and g,
//     starters for chi), Examples 2-1, 2-2, 2-4 (used by the tests).
//   [Battin] R. H. Battin, An Introduction to the Mathematics and Methods of Astrodynamics,
//     rev. ed. (1999), Ch. 4: the universal functions U0..U3 and their derivatives.
//   [Danby] J. M. A. Danby, Fundamentals of Celestial Mechanics, 2nd ed. (1988), Sect. 6.9:
//     Stumpff functions c_k(z) and their series.
//
// Accuracy of the elliptic solver for double (measured by bench/kepler_solver.cpp and asserted by
// tests/runtime_kepler): the result is the root rounded to double up to about 1/1000 ulp
// (|E - E*| <= 0.501 ulp(E) measured, 0.55 proved), so the residual E - e sin E - M is as small as
// any double E allows. The difficulty is e -> 1, M -> 0, where E - e sin E cancels: E - sin E ~ E^3/6
// while E ~ (6M)^(1/3). The solver never forms that difference. It expands around a table point
// E0 = k/64 whose sin, cos, E0 - sin E0 and 1 - cos E0 are known to 64 bits, and writes (with
// d = E - E0, s = sin E0, c = cos E0)
//   f(E0 + d) = [(1-e) E0 + e (E0 - sin E0) - M] + [(1-e) + e (1 - cos E0)] d
//               + e c (d - sin d) + e s (1 - cos d),
// in which the brackets are sums of same-sign terms of size <= 8 M (so their absolute error is a
// few 2^-64 M), and d - sin d, 1 - cos d are short polynomials for |d| <= 1/32. Markley's starter
// (with a one-step cube root) and one Halley step in double give d to ~1e-11 relative; one Newton
// step in long double (x87, 64-bit significand) on the same expansion then leaves an error far below
// half an ulp before the final rounding. No libm call is made at all (the table is filled with
// sinl/cosl once, on first use).
//
// Scalars: double, long double, or any class type S with std::numeric_limits<S>, conversions
// S(int), S(double) and static_cast<double>(S), the arithmetic and comparison operators, and these
// functions found by argument-dependent lookup (or as std:: overloads): abs, sqrt, sin, cos, tan,
// atan, atan2, sinh, cosh, asinh, atanh. Calls are written `using std::sin; sin(x)`, and the
// runtime's own helpers are called qualified, so a scalar's namespace cannot capture them. Starters
// are computed in double (their accuracy is that of the approximation), so |M| must fit a double.
// For types other than double the elliptic and hyperbolic solvers iterate in the scalar itself
// (Halley / Newton on the same cancellation-free forms): within 4.5 ulps of that type, about 2
// measured. Hyperbolic solves for double iterate in long double: within 0.55 ulp.

#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "eomc/runtime/errors.hpp"

namespace eomc::runtime {

// Thrown for invalid input (eccentricity out of range, non-finite values, a hyperbolic true
// anomaly beyond the asymptote) and for iterations that do not converge.
class KeplerError : public std::runtime_error {
 public:
  enum class Kind { invalid_input, no_convergence };

  KeplerError(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

  // "eccentric_from_mean: eccentricity outside [0, 1): e: 1.5"
  template <class S>
  static KeplerError invalid(const char* where, const char* what, S value) {
    return {Kind::invalid_input,
            std::string(where) + ": " + what + ": " + IntegrationError::format(value)};
  }
  // "solve_universal_kepler: no convergence after 400 iterations (last step 0.001)"
  template <class S>
  static KeplerError no_convergence(const char* where, int iterations, S last_step) {
    return {Kind::no_convergence, std::string(where) + ": no convergence after " +
                                      std::to_string(iterations) + " iterations (last step " +
                                      IntegrationError::format(last_step) + ")"};
  }

  Kind kind() const noexcept { return kind_; }

 private:
  Kind kind_;
};

namespace kepler_detail {

template <class S>
S eps() {
  return std::numeric_limits<S>::epsilon();
}

// False for infinities and NaN, for any scalar (x - x is NaN for both).
template <class S>
bool finite(const S& x) {
  return x - x == S(0);
}

template <class S>
S pi() {
  if constexpr (std::is_floating_point_v<S>) {
    return std::numbers::pi_v<S>;
  } else {
    using std::atan;
    return S(4) * atan(S(1));  // atan(1) correctly rounded makes this pi to the last bit
  }
}

// The type the double solvers compute their last correction in: x87 long double where it is
// wider than double, otherwise the scalar itself.
template <class S>
struct Wider {
  using type = S;
};
template <>
struct Wider<double> {
  using type = std::conditional_t<(std::numeric_limits<long double>::digits > 53), long double, double>;
};
template <class S>
using wider_t = typename Wider<S>::type;

// x - sin x without cancellation. For |x| < 1.5 the Taylor series x^3/3! - x^5/5! + ... (each term
// at least 8x smaller than the one before, the largest at most 1.12x the sum, so the alternating
// sum loses under a bit); for |x| >= 1.5 the plain difference (|sin x| <= 2 (x - sin x) there: one
// bit). The switch point is where the two errors cross (measured on the long-double solver: the
// worst case over the test grid drops from 2.36 to 1.85 ulp moving it from 2 to 1.5).
template <class S>
S x_minus_sin(S x) {
  using std::abs;
  using std::sin;
  if (abs(x) < S(1.5)) {
    const S x2 = x * x;
    S term = x * x2 / S(6);
    S sum = term;
    for (int k = 2; k < 60; ++k) {
      term *= -x2 / S((2 * k) * (2 * k + 1));
      sum += term;
      if (abs(term) <= eps<S>() * abs(sum) / S(4)) break;
    }
    return sum;
  }
  return x - sin(x);
}

// sinh x - x without cancellation: the series x^3/3! + x^5/5! + ... (same-sign terms) for |x| < 2,
// the difference for |x| >= 2 (sinh x >= 1.8 x there).
template <class S>
S sinh_minus_x(S x) {
  using std::abs;
  using std::sinh;
  if (abs(x) < S(2)) {
    const S x2 = x * x;
    S term = x * x2 / S(6);
    S sum = term;
    for (int k = 2; k < 60; ++k) {
      term *= x2 / S((2 * k) * (2 * k + 1));
      sum += term;
      if (abs(term) <= eps<S>() * abs(sum) / S(4)) break;
    }
    return sum;
  }
  return sinh(x) - x;
}

// 1 - cos x = 2 sin^2(x/2) and cosh x - 1 = 2 sinh^2(x/2), both free of cancellation.
template <class S>
S one_minus_cos(S x) {
  using std::sin;
  const S h = sin(x / S(2));
  return S(2) * h * h;
}
template <class S>
S cosh_minus_one(S x) {
  using std::sinh;
  const S h = sinh(x / S(2));
  return S(2) * h * h;
}

// Cube root of a positive normal double to 2.1e-5 relative (measured over 1e-30..1e30): the
// exponent divided by 3 with the bits as an integer (the classic initial guess, error ~3%), then one
// Halley step y (y^3 + 2x)/(2y^3 + x), cubically convergent. The starter needs no more, and this is
// about twice as fast as std::cbrt on the solver's critical path.
inline double cube_root_approx(double x) {
  std::uint64_t i = std::bit_cast<std::uint64_t>(x);
  i = i / 3 + 0x2A9F7893782DA1CEull;
  double y = std::bit_cast<double>(i);
  const double y3 = y * y * y;
  return y * (y3 + 2.0 * x) / (2.0 * y3 + x);
}
// Markley's cubic starter for E - e sin E = M, M in [0, pi], e in [0, 1) [Markley]:
//   alpha = (3 pi^2 + 1.6 pi (pi - M)/(1 + e))/(pi^2 - 6),  d = 3 (1 - e) + alpha e,
//   q = 2 alpha d (1 - e) - M^2,  r = 3 alpha d (d - 1 + e) M + M^3,
//   w = (|r| + sqrt(q^3 + r^2))^(2/3),  E1 = (2 r w/(w^2 + w q + q^2) + M)/d,
// arranged with two divisions fewer (constants folded, the last two divisions merged) and the cube
// root from cube_root_approx. Measured over a dense (e, M) grid: |E1 - E| <= 4.7e-4,
// |E1 - E| / E <= 2.8e-4 (4.4e-4 and 2.8e-4 with std::cbrt). Always double: its accuracy is that of
// the approximation, not of the arithmetic.
inline double markley_starter(double M, double e) {
  constexpr double pi = std::numbers::pi;
  constexpr double k1 = 3.0 * pi * pi / (pi * pi - 6.0), k2 = 1.6 * pi / (pi * pi - 6.0);
  const double alpha = k1 + k2 * (pi - M) / (1.0 + e);
  const double ome = 1.0 - e;
  const double d = 3.0 * ome + alpha * e;
  const double q = 2.0 * alpha * d * ome - M * M;
  const double r = (3.0 * alpha * d * (d - ome) + M * M) * M;
  const double disc = q * q * q + r * r;
  double w = cube_root_approx(std::fabs(r) + std::sqrt(disc > 0.0 ? disc : 0.0));
  w *= w;
  const double den = w * w + w * q + q * q;
  return (2.0 * r * w + M * den) / (den * d);
}

// d - sin d = d^3/6 (1 + mP) and 1 - cos d = d^2/2 (1 + mQ) for |d| <= 1/32, with
//   mP = -d^2/20 (1 - d^2/42 (1 - d^2/72)),  mQ = -d^2/12 (1 - d^2/30 (1 - d^2/56)):
// the Taylor series up to the term whose successor is below 2^-70 of the sum (d^11/11! against
// d^3/6; d^10/10! against d^2/2). The small parts mP, mQ (at most 1e-3 in size) need only double
// precision even when the leading terms are formed in long double.
inline void small_angle_parts(double d, double& mP, double& mQ) {
  const double d2 = d * d;
  mP = -d2 * (1.0 / 20) * (1.0 - d2 * (1.0 / 42) * (1.0 - d2 * (1.0 / 72)));
  mQ = -d2 * (1.0 / 12) * (1.0 - d2 * (1.0 / 30) * (1.0 - d2 * (1.0 / 56)));
}

// Table of E0 = k/64, k = 0..201 (201/64 < pi < 202/64): sin E0, cos E0, E0 - sin E0, 1 - cos E0
// in long double (libm's sinl/cosl are good to an ulp of long double, 2^-63 relative).
struct EllipticTableEntry {
  long double s, c, d, q;
  double sd, cd, dd, qd;  // the same rounded to double, for the double stage (no x87 round trip)
};
inline constexpr int elliptic_table_scale = 64;
inline constexpr int elliptic_table_last = 201;

inline const std::array<EllipticTableEntry, elliptic_table_last + 1>& elliptic_table() {
  static const std::array<EllipticTableEntry, elliptic_table_last + 1> table = [] {
    std::array<EllipticTableEntry, elliptic_table_last + 1> t{};
    for (int k = 0; k <= elliptic_table_last; ++k) {
      const long double x = static_cast<long double>(k) / elliptic_table_scale;
      const long double sx = std::sin(x), cx = std::cos(x);
      const long double dx = kepler_detail::x_minus_sin(x), qx = kepler_detail::one_minus_cos(x);
      t[static_cast<std::size_t>(k)] = {sx,
                                        cx,
                                        dx,
                                        qx,
                                        static_cast<double>(sx),
                                        static_cast<double>(cx),
                                        static_cast<double>(dx),
                                        static_cast<double>(qx)};
    }
    return t;
  }();
  return table;
}

// The double fast path for M in (0, pi], e in (0, 1); see the header comment. Steps:
//  1. Markley's starter E1 (relative error <= 2.8e-4); table point E0 = round(64 E1)/64, d = E1 - E0.
//  2. The expansion coefficients f(E0), f'(E0), e sin E0, e cos E0 in long double.
//  3. One Halley step on the expansion, in double: error <= 1.4e-11 E over the test grids
//     (Halley is cubic: (2.8e-4)^3 times a constant below 1 here); f' at the new point by Taylor.
//  4. One Newton step in long double with that derivative: the error becomes ~(1.4e-11)^2 E,
//     and the expansion's own round-off (a few 2^-64 M <= a few 2^-64 f' E, since f'(E) E >= M on
//     [0, pi]) dominates: |E - E*| <= ~2^-10 ulp(E) before the rounding to double.
// Returns false (the caller then iterates generically) when the Newton correction exceeds
// 2^-33 E, above which step 4 could no longer promise 64 bits; the tests check that this never
// happens on their grids (the largest seen is 1.4e-11 E, about 2^-36 E).
inline bool eccentric_from_mean_fast(double M, double e, double& E_out) {
  using W = long double;
  const double Es = markley_starter(M, e);
  if (!(Es >= 0.0 && Es <= 3.5)) return false;
  const int k = static_cast<int>(Es * elliptic_table_scale + 0.5);
  const int kk = k > elliptic_table_last ? elliptic_table_last : k;
  const EllipticTableEntry& t = elliptic_table()[static_cast<std::size_t>(kk)];
  const double E0 = static_cast<double>(kk) / elliptic_table_scale;  // exact

  // 1 - e is exact in long double (e has 53 bits; for e >= 2^-11 the difference needs at most 64,
  // and for smaller e its rounding is 2^-64 relative).
  const W eW = e;
  const W ome = W(1) - eW;
  const W f0 = ome * E0 + eW * t.d - W(M);  // f(E0) = E0 - e sin E0 - M: same-sign terms, then - M
  const W fp0 = ome + eW * t.q;             // f'(E0) = 1 - e cos E0
  const W es = eW * t.s;
  const W ec = eW * t.c;

  // 3. Halley in double on f(E0 + d) = f(E0) + f'(E0) d + e c (d - sin d) + e s (1 - cos d), with
  // the coefficients formed in double (independent of the long-double ones above, so both run
  // side by side): the same-sign sums err by a few eps of 8 M, i.e. a few eps of E after division
  // by f', far below the 1e-11 E the Halley step leaves anyway.
  const double a0 = (1.0 - e) * E0 + e * t.dd - M, a1 = (1.0 - e) + e * t.qd;
  const double esd = e * t.sd, ecd = e * t.cd;
  double d = Es - E0;
  if (!(std::fabs(d) <= 1.0 / 32)) return false;
  double mP, mQ;
  small_angle_parts(d, mP, mQ);
  const double P = d * d * d * (1.0 / 6) * (1.0 + mP), Q = d * d * 0.5 * (1.0 + mQ);
  const double sn = d - P, cs = 1.0 - Q;  // sin d, cos d
  const double g0 = a0 + a1 * d + ecd * P + esd * Q;
  const double g1 = a1 + ecd * Q + esd * sn;  // first derivative: 1 - e cos E
  const double g2 = ecd * sn + esd * cs;      // second: e sin E
  const double g3 = ecd * cs - esd * sn;      // third: e cos E
  const double h = -2.0 * g0 * g1 / (2.0 * g1 * g1 - g0 * g2);
  d += h;
  if (!(std::fabs(d) <= 1.0 / 32)) return false;
  const double inv = 1.0 / (g1 + h * (g2 + 0.5 * h * g3));

  // 4. Newton in long double; only the leading terms d^3/6, d^2/2 need the 64 bits.
  small_angle_parts(d, mP, mQ);
  const W dW = d;
  const W d2 = dW * dW;
  const W c3 = dW * d2 * (1.0L / 6), c2 = d2 * W(0.5);
  const W PW = c3 + c3 * W(mP), QW = c2 + c2 * W(mQ);
  const W g = f0 + fp0 * dW + ec * PW + es * QW;
  const W corr = g * W(inv);
  const W E = W(E0) + (dW - corr);
  using std::fabs;
  if (!(fabs(corr) <= 0x1p-33L * E)) return false;
  E_out = static_cast<double>(E);
  return true;
}

// E for M in (0, pi], e in (0, 1), by Halley's iteration in W on the cancellation-free
// f(E) = (1 - e) E + e (E - sin E) - M, f' = (1 - e) + e (1 - cos E), f'' = e sin E, from Markley's
// starter. Stops at round-off: a step below 4 eps E, or one that no longer shrinks (by half) while
// already below 1024 eps E (the iteration is then wandering in the noise of f). Accuracy: f is
// evaluated to (c + 2) u M (u the unit round-off, c <= 2 the error of x - sin x in units of u) and
// f'(E) E >= M, so the result is within (c + 2) u E + half an ulp of the root: under 4.5 ulps in the
// worst case, about 2 measured (tests/runtime_kepler, long double and __float128).
template <class W>
W eccentric_from_mean_iterate(W M, W e) {
  using std::abs;
  using std::sin;
  const W pi_w = pi<W>();
  const W ome = W(1) - e;
  W E = W(markley_starter(static_cast<double>(M), static_cast<double>(e)));
  W previous = W(-1);
  constexpr int max_iterations = 50;
  for (int it = 1; it <= max_iterations; ++it) {
    // For e < 1/2, M <= E <= M/(1 - e) <= 2M makes E - M exact (Sterbenz), and only e sin E is
    // rounded; for e >= 1/2, 1 - e is exact and the split form avoids the cancellation.
    const W f = e < W(0.5) ? (E - M) - e * sin(E) : ome * E + e * kepler_detail::x_minus_sin(E) - M;
    const W fp = ome + e * kepler_detail::one_minus_cos(E);
    const W fpp = e * sin(E);
    W step = -f / (fp - f * fpp / (W(2) * fp));
    W En = E + step;
    if (En < W(0)) En = E / W(2);  // stay in [0, pi], where the root is
    if (En > pi_w) En = (E + pi_w) / W(2);
    step = abs(En - E);
    E = En;
    if (step <= W(4) * eps<W>() * E) return E;
    if (previous >= W(0) && step > previous / W(2) && step <= W(1024) * eps<W>() * E) return E;
    previous = step;
  }
  throw KeplerError::no_convergence("eccentric_from_mean", max_iterations, previous);
}

// H for M > 0, e > 1, by Newton's iteration in W on f(H) = (e - 1) H + e (sinh H - H) - M,
// f' = (e - 1) + e (cosh H - 1). f is convex and increasing on H > 0, so Newton from an upper
// bound decreases monotonically to the root. Upper bounds: the root H_c of the cubic
// (e - 1) H + e H^3/6 = M (sinh H - H >= H^3/6 makes f(H_c) >= 0), and asinh((M + H_c)/e)
// (e sinh H* = M + H* <= M + H_c). The first is sharp for small H (near-parabolic), the second for
// large M, where H_c = O(M^(1/3)) would cost O(M^(1/3)) Newton steps.
template <class W>
W hyperbolic_from_mean_iterate(W M, W e) {
  using std::abs;
  const W em1 = e - W(1);
  const double md = static_cast<double>(M), ed = static_cast<double>(e), em1d = static_cast<double>(em1);
  // Cubic H^3 + p H - q = 0, p = 6 (e-1)/e > 0, q = 6 M/e: one real root,
  // H = 2 sqrt(p/3) sinh(asinh((3q/2p) sqrt(3/p))/3) (the trigonometric form of Cardano).
  const double p = 6.0 * em1d / ed, q = 6.0 * md / ed;
  double Hc = 2.0 * std::sqrt(p / 3.0) * std::sinh(std::asinh(1.5 * q / p * std::sqrt(3.0 / p)) / 3.0);
  if (!std::isfinite(Hc) || Hc <= 0.0) Hc = std::cbrt(q);  // p tiny or M huge: drop the linear term
  // Rounding may put H_c a hair below the root; Newton from there overshoots once and then
  // decreases, which the stopping rule below allows.
  const double Ha = std::asinh((md + Hc) / ed);
  W H = W(Ha < Hc ? Ha : Hc);
  W previous = W(-1);
  constexpr int max_iterations = 100;
  for (int it = 1; it <= max_iterations; ++it) {
    const W f = em1 * H + e * kepler_detail::sinh_minus_x(H) - M;
    const W fp = em1 + e * kepler_detail::cosh_minus_one(H);
    const W step = -f / fp;
    const W Hn = H + step;
    const W size = abs(step);
    H = Hn;
    if (size <= W(4) * eps<W>() * H) return H;
    if (previous >= W(0) && size > previous / W(2) && size <= W(1024) * eps<W>() * H) return H;
    previous = size;
  }
  throw KeplerError::no_convergence("hyperbolic_from_mean", max_iterations, previous);
}

template <class S>
void check_finite(const char* where, const char* what, const S& x) {
  if (!kepler_detail::finite(x)) throw KeplerError::invalid(where, what, x);
}

}  // namespace kepler_detail

// ---------------------------------------------------------------------------------------------
// Elliptic: E - e sin E = M.

// The eccentric anomaly E with E - e sin E = M, for 0 <= e < 1 and any finite M. M is reduced to
// [-pi, pi] first; the result is in the same revolution as M (E - M = e sin E, |E - M| <= e).
template <class S>
S eccentric_from_mean(S M, std::type_identity_t<S> e) {
  using std::abs;
  namespace kd = kepler_detail;
  kd::check_finite("eccentric_from_mean", "mean anomaly not finite", M);
  if (!(e >= S(0) && e < S(1)))
    throw KeplerError::invalid("eccentric_from_mean", "eccentricity outside [0, 1): e", e);
  const S pi = kd::pi<S>();
  if (e == S(0) || M == S(0)) return M;  // M = -0 gives E = -0

  // Reduction to [-pi, pi]: M - 2 pi k, in the wider type for double (2 pi to 64 bits), so the
  // reduced value is the correctly rounded M - 2 pi k up to 2^-11 ulp.
  S Mr = M;
  const bool reduced = !(abs(M) <= pi);
  if (reduced) {
    using W = kd::wider_t<S>;
    const W two_pi = W(2) * kd::pi<W>();
    const W k = W(std::nearbyint(static_cast<double>(W(M) / two_pi)));
    Mr = S(W(M) - k * two_pi);
    if (Mr > pi) Mr = pi;  // rounding at the edges
    if (Mr < -pi) Mr = -pi;
  }
  const S m = abs(Mr);
  S E = m;
  if (m > S(0)) {
    bool done = false;
    if constexpr (std::is_same_v<S, double> && !std::is_same_v<kd::wider_t<double>, double>) {
      done = kd::eccentric_from_mean_fast(m, e, E);
    }
    if (!done) {
      using W = kd::wider_t<S>;
      E = S(kd::eccentric_from_mean_iterate<W>(W(m), W(e)));
    }
  }
  if (Mr < S(0)) E = -E;
  // Back to M's revolution: E_full = M + (E - Mr), the periodic part e sin E added to M itself.
  return reduced ? M + (E - Mr) : E;
}

// M = E - e sin E, as (1 - e) E + e (E - sin E) for e >= 1/2 and |E| < 2 (no cancellation as
// e -> 1); as written otherwise, where e sin E <= E/2 or |E| >= 2 > 2 e |sin E| leaves one bit.
template <class S>
S mean_from_eccentric(S E, std::type_identity_t<S> e) {
  using std::abs;
  using std::sin;
  if (e >= S(0.5) && abs(E) < S(2)) return (S(1) - e) * E + e * kepler_detail::x_minus_sin(E);
  return E - e * sin(E);
}

// ---------------------------------------------------------------------------------------------
// Hyperbolic: e sinh H - H = M.

// The hyperbolic anomaly H with e sinh H - H = M, for e > 1 and finite M (|M| within the double
// range, which the starter uses).
template <class S>
S hyperbolic_from_mean(S M, std::type_identity_t<S> e) {
  namespace kd = kepler_detail;
  using std::abs;
  kd::check_finite("hyperbolic_from_mean", "mean anomaly not finite", M);
  if (!(e > S(1)) || !kd::finite(e))
    throw KeplerError::invalid("hyperbolic_from_mean", "eccentricity not in (1, inf): e", e);
  if (!std::isfinite(static_cast<double>(M)))
    throw KeplerError::invalid("hyperbolic_from_mean", "|M| beyond the double range: M", M);
  if (M == S(0)) return M;
  using W = kd::wider_t<S>;
  const S H = S(kd::hyperbolic_from_mean_iterate<W>(W(abs(M)), W(e)));
  return M < S(0) ? -H : H;
}

// M = e sinh H - H = (e - 1) H + e (sinh H - H).
template <class S>
S mean_from_hyperbolic(S H, std::type_identity_t<S> e) {
  return (e - S(1)) * H + e * kepler_detail::sinh_minus_x(H);
}

// ---------------------------------------------------------------------------------------------
// True anomaly. Half-angle atan2 forms [Vallado, Ch. 2], well conditioned for all angles
// and all e (tan(nu/2) forms blow up at nu = pi). Angles outside (-pi, pi] keep their revolution.

namespace kepler_detail {
// Splits x = 2 pi k + xr with xr in [-pi, pi]; returns xr and stores 2 pi k.
template <class S>
S reduce_angle(S x, S& revolutions) {
  using std::abs;
  const S pi_s = pi<S>();
  revolutions = S(0);
  if (abs(x) <= pi_s) return x;
  const S k = S(std::nearbyint(static_cast<double>(x / (S(2) * pi_s))));
  revolutions = k * S(2) * pi_s;
  return x - revolutions;
}
}  // namespace kepler_detail

// E from nu (0 <= e < 1): tan(E/2) = sqrt((1-e)/(1+e)) tan(nu/2).
template <class S>
S eccentric_from_true(S nu, std::type_identity_t<S> e) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  S rev;
  const S x = kepler_detail::reduce_angle(nu, rev) / S(2);
  return S(2) * atan2(sqrt(S(1) - e) * sin(x), sqrt(S(1) + e) * cos(x)) + rev;
}

// nu from E (0 <= e < 1): tan(nu/2) = sqrt((1+e)/(1-e)) tan(E/2).
template <class S>
S true_from_eccentric(S E, std::type_identity_t<S> e) {
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  S rev;
  const S x = kepler_detail::reduce_angle(E, rev) / S(2);
  return S(2) * atan2(sqrt(S(1) + e) * sin(x), sqrt(S(1) - e) * cos(x)) + rev;
}

// H from nu (e > 1): tanh(H/2) = sqrt((e-1)/(e+1)) tan(nu/2), for |nu| below the asymptote
// acos(-1/e); beyond it (no point of the hyperbola) KeplerError::invalid_input.
template <class S>
S hyperbolic_from_true(S nu, std::type_identity_t<S> e) {
  using std::abs;
  using std::atanh;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S x = nu / S(2);
  const S t = sqrt(e - S(1)) * sin(x) / (sqrt(e + S(1)) * cos(x));
  if (!(abs(t) < S(1)) || !(abs(nu) < kepler_detail::pi<S>()))
    throw KeplerError::invalid("hyperbolic_from_true", "true anomaly beyond the asymptote: nu", nu);
  return S(2) * atanh(t);
}

// nu from H (e > 1): tan(nu/2) = sqrt((e+1)/(e-1)) tanh(H/2).
template <class S>
S true_from_hyperbolic(S H, std::type_identity_t<S> e) {
  using std::atan2;
  using std::cosh;
  using std::sinh;
  using std::sqrt;
  const S x = H / S(2);
  return S(2) * atan2(sqrt(e + S(1)) * sinh(x), sqrt(e - S(1)) * cosh(x));
}

// nu from M and back, for e < 1 (through E) or e > 1 (through H). e = 1 (parabolic: no mean
// anomaly in these units) is invalid input; propagate parabolic orbits with propagate_kepler.
template <class S>
S true_from_mean(S M, std::type_identity_t<S> e) {
  if (e < S(1)) return runtime::true_from_eccentric(runtime::eccentric_from_mean(M, e), e);
  if (e > S(1)) return runtime::true_from_hyperbolic(runtime::hyperbolic_from_mean(M, e), e);
  throw KeplerError::invalid("true_from_mean", "parabolic (or NaN) eccentricity: e", e);
}
template <class S>
S mean_from_true(S nu, std::type_identity_t<S> e) {
  if (!(e >= S(0))) throw KeplerError::invalid("mean_from_true", "negative or NaN eccentricity: e", e);
  if (e < S(1)) return runtime::mean_from_eccentric(runtime::eccentric_from_true(nu, e), e);
  if (e > S(1)) return runtime::mean_from_hyperbolic(runtime::hyperbolic_from_true(nu, e), e);
  throw KeplerError::invalid("mean_from_true", "parabolic eccentricity: e", e);
}

// ---------------------------------------------------------------------------------------------
// Universal variables [Battin Ch. 4; Vallado Algorithm 8; Danby Sect. 6.9].

template <class S>
struct Stumpff {
  S c2, c3;  // c2(z) = (1 - cos sqrt z)/z, c3(z) = (sqrt z - sin sqrt z)/sqrt(z)^3, analytic in z
};

// Series sum_k (-z)^k/(2k+2)!, sum_k (-z)^k/(2k+3)! for |z| < 2.5 (the terms shrink by at least
// 4.8x, the first dominates: no cancellation), closed forms with the half-angle 1 - cos beyond.
template <class S>
Stumpff<S> stumpff(S z) {
  using std::abs;
  using std::sin;
  using std::sinh;
  using std::sqrt;
  namespace kd = kepler_detail;
  if (abs(z) < S(2.5)) {
    S t2 = S(1) / S(2), t3 = S(1) / S(6);
    S c2 = t2, c3 = t3;
    for (int k = 1; k < 60; ++k) {
      t2 *= -z / S((2 * k + 1) * (2 * k + 2));
      t3 *= -z / S((2 * k + 2) * (2 * k + 3));
      c2 += t2;
      c3 += t3;
      if (abs(t2) <= kd::eps<S>() * c2 / S(4) && abs(t3) <= kd::eps<S>() * c3 / S(4)) break;
    }
    return {c2, c3};
  }
  if (z > S(0)) {
    const S s = sqrt(z);
    return {kd::one_minus_cos(s) / z, kd::x_minus_sin(s) / (z * s)};
  }
  const S s = sqrt(-z);
  return {kd::cosh_minus_one(s) / -z, kd::sinh_minus_x(s) / (-z * s)};
}

// The universal anomaly chi and the Lagrange coefficients for a time of flight dt.
template <class S>
struct UniversalKepler {
  S chi;        // universal anomaly at dt (sqrt of length): chi = sqrt(a) (E - E0) on ellipses,
                // sqrt(-a) (H - H0) on hyperbolas; whole revolutions included
  S r;          // |r(dt)|
  S f, g, fdot, gdot;  // r(dt) = f r0 + g v0,  v(dt) = fdot r0 + gdot v0
  int iterations;
};

// Solves sqrt(mu) dt = r0 U1 + sigma U2 + U3, sigma = (r0 . v0)/sqrt(mu), U_k = chi^k c_k(alpha chi^2)
// (U1 = chi (1 - z c3), U0 = 1 - z c2), for chi, given dt, r0 = |r0|, r0_dot_v0 = r0 . v0,
// alpha = 1/a = 2/r0 - v0^2/mu (any sign: ellipse, parabola, hyperbola) and mu.
// F(chi) = r0 U1 + sigma U2 + U3 - sqrt(mu) dt is increasing (F' = r > 0), so the root is
// bracketed (from 0 and by doubling) and found by Halley's method [Battin Ch. 4: F'' = sigma U0 +
// (1 - alpha r0) U1], falling back to bisection when a step leaves the bracket or converges slowly. On ellipses whole
// periods are taken out of dt first (f and g are periodic in chi with period 2 pi/sqrt(alpha)),
// which keeps z = alpha chi^2 <= pi^2.
template <class S>
UniversalKepler<S> solve_universal_kepler(S dt, S r0, S r0_dot_v0, S alpha, S mu) {
  using std::abs;
  using std::sqrt;
  namespace kd = kepler_detail;
  constexpr const char* where = "solve_universal_kepler";
  kd::check_finite(where, "time of flight not finite", dt);
  kd::check_finite(where, "alpha = 1/a not finite", alpha);
  kd::check_finite(where, "r0 . v0 not finite", r0_dot_v0);
  if (!(r0 > S(0)) || !kd::finite(r0)) throw KeplerError::invalid(where, "|r0| not positive and finite", r0);
  if (!(mu > S(0)) || !kd::finite(mu)) throw KeplerError::invalid(where, "mu not positive and finite", mu);

  const S sqmu = sqrt(mu);
  const S sigma = r0_dot_v0 / sqmu;
  const S pi = kd::pi<S>();

  S dtr = dt, chi_revolutions = S(0);
  if (alpha > S(0)) {
    const S sa = sqrt(alpha);
    const S period = S(2) * pi / (sqmu * alpha * sa);
    if (kd::finite(period) && abs(dt) > period / S(2)) {
      const S n = S(std::nearbyint(static_cast<double>(dt / period)));
      dtr = dt - n * period;
      chi_revolutions = n * S(2) * pi / sa;
    }
  }

  struct Eval {
    S F, Fp, Fpp, u0, u1, u2, u3;
    bool ok;
  };
  const S target = sqmu * dtr;
  auto eval = [&](S chi) {
    const S z = alpha * chi * chi;
    const Stumpff<S> c = runtime::stumpff(z);
    Eval v;
    v.u0 = S(1) - z * c.c2;
    v.u1 = chi * (S(1) - z * c.c3);
    v.u2 = chi * chi * c.c2;
    v.u3 = chi * chi * chi * c.c3;
    v.F = r0 * v.u1 + sigma * v.u2 + v.u3 - target;
    v.Fp = r0 * v.u0 + sigma * v.u1 + v.u2;
    v.Fpp = sigma * v.u0 + (S(1) - alpha * r0) * v.u1;
    v.ok = kd::finite(v.F) && kd::finite(v.Fp) && kd::finite(v.Fpp) && v.Fp > S(0);
    return v;
  };

  UniversalKepler<S> out{};
  S chi = S(0);
  int iterations = 0;
  if (dtr != S(0)) {
    // The root has the sign of dt (F(0) = -sqrt(mu) dt, F increasing). With s = sign(dt), `inner`
    // has s F < 0 and `outer` s F >= 0 (or F not finite: far past the root).
    const S s = dtr > S(0) ? S(1) : S(-1);
    // Starters [Vallado Alg. 8], in double (only their size matters): sqrt(mu) alpha dt on
    // ellipses (after the reduction |dt| <= T/2, so this is at most pi/sqrt(alpha), the right
    // scale), the logarithmic estimate on hyperbolas, sqrt(mu) dt/r0 otherwise. Bracketing and the
    // safeguards below make convergence independent of their quality.
    const double alpha_d = static_cast<double>(alpha), dt_d = static_cast<double>(dtr);
    const double mu_d = static_cast<double>(mu), r0_d = static_cast<double>(r0), s_d = static_cast<double>(s);
    double chi0 = static_cast<double>(target / r0);
    if (alpha_d > 0.0) {
      chi0 = std::sqrt(mu_d) * alpha_d * dt_d;
    } else if (alpha_d < 0.0) {
      const double a = 1.0 / alpha_d;
      const double arg = -2.0 * mu_d * alpha_d * dt_d /
                         (static_cast<double>(r0_dot_v0) + s_d * std::sqrt(-mu_d * a) * (1.0 - r0_d * alpha_d));
      const double c = s_d * std::sqrt(-a) * std::log(arg);
      if (std::isfinite(c) && c * s_d > 0.0) chi0 = c;
    }
    if (!(chi0 * s_d > 0.0) || !std::isfinite(chi0)) chi0 = static_cast<double>(target / r0);
    S inner = S(0), outer = S(chi0);
    constexpr int max_doublings = 4000;
    int doublings = 0;
    for (;;) {
      const Eval v = eval(outer);
      if (!v.ok || v.F * s >= S(0)) break;
      inner = outer;
      outer *= S(2);
      if (++doublings > max_doublings) throw KeplerError::no_convergence(where, doublings, outer);
    }
    // Halley's method kept inside the bracket, with the safeguard of Numerical Recipes' rtsafe:
    // bisect when the step would leave the bracket or is not at most half the step before last
    // (the slow approach to a root from far out on an exponential or a cubic).
    chi = outer;
    S step = abs(outer - inner), step_before = step;
    constexpr int max_iterations = 400;
    for (;;) {
      if (++iterations > max_iterations) throw KeplerError::no_convergence(where, max_iterations, step);
      const Eval v = eval(chi);
      if (v.ok && v.F == S(0)) break;
      if (!v.ok || v.F * s > S(0))
        outer = chi;
      else
        inner = chi;
      S next = (inner + outer) / S(2);
      if (v.ok) {
        const S denom = v.Fp - v.F * v.Fpp / (S(2) * v.Fp);
        const S halley = chi - (denom > S(0) ? v.F / denom : v.F / v.Fp);
        const S lo = inner < outer ? inner : outer, hi = inner < outer ? outer : inner;
        if (halley > lo && halley < hi && S(2) * abs(halley - chi) <= step_before) next = halley;
      }
      step_before = step;
      step = abs(next - chi);
      chi = next;
      if (step <= S(2) * kd::eps<S>() * abs(chi)) break;
      if (abs(outer - inner) <= S(4) * kd::eps<S>() * abs(chi)) break;
    }
  }
  const Eval v = eval(chi);
  out.chi = chi + chi_revolutions;
  out.r = v.Fp;
  out.f = S(1) - v.u2 / r0;
  // g = (r0 U1 + sigma U2)/sqrt(mu), equal to dt - U3/sqrt(mu) at the root but free of the
  // cancellation between dt and U3 on hyperbolic arcs far from periapsis.
  out.g = (r0 * v.u1 + sigma * v.u2) / sqmu;
  out.fdot = -sqmu * v.u1 / (v.Fp * r0);
  out.gdot = S(1) - v.u2 / v.Fp;
  out.iterations = iterations;
  return out;
}

// The two-body propagator: the Cartesian state x = (x, y, z, vx, vy, vz) after dt under
// r'' = -mu r/|r|^3, by the universal-variable f and g functions. Any conic, dt of either sign.
template <class S>
std::array<S, 6> propagate_kepler(const std::array<S, 6>& x0, S dt, S mu) {
  using std::sqrt;
  namespace kd = kepler_detail;
  constexpr const char* where = "propagate_kepler";
  for (const S& c : x0) kd::check_finite(where, "state component not finite", c);
  if (!(mu > S(0)) || !kd::finite(mu)) throw KeplerError::invalid(where, "mu not positive and finite", mu);
  const S r0 = sqrt(x0[0] * x0[0] + x0[1] * x0[1] + x0[2] * x0[2]);
  if (!(r0 > S(0))) throw KeplerError::invalid(where, "|r0| not positive", r0);
  const S v2 = x0[3] * x0[3] + x0[4] * x0[4] + x0[5] * x0[5];
  const S rv = x0[0] * x0[3] + x0[1] * x0[4] + x0[2] * x0[5];
  const S alpha = S(2) / r0 - v2 / mu;
  const UniversalKepler<S> k = runtime::solve_universal_kepler(dt, r0, rv, alpha, mu);
  std::array<S, 6> x;
  for (int i = 0; i < 3; ++i) {
    x[static_cast<std::size_t>(i)] = k.f * x0[static_cast<std::size_t>(i)] + k.g * x0[static_cast<std::size_t>(i + 3)];
    x[static_cast<std::size_t>(i + 3)] =
        k.fdot * x0[static_cast<std::size_t>(i)] + k.gdot * x0[static_cast<std::size_t>(i + 3)];
  }
  return x;
}

}  // namespace eomc::runtime
