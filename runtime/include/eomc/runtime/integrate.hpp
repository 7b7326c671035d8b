#pragma once

// Integration drivers: fixed-step, adaptive (observer after every accepted step) and adaptive
// with output at prescribed times through dense output, and both kinds with event location. Each call owns one NoProgressChecker.
// The stepper and the system are taken by reference and keep their state after the call.

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/stepper/dopri5.hpp"
#include "eomc/runtime/events.hpp"
#include "eomc/runtime/stepper/rk4.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"
#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/control/initial_step.hpp"

namespace eomc::runtime {

// Anything with do_step(sys, x, t, h) and rhs_evals(): Rk4, Dopri5 (fifth-order fixed step).
template <class Stepper, class Sys, class S>
concept FixedStepper = System<Sys, S> && requires(Stepper& st, Sys& sys, State<S>& x, S t) {
  st.do_step(sys, x, t, t);
  { st.rhs_evals() } -> std::convertible_to<std::size_t>;
};

// A system that edits its state between steps: project(t, x) maps x back onto a manifold (a unit
// quaternion, constraint rows) or changes its variables without changing the motion (Encke's
// rectification, which needs t). The drivers call it after every accepted step, with the step's
// end time, before the observer and the events see the step: what they see is the state the
// integration goes on from (a CSV row on the rows to round-off, not to the step's tolerance). The
// events are located on the dense output, which describes the step as integrated, and each
// located state is projected in turn; an edited state is projected again. The steppers notice the
// edited state and recompute their first-same-as-last derivative and drop the compensation.
template <class Sys, class S>
concept Projecting = requires(Sys& sys, S t, State<S>& x) { sys.project(t, x); };

namespace detail {

// project(t, x) of a Projecting system, as a callable; nothing for the others.
template <class S, class Sys>
auto projection(Sys& sys) {
  return [&sys](S t, State<S>& x) {
    if constexpr (Projecting<Sys, S>) sys.project(t, x);
  };
}

// How a step's callback ends it: go on, stop the loop, or restart from the (t, x) it wrote (a state
// edited at an event; the loop then resets the stepper).
enum class StepEnd { go_on, stop, restart };

// on_step(t_old, t_new, x) may return void, or bool (false stops the loop after that step), or
// StepEnd: then it is called with t_new and x as lvalues it may overwrite for a restart, with a
// state already projected (the loop projects before the callback, not after it).
template <class F, class S>
inline constexpr bool restarts = std::is_same_v<std::invoke_result_t<F&, S, S&, State<S>&>, StepEnd>;

template <class F, class S>
StepEnd step_end(F& f, S t_old, S& t_new, State<S>& x) {
  if constexpr (restarts<F, S>) {
    return f(t_old, t_new, x);
  } else if constexpr (std::is_same_v<std::invoke_result_t<F&, S, S, const State<S>&>, bool>) {
    return f(t_old, t_new, static_cast<const State<S>&>(x)) ? StepEnd::go_on : StepEnd::stop;
  } else {
    f(t_old, t_new, static_cast<const State<S>&>(x));
    return StepEnd::go_on;
  }
}

// The fixed-step loop shared by integrate_fixed and integrate_fixed_events (see integrate_fixed);
// before_step(t, x) runs before each step, on_step(t_old, t_new, x) after it.
template <class Stepper, class S, class Sys, class Before, class OnStep>
Stats fixed_loop(Stepper& stepper, Sys& sys, State<S>& x, S t0, S t1, S h, NoProgressChecker<S>& checker,
                 Before&& before_step, OnStep&& on_step) {
  using std::abs;
  Stats stats;
  if (t0 == t1) return stats;
  const S dir = t1 > t0 ? S(1) : S(-1);
  const S land = S(8) * std::numeric_limits<S>::epsilon() * (abs(t0) > abs(t1) ? abs(t0) : abs(t1));
  S t = t0;
  for (std::size_t k = 1;; ++k) {
    checker.count_attempt(t);
    S t_next = t0 + S(k) * h;
    const bool last = (t_next - t1) * dir >= -land;
    if (last) t_next = t1;
    before_step(t, static_cast<const State<S>&>(x));
    stepper.do_step(sys, x, t, t_next - t);
    const S t_old = t;
    t = t_next;
    ++stats.accepted;
    checker.check_state(t, x);
    if constexpr (Projecting<Sys, S>) sys.project(t, x);
    const StepEnd end = step_end(on_step, t_old, t, x);
    if (end == StepEnd::stop) break;
    if constexpr (restarts<OnStep, S>) {
      if (end == StepEnd::restart) {
        // The state was edited at t inside the step (and projected by handle_events): the stepper
        // forgets what it carried, and the step is redone from t to the same grid point (none left
        // when t is that point).
        stepper.reset();
        checker.check_state(t, x);
        if (t != t_next) {
          --k;
          continue;
        }
      }
    }
    if (last) break;
  }
  return stats;
}

}  // namespace detail

// Fixed steps of size h from t0 to t1; the last step is shortened to land exactly on t1 (a
// remainder below round-off of t0 + k*h is merged into the previous step). Step k ends at
// t0 + k*h, computed afresh rather than accumulated. observer(t, x) at t0 and after every step.
// h must be non-zero with the sign of t1 - t0. Throws IntegrationError on a non-finite state or
// when more than limits.max_steps steps would be needed.
template <class Stepper, class S, class Sys, class Obs>
  requires FixedStepper<Stepper, Sys, S> && Observer<Obs, S>
Stats integrate_fixed(Stepper& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                      std::type_identity_t<S> t1, std::type_identity_t<S> h, Obs&& observer,
                      const Limits& limits = {}) {
  if (h == S(0) || (t1 - t0) * h < S(0))
    throw std::invalid_argument("integrate_fixed: h must be non-zero with the sign of t1 - t0");
  NoProgressChecker<S> checker(limits);
  const std::size_t evals0 = stepper.rhs_evals();
  checker.check_state(t0, x);
  observer(t0, static_cast<const State<S>&>(x));
  Stats stats = detail::fixed_loop(stepper, sys, x, S(t0), S(t1), S(h), checker, [](S, const State<S>&) {},
                                   [&](S, S t, const State<S>& xs) { observer(t, xs); });
  stats.rhs_evals = stepper.rhs_evals() - evals0;
  return stats;
}

namespace detail {

// The adaptive loop shared by integrate_adaptive and integrate_times: steps from t0 to t1 and
// calls on_accept(t_old, t_new, x) after every accepted step (returning false stops it there); the
// last step lands exactly on t1.
template <template <class> class Stepper, class S, class Sys, class OnAccept>
Stats adaptive_loop(Stepper<S>& stepper, Sys& sys, State<S>& x, S t0, S t1, S h0, const Tolerances& tol,
                    const Limits& limits, NoProgressChecker<S>& checker, OnAccept&& on_accept) {
  using std::abs;
  Stats stats;
  const std::size_t evals0 = stepper.rhs_evals();
  const S dir = t1 > t0 ? S(1) : S(-1);
  S hmax = abs(t1 - t0);
  if (limits.max_step > 0.0 && S(limits.max_step) < hmax) hmax = S(limits.max_step);

  checker.check_derivative(t0, stepper.prepare(sys, x, t0));
  std::size_t extra_evals = 0;
  // The first step from (t, x), where the derivative is prepared: at the start, and again after a
  // restart, where the last step size says nothing about the edited solution.
  const auto first_step = [&](S t_from) {
    return h0 > S(0) ? (h0 < hmax ? h0 : hmax)
                     : initial_step(sys, t_from, static_cast<const State<S>&>(x), stepper.derivative(), dir,
                                    Stepper<S>::error_order, tol, hmax, extra_evals);
  };
  S h = first_step(t0);
  checker.set_reference_step(h);
  h *= dir;

  S t = t0;
  for (;;) {
    if (checker.underflows(t, h)) {
      // Shrinking because the system produced NaN/Inf just ahead: report that, not the symptom.
      const std::size_t c = stepper.last_non_finite_component();
      if (c != IntegrationError::no_component)
        throw IntegrationError::non_finite(t, "derivative", c);
      checker.check_step_size(t, h);
    }
    checker.count_attempt(t);
    if (abs(h) > hmax) h = dir * hmax;
    const bool last = (t + h - t1) * dir >= S(0);
    if (last) h = t1 - t;
    const S t_old = t;
    if (stepper.try_step(sys, x, t, h, tol)) {
      ++stats.accepted;
      if (last) t = t1;  // t_old + (t1 - t_old) can miss t1 by an ulp
      checker.check_state(t, x);
      checker.check_derivative(t, stepper.derivative());
      if constexpr (Projecting<Sys, S>) sys.project(t, x);
      const StepEnd end = step_end(on_accept, t_old, t, x);
      if (end == StepEnd::stop) break;
      if constexpr (restarts<OnAccept, S>) {
        if (end == StepEnd::restart) {
          // The state was edited at t (a discontinuity, projected by handle_events): the integration
          // starts afresh there, no FSAL derivative, dense output, controller memory or step size
          // carried over it ([HNW] Sect. II.6, "Discontinuities").
          stepper.reset();
          checker.check_state(t, x);
          checker.check_derivative(t, stepper.prepare(sys, x, t));
          if ((t1 - t) * dir <= S(0)) break;
          h = dir * first_step(t);
          continue;
        }
      }
      if (last) break;
    } else {
      ++stats.rejected;
    }
  }
  stats.rhs_evals = stepper.rhs_evals() - evals0 + extra_evals;
  return stats;
}

}  // namespace detail

// Adaptive integration with an adaptive stepper (Dopri5, Dop853: AdaptiveStepper in
// stepper/concepts.hpp) from t0 to t1 (either direction). h0 > 0 is the magnitude of the
// first step; h0 <= 0 chooses it with initial_step(). observer(t, x) at t0 and after every
// accepted step, landing exactly on t1. Throws IntegrationError on step underflow, an exhausted
// step budget or a non-finite state/derivative.
template <template <class> class Stepper, class S, class Sys, class Obs>
  requires AdaptiveStepper<Stepper<S>> && System<Sys, S> && Observer<Obs, S>
Stats integrate_adaptive(Stepper<S>& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                         std::type_identity_t<S> t1, std::type_identity_t<S> h0, const Tolerances& tol,
                         Obs&& observer, const Limits& limits = {}) {
  validate(tol);
  NoProgressChecker<S> checker(limits);
  checker.check_state(t0, x);
  observer(t0, static_cast<const State<S>&>(x));
  if (t0 == t1) return {};
  return detail::adaptive_loop(stepper, sys, x, S(t0), S(t1), S(h0), tol, limits, checker,
                               [&](S, S t, const State<S>& xs) { observer(t, xs); });
}

// Adaptive integration from times.front() to times.back() (monotone, either direction; repeated
// values allowed); x is the state at times.front() on entry and at times.back() on return.
// observer(t, x) is called exactly once per entry of times, at exactly that time: interior times are
// evaluated with the dense output of the step containing them (steps are not shortened for them),
// times that coincide with a step end get that step's state.
template <template <class> class Stepper, class S, class Sys, class Obs>
  requires AdaptiveStepper<Stepper<S>> && DenseOutputStepper<Stepper<S>> && System<Sys, S> && Observer<Obs, S>
Stats integrate_times(Stepper<S>& stepper, Sys& sys, State<S>& x, const std::vector<S>& times,
                      std::type_identity_t<S> h0, const Tolerances& tol, Obs&& observer,
                      const Limits& limits = {}) {
  validate(tol);
  if (times.empty()) return {};
  const S t0 = times.front(), t1 = times.back();
  const S dir = t1 >= t0 ? S(1) : S(-1);
  for (std::size_t i = 1; i < times.size(); ++i)
    if (!((times[i] - times[i - 1]) * dir >= S(0)))
      throw std::invalid_argument("integrate_times: output times must be monotone");
  NoProgressChecker<S> checker(limits);
  checker.check_state(t0, x);
  std::size_t next = 0;
  while (next < times.size() && times[next] == t0) observer(times[next++], static_cast<const State<S>&>(x));
  if (next == times.size()) return {};
  State<S> buf(x.size());
  return detail::adaptive_loop(stepper, sys, x, t0, t1, S(h0), tol, limits, checker,
                               [&](S, S t_new, const State<S>& xs) {
                                 while (next < times.size() && (times[next] - t_new) * dir <= S(0)) {
                                   if (times[next] == t_new) {
                                     observer(times[next], xs);
                                   } else {
                                     stepper.calc_state(times[next], buf);
                                     detail::projection<S>(sys)(times[next], buf);
                                     observer(times[next], static_cast<const State<S>&>(buf));
                                   }
                                   ++next;
                                 }
                               });
}

// How an integration with events ended.
template <class S>
struct EventOutcome {
  Stats stats;
  S t = S(0);             // the end time reached: t1, or the time of the terminal event
  bool stopped = false;   // a terminal event ended it
  std::size_t event = 0;  // which one, when stopped
  std::size_t edits = 0;  // states edited by EventAction::edit events (each a restart)
  S last_edit_t = S(0);   // the time and event of the latest edit (valid when edits > 0)
  std::size_t last_edit_event = 0;
};

namespace detail {

// The edit callback of the drivers without one: their specs may not ask for edits.
struct NoEdit {
  template <class Hit, class X>
  void operator()(const Hit&, X&) const {}
};

inline void require_no_edits(const std::vector<EventSpec>& specs) {
  for (const EventSpec& spec : specs)
    if (spec.effective_action() == EventAction::edit)
      throw std::invalid_argument("an event with EventAction::edit needs an edit callback");
}

// After each step: locate the step's events, report them (in time order, before the step's own
// observer call), stop at a stopping one, or edit the state at an editing one: t_new and x become
// the event's time and the edited state, the locator restarts there, the observer sees it, and the
// loop restarts the stepper.
//
// With a Projecting system x arrives projected, and the locator compares g's sign at the step's
// start with its sign at that projected end, with the dense output (the step as integrated,
// unprojected) in between. The projected end is the one to compare: it is the state the next step
// starts from and whose g opens the next bracket, so the brackets chain without a gap and a
// crossing is seen exactly once. Compared at the unprojected end, a g that only the projection
// moved across zero would be missed by both steps or seen by both. Such a crossing lies within the
// projection's correction (the size of the step's local error) of t_new, where Brent's method,
// which needs only the bracket's signs, puts it. The located states and an edited state are
// projected (project, nothing for other systems) before anyone sees them: the locator's restart
// and the observer get the state the integration restarts from.
template <class S, class G, class StateAt, class Project, class Obs, class OnEvent, class Edit>
StepEnd handle_events(EventLocator<S>& events, G& g, S t_old, S& t_new, State<S>& x, StateAt&& state_at,
                      Project&& project, std::vector<EventHit<S>>& hits, EventOutcome<S>& out, Obs& observer,
                      OnEvent& on_event, Edit& edit) {
  const bool interrupted = events.step(g, t_old, t_new, static_cast<const State<S>&>(x), state_at, hits);
  for (EventHit<S>& hit : hits) project(hit.t, hit.x);  // a Projecting system's, else nothing
  for (const EventHit<S>& hit : hits) on_event(hit);
  if (interrupted && hits.back().action == EventAction::stop) {
    out.stopped = true;
    out.event = hits.back().index;
    out.t = hits.back().t;
    return StepEnd::stop;
  }
  if (interrupted) {
    const EventHit<S>& hit = hits.back();
    // An edit that leaves the state on the old side of its own event's surface, still heading for
    // it, makes the event cross again at the same time: the loop would edit forever without
    // advancing t. Refused with the reason rather than left to exhaust the step budget.
    using std::abs;
    const S same = S(8) * std::numeric_limits<S>::epsilon() * (abs(hit.t) > S(1) ? abs(hit.t) : S(1));
    if (out.edits > 0 && hit.index == out.last_edit_event && abs(hit.t - out.last_edit_t) <= same)
      throw IntegrationError::event_loop(hit.t, hit.index);
    x = hit.x;
    edit(hit, x);
    t_new = hit.t;
    project(t_new, x);
    ++out.edits;
    out.last_edit_t = hit.t;
    out.last_edit_event = hit.index;
    events.restart(g, t_new, static_cast<const State<S>&>(x));
    observer(t_new, static_cast<const State<S>&>(x));
    return StepEnd::restart;
  }
  observer(t_new, static_cast<const State<S>&>(x));
  return StepEnd::go_on;
}

}  // namespace detail

// integrate_adaptive with events g(t, x, out) (one value per spec of `events`) located on the
// stepper's dense output. observer(t, x) at t0 and after every accepted step; on_event(hit) for
// every event, in time order, before the observer call of the step that holds it. A stopping event
// (EventAction::stop, or terminal) ends the integration at its time: x is then the state there, and
// that step gets no observer call. An editing event (EventAction::edit) ends the step at its time
// t_e: edit(hit, x) changes the state there (x starts as hit.x), observer(t_e, x) sees the edited
// state, and the integration restarts from it with the stepper reset; the rest of the step and its
// later events are dropped.
template <template <class> class Stepper, class S, class Sys, class G, class Obs, class OnEvent, class Edit>
  requires AdaptiveStepper<Stepper<S>> && DenseOutputStepper<Stepper<S>> && System<Sys, S> && Observer<Obs, S> &&
           std::invocable<OnEvent&, const EventHit<S>&> && std::invocable<Edit&, const EventHit<S>&, State<S>&>
EventOutcome<S> integrate_adaptive_events(Stepper<S>& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                                          std::type_identity_t<S> t1, std::type_identity_t<S> h0,
                                          const Tolerances& tol, EventLocator<S>& events, G& g, Obs&& observer,
                                          OnEvent&& on_event, Edit&& edit, const Limits& limits = {}) {
  validate(tol);
  NoProgressChecker<S> checker(limits);
  checker.check_state(t0, x);
  if (!events.resolving()) events.resolve_with(tol.rtol, tol.atol);  // g on its own scale (events.hpp)
  events.start(g, t0, static_cast<const State<S>&>(x));
  observer(t0, static_cast<const State<S>&>(x));
  EventOutcome<S> out;
  out.t = t1;
  if (t0 == t1) return out;
  std::vector<EventHit<S>> hits;
  const auto dense = [&](S tau, State<S>& o) { stepper.calc_state(tau, o); };
  out.stats = detail::adaptive_loop(stepper, sys, x, S(t0), S(t1), S(h0), tol, limits, checker,
                                    [&](S t_old, S& t_new, State<S>& xs) {
                                      return detail::handle_events(events, g, t_old, t_new, xs, dense,
                                                                   detail::projection<S>(sys), hits, out, observer,
                                                                   on_event, edit);
                                    });
  if (out.stopped) x = hits.back().x;
  return out;
}

// The same without edits: no spec may ask for EventAction::edit.
template <template <class> class Stepper, class S, class Sys, class G, class Obs, class OnEvent>
  requires AdaptiveStepper<Stepper<S>> && DenseOutputStepper<Stepper<S>> && System<Sys, S> && Observer<Obs, S> &&
           std::invocable<OnEvent&, const EventHit<S>&>
EventOutcome<S> integrate_adaptive_events(Stepper<S>& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                                          std::type_identity_t<S> t1, std::type_identity_t<S> h0,
                                          const Tolerances& tol, EventLocator<S>& events, G& g, Obs&& observer,
                                          OnEvent&& on_event, const Limits& limits = {}) {
  detail::require_no_edits(events.specs());
  return integrate_adaptive_events(stepper, sys, x, t0, t1, h0, tol, events, g, observer, on_event, detail::NoEdit{},
                                   limits);
}

// integrate_fixed with events, same contract as integrate_adaptive_events (after an edited state
// the steps go on from the event time to the next point of the grid t0 + k h). A fixed-step method
// has no dense output of its own order, so inside a step where some g changes sign the solution at
// t_old + tau is the method's own step of size tau from the step's start (a copy of the stepper,
// reset, does it). The event then carries the method's full order (a cubic Hermite interpolant
// would cap it at 4 for gl6, gl8 and the compositions), and steps without a sign change cost
// nothing extra; the re-steps' system calls are counted in the stats.
template <class Stepper, class S, class Sys, class G, class Obs, class OnEvent, class Edit>
  requires FixedStepper<Stepper, Sys, S> && Observer<Obs, S> && std::invocable<OnEvent&, const EventHit<S>&> &&
           std::invocable<Edit&, const EventHit<S>&, State<S>&>
EventOutcome<S> integrate_fixed_events(Stepper& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                                       std::type_identity_t<S> t1, std::type_identity_t<S> h, EventLocator<S>& events,
                                       G& g, Obs&& observer, OnEvent&& on_event, Edit&& edit,
                                       const Limits& limits = {}) {
  if (h == S(0) || (t1 - t0) * h < S(0))
    throw std::invalid_argument("integrate_fixed_events: h must be non-zero with the sign of t1 - t0");
  NoProgressChecker<S> checker(limits);
  const std::size_t evals0 = stepper.rhs_evals();
  Stepper probe(stepper);
  const std::size_t probe0 = probe.rhs_evals();
  checker.check_state(t0, x);
  events.start(g, t0, static_cast<const State<S>&>(x));
  observer(t0, static_cast<const State<S>&>(x));
  EventOutcome<S> out;
  out.t = t1;
  std::vector<EventHit<S>> hits;
  State<S> x_old = x;
  S t_start = t0;
  const auto restep = [&](S tau, State<S>& o) {
    o = x_old;
    if (tau == t_start) return;
    probe.reset();
    probe.do_step(sys, o, t_start, tau - t_start);
  };
  out.stats = detail::fixed_loop(stepper, sys, x, S(t0), S(t1), S(h), checker,
                                 [&](S t, const State<S>& xs) {
                                   t_start = t;
                                   x_old = xs;
                                 },
                                 [&](S t_old, S& t_new, State<S>& xs) {
                                   return detail::handle_events(events, g, t_old, t_new, xs, restep,
                                                                detail::projection<S>(sys), hits, out, observer,
                                                                on_event, edit);
                                 });
  out.stats.rhs_evals = stepper.rhs_evals() - evals0 + (probe.rhs_evals() - probe0);
  if (out.stopped) x = hits.back().x;
  return out;
}

// The same without edits: no spec may ask for EventAction::edit.
template <class Stepper, class S, class Sys, class G, class Obs, class OnEvent>
  requires FixedStepper<Stepper, Sys, S> && Observer<Obs, S> && std::invocable<OnEvent&, const EventHit<S>&>
EventOutcome<S> integrate_fixed_events(Stepper& stepper, Sys& sys, State<S>& x, std::type_identity_t<S> t0,
                                       std::type_identity_t<S> t1, std::type_identity_t<S> h, EventLocator<S>& events,
                                       G& g, Obs&& observer, OnEvent&& on_event, const Limits& limits = {}) {
  detail::require_no_edits(events.specs());
  return integrate_fixed_events(stepper, sys, x, t0, t1, h, events, g, observer, on_event, detail::NoEdit{}, limits);
}

}  // namespace eomc::runtime
