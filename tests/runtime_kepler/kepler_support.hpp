#pragma once

// Shared by the Kepler tests: ulps, the reference residuals (evaluated in a wider type without
// cancellation, written here independently of the solver), and, where GCC's libquadmath is
// available, a minimal __float128 wrapper: a class-type scalar with ADL math functions, which is
// both a 113-bit reference and a check that the runtime is generic in the scalar.

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#ifdef EOMC_HAVE_QUADMATH
#include <quadmath.h>
#endif

namespace kepler_test {

template <class S>
S ulp(S x) {
  x = std::fabs(x);
  return std::nextafter(x, std::numeric_limits<S>::infinity()) - x;
}

// E - sin E by its Taylor series for |E| < 2 (alternating, largest term <= 1.3x the sum), the
// difference beyond; in T (long double for double arguments).
template <class T>
T x_minus_sin(T x) {
  using std::sin;
  if (x < T(2) && x > T(-2)) {
    const T x2 = x * x;
    T term = x * x2 / T(6), sum = term;
    for (int k = 2; k < 45; ++k) {
      term *= -x2 / T((2 * k) * (2 * k + 1));
      sum += term;
    }
    return sum;
  }
  return x - sin(x);
}
template <class T>
T sinh_minus_x(T x) {
  using std::sinh;
  if (x < T(2) && x > T(-2)) {
    const T x2 = x * x;
    T term = x * x2 / T(6), sum = term;
    for (int k = 2; k < 45; ++k) {
      term *= x2 / T((2 * k) * (2 * k + 1));
      sum += term;
    }
    return sum;
  }
  return sinh(x) - x;
}

// Residual f(E) = E - e sin E - M and f'(E) = 1 - e cos E in T, without cancellation.
template <class T, class S>
T elliptic_residual(S E, S M, S e) {
  const T EW = T(E), eW = T(e);
  return (T(1) - eW) * EW + eW * x_minus_sin(EW) - T(M);
}
template <class T, class S>
T elliptic_derivative(S E, S e) {
  using std::sin;
  const T h = sin(T(E) / T(2));
  return (T(1) - T(e)) + T(e) * T(2) * h * h;
}
// Residual e sinh H - H - M and derivative e cosh H - 1, in T.
template <class T, class S>
T hyperbolic_residual(S H, S M, S e) {
  const T HW = T(H), eW = T(e);
  return (eW - T(1)) * HW + eW * sinh_minus_x(HW) - T(M);
}
template <class T, class S>
T hyperbolic_derivative(S H, S e) {
  using std::sinh;
  const T h = sinh(T(H) / T(2));
  return (T(e) - T(1)) + T(e) * T(2) * h * h;
}

#ifdef EOMC_HAVE_QUADMATH
// A scalar class over __float128, the way a user's quad wrapper would look: arithmetic,
// comparisons, explicit conversions, and the math functions as friends found by ADL.
__extension__ typedef __float128 float128;
struct Quad {
  float128 v = 0;
  Quad() = default;
  Quad(int x) : v(x) {}
  Quad(double x) : v(x) {}
  Quad(long double x) : v(x) {}
  static Quad raw(float128 x) {
    Quad q;
    q.v = x;
    return q;
  }
  explicit operator double() const { return static_cast<double>(v); }
  explicit operator long double() const { return static_cast<long double>(v); }
  friend Quad operator+(Quad a, Quad b) { return raw(a.v + b.v); }
  friend Quad operator-(Quad a, Quad b) { return raw(a.v - b.v); }
  friend Quad operator*(Quad a, Quad b) { return raw(a.v * b.v); }
  friend Quad operator/(Quad a, Quad b) { return raw(a.v / b.v); }
  friend Quad operator-(Quad a) { return raw(-a.v); }
  Quad& operator+=(Quad b) { return v += b.v, *this; }
  Quad& operator-=(Quad b) { return v -= b.v, *this; }
  Quad& operator*=(Quad b) { return v *= b.v, *this; }
  Quad& operator/=(Quad b) { return v /= b.v, *this; }
  friend bool operator<(Quad a, Quad b) { return a.v < b.v; }
  friend bool operator>(Quad a, Quad b) { return a.v > b.v; }
  friend bool operator<=(Quad a, Quad b) { return a.v <= b.v; }
  friend bool operator>=(Quad a, Quad b) { return a.v >= b.v; }
  friend bool operator==(Quad a, Quad b) { return a.v == b.v; }
  friend bool operator!=(Quad a, Quad b) { return a.v != b.v; }
  friend Quad abs(Quad a) { return raw(fabsq(a.v)); }
  friend Quad fabs(Quad a) { return raw(fabsq(a.v)); }
  friend Quad sqrt(Quad a) { return raw(sqrtq(a.v)); }
  friend Quad sin(Quad a) { return raw(sinq(a.v)); }
  friend Quad cos(Quad a) { return raw(cosq(a.v)); }
  friend Quad tan(Quad a) { return raw(tanq(a.v)); }
  friend Quad atan(Quad a) { return raw(atanq(a.v)); }
  friend Quad atan2(Quad a, Quad b) { return raw(atan2q(a.v, b.v)); }
  friend Quad sinh(Quad a) { return raw(sinhq(a.v)); }
  friend Quad cosh(Quad a) { return raw(coshq(a.v)); }
  friend Quad asinh(Quad a) { return raw(asinhq(a.v)); }
  friend Quad atanh(Quad a) { return raw(atanhq(a.v)); }
  friend Quad nextafter(Quad a, Quad b) { return raw(nextafterq(a.v, b.v)); }
};
inline std::string to_string(Quad q) {
  char buf[64];
  quadmath_snprintf(buf, sizeof buf, "%.36Qg", q.v);
  return buf;
}
#endif

}  // namespace kepler_test

#ifdef EOMC_HAVE_QUADMATH
template <>
class std::numeric_limits<kepler_test::Quad> {
 public:
  static constexpr bool is_specialized = true;
  static constexpr int digits = 113;
  static kepler_test::Quad epsilon() { return kepler_test::Quad::raw(scalbnq(1, 1 - digits)); }
  static kepler_test::Quad infinity() { return kepler_test::Quad::raw(__builtin_huge_valq()); }
};
#endif
