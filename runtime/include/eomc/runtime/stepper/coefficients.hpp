#pragma once

// Method coefficients written once as decimal literals and rounded to each scalar type.
//
// A coefficient keeps both its long double value and its decimal text:
//   EOMC_COEFFICIENT(0.526001519587677318785587544488e-01)
// is {0.526001519587677318785587544488e-01L, "0.526001519587677318785587544488e-01"}. Scalars no
// wider than long double get the long double value rounded once (so double and long double
// results are those of plain long double literals); a wider scalar (float128) reads the digits
// in its own arithmetic, so a 30-digit coefficient is good to 30 digits there instead of the 19
// a long double literal carries. Reading happens in constant expressions, once per type.

#include <limits>

namespace eomc::runtime::detail {

struct Coefficient {
  long double value;
  const char* digits;
};

// [+-]digits[.digits][(e|E)[+-]digits], read in S: the significand as an integer (exact while it
// has at most 34 digits in float128), then one multiplication or division by an exact power of ten
// (10^k is exact in float128 for k <= 48), so the result is within about an ulp of the decimal.
template <class S>
constexpr S parse_decimal(const char* s) {
  bool negative = false;
  if (*s == '-' || *s == '+') negative = *s++ == '-';
  S significand = S(0);
  int exponent = 0;
  bool fraction = false;
  for (; *s != '\0' && *s != 'e' && *s != 'E'; ++s) {
    if (*s == '.') {
      fraction = true;
      continue;
    }
    significand = significand * S(10) + S(*s - '0');
    if (fraction) --exponent;
  }
  if (*s == 'e' || *s == 'E') {
    ++s;
    bool negative_exponent = false;
    if (*s == '-' || *s == '+') negative_exponent = *s++ == '-';
    int e = 0;
    for (; *s != '\0'; ++s) e = 10 * e + (*s - '0');
    exponent += negative_exponent ? -e : e;
  }
  S scale = S(1);
  for (int k = 0; k < (exponent < 0 ? -exponent : exponent); ++k) scale *= S(10);
  const S magnitude = exponent < 0 ? significand / scale : significand * scale;
  return negative ? -magnitude : magnitude;
}

template <class S>
inline constexpr bool wider_than_long_double =
    std::numeric_limits<S>::is_specialized &&
    std::numeric_limits<S>::digits > std::numeric_limits<long double>::digits;

// The coefficient rounded to S. A value-initialised Coefficient (no digits) is zero.
template <class S>
constexpr S coefficient(const Coefficient& c) {
  if constexpr (wider_than_long_double<S>)
    return c.digits ? parse_decimal<S>(c.digits) : S(0);
  else
    return S(c.value);
}

}  // namespace eomc::runtime::detail

// The argument is a plain decimal literal without suffix (a leading minus sign is allowed).
#define EOMC_COEFFICIENT(x) ::eomc::runtime::detail::Coefficient{x##L, #x}
