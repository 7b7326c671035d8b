#pragma once

// Event location: the times at which functions g_i(t, x) of the solution cross zero.
//
// After every accepted step [t_old, t_new] the locator looks for the crossings of each g on a
// continuous solution over the step (the stepper's dense output for the adaptive methods, a re-step
// for the fixed-step ones, see integrate.hpp), compared with the last non-zero sign seen for each
// event (so a g that touches zero and turns back is not a crossing, and a g that starts at zero,
// like a ground height at launch, is armed only once it leaves zero). A crossing in an allowed
// direction is located with Brent's method to a bracket of a few ulps of t and reported with the
// state there.
//
// The step's own size says nothing about g: the stepper controls the error of x, and a gap that
// dips below zero and returns within one step (a ball thrown at a ceiling it just reaches, in free
// flight, where the error estimate of a quadratic is zero and the steps grow without bound; a table
// that vibrates faster than the ball moves) has the same sign at both ends. So, once the locator
// knows the integration's tolerances (resolve_with, which the adaptive drivers call), it resolves
// g over the step on its own scale: the cubic through g at θ = 0, 0.3, 0.7, 1 of the step must
// agree with g at θ = 0.45 (an embedded estimate of the cubic's error, O(h⁴ g⁗), taken at an
// asymmetric point so that no sinusoid whose period divides the step fits it) to δ_i = rtol |g_i|
// + atol, or to a quarter of g_i's least distance from zero on the piece where that is larger;
// else the piece is split at θ = 0.45 on the dense output, again and again, until it does. On a
// resolved piece every sign change between samples is a crossing, and where the cubic has an
// extremum that comes within twice that misfit of zero between two samples of one sign, the
// extremum of g itself is found (golden section) and decides: below zero, two crossings; not, a
// graze. What remains taken on trust is that g is smooth on the scale of its samples: a kink or a
// spike narrower than their spacing that leaves the check at θ = 0.45 undisturbed is not seen.
// Free flight (g quadratic
// in t) is resolved by the first cubic at no cost beyond three evaluations of g per step. A piece
// that will not resolve down to a few ulps of t (a g that is not smooth) is counted and its time
// kept (unresolved(), first_unresolved()) so that a driver can say so. Without resolve_with, only
// the signs at the step's ends are compared (the fixed-step drivers, whose continuous solution is
// a re-step): two crossings of one g inside one such step cancel.
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
// References: R.P. Brent, Algorithms for Minimization without Derivatives (1973), ch. 4 (zeroin);
// [HNW] Hairer-Norsett-Wanner I, Sect. II.6 (dense output, event location).

#include <algorithm>
#include <array>
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

