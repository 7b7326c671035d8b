#pragma once

// The starting step size of an adaptive method. Reference: [HNW] E. Hairer, S.P. Norsett,
// G. Wanner, Solving Ordinary Differential Equations I, 2nd ed., Springer 1993, Sect. II.4,
// "Starting Step Size".

#include <cmath>
#include <cstddef>

#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

// Starting step size [HNW, Sect. II.4, "Starting Step Size"], with the RMS norm weighted by
// sc_i = atol + rtol*|x0_i|:  h0 = 0.01*||x0||/||f0||, one explicit Euler step of h0 to estimate
// the second derivative d2, then h = min(100*h0, (0.01/max(||f0||, d2))^(1/(q+1))), q = error
// order; the result is at most hmax. Returns a magnitude; dir (+1 or -1) is the direction of
// integration. f0 = f(t0, x0) is supplied by the caller; the one extra system call is added to
// rhs_evals.
template <class S, class Sys>
  requires System<Sys, S>
S initial_step(Sys& sys, S t0, const State<S>& x0, const State<S>& f0, S dir, int error_order,
               const Tolerances& tol, S hmax, std::size_t& rhs_evals) {
  using std::abs;
  using std::isfinite;
  using std::pow;
  using std::sqrt;
  const std::size_t n = x0.size();
  if (n == 0) return hmax;
  const S rtol = S(tol.rtol), atol = S(tol.atol);
  S d0 = 0, d1 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const S sc = atol + rtol * abs(x0[i]);
    d0 += (x0[i] / sc) * (x0[i] / sc);
    d1 += (f0[i] / sc) * (f0[i] / sc);
  }
  d0 = sqrt(d0 / S(n));
  d1 = sqrt(d1 / S(n));
  S h0 = (d0 < S(1e-5) || d1 < S(1e-5)) ? S(1e-6) : S(0.01) * d0 / d1;
  if (h0 > hmax) h0 = hmax;

  State<S> x1(n), f1(n);
  for (std::size_t i = 0; i < n; ++i) x1[i] = x0[i] + dir * h0 * f0[i];
  sys(t0 + dir * h0, static_cast<const State<S>&>(x1), f1);
  ++rhs_evals;
  S d2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const S sc = atol + rtol * abs(x0[i]);
    d2 += ((f1[i] - f0[i]) / sc) * ((f1[i] - f0[i]) / sc);
  }
  d2 = sqrt(d2 / S(n)) / h0;
  // A non-finite Euler probe (singular or blowing-up system): keep the first guess and let the
  // controller shrink it.
  if (!isfinite(d2)) return h0;

  const S dmax = d1 > d2 ? d1 : d2;
  S h1 = dmax <= S(1e-15) ? (h0 * S(1e-3) > S(1e-6) ? h0 * S(1e-3) : S(1e-6))
                          : pow(S(0.01) / dmax, S(1) / S(error_order + 1));
  S h = S(100) * h0 < h1 ? S(100) * h0 : h1;
  return h < hmax ? h : hmax;
}

}  // namespace eomc::runtime
