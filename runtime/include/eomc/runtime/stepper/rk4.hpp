#pragma once

// The classical fourth-order Runge-Kutta method (Kutta 1901; [HNW] Table 1.2 of Sect. II.1),
// a fixed-step stepper without error estimate. Optionally with compensated (Kahan) summation of
// x += increment, as the symplectic methods do by default ([GNI] Sect. VIII.5): the bits each
// update loses are carried into the next one, so round-off grows like a random walk in the
// increments' errors rather than in eps |x| per step. The compensation is dropped when x differs
// from what the last step returned (an edited state) or after reset().

#include <cstddef>

#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

template <class S>
class Rk4 {
 public:
  using value_type = S;
  static constexpr int order = 4;

  // Advances x from t to t + h in place.
  template <class Sys>
    requires System<Sys, S>
  void do_step(Sys& sys, State<S>& x, S t, S h) {
    const std::size_t n = x.size();
    resize(n);
    const S h2 = h / S(2), h6 = h / S(6);
    const State<S>& xc = x;
    sys(t, xc, k1_);
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i] + h2 * k1_[i];
    sys(t + h2, cy(), k2_);
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i] + h2 * k2_[i];
    sys(t + h2, cy(), k3_);
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i] + h * k3_[i];
    sys(t + h, cy(), k4_);
    if (compensated_) {
      if (comp_.size() != n || x != x_last_) comp_.assign(n, S(0));
      for (std::size_t i = 0; i < n; ++i) {
        const S y = h6 * (k1_[i] + S(2) * (k2_[i] + k3_[i]) + k4_[i]) - comp_[i];
        const S sum = x[i] + y;
        comp_[i] = (sum - x[i]) - y;
        x[i] = sum;
      }
      x_last_ = x;
    } else {
      for (std::size_t i = 0; i < n; ++i) x[i] += h6 * (k1_[i] + S(2) * (k2_[i] + k3_[i]) + k4_[i]);
    }
    rhs_evals_ += 4;
  }

  // Compensated summation of the update (off by default).
  void set_compensated(bool on) {
    compensated_ = on;
    reset();
  }
  bool compensated() const { return compensated_; }

  // System calls made by this stepper since construction.
  std::size_t rhs_evals() const { return rhs_evals_; }
  // Forgets the compensation (the only state kept between steps).
  void reset() {
    comp_.clear();
    x_last_.clear();
  }

 private:
  const State<S>& cy() const { return y_; }
  void resize(std::size_t n) {
    if (y_.size() == n) return;
    k1_.assign(n, S(0));
    k2_.assign(n, S(0));
    k3_.assign(n, S(0));
    k4_.assign(n, S(0));
    y_.assign(n, S(0));
  }

  State<S> k1_, k2_, k3_, k4_, y_;
  State<S> comp_, x_last_;  // compensation, and the state it belongs to
  bool compensated_ = false;
  std::size_t rhs_evals_ = 0;
};

}  // namespace eomc::runtime
