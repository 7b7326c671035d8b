#pragma once

// Step control for embedded Runge-Kutta pairs: the error checker (weighted RMS norm), the step
// adjuster (I or PI controller) and the starting-step heuristic. References:
//   [HNW] E. Hairer, S.P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.,
//         Springer 1993, Sect. II.4 (error norm, step-size selection, starting step size);
//   [HW]  E. Hairer, G. Wanner, ... II, Sect. IV.2 (PI control after Gustafsson), and the
//         controller constants of Hairer's code DOPRI5.

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
    using std::abs;
    using std::sqrt;
    if (e.empty()) return S(0);
    S sum = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const S xo = abs(x_old[i]), xn = abs(x_new[i]);
      const S sc = atol_ + rtol_ * (xo > xn ? xo : xn);
      // Pure relative control (atol = 0) at an exact zero: a zero error is fine, any other is not.
      const S r = sc > S(0) ? e[i] / sc : (e[i] == S(0) ? S(0) : std::numeric_limits<S>::infinity());
      sum += r * r;
    }
    return sqrt(sum / S(e.size()));
  }

 private:
  S rtol_, atol_;
};

// Proposes the next step size from the error norm of the current attempt. With beta > 0 this is
// the PI controller of Gustafsson in the form Hairer's DOPRI5 uses:
//   factor = safety * err^-(1/(q+1) - 0.75 beta) * err_prev^beta,  clamped to [fac_min, fac_max],
// q the order of the error estimate; beta = 0 gives the classical controller safety*err^(-1/(q+1)).
// After a rejection the next accepted step may not grow (avoids accept/reject oscillation).
template <class S>
class StepAdjuster {
 public:
  struct Settings {
    S safety = S(0.9);
    S fac_min = S(0.2);   // largest reduction per attempt
    S fac_max = S(10);    // largest growth per step
    S beta = S(0.04);     // PI weight; DOPRI5's default for its 5(4) pair
  };

  explicit StepAdjuster(int error_order, Settings settings = {})
      : s_(settings), expo_(S(1) / S(error_order + 1) - S(0.75) * settings.beta) {
    if (!(s_.fac_min > S(0) && s_.fac_min < S(1) && s_.fac_max > S(1) && s_.safety > S(0) && s_.safety <= S(1) &&
          s_.beta >= S(0) && expo_ > S(0)))
      throw std::invalid_argument("StepAdjuster: need 0 < fac_min < 1 < fac_max, 0 < safety <= 1, beta >= 0");
  }

  // Growth factor for the next step after an accepted attempt with error norm err <= 1.
  S accepted(S err) {
    using std::pow;
    S fac = s_.fac_max;
    if (err > S(0)) {
      fac = s_.safety * pow(err, -expo_) * pow(err_prev_, s_.beta);
      fac = clamp(fac);
    }
    if (rejected_last_ && fac > S(1)) fac = S(1);
    err_prev_ = err > err_floor ? err : err_floor;
    rejected_last_ = false;
    return fac;
  }

  // Reduction factor after a rejected attempt (err > 1, or not finite).
  S rejected(S err) {
    using std::isfinite;
    using std::pow;
    rejected_last_ = true;
    if (!isfinite(err)) return s_.fac_min;
    const S fac = s_.safety * pow(err, -expo_);
    return fac > s_.fac_min ? fac : s_.fac_min;
  }

  void reset() {
    err_prev_ = err_floor;
    rejected_last_ = false;
  }

  const Settings& settings() const { return s_; }

 private:
  // DOPRI5 starts and floors the remembered error at 1e-4, so one lucky step cannot inflate the next.
  static constexpr S err_floor = S(1e-4);

  S clamp(S f) const { return f < s_.fac_min ? s_.fac_min : (f > s_.fac_max ? s_.fac_max : f); }

  Settings s_;
  S expo_;
  S err_prev_ = err_floor;
  bool rejected_last_ = false;
};

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
