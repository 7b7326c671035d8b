#pragma once

// Event location: the times at which functions g_i(t, x) of the solution cross zero.
//
// After every accepted step [t_old, t_new] the locator evaluates g at t_new and compares signs
// with the last non-zero sign seen for each event (so a g that touches zero and turns back is not
// a crossing, and a g that starts at zero, like a ground height at launch, is armed only once it
// leaves zero). A crossing in an allowed direction is then located on a continuous solution over
// the step (the stepper's dense output for the adaptive methods, a re-step for the fixed-step
// ones, see integrate.hpp) with Brent's method to a bracket of a few ulps of t, and reported with
// the state there.
//
// What an event does (EventAction): record it (the default), stop the integration at its time, or
// edit the state there (an impact law, an impulsive manoeuvre) and restart the integration from the
// edited state, the stepper reset (no first-same-as-last derivative, no dense output carried over
// the discontinuity). A stopping or editing event ends the step at its time: later crossings are
// dropped. A cooldown keeps an event function from being detected again for a time span after it
// fired: an impact that leaves the gap at zero, or a hair on the wrong side of it, would otherwise
// fire again at once. This is the restart-after-discontinuity scheme of Hairer's codes ([HNW]
// Sect. II.6, "Discontinuities") and of L.F. Shampine, S. Thompson, "Event location for ordinary
// differential equations", Comput. Math. Appl. 39 (2000) 43-54.
//
// Limitation, as in every sign-change locator (Hairer's, SciPy's): two crossings of one g inside
// one step cancel and are not seen; the step must resolve the events' own time scale.
//
// References: R.P. Brent, Algorithms for Minimization without Derivatives (1973), ch. 4 (zeroin);
// [HNW] Hairer-Norsett-Wanner I, Sect. II.6 (dense output, event location).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

// Which crossings count: up = g from negative to positive, down = from positive to negative.
enum class EventDirection : int { both = 0, up = 1, down = -1 };

// What a located event does: record it and go on, stop the integration there, or edit the state
// there and restart from the edited state (the drivers then call the caller's edit(hit, x)).
enum class EventAction : int { record = 0, stop = 1, edit = 2 };

struct EventSpec {
  EventDirection direction = EventDirection::both;
  bool terminal = false;  // stop the integration at the event (the same as action = stop)
  EventAction action = EventAction::record;
  // After the event fired at t_e, the same event function is not detected in (t_e, t_e + cooldown]
  // (in the direction of integration); its sign is read afresh where the cooldown ends. >= 0.
  double cooldown = 0.0;

  EventAction effective_action() const { return terminal ? EventAction::stop : action; }
};

template <class S>
struct EventHit {
  std::size_t index = 0;  // which event, in the order of the specs
  S t = S(0);
  int direction = 0;      // +1: g went up through zero, -1: down
  bool terminal = false;  // action == stop
  State<S> x;             // the state at t (before an edit)
  EventAction action = EventAction::record;
};

