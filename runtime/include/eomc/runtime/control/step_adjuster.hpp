#pragma once

// The step adjuster of embedded Runge-Kutta pairs (I, PI or predictive controller). References:
//   [HNW] E. Hairer, S.P. Norsett, G. Wanner, Solving Ordinary Differential Equations I, 2nd ed.,
//         Springer 1993, Sect. II.4 (step-size selection);
//   [HW]  E. Hairer, G. Wanner, Solving Ordinary Differential Equations II, 2nd ed., Springer 1996,
//         Sect. IV.2 (PI control after Gustafsson), Sect. IV.8 (predictive control), and the
//         controller constants of Hairer's codes DOPRI5, DOP853 and RADAU5.

#include <cmath>
#include <stdexcept>

namespace eomc::runtime {

// Proposes the next step size from the error norm of the current attempt. With beta > 0 this is
// the PI controller of Gustafsson in the form of Hairer's codes:
//   factor = safety * err^-(1/(q+1) - beta_weight beta) * err_prev^beta,  clamped to [fac_min, fac_max],
// q the order of the error estimate (beta_weight is 0.75 in DOPRI5, 0.2 in DOP853); beta = 0 gives
// the classical controller safety*err^(-1/(q+1)). After a rejection the next accepted step may not
// grow (avoids accept/reject oscillation).
//
// predictive = true adds Gustafsson's predictive controller, in the form of Hairer's RADAU5
// ([HW] Sect. IV.8, (8.21)): after two accepted steps h_acc (error err_acc) and h (error err),
//   factor_pred = safety * (h / h_acc) * (err_acc / err^2)^(1/(q+1)),
// and the smaller of the two proposals is taken. The classical controller assumes that the error
// constant stays what it was at this step; when it grows from step to step (an eccentric orbit
// falling towards pericentre: err ~ r^-12 at fixed h) every accepted step is followed by a rejected
// one. The predictive term extrapolates the growth from the last two steps and shrinks in time.
template <class S>
class StepAdjuster {
 public:
  struct Settings {
    S safety = S(0.9);
    S fac_min = S(0.2);   // largest reduction per attempt
    S fac_max = S(10);    // largest growth per step
    S beta = S(0.04);     // PI weight; DOPRI5's default for its 5(4) pair
    S beta_weight = S(0.75);  // exponent 1/(q+1) - beta_weight * beta (DOPRI5: 0.75, DOP853: 0.2)
    bool predictive = false;  // also Gustafsson's predictive controller (see above)
  };

  explicit StepAdjuster(int error_order, Settings settings = {})
      : s_(settings), expo_(S(1) / S(error_order + 1) - settings.beta_weight * settings.beta),
        root_(error_order + 1) {
    if (!(s_.fac_min > S(0) && s_.fac_min < S(1) && s_.fac_max > S(1) && s_.safety > S(0) && s_.safety <= S(1) &&
          s_.beta >= S(0) && s_.beta_weight >= S(0) && expo_ > S(0)))
      throw std::invalid_argument(
          "StepAdjuster: need 0 < fac_min < 1 < fac_max, 0 < safety <= 1, beta >= 0, beta_weight >= 0");
  }

  // Growth factor for the next step after an accepted attempt of size h (either sign) with error
  // norm err <= 1. h is needed only by the predictive controller.
  S accepted(S err, S h = S(0)) {
    using std::abs;
    using std::pow;
    S fac = s_.fac_max;
    S root = S(0);  // err^-(1/(q+1)), when err > 0
    if (err > S(0)) {
      root = root_power(err);
      fac = s_.safety * (s_.beta == S(0) ? root : pow(err, -expo_));
      if (s_.beta > S(0)) fac *= pow(err_prev_, s_.beta);
      fac = clamp(fac);
    }
    if (s_.predictive) {
      // (err_acc / err^2)^(1/(q+1)) = root^2 * err_acc^(1/(q+1)); the last factor is kept from the
      // previous step, so a step costs one root, not two.
      if (h_acc_ > S(0) && err > S(0) && h != S(0)) {
        const S pred = clamp(s_.safety * (abs(h) / h_acc_) * root * root * acc_root_);
        if (pred < fac) fac = pred;
      }
      h_acc_ = abs(h);
      // RADAU5 floors err_acc at 1e-2: no prediction from a lucky step.
      acc_root_ = err > S(1e-2) ? S(1) / root : S(1) / root_power(S(1e-2));
    }
    if (rejected_last_ && fac > S(1)) fac = S(1);
    err_prev_ = err > err_floor ? err : err_floor;
    rejected_last_ = false;
    return fac;
  }

  // Reduction factor after a rejected attempt (err > 1, or not finite).
  S rejected(S err) {
    using std::isfinite;
    rejected_last_ = true;
    if (!isfinite(err)) return s_.fac_min;
    const S fac = s_.safety * inverse_power(err);
    return fac > s_.fac_min ? fac : s_.fac_min;
  }

  void reset() {
    err_prev_ = err_floor;
    rejected_last_ = false;
    h_acc_ = S(0);
    acc_root_ = S(1);
  }

  const Settings& settings() const { return s_; }

 private:
  // DOPRI5 starts and floors the remembered error at 1e-4, so one lucky step cannot inflate the next.
  static constexpr S err_floor = S(1e-4);

  S clamp(S f) const { return f < s_.fac_min ? s_.fac_min : (f > s_.fac_max ? s_.fac_max : f); }
  // x^-(1/(q+1)); for q + 1 = 2, 4, 8 (DOP853: 8) by square roots, which cost a fraction of pow
  // (a noticeable share of a step of a small system) and differ from it by an ulp or two, which a
  // step-size factor does not notice.
  S root_power(S x) const {
    using std::pow;
    using std::sqrt;
    if (root_ == 2 || root_ == 4 || root_ == 8) {
      S r = sqrt(x);
      if (root_ >= 4) r = sqrt(r);
      if (root_ == 8) r = sqrt(r);
      return S(1) / r;
    }
    return pow(x, -S(1) / S(root_));
  }

  // err^-expo.
  S inverse_power(S err) const {
    using std::pow;
    return s_.beta == S(0) ? root_power(err) : pow(err, -expo_);
  }

  Settings s_;
  S expo_;
  int root_;                       // q + 1
  S err_prev_ = err_floor;
  bool rejected_last_ = false;
  // The last accepted step and err_acc^(1/(q+1)) of its (floored) error, for `predictive`.
  S h_acc_ = S(0), acc_root_ = S(1);
};

}  // namespace eomc::runtime
