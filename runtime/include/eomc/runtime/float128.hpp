#pragma once

// float128: IEEE binary128 (113-bit significand, about 34 decimal digits) as a scalar the
// runtime and the generated kernels take like double, for reference solutions computed far
// beyond the precision of the runs they judge. GCC's __float128 does the arithmetic; the
// elementary functions come from libquadmath (link with -lquadmath).
//
// A class rather than the bare __float128 because generated kernels and the steppers call math
// functions as `using std::cos; cos(x)`: for __float128 that would pick std::cos(double) or
// fail, for a class type argument-dependent lookup finds the hidden friends below. Arithmetic
// and comparisons are constexpr (GCC folds __float128 in constant expressions), so method
// coefficients can be computed at compile time in full precision (see coefficients.hpp).
//
// Conversions from every arithmetic type are implicit (S(2), S(p.mu), x * 0.5 work as for
// double); conversions to them are explicit (static_cast<double>(x)), so no expression
// silently drops to double.

#include <quadmath.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <ostream>
#include <string>
#include <type_traits>

#include <Eigen/Core>

namespace eomc::runtime {

class float128 {
 public:
  using native_type = __float128;

  constexpr float128() = default;
  template <class A>
    requires std::is_arithmetic_v<A>
  constexpr float128(A a) : v_(static_cast<native_type>(a)) {}
  constexpr float128(native_type v) : v_(v) {}

  template <class A>
    requires std::is_arithmetic_v<A>
  explicit constexpr operator A() const {
    return static_cast<A>(v_);
  }
  constexpr native_type native() const { return v_; }

  constexpr float128& operator+=(float128 b) { v_ += b.v_; return *this; }
  constexpr float128& operator-=(float128 b) { v_ -= b.v_; return *this; }
  constexpr float128& operator*=(float128 b) { v_ *= b.v_; return *this; }
  constexpr float128& operator/=(float128 b) { v_ /= b.v_; return *this; }

  friend constexpr float128 operator+(float128 a) { return a; }
  friend constexpr float128 operator-(float128 a) { return float128(-a.v_); }
  friend constexpr float128 operator+(float128 a, float128 b) { return float128(a.v_ + b.v_); }
  friend constexpr float128 operator-(float128 a, float128 b) { return float128(a.v_ - b.v_); }
  friend constexpr float128 operator*(float128 a, float128 b) { return float128(a.v_ * b.v_); }
  friend constexpr float128 operator/(float128 a, float128 b) { return float128(a.v_ / b.v_); }

  friend constexpr bool operator==(float128 a, float128 b) { return a.v_ == b.v_; }
  friend constexpr bool operator!=(float128 a, float128 b) { return a.v_ != b.v_; }
  friend constexpr bool operator<(float128 a, float128 b) { return a.v_ < b.v_; }
  friend constexpr bool operator<=(float128 a, float128 b) { return a.v_ <= b.v_; }
  friend constexpr bool operator>(float128 a, float128 b) { return a.v_ > b.v_; }
  friend constexpr bool operator>=(float128 a, float128 b) { return a.v_ >= b.v_; }

  // Classification, constexpr through GCC's type-generic builtins.
  friend constexpr bool isnan(float128 a) { return __builtin_isnan(a.v_); }
  friend constexpr bool isinf(float128 a) { return __builtin_isinf(a.v_); }
  friend constexpr bool isfinite(float128 a) { return __builtin_isfinite(a.v_); }
  friend constexpr bool signbit(float128 a) { return __builtin_signbit(a.v_); }
  friend constexpr float128 abs(float128 a) { return a.v_ < 0 ? float128(-a.v_) : a; }
  friend constexpr float128 fabs(float128 a) { return abs(a); }

  // Everything generated kernels may call (generator/model/functions.hpp, sqrt and pow) and what
  // the steppers and Eigen use, from libquadmath.
  friend float128 sqrt(float128 a) { return sqrtq(a.v_); }
  friend float128 cbrt(float128 a) { return cbrtq(a.v_); }
  friend float128 exp(float128 a) { return expq(a.v_); }
  friend float128 expm1(float128 a) { return expm1q(a.v_); }
  friend float128 log(float128 a) { return logq(a.v_); }
  friend float128 log1p(float128 a) { return log1pq(a.v_); }
  friend float128 log2(float128 a) { return log2q(a.v_); }
  friend float128 log10(float128 a) { return log10q(a.v_); }
  friend float128 pow(float128 a, float128 b) { return powq(a.v_, b.v_); }
  friend float128 sin(float128 a) { return sinq(a.v_); }
  friend float128 cos(float128 a) { return cosq(a.v_); }
  friend float128 tan(float128 a) { return tanq(a.v_); }
  friend float128 asin(float128 a) { return asinq(a.v_); }
  friend float128 acos(float128 a) { return acosq(a.v_); }
  friend float128 atan(float128 a) { return atanq(a.v_); }
  friend float128 atan2(float128 y, float128 x) { return atan2q(y.v_, x.v_); }
  friend float128 sinh(float128 a) { return sinhq(a.v_); }
  friend float128 cosh(float128 a) { return coshq(a.v_); }
  friend float128 tanh(float128 a) { return tanhq(a.v_); }
  friend float128 asinh(float128 a) { return asinhq(a.v_); }
  friend float128 acosh(float128 a) { return acoshq(a.v_); }
  friend float128 atanh(float128 a) { return atanhq(a.v_); }
  friend float128 hypot(float128 a, float128 b) { return hypotq(a.v_, b.v_); }
  friend float128 fmod(float128 a, float128 b) { return fmodq(a.v_, b.v_); }
  friend float128 floor(float128 a) { return floorq(a.v_); }
  friend float128 ceil(float128 a) { return ceilq(a.v_); }
  friend float128 trunc(float128 a) { return truncq(a.v_); }
  friend float128 round(float128 a) { return roundq(a.v_); }
  friend float128 fma(float128 a, float128 b, float128 c) { return fmaq(a.v_, b.v_, c.v_); }
  friend float128 ldexp(float128 a, int e) { return ldexpq(a.v_, e); }
  friend float128 frexp(float128 a, int* e) { return frexpq(a.v_, e); }
  friend float128 copysign(float128 a, float128 b) { return copysignq(a.v_, b.v_); }
  friend float128 nextafter(float128 a, float128 b) { return nextafterq(a.v_, b.v_); }
  friend constexpr float128 fmin(float128 a, float128 b) { return b < a ? b : a; }
  friend constexpr float128 fmax(float128 a, float128 b) { return a < b ? b : a; }