// Brent's zeroin on [a, b] with f(a) = fa, f(b) = fb of opposite signs (or one of them zero).
// Returns a point within tol + 2 eps |root| of a sign change of f, or an exact zero; tol = 0
// asks for the bracket to shrink to a few ulps. At most max_evals evaluations of f.
template <class S, class F>
S brent_root(F&& f, S a, S b, S fa, S fb, S tol = S(0), int max_evals = 200) {
  using std::abs;
  if (fa == S(0)) return a;
  if (fb == S(0)) return b;
  if ((fa > S(0)) == (fb > S(0))) throw std::invalid_argument("brent_root: f(a) and f(b) must differ in sign");
  const S eps = std::numeric_limits<S>::epsilon();
  S c = a, fc = fa, d = b - a, e = d;
  for (int evals = 0;;) {
    if ((fb > S(0)) == (fc > S(0))) {  // keep the root between b and c
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (abs(fc) < abs(fb)) {  // b is the best estimate
      a = b;
      b = c;
      c = a;
      fa = fb;
      fb = fc;
      fc = fa;
    }
    const S tol1 = S(2) * eps * abs(b) + S(0.5) * tol + std::numeric_limits<S>::denorm_min();
    const S xm = S(0.5) * (c - b);
    if (abs(xm) <= tol1 || fb == S(0) || evals >= max_evals) return b;
    if (abs(e) >= tol1 && abs(fa) > abs(fb)) {
      // Secant (a == c) or inverse quadratic interpolation, taken only when it stays well inside.
      const S s = fb / fa;
      S p, q;
      if (a == c) {
        p = S(2) * xm * s;
        q = S(1) - s;
      } else {
        const S qa = fa / fc, r = fb / fc;
        p = s * (S(2) * xm * qa * (qa - r) - (b - a) * (r - S(1)));
        q = (qa - S(1)) * (r - S(1)) * (s - S(1));
      }
      if (p > S(0)) q = -q;
      else p = -p;
      if (S(2) * p < std::min(S(3) * xm * q - abs(tol1 * q), abs(e * q))) {
        e = d;
        d = p / q;
      } else {
        d = xm;
        e = d;
      }
    } else {
      d = xm;  // bisection
      e = d;
    }
    a = b;
    fa = fb;
    b += abs(d) > tol1 ? d : (xm > S(0) ? tol1 : -tol1);
    fb = f(b);
    ++evals;
  }
}

// Tracks the signs of n event functions g(t, x, out) (out presized to n) along an integration.
template <class S>
class EventLocator {
 public:
  explicit EventLocator(std::vector<EventSpec> specs) : specs_(std::move(specs)) {
    for (const EventSpec& spec : specs_)
      if (!(spec.cooldown >= 0.0)) throw std::invalid_argument("EventSpec: cooldown must be >= 0");
  }

  std::size_t size() const { return specs_.size(); }
  const std::vector<EventSpec>& specs() const { return specs_; }
  // Evaluations of g since construction (step ends and root-solver iterates).
  std::size_t evaluations() const { return evaluations_; }

  // The values at the initial point arm the events whose g is not zero there; no cooldown runs.
  template <class G>
  void start(G& g, S t, const State<S>& x) {
    g_prev_.assign(size(), S(0));
    g_new_.assign(size(), S(0));
    g_tmp_.assign(size(), S(0));
    cooling_.assign(size(), false);
    cool_end_.assign(size(), S(0));
    restart(g, t, x);
  }

  // Goes on from (t, x) after the state was edited there (an EventAction::edit): the signs are read
  // afresh, as at the start, and running cooldowns are kept.
  template <class G>
  void restart(G& g, S t, const State<S>& x) {
    sign_.assign(size(), 0);
    eval(g, t, x, g_prev_);
    for (std::size_t i = 0; i < size(); ++i) sign_[i] = sign(g_prev_[i]);
  }

  // Whether event i is in its cooldown, and where that ends.
  bool cooling(std::size_t i) const { return cooling_[i]; }
  S cooldown_end(std::size_t i) const { return cool_end_[i]; }

  // After a step from t_old to t_new with x_new the state at t_new; state_at(tau, out) gives the
  // solution at any tau in [t_old, t_new]. Replaces `hits` by the step's events in time order
  // (equal times in index order) and returns true when the last of them interrupts the step
  // (hits.back().action is stop or edit): the integration must then stop at hits.back().t with the
  // state hits.back().x, or edit that state and go on from there after restart(). Events in their
  // cooldown are not detected; where a cooldown ends inside the step, the sign there is the
  // reference and only [cooldown end, t_new] is searched.
  template <class G, class StateAt>
  bool step(G& g, S t_old, S t_new, const State<S>& x_new, StateAt&& state_at, std::vector<EventHit<S>>& hits) {
    using std::abs;
    hits.clear();
    if (size() == 0) return false;
    eval(g, t_new, x_new, g_new_);
    const S step_dir = t_new >= t_old ? S(1) : S(-1);
    for (std::size_t i = 0; i < size(); ++i) {
      const int s_new = sign(g_new_[i]);
      // The bracket's start: t_old, or where the cooldown of event i ends inside this step.
      S t_a = t_old, g_a = g_prev_[i];
      if (cooling_[i]) {
        if ((t_new - cool_end_[i]) * step_dir <= S(0)) continue;  // its sign is updated below
        cooling_[i] = false;
        if ((cool_end_[i] - t_old) * step_dir > S(0)) {
          t_a = cool_end_[i];
          state_at(t_a, buf_);
          eval(g, t_a, buf_, g_tmp_);
          g_a = g_tmp_[i];
          if (const int s_a = sign(g_a); s_a != 0) sign_[i] = s_a;
        }
      }
      if (s_new == 0 || sign_[i] == 0 || s_new == sign_[i]) continue;
      const int dir = s_new > 0 ? 1 : -1;
      const EventDirection want = specs_[i].direction;
      if (want != EventDirection::both && static_cast<int>(want) != dir) continue;
      EventHit<S> hit;
      hit.index = i;
      hit.direction = dir;
      hit.action = specs_[i].effective_action();
      hit.terminal = hit.action == EventAction::stop;
      if (g_a == S(0)) {
        // g sat exactly on zero at the bracket's start and has now left it on the other side.
        hit.t = t_a;
      } else {
        auto gi = [&](S tau) {
          state_at(tau, buf_);
          eval(g, tau, buf_, g_tmp_);
          return g_tmp_[i];
        };
        const S scale = abs(t_a) > abs(t_new) ? abs(t_a) : abs(t_new);
        hit.t = brent_root(gi, t_a, t_new, g_a, g_new_[i], std::numeric_limits<S>::epsilon() * scale);
      }
      if (hit.t == t_new) {
        hit.x = x_new;
      } else {
        state_at(hit.t, hit.x);
      }
      hits.push_back(std::move(hit));
    }
    for (std::size_t i = 0; i < size(); ++i)
      if (const int s = sign(g_new_[i]); s != 0) sign_[i] = s;
    std::swap(g_prev_, g_new_);
    std::stable_sort(hits.begin(), hits.end(),
                     [&](const EventHit<S>& a, const EventHit<S>& b) { return (a.t - b.t) * step_dir < S(0); });
    bool interrupted = false;
    for (std::size_t k = 0; k < hits.size(); ++k)
      if (hits[k].action != EventAction::record) {
        hits.resize(k + 1);
        interrupted = true;
        break;
      }
    // The reported events start their cooldowns.
    for (const EventHit<S>& hit : hits)
      if (const double c = specs_[hit.index].cooldown; c > 0.0) {
        cooling_[hit.index] = true;
        cool_end_[hit.index] = hit.t + step_dir * S(c);
      }
    return interrupted;
  }

 private:
  static int sign(S v) { return v > S(0) ? 1 : (v < S(0) ? -1 : 0); }

  template <class G>
  void eval(G& g, S t, const State<S>& x, State<S>& out) {
    g(t, x, out);
    ++evaluations_;
  }

  std::vector<EventSpec> specs_;
  State<S> g_prev_, g_new_, g_tmp_, buf_;
  std::vector<int> sign_;  // last non-zero sign of each g (0: not armed yet)
  std::vector<bool> cooling_;
  State<S> cool_end_;  // where each running cooldown ends
  std::size_t evaluations_ = 0;
};

}  // namespace eomc::runtime
