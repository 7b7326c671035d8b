#pragma once

// The no-progress checker: one object per integrate_* call that throws IntegrationError when the
// integration cannot go on (step underflow, exhausted step budget, non-finite state).

#include <cmath>
#include <cstddef>
#include <limits>

#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

// Index of the first component that is NaN or infinite, or IntegrationError::no_component.
template <class S>
std::size_t first_non_finite(const State<S>& v) {
  using std::isfinite;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!isfinite(v[i])) return i;
  return IntegrationError::no_component;
}

template <class S>
class NoProgressChecker {
 public:
  explicit NoProgressChecker(const Limits& limits) : limits_(limits) {}

  // Scale for the underflow test while |t| is small (see Limits::underflow_factor).
  void set_reference_step(S h) {
    using std::abs;
    h_ref_ = abs(h);
  }

  // Called before every step attempt; throws once max_steps attempts have been made.
  void count_attempt(S t) {
    if (attempts_ >= limits_.max_steps)
      throw IntegrationError::step_budget(t, limits_.max_steps);
    ++attempts_;
  }

  bool underflows(S t, S h) const {
    using std::abs;
    const S scale = abs(t) > h_ref_ ? abs(t) : h_ref_;
    return abs(h) < S(limits_.underflow_factor) * std::numeric_limits<S>::epsilon() * scale;
  }

  void check_step_size(S t, S h) const {
    if (underflows(t, h)) throw IntegrationError::step_underflow(t, h);
  }

  void check_state(S t, const State<S>& x) const { check_vector(t, x, "state"); }
  void check_derivative(S t, const State<S>& dxdt) const { check_vector(t, dxdt, "derivative"); }

  std::size_t attempts() const { return attempts_; }
  const Limits& limits() const { return limits_; }

 private:
  static void check_vector(S t, const State<S>& v, const char* what) {
    const std::size_t i = first_non_finite(v);
    if (i != IntegrationError::no_component) throw IntegrationError::non_finite(t, what, i);
  }

  Limits limits_;
  S h_ref_ = S(0);
  std::size_t attempts_ = 0;
};

}  // namespace eomc::runtime
