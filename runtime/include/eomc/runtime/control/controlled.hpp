#pragma once

// One controlled stepper over any embedded Runge-Kutta pair: the error stepper computes a step and
// its local error estimate, the error checker measures it, the step adjuster proposes the next
// step size. The structure is that of Boost.Odeint's controlled_runge_kutta (K. Ahnert,
// M. Mulansky, "Odeint - solving ordinary differential equations in C++", AIP Conf. Proc. 1389
// (2011) 1586-1589); the control itself is [HNW] E. Hairer, S.P. Norsett, G. Wanner, Solving
// Ordinary Differential Equations I, 2nd ed., Springer 1993, Sect. II.4.
//
// Written once here: the first-same-as-last (FSAL) bookkeeping (prepare), the compensated
// summation's carry, the accept/reject tail of an attempt, and reset(). The error stepper owns its
// stages, its error estimate and its dense output (see ErrorStepper in stepper/concepts.hpp).

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/control/step_adjuster.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"

namespace eomc::runtime {

template <ErrorStepper E, class Adjuster = StepAdjuster<typename E::value_type>,
          class Checker = ErrorChecker<typename E::value_type>>
class ControlledStepper {
  using S = typename E::value_type;

 public:
  using value_type = S;
  using error_stepper_type = E;
  using Settings = typename Adjuster::Settings;
  static constexpr int order = E::order, error_order = E::error_order;

  explicit ControlledStepper(E stepper = {}, Settings settings = {})
      : stepper_(std::move(stepper)), adjuster_(error_order, settings) {}

  // Makes k1 = f(t, x) available and returns it. Reuses the FSAL derivative when (t, x) is exactly
  // the end point of the last step, so a state the user edited between steps (an impulse, a
  // projection, an event action) is never paired with a stale derivative.
  template <class Sys>
    requires System<Sys, value_type>
  const State<S>& prepare(Sys& sys, const State<S>& x, S t) {
    if (!(k1_valid_ && t == t_k1_ && x == x_k1_)) {
      // The compensation belongs to x: kept when only t moved (a fixed-step caller computing
      // t afresh), dropped for an edited state or after reset().
      if (!(k1_valid_ && x == x_k1_)) comp_.assign(x.size(), S(0));
      if (comp_new_.size() != x.size()) comp_new_.assign(x.size(), S(0));
      stepper_.evaluate_first(sys, t, x);
      x_k1_ = x;
      t_k1_ = t;
      k1_valid_ = true;
    }
    return stepper_.first_derivative();
  }

  // One controlled attempt from (t, x) with step h (either sign). Accepted: advances t and x, sets h
  // to the proposed next step, returns true. Rejected: leaves t and x, reduces h, returns false.
  // An attempt whose error norm is NaN or infinite (overflow, a system undefined past some point)
  // is rejected with the largest reduction; last_non_finite_component() then names the first
  // derivative component that went non-finite.
  template <class Sys>
    requires System<Sys, value_type>
  bool try_step(Sys& sys, State<S>& x, S& t, S& h, const Tolerances& tol) {
    using std::isfinite;
    if (h == S(0)) throw std::invalid_argument(std::string(E::name) + "::try_step: zero step size");
    prepare(sys, x, t);
    last_error_ = stepper_.attempt(sys, x, t, h, Checker(tol), compensation(), compensation_next());
    if (isfinite(last_error_) && last_error_ <= S(1)) {
      non_finite_component_ = IntegrationError::no_component;
      commit(sys, x, t, h);
      t = stepper_.current_time();
      h *= adjuster_.accepted(last_error_, h);
      return true;
    }
    non_finite_component_ = isfinite(last_error_) ? IntegrationError::no_component : stepper_.locate_non_finite();
    h *= adjuster_.rejected(last_error_);
    return false;
  }

  // A plain step of the higher-order method, no error control (fixed-step use, order tests).
  // Updates the FSAL derivative and the dense output like an accepted step.
  template <class Sys>
    requires System<Sys, value_type>
  void do_step(Sys& sys, State<S>& x, S t, S h) {
    prepare(sys, x, t);
    stepper_.advance(sys, x, t, h, compensation(), compensation_next());
    commit(sys, x, t, h);
  }

  // Dense output on the last accepted step [previous_time(), current_time()].
  void calc_state(S tau, State<S>& out) const { stepper_.calc_state(tau, out); }

  S previous_time() const { return stepper_.previous_time(); }
  S current_time() const { return stepper_.current_time(); }
  // f(current_time(), x) after an accepted step (the FSAL stage), or f(t, x) after prepare().
  const State<S>& derivative() const { return stepper_.first_derivative(); }
  // Error norm of the last attempt (<= 1 means accepted).
  S last_error() const { return last_error_; }
  // After a rejection caused by non-finite values: the first non-finite component of the earliest
  // stage derivative (or of the new state), else IntegrationError::no_component.
  std::size_t last_non_finite_component() const { return non_finite_component_; }
  bool has_dense_output() const { return stepper_.has_dense_output(); }
  std::size_t rhs_evals() const { return stepper_.rhs_evals(); }
  Adjuster& adjuster() { return adjuster_; }
  const E& error_stepper() const { return stepper_; }
  // Compensated (Kahan) summation of x_{n+1} = x_n + h sum b_i k_i (off by default): the
  // compensation is carried from accepted step to accepted step and dropped whenever the FSAL
  // derivative is (an edited state, another time, reset()).
  void set_compensated(bool on) {
    compensated_ = on;
    k1_valid_ = false;
  }
  bool compensated() const { return compensated_; }

  // Forgets the FSAL derivative, the dense output and the controller's memory. Call it when the
  // system itself changes (parameters, switched dynamics); state edits are detected automatically.
  void reset() {
    k1_valid_ = false;
    stepper_.invalidate_dense_output();
    adjuster_.reset();
    non_finite_component_ = IntegrationError::no_component;
  }

 private:
  const S* compensation() const { return compensated_ ? comp_.data() : nullptr; }
  S* compensation_next() { return compensated_ ? comp_new_.data() : nullptr; }

  // The accepted step (t, x) -> (t + h, y): the error stepper writes y into x, its dense output
  // and the FSAL derivative f(t + h, y); the carry and the FSAL point follow.
  template <class Sys>
  void commit(Sys& sys, State<S>& x, S t, S h) {
    stepper_.accept(sys, x, t, h);
    if (compensated_) comp_.swap(comp_new_);
    x_k1_ = x;
    t_k1_ = stepper_.current_time();
  }

  E stepper_;
  Adjuster adjuster_;
  State<S> x_k1_;             // the state at which k1 = f(t_k1_, x_k1_) was evaluated
  State<S> comp_, comp_new_;  // compensation of x, and of the attempted step's new state
  bool compensated_ = false;
  S t_k1_ = S(0);
  S last_error_ = S(0);
  bool k1_valid_ = false;
  std::size_t non_finite_component_ = IntegrationError::no_component;
};

}  // namespace eomc::runtime
