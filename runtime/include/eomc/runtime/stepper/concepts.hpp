#pragma once

// What the drivers and the step controller ask of a stepper, as C++20 concepts. The split follows
// Boost.Odeint's stepper categories (error stepper, controlled stepper, dense-output stepper; K.
// Ahnert, M. Mulansky, AIP Conf. Proc. 1389 (2011) 1586-1589), in this runtime's calling
// convention: systems sys(t, x, dxdt) on State<S>, time and step passed by value or reference.
//
// The fixed-step contract (do_step and rhs_evals) is FixedStepper in integrate.hpp: it is checked
// against the caller's own system, since the splitting methods take an acceleration instead.

#include <concepts>
#include <cstddef>

#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

namespace detail {

// A stand-in system for checking the concepts below: any System behaves alike to a stepper.
template <class S>
struct SystemArchetype {
  void operator()(S, const State<S>&, State<S>&) const {}
};

template <class E, class S>
concept error_stepper_for = requires(E& e, const E& ce, SystemArchetype<S>& sys, State<S>& x, const State<S>& cx,
                                     S t, const ErrorChecker<S>& checker, const S* carry, S* carry_next) {
  { E::order } -> std::convertible_to<int>;
  { E::error_order } -> std::convertible_to<int>;
  { E::name } -> std::convertible_to<const char*>;
  // k1 = f(t, x) into the stepper's first stage (sized to x), and read back.
  e.evaluate_first(sys, t, cx);
  { ce.first_derivative() } -> std::same_as<const State<S>&>;
  // The stages of a step of h from (t, x) with k1 in place: the new state is kept, the error norm
  // returned. carry/carry_next: the compensated summation's carry in and out (null when off).
  { e.attempt(sys, cx, t, t, checker, carry, carry_next) } -> std::same_as<S>;
  // The same stages without the error estimate.
  e.advance(sys, cx, t, t, carry, carry_next);
  // Commits the last attempt: x becomes the new state, k1 becomes f(t + h, x) (FSAL), the dense
  // output describes the step.
  e.accept(sys, x, t, t);
  { ce.locate_non_finite() } -> std::same_as<std::size_t>;
  { ce.current_time() } -> std::same_as<S>;
  { ce.rhs_evals() } -> std::same_as<std::size_t>;
  e.invalidate_dense_output();
};

template <class St, class S>
concept adaptive_stepper_for = requires(St& st, const St& cst, SystemArchetype<S>& sys, State<S>& x,
                                        const State<S>& cx, S t, S& t_ref, S& h, const Tolerances& tol) {
  { St::order } -> std::convertible_to<int>;
  { St::error_order } -> std::convertible_to<int>;
  { st.prepare(sys, cx, t) } -> std::same_as<const State<S>&>;
  { st.try_step(sys, x, t_ref, h, tol) } -> std::same_as<bool>;
  { cst.derivative() } -> std::same_as<const State<S>&>;
  { cst.last_non_finite_component() } -> std::same_as<std::size_t>;
  { cst.rhs_evals() } -> std::convertible_to<std::size_t>;
  st.reset();
};

template <class St, class S>
concept dense_output_stepper_for = requires(const St& cst, S t, State<S>& out) {
  cst.calc_state(t, out);
  { cst.previous_time() } -> std::same_as<S>;
  { cst.current_time() } -> std::same_as<S>;
  { cst.has_dense_output() } -> std::same_as<bool>;
};

}  // namespace detail

// An embedded Runge-Kutta pair: one step and its local error estimate, nothing decided
// (ControlledStepper decides; control/controlled.hpp).
template <class E>
concept ErrorStepper = requires { typename E::value_type; } && detail::error_stepper_for<E, typename E::value_type>;

// A stepper that chooses its own step sizes: try_step accepts or rejects an attempt and proposes
// the next h (integrate_adaptive and the other adaptive drivers).
template <class St>
concept AdaptiveStepper = requires { typename St::value_type; } &&
                          detail::adaptive_stepper_for<St, typename St::value_type>;

// A stepper with a continuous solution over its last accepted step (integrate_times, event location).
template <class St>
concept DenseOutputStepper = requires { typename St::value_type; } &&
                             detail::dense_output_stepper_for<St, typename St::value_type>;

}  // namespace eomc::runtime