 private:
  native_type v_ = 0;
};

// Decimal text with `digits` significant digits (36 = enough to read the same value back).
inline std::string to_string(float128 x, int digits = 36) {
  char buf[64];
  quadmath_snprintf(buf, sizeof buf, "%.*Qg", digits, x.native());
  return buf;
}

// Parses decimal text (strtoflt128); the whole string must be a number.
inline float128 float128_from_string(const std::string& text, bool* ok = nullptr) {
  char* end = nullptr;
  const __float128 v = strtoflt128(text.c_str(), &end);
  if (ok) *ok = !text.empty() && end == text.c_str() + text.size();
  return v;
}

// Written with the stream's precision (default 6 significant digits, as for double).
inline std::ostream& operator<<(std::ostream& out, float128 x) {
  return out << to_string(x, static_cast<int>(out.precision()));
}

namespace detail {
// 2^e by repeated doubling or halving: exact, and evaluated at compile time for the limits below.
constexpr __float128 f128_pow2(int e) {
  __float128 r = 1;
  for (; e > 0; --e) r *= 2;
  for (; e < 0; ++e) r /= 2;
  return r;
}
inline constexpr __float128 f128_epsilon = f128_pow2(-112);
inline constexpr __float128 f128_min = f128_pow2(-16382);
inline constexpr __float128 f128_denorm_min = f128_pow2(-16494);
inline constexpr __float128 f128_max = (2 - f128_pow2(-112)) * f128_pow2(16383);
}  // namespace detail

}  // namespace eomc::runtime

template <>
class std::numeric_limits<eomc::runtime::float128> {
  using T = eomc::runtime::float128;

 public:
  static constexpr bool is_specialized = true;
  static constexpr T min() noexcept { return eomc::runtime::detail::f128_min; }
  static constexpr T max() noexcept { return eomc::runtime::detail::f128_max; }
  static constexpr T lowest() noexcept { return -eomc::runtime::detail::f128_max; }
  static constexpr int digits = 113;
  static constexpr int digits10 = 33;
  static constexpr int max_digits10 = 36;
  static constexpr bool is_signed = true;
  static constexpr bool is_integer = false;
  static constexpr bool is_exact = false;
  static constexpr int radix = 2;
  static constexpr T epsilon() noexcept { return eomc::runtime::detail::f128_epsilon; }
  static constexpr T round_error() noexcept { return T(0.5); }
  static constexpr int min_exponent = -16381;
  static constexpr int min_exponent10 = -4931;
  static constexpr int max_exponent = 16384;
  static constexpr int max_exponent10 = 4932;
  static constexpr bool has_infinity = true;
  static constexpr bool has_quiet_NaN = true;
  static constexpr bool has_signaling_NaN = true;
  static constexpr float_denorm_style has_denorm = denorm_present;
  static constexpr bool has_denorm_loss = false;
  static constexpr T infinity() noexcept { return T(__builtin_huge_valq()); }
  static constexpr T quiet_NaN() noexcept { return T(__builtin_nanq("")); }
  static constexpr T signaling_NaN() noexcept { return T(__builtin_nansq("")); }
  static constexpr T denorm_min() noexcept { return eomc::runtime::detail::f128_denorm_min; }
  static constexpr bool is_iec559 = true;
  static constexpr bool is_bounded = true;
  static constexpr bool is_modulo = false;
  static constexpr bool traps = false;
  static constexpr bool tinyness_before = false;
  static constexpr float_round_style round_style = round_to_nearest;
};

// Eigen (Gauss-Legendre's LU, the kernels' LDLT for n > 2) over float128.
template <>
struct Eigen::NumTraits<eomc::runtime::float128> : Eigen::GenericNumTraits<eomc::runtime::float128> {
  using Real = eomc::runtime::float128;
  using NonInteger = eomc::runtime::float128;
  using Literal = eomc::runtime::float128;
  using Nested = eomc::runtime::float128;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 2,
    AddCost = 4,  // software arithmetic: tens of cycles per operation
    MulCost = 4
  };
  static inline Real epsilon() { return std::numeric_limits<Real>::epsilon(); }
  static inline Real dummy_precision() { return Real(1e-30); }
  static inline Real highest() { return std::numeric_limits<Real>::max(); }
  static inline Real lowest() { return std::numeric_limits<Real>::lowest(); }
  static inline int digits10() { return std::numeric_limits<Real>::digits10; }
};