namespace detail {

// The cubic through (θ_k, v_k), k = 0..3, as c0 + c1 θ + c2 θ² + c3 θ³ (Newton's divided
// differences, expanded).
template <class S>
std::array<S, 4> cubic_through(const std::array<S, 4>& th, const std::array<S, 4>& v) {
  S d[4] = {v[0], v[1], v[2], v[3]};
  for (int j = 1; j < 4; ++j)
    for (int k = 3; k >= j; --k) d[k] = (d[k] - d[k - 1]) / (th[std::size_t(k)] - th[std::size_t(k - j)]);
  // d0 + d1 (θ − θ0) + d2 (θ − θ0)(θ − θ1) + d3 (θ − θ0)(θ − θ1)(θ − θ2), with θ0 = 0 here.
  std::array<S, 4> c{d[3], S(0), S(0), S(0)};  // Horner on the Newton form, highest first
  for (int k = 2; k >= 0; --k) {
    // c(θ) ← c(θ) (θ − θ_k) + d_k
    const S tk = th[std::size_t(k)];
    std::array<S, 4> next{S(0), S(0), S(0), S(0)};
    for (int j = 0; j < 3; ++j) {
      next[std::size_t(j + 1)] += c[std::size_t(j)];
      next[std::size_t(j)] -= tk * c[std::size_t(j)];
    }
    next[0] += d[k];
    c = next;
  }
  return c;
}

// The real roots of a θ² + b θ + c in increasing order (none, one or two).
template <class S>
int quadratic_roots(S a, S b, S c, S out[2]) {
  using std::abs;
  using std::sqrt;
  if (a == S(0)) {
    if (b == S(0)) return 0;
    out[0] = -c / b;
    return 1;
  }
  const S disc = b * b - S(4) * a * c;
  if (disc < S(0)) return 0;
  const S q = S(-0.5) * (b + (b < S(0) ? -sqrt(disc) : sqrt(disc)));
  if (q == S(0)) {
    out[0] = S(0);
    return 1;
  }
  out[0] = q / a;
  out[1] = c / q;
  if (out[0] > out[1]) std::swap(out[0], out[1]);
  return 2;
}

}  // namespace detail

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
  // Evaluations of g since construction (step ends, resolution samples and root-solver iterates).
  std::size_t evaluations() const { return evaluations_; }

  // From now on g is resolved over every step to δ_i = rtol |g_i| + atol (the top of this file);
  // the adaptive drivers pass their own tolerances.
  void resolve_with(double rtol, double atol) {
    if (!(rtol >= 0.0) || !(atol >= 0.0) || (rtol == 0.0 && atol == 0.0))
      throw std::invalid_argument("EventLocator::resolve_with: tolerances must be non-negative and not both zero");
    rtol_ = S(rtol);
    atol_ = S(atol);
    resolve_ = true;
  }
  bool resolving() const { return resolve_; }
  // Pieces of steps on which g could not be resolved down to a few ulps of t (a g that is not
  // smooth there): a crossing and its return inside such a piece may have gone unseen.
  std::size_t unresolved() const { return unresolved_; }
  S first_unresolved() const { return first_unresolved_; }

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
    hits.clear();
    if (size() == 0) return false;
    eval(g, t_new, x_new, g_new_);
    dir_ = t_new >= t_old ? S(1) : S(-1);
    sample(g, t_old, t_new, state_at);
    for (std::size_t i = 0; i < size(); ++i) {
      // The search's start: t_old, or where the cooldown of event i ends inside this step.
      S t_a = t_old, g_a = g_prev_[i];
      if (cooling_[i]) {
        if ((t_new - cool_end_[i]) * dir_ <= S(0)) continue;  // its sign is updated below
        cooling_[i] = false;
        if ((cool_end_[i] - t_old) * dir_ > S(0)) {
          t_a = cool_end_[i];
          state_at(t_a, buf_);
          eval(g, t_a, buf_, g_tmp_);
          g_a = g_tmp_[i];
          if (const int s_a = sign(g_a); s_a != 0) sign_[i] = s_a;
        }
      }
      crossings(g, i, t_a, g_a, x_new, state_at, hits);
    }
    for (std::size_t i = 0; i < size(); ++i)
      if (const int s = sign(g_new_[i]); s != 0) sign_[i] = s;
    std::swap(g_prev_, g_new_);
    std::stable_sort(hits.begin(), hits.end(),
                     [&](const EventHit<S>& a, const EventHit<S>& b) { return (a.t - b.t) * dir_ < S(0); });
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
        cool_end_[hit.index] = hit.t + dir_ * S(c);
      }
    return interrupted;
  }

 private:
  static int sign(S v) { return v > S(0) ? 1 : (v < S(0) ? -1 : 0); }
  // Where the resolution samples sit in a piece, as fractions θ of it: the cubic's nodes 0, 0.3,
  // 0.7, 1 and its check at 0.45, where the piece is split when the check fails.
  static constexpr std::array<double, 5> theta_ = {0.0, 0.3, 0.45, 0.7, 1.0};
  static constexpr std::size_t max_pieces_ = 4096;  // per step, before the rest is taken unresolved
  // Lagrange's weights of the nodes 0, 0.3, 0.7, 1 at θ = 0.45: the cubic's value at the check.
  static constexpr std::array<double, 4> check_weights_ = [] {
    const double nodes[4] = {theta_[0], theta_[1], theta_[3], theta_[4]};
    std::array<double, 4> w{};
    for (std::size_t k = 0; k < 4; ++k) {
      w[k] = 1.0;
      for (std::size_t j = 0; j < 4; ++j)
        if (j != k) w[k] *= (theta_[2] - nodes[j]) / (nodes[k] - nodes[j]);
    }
    return w;
  }();

  template <class G>
  void eval(G& g, S t, const State<S>& x, State<S>& out) {
    g(t, x, out);
    ++evaluations_;
  }
  template <class G, class StateAt>
  void eval_at(G& g, S t, StateAt& state_at, State<S>& out) {
    state_at(t, buf_);
    eval(g, t, buf_, out);
  }

  // The samples of g over the step, in time order: times_[k] and g at it (row k of values_, size()
  // each). piece_[k] is the index of the sample where the resolved piece holding (t_{k−1}, t_k]
  // starts (its five samples are piece_[k] + 0..4). Without resolution: the step's two ends.
  S value(std::size_t k, std::size_t i) const { return values_[k * size() + i]; }
  void push_sample(S t, const S* v, std::size_t piece) {
    times_.push_back(t);
    values_.insert(values_.end(), v, v + size());
    piece_.push_back(piece);
  }

  template <class G, class StateAt>
  void sample(G& g, S t_old, S t_new, StateAt& state_at) {
    times_.clear();
    values_.clear();
    piece_.clear();
    push_sample(t_old, g_prev_.data(), 0);
    if (!resolve_) {
      push_sample(t_new, g_new_.data(), 0);
      return;
    }
    // Pieces still to resolve, the next on top: their right ends and g there. The left end of the
    // piece on top is always the last sample.
    pending_t_.assign(1, t_new);
    pending_v_.assign(g_new_.begin(), g_new_.end());
    std::size_t pieces = 0;
    mid_.resize(3 * size());
    while (!pending_t_.empty()) {
      const S a = times_.back(), b = pending_t_.back();
      for (std::size_t j = 0; j < 3; ++j) {
        eval_at(g, a + (b - a) * S(theta_[j + 1]), state_at, g_tmp_);
        std::copy(g_tmp_.begin(), g_tmp_.end(), mid_.begin() + std::ptrdiff_t(j * size()));
      }
      const std::size_t top = pending_t_.size() - 1;
      const S* vb = pending_v_.data() + top * size();
      const bool too_short = abs_(b - a) <= S(64) * eps_ * std::max(abs_(a), abs_(b));
      const bool resolved = piece_resolved(vb);
      if (!resolved && !too_short && ++pieces < max_pieces_) {
        // Split at θ = 0.45: the right part stays pending, the left part [a, split] goes on top.
        pending_t_.push_back(a + (b - a) * S(theta_[2]));
        pending_v_.insert(pending_v_.end(), mid_.begin() + std::ptrdiff_t(size()), mid_.begin() + std::ptrdiff_t(2 * size()));
        continue;
      }
      if (!resolved) {
        if (unresolved_++ == 0) first_unresolved_ = a;
      }
      const std::size_t start = times_.size() - 1;
      for (std::size_t j = 0; j < 3; ++j) push_sample(a + (b - a) * S(theta_[j + 1]), mid_.data() + j * size(), start);
      push_sample(b, vb, start);
      pending_t_.pop_back();
      pending_v_.resize(pending_t_.size() * size());
    }
  }

  // The cubic through the piece's samples at θ = 0, 0.3, 0.7, 1 against g at 0.45, every g.
  bool piece_resolved(const S* vb) const {
    const std::size_t a = times_.size() - 1;
    for (std::size_t i = 0; i < size(); ++i) {
      const std::array<S, 4> v{value(a, i), mid_[i], mid_[2 * size() + i], vb[i]};
      const S check = mid_[size() + i];
      S cubic = S(0);
      for (std::size_t k = 0; k < 4; ++k) cubic += S(check_weights_[k]) * v[k];
      if (abs_(cubic - check) > allowed(v[0], v[1], check, v[2], v[3])) return false;
    }
    return true;
  }
  // δ for a g of size `scale`: the caller's tolerance, and never below the rounding of g itself.
  S tolerance(S scale) const { return atol_ + std::max(rtol_, S(64) * eps_) * scale; }
  // The misfit a piece may have, from its five samples of one g: δ, or a quarter of the least
  // distance of g from zero there, whichever is larger. A cubic that far from the truth still
  // cannot hide a zero between samples that stay four times as far from it; only where g comes
  // near zero must it be resolved to δ (a fast table is resolved near the ball, not everywhere).
  S allowed(S v0, S v1, S v2, S v3, S v4) const {
    const S scale = std::max({abs_(v0), abs_(v1), abs_(v2), abs_(v3), abs_(v4)});
    const S nearest = std::min({abs_(v0), abs_(v1), abs_(v2), abs_(v3), abs_(v4)});
    return std::max(tolerance(scale), S(0.25) * nearest);
  }

  // Whether the cubic of the piece holding sample k has an extremum in (t_lo, t_k) that comes
  // within twice the piece's allowed misfit of zero from the side s of g_i: a dip below zero the
  // samples may straddle.
  bool dip_suspected(std::size_t i, std::size_t k, S t_lo, int s) const {
    const std::size_t p = piece_[k];
    const S a = times_[p], h = times_[p + 4] - a;
    const std::array<S, 4> nodes{S(theta_[0]), S(theta_[1]), S(theta_[3]), S(theta_[4])};
    const std::array<S, 4> v{value(p, i), value(p + 1, i), value(p + 3, i), value(p + 4, i)};
    const std::array<S, 4> c = detail::cubic_through(nodes, v);
    S roots[2];
    const int nr = detail::quadratic_roots(S(3) * c[3], S(2) * c[2], c[1], roots);
    const S misfit = allowed(v[0], v[1], value(p + 2, i), v[2], v[3]);
    for (int r = 0; r < nr; ++r) {
      const S th = roots[r], tc = a + h * th;
      if (!((tc - t_lo) * dir_ > S(0) && (times_[k] - tc) * dir_ > S(0))) continue;
      const S at = c[0] + th * (c[1] + th * (c[2] + th * c[3]));
      if (S(s) * at <= S(2) * misfit) return true;
    }
    return false;
  }

  // The least of s g_i over [ta, tb] by golden section, ended early at a point where g_i has the
  // other sign (all a crossing needs); returns that point or the minimum, and g_i there.
  template <class G, class StateAt>
  std::pair<S, S> extremum(G& g, std::size_t i, S ta, S tb, int s, StateAt& state_at) {
    using std::sqrt;
    const S r = (sqrt(S(5)) - S(1)) / S(2);
    const auto phi = [&](S t) {
      eval_at(g, t, state_at, g_tmp_);
      return g_tmp_[i];
    };
    S c = tb - r * (tb - ta), d = ta + r * (tb - ta);
    S gc = phi(c), gd = phi(d);
    const S width = sqrt(eps_) * std::max({abs_(ta), abs_(tb), abs_(tb - ta)});
    while (abs_(tb - ta) > width) {
      if (sign(gc) == -s) return {c, gc};
      if (sign(gd) == -s) return {d, gd};
      if (S(s) * gc < S(s) * gd) {
        tb = d;
        d = c;
        gd = gc;
        c = tb - r * (tb - ta);
        gc = phi(c);
      } else {
        ta = c;
        c = d;
        gc = gd;
        d = ta + r * (tb - ta);
        gd = phi(d);
      }
    }
    return S(s) * gc < S(s) * gd ? std::pair<S, S>{c, gc} : std::pair<S, S>{d, gd};
  }

  // Event i's sign changes over the step from (t_a, g_a), in time order, each in an allowed direction
  // located and appended to hits; the sign seen last is kept in sign_[i].
  template <class G, class StateAt>
  void crossings(G& g, std::size_t i, S t_a, S g_a, const State<S>& x_new, StateAt& state_at,
                 std::vector<EventHit<S>>& hits) {
    S tp = t_a, gp = g_a;
    const std::size_t last = times_.size() - 1;
    for (std::size_t k = 1; k <= last; ++k) {
      if ((times_[k] - tp) * dir_ <= S(0)) continue;
      const S tk = times_[k], gk = value(k, i);
      const int s = sign_[i];
      if (resolve_ && s != 0 && sign(gp) == s && sign(gk) == s && dip_suspected(i, k, tp, s)) {
        const auto [tm, gm] = extremum(g, i, tp, tk, s, state_at);
        if (sign(gm) == -s) {
          cross(g, i, tp, gp, tm, gm, state_at, nullptr, hits);
          tp = tm;
          gp = gm;
        }
      }
      cross(g, i, tp, gp, tk, gk, state_at, k == last ? &x_new : nullptr, hits);
      tp = tk;
      gp = gk;
    }
  }

  // From (ta, ga) to (tb, gb): where g_i leaves its armed sign, a crossing (reported when its
  // direction is wanted); a first non-zero sign arms the event.
  template <class G, class StateAt>
  void cross(G& g, std::size_t i, S ta, S ga, S tb, S gb, StateAt& state_at, const State<S>* x_at_tb,
             std::vector<EventHit<S>>& hits) {
    const int sb = sign(gb);
    if (sb == 0) return;
    if (sign_[i] == 0 || sb == sign_[i]) {
      sign_[i] = sb;
      return;
    }
    sign_[i] = sb;
    const EventDirection want = specs_[i].direction;
    if (want != EventDirection::both && static_cast<int>(want) != sb) return;
    EventHit<S> hit;
    hit.index = i;
    hit.direction = sb;
    hit.action = specs_[i].effective_action();
    hit.terminal = hit.action == EventAction::stop;
    if (ga == S(0)) {
      hit.t = ta;  // g sat exactly on zero there and has now left it on the other side
    } else {
      auto gi = [&](S tau) {
        eval_at(g, tau, state_at, g_tmp_);
        return g_tmp_[i];
      };
      hit.t = brent_root(gi, ta, tb, ga, gb, eps_ * std::max(abs_(ta), abs_(tb)));
    }
    if (hit.t == tb && x_at_tb) hit.x = *x_at_tb;
    else state_at(hit.t, hit.x);
    hits.push_back(std::move(hit));
  }

  static S abs_(S v) { return v < S(0) ? -v : v; }

  const S eps_ = std::numeric_limits<S>::epsilon();
  std::vector<EventSpec> specs_;
  State<S> g_prev_, g_new_, g_tmp_, buf_;
  std::vector<int> sign_;  // last non-zero sign of each g (0: not armed yet)
  std::vector<bool> cooling_;
  State<S> cool_end_;  // where each running cooldown ends
  std::size_t evaluations_ = 0;
  bool resolve_ = false;
  S rtol_ = S(0), atol_ = S(0), dir_ = S(1);
  std::size_t unresolved_ = 0;
  S first_unresolved_ = S(0);
  std::vector<S> times_, values_, pending_t_, pending_v_, mid_;
  std::vector<std::size_t> piece_;
};

}  // namespace eomc::runtime
