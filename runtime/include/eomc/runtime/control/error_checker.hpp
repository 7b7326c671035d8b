#pragma once

// The error checker of embedded Runge-Kutta pairs: the weighted RMS norm of the local error
// estimate. Reference: [HNW] E. Hairer, S.P. Norsett, G. Wanner, Solving Ordinary Differential
// Equations I, 2nd ed., Springer 1993, Sect. II.4, (4.10)-(4.11).

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

inline void validate(const Tolerances& tol) {
  if (!(tol.rtol >= 0.0) || !(tol.atol >= 0.0) || (tol.rtol == 0.0 && tol.atol == 0.0))
    throw std::invalid_argument("tolerances must be non-negative and not both zero");
}

// err = sqrt( (1/n) sum_i (e_i / sc_i)^2 ),  sc_i = atol + rtol * max(|x_i|, |x_new_i|)   [HNW (4.10)-(4.11)]
// A step is acceptable when err <= 1.
template <class S>
class ErrorChecker {
 public:
  explicit ErrorChecker(const Tolerances& tol) : rtol_(S(tol.rtol)), atol_(S(tol.atol)) {}

  S norm(const State<S>& e, const State<S>& x_old, const State<S>& x_new) const {
    using std::sqrt;
    if (e.empty()) return S(0);
    S sum = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const S r = ratio(e[i], scale(x_old[i], x_new[i]));
      sum += r * r;
    }
    return sqrt(sum / S(e.size()));
  }

  // sc_i for the old and new value of one component.
  S scale(S x_old, S x_new) const {
    using std::abs;
    const S xo = abs(x_old), xn = abs(x_new);
    return atol_ + rtol_ * (xo > xn ? xo : xn);
  }

  // e_i / sc_i. Pure relative control (atol = 0) at an exact zero: a zero error is fine, any other is not.
  static S ratio(S e, S sc) {
    return sc > S(0) ? e / sc : (e == S(0) ? S(0) : std::numeric_limits<S>::infinity());
  }

 private:
  S rtol_, atol_;
};

}  // namespace eomc::runtime
