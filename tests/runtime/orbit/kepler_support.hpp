#pragma once

// Shared by the Kepler tests: ulps, the reference residuals (evaluated in a wider type without
// cancellation, written here independently of the solver), and the quad scalar.

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "eomc/runtime/float128.hpp"

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

// The 113-bit reference and class-type scalar: the runtime's own float128 (hidden-friend math
// found by ADL, which is what checks that the Kepler runtime is generic in the scalar).
using Quad = eomc::runtime::float128;

}  // namespace kepler_test
