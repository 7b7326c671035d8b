#pragma once

// The event-driven hybrid driver for unilateral constraints (Mei, Special Topics in Analytical
// Mechanics, ch. 6): smooth phases integrated by an adaptive stepper, separated by events located
// on its dense output, after the scheme of F. Pfeiffer, C. Glocker, Multibody Dynamics with
// Unilateral Contacts, Wiley 1996, ch. 6 (the phases, the indicators g_α for open and λ_α for
// closed contacts, the contact-phase LCP) and ch. 7 (Newton's impact law as an LCP).
//
//   M(t, q) u̇ = f(t, q, u) + Wᵀ λ,   q̇ = u,   g_α(t, q) ≥ 0,  W_α = ∂g_α/∂q,  w_α = ∂g_α/∂t,
//   ġ_α = W_α u + w_α,   g̈_α = W_α u̇ + b_α.
//
// Moving (rheonomic) gaps g_α(t, q), a wall or a table driven in time: the rate of a gap is
// ġ_α = W_α u + w_α with the explicit time rate w_α = ∂g_α/∂t (zero for a fixed wall), and b_α holds
// ∂²g_α/∂t² and 2 Σ ∂²g_α/∂q∂t q̇ beside the quadratic terms. Every test on a gap's rate uses ġ_α:
// the closing test, Newton's law ġ⁺ = −e ġ⁻ on the relative normal velocity (Mei §6.5: the
// impulsive equations M Δu = Wᵀ P with the restitution acting on the rates of the constraints; for
// one contact W Δu = −(1 + e) ġ⁻), the resting test and the projection onto ġ = 0, the first step's
// apex bound. Carnot's theorem then holds in the wall's frame: in the ground frame the wall's
// impulse does the work −Pᵀw besides, T⁺ − T⁻ = −((1 − e)/(1 + e)) ½ ΔuᵀMΔu − Pᵀw (from
// T⁺ − T⁻ = ½ Pᵀ W (u⁺ + u⁻) = ½ Pᵀ(ġ⁺ + ġ⁻) − Pᵀw and ½ ΔuᵀMΔu = ½ Pᵀ(ġ⁺ − ġ⁻)), which is what
// the events record as carnot.
//
// Phases and transitions:
//  * free flight (no active contact): u̇ = M⁻¹ f; the indicators are the gaps g_α, an event is a
//    gap going down through zero, located with Brent's method on the dense output (events.hpp).
//  * impact (g_α = 0, ġ_α⁻ < 0): Newton's law on the set I of closed contacts. One contact in
//    closed form, P = −(1 + e) ġ⁻ / G with G = W M⁻¹ Wᵀ (Pfeiffer-Glocker (7.9)); several by
//    the LCP 0 ≤ P ⊥ G P + (1 + E) ġ⁻ ≥ 0 (ibid. §7.2), i.e. W u⁺ + E ġ⁻ ≥ 0. u⁺ = u⁻ + M⁻¹WᵀP.
//    Energy: ΔT = ½ G P² + ġ⁻ P = −((1 − e)/(1 + e)) ½ Δuᵀ M Δu, Carnot's theorem for a Newton
//    impact on a fixed wall (Mei ch. 6; Pfeiffer-Glocker §7.3), recorded beside the measured ΔT
//    (less Pᵀw for a moving wall, above).
//    With the sequential impact law the closed contacts instead take one-contact Newton impacts one after
//    another, the fastest approaching first, until none approaches (contact/impact.hpp's sequential
//    law: Newton's cradle of three balls, e = 1, ends at (0, 0, 1), the simultaneous LCP at
//    (−1/3, 2/3, 2/3)); Carnot's prediction is then the sum of each two-body impact's.
//  * contact phase: the closed contacts with ġ ≈ 0 enter the acceleration-level LCP
//    g̈ = G λ + (W M⁻¹ f + b) ≥ 0, λ ≥ 0, λ·g̈ = 0 (Pfeiffer-Glocker (6.19)); those with λ > 0
//    are the active set A. Between transitions A is fixed: g̈_A = 0 is solved as the bilateral
//    system of constraints.hpp (schur_solve), so λ_A(t, x) is smooth, and the indicators of the
//    active contacts are λ_α: separation is λ_α going down through zero, located like a gap. (An
//    LCP in every right-hand side would clamp λ at zero and give the locator no sign change.)
//    After every accepted step the state is projected back onto g_A = 0, ġ_A = 0 in the M-metric
//    (project_onto_constraints; Hairer-Lubich-Wanner, GNI §IV.4).
//  * after every transition every row is checked: no gap below zero beyond a position's tolerance
//    and no closed contact left approaching; a contact closing where its gradient W_α vanishes
//    (y³ ≥ 0) is refused (the constraint qualification), as are impacts that accumulate without a
//    geometric series below the resolution above (an unresolved Zeno point). Each as an
//    IntegrationError of Kind::contact with the contact and the time.
//  * grazing: a gap that only touches zero is no sign change and is not located; a located gap
//    reaching zero with ġ ≈ 0 is no impact: the LCP decides between contact and free flight, and
//    the locator's signs are read afresh there, so it does not fire again at the same time.
//  * Zeno: the impact times t_k of one contact accumulating geometrically (the ratios of successive
//    intervals r_k = Δt_k / Δt_{k−1} in (0, 1) and agreeing to zeno_rtol (1 − r) over zeno_ratios
//    ratios) are summed as a geometric series, t∞ = t_k + Δt_k r / (1 − r) (Aitken's Δ² on the
//    t_k). Every impact the integration resolves is integrated first: the series takes over only
//    once Δt_k is below zeno_resolution (100) times the error σ_k of an impact time (8 ε |t| + the
//    gap's tolerance over |ġ⁻|), so the impacts it skips are worth less than the ones already
//    made carry. (The ratios then agree to zeno_rtol (1 − r) besides what the impact times' errors
//    make of them, 4 σ_k / Δt_k.) The series' own error is about Δt_k δr / (1 − r)², δr the
//    ratios' spread: the impacts go on until that falls below the integrator's tolerance in t
//    (rtol |t| + atol), or stops falling, which is where the round-off of the impact times
//    outweighs the ratios' drift (a pendulum leaning on a wall: r_k → e only as the bounces
//    shrink). The last integrated impact is shown at its time; then the state moves to t∞, each
//    coordinate extrapolated by the same series from the last two post-impact states, then
//    projected onto g_α = 0, ġ_α = 0 (for the bouncing ball exactly rest on the floor). The contact
//    phase follows. (The accumulation point of the bouncing ball: Mei ch. 6; K.H. Johansson,
//    M. Egerstedt, J. Lygeros, S. Sastry, "On the regularization of Zeno hybrid automata", Systems
//    & Control Letters 38 (1999) 141-150.)
//  * kinematic (velocity-level) unilateral constraints φ_α(t, q, u) ≥ 0, linear in u, with
//    φ̇_α = W_α u̇ + b_α (Mei §6.7, the ratchet): no impact (φ reaching zero needs no velocity
//    jump); their contact phase holds φ_A = 0 at velocity level through the same LCP, projection
//    of u only.
//
//  * bilateral rows (Mei §6.6, a nonholonomic system with unilateral holonomic constraints): k rows
//    C u̇ = r (holonomic ∂f/∂q, or kinematic ∂φ/∂u), always active, multipliers of free sign. Every
//    solve eliminates them: the free acceleration is the Schur solve with C alone, the contact
//    phase's with [C; W_A], and the Delassus matrices and impacts use the constrained inverse mass
//    M̃⁻¹ = M⁻¹ − M⁻¹Cᵀ(C M⁻¹ Cᵀ)⁻¹ C M⁻¹ (Pfeiffer-Glocker §6.1 on bilateral constraints beside
//    unilateral ones), so C Δu = 0 over an impact: the bilateral impulses are free, the rows hold
//    across it, and Carnot's theorem keeps its form (C u± = 0 for scleronomic rows). The projection
//    after every step covers the bilateral rows together with the active contacts.
//
//  * scene events (options.events): functions h_i(t, x) located like the contacts' indicators, on
//    the dense output of whichever smooth phase holds them (free flight or a contact phase), with
//    the actions record and stop; they never change the mode.
//
// Assumptions: q̇ = u (so W_α is also ∂ġ_α/∂u), forward time. Kinematic contacts take no part in
// impacts (their φ is already a rate: no time rate is added to it).

#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "eomc/runtime/checker.hpp"
#include "eomc/runtime/constraints.hpp"
#include "eomc/runtime/contact/lcp.hpp"
#include "eomc/runtime/contact/system.hpp"
#include "eomc/runtime/control/error_checker.hpp"
#include "eomc/runtime/control/initial_step.hpp"
#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/events.hpp"
#include "eomc/runtime/state.hpp"
#include "eomc/runtime/stepper/concepts.hpp"

namespace eomc::runtime::contact {

template <class S>
struct EventDrivenOptions {
  // A gap counts as closed at |g| ≤ closed_gap, a velocity as resting at |ġ| ≤ resting_rate (and a
  // kinematic constraint as closed at |φ| ≤ resting_rate). 0 derives them: closed_gap = atol +
  // 100 ε (1 + |q|∞) (a located gap is zero to round-off; other contacts closed within the
  // integrator's tolerance), resting_rate = 1000 ε (1 + |u|∞) (an e = 0 impact leaves ġ⁺ at
  // round-off of the impact velocity).
  S closed_gap = S(0), resting_rate = S(0);
  // Zeno detection: zeno_ratios consecutive interval ratios in (0, 1) agreeing to zeno_rtol (1 − r)
  // mark a geometric accumulation (a pendulum's intervals tending to its half period have a spread
  // of order 1 − r and never qualify); the extrapolation then waits until the intervals are no
  // longer resolved (below zeno_resolution impact-time errors) and for its own error estimate.
  bool detect_zeno = true;
  int zeno_ratios = 3;
  S zeno_rtol = S(1e-2);
  S zeno_resolution = S(100);
  // Impacts allowed in one call, 0 for no limit (an elastic ball bounces for ever, and its
  // intervals do not shrink). Impacts that accumulate without a geometric series are refused
  // whatever this is: unresolved_impacts of one contact in a row, each interval below
  // zeno_resolution impact-time errors.
  std::size_t max_impacts = 0;
  std::size_t unresolved_impacts = 64;
  // The multiple-impact law (method.hpp): Moreau's simultaneous LCP or sequential two-body impacts.
  ImpactLaw impact_law = ImpactLaw::simultaneous;
  // Called with each event, complete, just before the observer sees the state after its transition
  // (so that an observer can label that state): the events of one transition in time order.
  std::function<void(const ContactEvent<S>&)> on_event;
  // Scene events beside the contacts (none by default): their specs (action record or stop; edit is
  // refused), event_functions(t, x, h) writing h_i for each, and on_scene_event(hit, λ, active)
  // at each located one, in time order (hit.index counts the scene events from 0).
  std::vector<EventSpec> events;
  std::function<void(S, const State<S>&, State<S>&)> event_functions;
  std::function<void(const EventHit<S>&, const Vector<S>&, const std::vector<bool>&)> on_scene_event;
};

template <class S>
struct EventDrivenOutcome {
  Stats stats;
  S t = S(0);
  std::vector<ContactEvent<S>> events;
  std::vector<bool> active;  // the active set at the end
  Vector<S> lambda;          // λ at the end (zero off the active set)
  bool stopped = false;      // a terminal scene event ended the run at t
  std::size_t stopped_by = 0;  // which (in options.events)
  // Pieces of steps on which an indicator (a gap, a λ, a scene event) would not resolve, and the
  // first one's time (EventLocator::unresolved): a crossing may have gone unseen there.
  std::size_t unresolved = 0;
  S first_unresolved = S(0);
};

namespace detail {

// The complementarity problem 0 ≤ z ⊥ A z + c ≥ 0 with A symmetric positive definite (a Delassus
// matrix G): one row in closed form, several by Lemke's method (contact/lcp.hpp).
template <class S>
Vector<S> solve_contact_lcp(const Matrix<S>& A, const Vector<S>& c) {
  if (c.size() == 1) {
    Vector<S> z(1);
    z[0] = c[0] < S(0) ? -c[0] / A(0, 0) : S(0);
    return z;
  }
  // A Delassus matrix is positive semidefinite: Lemke's method then ends in a solution unless the
  // LCP is infeasible (Cottle, Pang, Stone, The Linear Complementarity Problem, 1992, Thm 4.4.13).
  const LcpResult<S> r = solve_lcp<S>(A, c);
  if (r.status != LcpStatus::solved)
    throw std::runtime_error(std::string("integrate_event_driven: the contact LCP failed: ") + to_string(r.status));
  return r.z;
}

// The blocks of a ContactSystem at one state, and the solves the driver builds from them.
template <class S>
class ContactModel {
 public:
  explicit ContactModel(const ContactSystem<S>& sys)
      : sys_(sys), n_(sys.dof), m_(static_cast<int>(sys.contacts.size())),
        k_(static_cast<int>(sys.bilateral_holonomic.size())), q_(n_), u_(n_), M_(n_, n_), f_(n_), g_(m_),
        W_(m_, n_), b_(m_), w_(Vector<S>::Zero(m_)), bf_(k_), bphi_(k_), C_(k_, n_), r_(k_),
        row_norm_max_(Vector<S>::Zero(m_)) {
    if (k_ > 0 && !sys.bilateral) throw std::invalid_argument("integrate_event_driven: bilateral rows need bilateral()");
  }

  int dof() const { return n_; }
  int contacts() const { return m_; }
  const Contact<S>& contact(int a) const { return sys_.contacts[std::size_t(a)]; }
  bool kinematic(int a) const { return contact(a).level == GapLevel::velocity; }
  int bilateral() const { return k_; }

  // M, f, g, W, b at (t, x) and the LDLT of M.
  void evaluate(S t, const State<S>& x) {
    split(x);
    sys_.mass(t, q_, M_);
    sys_.force(t, q_, u_, f_);
    sys_.gaps(t, q_, u_, g_);
    sys_.rows(t, q_, u_, W_, b_);
    for (int a = 0; a < m_; ++a) row_norm_max_[a] = std::max(row_norm_max_[a], S(W_.row(a).norm()));
    time_rates(t);
    ldlt_.compute(M_);
    free_ = ldlt_.solve(f_);
    if (k_ > 0) {
      sys_.bilateral(t, q_, u_, bf_, bphi_, C_, r_);
      Yc_ = ldlt_.solve(Matrix<S>(C_.transpose()));
      Gc_.compute(C_ * Yc_);
      free_ += Yc_ * Gc_.solve(Vector<S>(r_ - C_ * free_));
    }
  }
  void gaps_only(S t, const State<S>& x) {
    split(x);
    sys_.gaps(t, q_, u_, g_);
  }

  const Vector<S>& q() const { return q_; }
  const Vector<S>& u() const { return u_; }
  const Matrix<S>& M() const { return M_; }
  const Vector<S>& g() const { return g_; }
  const Matrix<S>& W() const { return W_; }
  const Vector<S>& b() const { return b_; }
  const Vector<S>& w() const { return w_; }
  // The contact's closing rate: ġ_α = W_α u + w_α for a gap (w_α = ∂g_α/∂t of a moving wall), φ_α
  // itself for a kinematic constraint.
  S rate(int a) const { return kinematic(a) ? g_[a] : S(W_.row(a).dot(u_) + w_[a]); }
  // The time rates of the rows of `set`.
  Vector<S> time_rates_of(const std::vector<int>& set) const {
    Vector<S> out(Eigen::Index(set.size()));
    for (std::size_t i = 0; i < set.size(); ++i) out[Eigen::Index(i)] = w_[set[i]];
    return out;
  }

  Matrix<S> rows_of(const std::vector<int>& set) const {
    Matrix<S> out(Eigen::Index(set.size()), n_);
    for (std::size_t i = 0; i < set.size(); ++i) out.row(Eigen::Index(i)) = W_.row(set[i]);
    return out;
  }
  // G = W_C M̃⁻¹ W_Cᵀ and W_C u̇_free + b_C, the contact-phase LCP's data on the set C (u̇_free
  // holds the bilateral rows).
  void delassus(const std::vector<int>& set, Matrix<S>& G, Vector<S>& c) const {
    const Matrix<S> Wc = rows_of(set);
    G = Wc * solve_mass(Matrix<S>(Wc.transpose()));
    c = Wc * free_;
    for (std::size_t i = 0; i < set.size(); ++i) c[Eigen::Index(i)] += b_[set[i]];
  }
  // M̃⁻¹ B for a vector or a matrix B: M⁻¹ B with the bilateral rows' reaction taken out, so that
  // C M̃⁻¹ B = 0 (M⁻¹ B when there are no bilateral rows).
  template <class B>
  auto solve_mass(const B& v) const {
    using Out = std::conditional_t<B::ColsAtCompileTime == 1, Vector<S>, Matrix<S>>;
    Out out = ldlt_.solve(v);
    if (k_ > 0) out -= Yc_ * Gc_.solve(Out(C_ * out));
    return out;
  }

  // u̇ and λ (m, zero off the active set) with g̈_A = 0 held (constraints.hpp's Schur solve).
  void accelerations(S t, const State<S>& x, const std::vector<bool>& active, Vector<S>& udot, Vector<S>& lambda) {
    evaluate(t, x);
    lambda.setZero(m_);
    std::vector<int> set;
    for (int a = 0; a < m_; ++a)
      if (active[std::size_t(a)]) set.push_back(a);
    if (set.empty()) {
      udot = free_;
      return;
    }
    // The bilateral rows first, then the active contacts: M u̇ − [C; W_A]ᵀ(μ, λ_A) = f.
    const Eigen::Index k = k_, s = Eigen::Index(set.size());
    Matrix<S> rows(k + s, n_);
    Vector<S> r(k + s), la;
    rows.topRows(k) = C_;
    r.head(k) = r_;
    rows.bottomRows(s) = rows_of(set);
    for (Eigen::Index i = 0; i < s; ++i) r[k + i] = -b_[set[std::size_t(i)]];
    schur_solve<S>(M_, f_, rows, r, udot, la);
    for (Eigen::Index i = 0; i < s; ++i) lambda[set[std::size_t(i)]] = la[k + i];
  }

  // Puts x back on the bilateral rows and on g_α = 0 (gaps) and ġ_α = 0 / φ_α = 0 for the rows
  // with on[α], together, in the M-metric. The bilateral rows come first in the stacked system.
  void project(S t, State<S>& x, const std::vector<bool>& on) {
    const int all = k_ + m_;
    std::unique_ptr<bool[]> projected(new bool[std::size_t(all)]), holonomic(new bool[std::size_t(all)]);
    bool any = k_ > 0;
    for (int i = 0; i < k_; ++i) {
      projected[std::size_t(i)] = true;
      holonomic[std::size_t(i)] = sys_.bilateral_holonomic[std::size_t(i)];
    }
    for (int a = 0; a < m_; ++a) {
      projected[std::size_t(k_ + a)] = on[std::size_t(a)];
      holonomic[std::size_t(k_ + a)] = !kinematic(a);
      any = any || on[std::size_t(a)];
    }
    if (!any) return;
    const ConstraintLayout layout{n_, n_, n_, all};
    const auto residuals = [&](S tt, const S* xp, S* f, S* phi) {
      split(xp);
      sys_.gaps(tt, q_, u_, g_);
      sys_.rows(tt, q_, u_, W_, b_);
      time_rates(tt);
      if (k_ > 0) sys_.bilateral(tt, q_, u_, bf_, bphi_, C_, r_);
      for (int i = 0; i < k_; ++i) {
        f[i] = bf_[i];
        phi[i] = bphi_[i];
      }
      for (int a = 0; a < m_; ++a) {
        f[k_ + a] = kinematic(a) ? S(0) : g_[a];
        phi[k_ + a] = rate(a);
      }
    };
    const auto jacobian = [&](S tt, const S* xp, S* out) {
      split(xp);
      sys_.rows(tt, q_, u_, W_, b_);
      if (k_ > 0) sys_.bilateral(tt, q_, u_, bf_, bphi_, C_, r_);
      for (int i = 0; i < k_; ++i)
        for (int k = 0; k < n_; ++k) out[i * n_ + k] = C_(i, k);
      for (int a = 0; a < m_; ++a)
        for (int k = 0; k < n_; ++k) out[(k_ + a) * n_ + k] = W_(a, k);
    };
    const auto mass = [&](S tt, const S* xp, S* out) {
      split(xp);
      sys_.mass(tt, q_, M_);
      for (int i = 0; i < n_; ++i)
        for (int k = 0; k < n_; ++k) out[i * n_ + k] = M_(i, k);
    };
    project_onto_constraints<S>(t, x.data(), layout, projected.get(), holonomic.get(), residuals, jacobian, mass);
  }

  S kinetic_energy(const Vector<S>& u) const { return S(0.5) * u.dot(M_ * u); }

  // Whether row a has kept its gradient at the last evaluation: |W_a| above √ε times the largest
  // |W_a| seen so far. A gap whose gradient vanishes on g = 0 (y³ ≥ 0, the same set as y ≥ 0)
  // violates the constraint qualification: its impulse and its λ are W⁻¹ of a finite velocity
  // or force, and come out as 10⁴⁷ where they should be an error.
  bool qualified(int a) const {
    using std::sqrt;
    return S(W_.row(a).norm()) > sqrt(std::numeric_limits<S>::epsilon()) * row_norm_max_[a];
  }

 private:
  void split(const State<S>& x) { split(x.data()); }
  // w at (t, q_): the system's, zero on kinematic rows (their φ is already a rate); zero without it.
  void time_rates(S t) {
    if (!sys_.time_rates) return;
    sys_.time_rates(t, q_, w_);
    for (int a = 0; a < m_; ++a)
      if (kinematic(a)) w_[a] = S(0);
  }
  void split(const S* x) {
    for (int k = 0; k < n_; ++k) {
      q_[k] = x[k];
      u_[k] = x[n_ + k];
    }
  }

  const ContactSystem<S>& sys_;
  int n_, m_, k_;
  Vector<S> q_, u_;
  Matrix<S> M_;
  Vector<S> f_, g_;
  Matrix<S> W_;
  Vector<S> b_, w_;       // the bias of g̈ and the time rates ∂g/∂t
  Vector<S> bf_, bphi_;  // the bilateral rows' residuals
  Matrix<S> C_, Yc_;     // their Jacobian and M⁻¹Cᵀ
  Vector<S> r_, free_;   // C u̇ = r; the free acceleration (bilateral rows held)
  Vector<S> row_norm_max_;  // the largest |W_α| evaluated so far, per contact (qualified())
  Eigen::LDLT<Matrix<S>> ldlt_, Gc_;
};


// One run of integrate_event_driven (below; its arguments already validated): the state its phases
// share (the model, the outcome, the active set, λ and u̇, the impact histories, the locator, the
// checker, the counters) and its steps as member functions, in the order of the run: start(), then
// first_step() and step() until t1 or a stop, then finish().
template <template <class> class Stepper, class S, class Obs>
class EventDrivenRun {
 public:
  EventDrivenRun(Stepper<S>& stepper, const ContactSystem<S>& sys, State<S>& x, S t0, S t1, const Tolerances& tol,
                 Obs& observer, const EventDrivenOptions<S>& options, const Limits& limits)
      : stepper_(stepper), x_(x), t1_(t1), tol_(tol), observer_(observer), options_(options), n_(sys.dof),
        m_(static_cast<int>(sys.contacts.size())), n_events_(options.events.size()), model_(sys),
        active_(std::size_t(m_), false), udot_(n_), lambda_(Vector<S>::Zero(m_)),
        history_(std::size_t(m_), History{}), scene_values_(n_events_), checker_(limits), t_(t0),
        hmax_(max_step(t0, t1, limits)) {}
  EventDrivenRun(const EventDrivenRun&) = delete;
  EventDrivenRun& operator=(const EventDrivenRun&) = delete;

  EventDrivenOutcome<S> run() {
    start();
    out_.t = t1_;
    if (t_ >= t1_) {
      out_.active = active_;
      out_.lambda = lambda_;
      return std::move(out_);
    }
    evals0_ = stepper_.rhs_evals();
    h_ = first_step(t_);
    checker_.set_reference_step(h_);
    while (t_ < t1_)
      if (!step()) break;
    return finish();
  }

 private:
  // Per contact: its impact times and post-impact states since it last left a contact phase.
  struct History {
    std::vector<S> t;
    State<S> x_last, x_prev;
    S estimate = std::numeric_limits<S>::infinity();  // the last Zeno error estimate
    S sigma = S(0);             // the last impact time's error: 8 ε |t| + the gap's tolerance / |ġ⁻|
    std::size_t unresolved = 0;  // impacts in a row whose interval was below zeno_resolution σ
  };

  static S inf_norm(const Vector<S>& v) { return v.size() ? S(v.cwiseAbs().maxCoeff()) : S(0); }
  static S max_step(S t0, S t1, const Limits& limits) {
    S hmax = t1 - t0;
    if (limits.max_step > 0.0 && S(limits.max_step) < hmax) hmax = S(limits.max_step);
    return hmax;
  }

  S gap_tol() const {
    return options_.closed_gap > S(0) ? options_.closed_gap
                                      : S(tol_.atol) + S(100) * eps_ * (S(1) + inf_norm(model_.q()));
  }
  S rate_tol(S scale) const {
    return options_.resting_rate > S(0) ? options_.resting_rate
                                        : S(1000) * eps_ * (S(1) + inf_norm(model_.u()) + scale);
  }

  void rates(S t, const State<S>& xs, State<S>& dx) {
    model_.accelerations(t, xs, active_, udot_, lambda_);
    for (int k = 0; k < n_; ++k) {
      dx[std::size_t(k)] = xs[std::size_t(n_ + k)];
      dx[std::size_t(n_ + k)] = udot_[k];
    }
  }
  // The indicators: g_α of the open contacts, λ_α of the active ones, each event one going down;
  // then the scene's event functions.
  void indicators(S t, const State<S>& xs, State<S>& o) {
    if (any_active_) model_.accelerations(t, xs, active_, udot_, lambda_);
    else model_.gaps_only(t, xs);
    for (int a = 0; a < m_; ++a) o[std::size_t(a)] = active_[std::size_t(a)] ? lambda_[a] : model_.g()[a];
    if (n_events_ == 0) return;
    options_.event_functions(t, xs, scene_values_);
    for (std::size_t i = 0; i < n_events_; ++i) o[std::size_t(m_) + i] = scene_values_[i];
  }
  // rates and indicators as the callables the stepper and the locator take (by reference).
  auto rates_function() {
    return [this](S t, const State<S>& xs, State<S>& dx) { rates(t, xs, dx); };
  }
  auto indicator_functions() {
    return [this](S t, const State<S>& xs, State<S>& o) { indicators(t, xs, o); };
  }

  ContactEvent<S>& record(ContactEventKind kind, int a, S t) {
    ContactEvent<S> e;
    e.kind = kind;
    e.contact = std::size_t(a);
    e.t = t;
    out_.events.push_back(e);
    return out_.events.back();
  }

  // The contact decision at (t, x): the closed, resting contacts (not `excluded`, which has just
  // separated) enter the acceleration-level LCP; λ > 0 makes the active set.
  void decide_mode(S t, State<S>& xs, int excluded) {
    using std::abs;
    model_.evaluate(t, xs);
    const S gtol = gap_tol(), vtol = rate_tol(S(0));
    std::vector<int> closed;
    for (int a = 0; a < m_; ++a) {
      if (a == excluded) continue;
      const bool gap_closed = model_.kinematic(a) || abs(model_.g()[a]) <= gtol;
      if (gap_closed && abs(model_.rate(a)) <= vtol) closed.push_back(a);
    }
    for (int c : closed) require_qualified(t, c);
    std::vector<bool> next(std::size_t(m_), false);
    Vector<S> la;
    if (!closed.empty()) {
      Matrix<S> G;
      Vector<S> c;
      model_.delassus(closed, G, c);
      la = solve_contact_lcp<S>(G, c);
      for (std::size_t i = 0; i < closed.size(); ++i) next[std::size_t(closed[i])] = la[Eigen::Index(i)] > S(0);
    }
    for (int a = 0; a < m_; ++a) {
      const std::size_t ia = std::size_t(a);
      if (next[ia] && !active_[ia]) {
        S lam = S(0);
        for (std::size_t i = 0; i < closed.size(); ++i)
          if (closed[i] == a) lam = la[Eigen::Index(i)];
        record(ContactEventKind::contact, a, t).lambda = lam;
        history_[ia].t.clear();
        history_[ia].estimate = std::numeric_limits<S>::infinity();
      } else if (!next[ia] && active_[ia] && a != excluded) {
        record(ContactEventKind::separation, a, t);
      }
    }
    active_ = next;
    any_active_ = false;
    for (bool on : active_) any_active_ = any_active_ || on;
    model_.project(t, xs, active_);  // the bilateral rows and the active contacts
  }

  // Geometric accumulation of contact a's impacts: moves (t, x) to the limit and returns true.
  bool zeno(S& t, State<S>& xs, int a) {
    using std::abs;
    History& hist = history_[std::size_t(a)];
    const std::size_t k = hist.t.size(), need = std::size_t(options_.zeno_ratios) + 2;
    if (!options_.detect_zeno || k < need) return false;
    const auto interval = [&](std::size_t i) { return hist.t[i] - hist.t[i - 1]; };
    S rmin = S(2), rmax = S(-1);
    for (std::size_t i = k - std::size_t(options_.zeno_ratios); i < k; ++i) {
      const S r = interval(i) / interval(i - 1);
      rmin = r < rmin ? r : rmin;
      rmax = r > rmax ? r : rmax;
    }
    const S r = interval(k - 1) / interval(k - 2), dt = interval(k - 1);
    const S previous = hist.estimate;
    hist.estimate = std::numeric_limits<S>::infinity();
    // Every impact the integration resolves is integrated: the series takes over only where the
    // intervals fall below zeno_resolution times the error of an impact time, and what it then
    // skips is worth less than that error once more (Σ σ_k over the rest, a geometric series).
    if (!(dt <= options_.zeno_resolution * hist.sigma)) return false;
    // The ratios agree to zeno_rtol (1 − r), beside what the impact times' own errors make of them
    // (each ratio of two intervals of at least dt, each end off by up to σ: 4 σ / dt).
    const S noise = S(4) * hist.sigma / dt;
    if (!(rmin > S(0) && rmax < S(1) && rmax - rmin <= options_.zeno_rtol * (S(1) - r) + noise)) return false;
    const S estimate = dt * (rmax - rmin) / ((S(1) - r) * (S(1) - r));
    hist.estimate = estimate;
    if (!(estimate <= S(tol_.rtol) * abs(hist.t[k - 1]) + S(tol_.atol) || estimate >= previous)) return false;
    const S factor = r / (S(1) - r), t_inf = hist.t[k - 1] + dt * factor;
    if (!(t_inf < t1_)) return false;
    observe(t, xs);  // the last integrated impact, at its own time, before the jump to t∞
    // The same series for every coordinate: x∞ = x_k + (x_k − x_{k−1}) r / (1 − r).
    for (std::size_t i = 0; i < xs.size(); ++i) xs[i] = hist.x_last[i] + (hist.x_last[i] - hist.x_prev[i]) * factor;
    std::vector<bool> on = active_;
    on[std::size_t(a)] = true;
    model_.evaluate(t_inf, xs);
    model_.project(t_inf, xs, on);
    ContactEvent<S>& e = record(ContactEventKind::zeno, a, t_inf);
    e.ratio = r;
    e.extrapolation_error = estimate;
    t = t_inf;
    hist.t.clear();
    hist.estimate = std::numeric_limits<S>::infinity();
    hist.unresolved = 0;
    return true;
  }

  // Newton's impact law at (t, x) on the closed gaps, contact a having fired.
  bool impact(S& t, State<S>& xs, int a) {
    using std::abs;
    if (++impacts_ > options_.max_impacts && options_.max_impacts > 0)
      throw IntegrationError::contact(t, std::size_t(a), "more than max_impacts = " +
                                                             std::to_string(options_.max_impacts) + " impacts");
    model_.evaluate(t, xs);
    const S gtol = gap_tol();
    std::vector<int> set;
    for (int c = 0; c < m_; ++c)
      if (!model_.kinematic(c) && (c == a || abs(model_.g()[c]) <= gtol)) set.push_back(c);
    for (int c : set) require_qualified(t, c);
    const Matrix<S> Wi = model_.rows_of(set);
    const Vector<S> wi = model_.time_rates_of(set);  // ∂g/∂t: ġ = W u + w (a moving wall)
    const Vector<S> u_minus = model_.u(), rate_minus = Wi * u_minus + wi;
    const Eigen::Index ns = Eigen::Index(set.size());
    const auto restitution = [&](Eigen::Index i) { return model_.contact(set[std::size_t(i)]).restitution; };
    Vector<S> P = Vector<S>::Zero(ns), u_plus = u_minus;
    S carnot = S(0);
    if (options_.impact_law == ImpactLaw::sequential) {
      // One-contact Newton impacts, the fastest approaching contact first, until none approaches
      // beyond the rounding of its rate (64 ε (Σ_j |W_αj u_j| + |w_α|), as contact/impact.hpp).
      const Matrix<S> Y = model_.solve_mass(Matrix<S>(Wi.transpose()));  // M̃⁻¹ W_Iᵀ
      for (std::size_t count = 0;; ++count) {
        const Vector<S> rate = Wi * u_plus + wi;
        const Vector<S> noise = S(64) * eps_ * (Wi.cwiseAbs() * u_plus.cwiseAbs() + wi.cwiseAbs());
        Eigen::Index i = -1;
        for (Eigen::Index j = 0; j < ns; ++j)
          if (rate[j] < -noise[j] && (i < 0 || rate[j] < rate[i])) i = j;
        if (i < 0) break;
        if (count >= sequential_limit)
          throw IntegrationError::contact(t, std::size_t(set[std::size_t(i)]),
                                          "the sequential impact law did not end after " +
                                              std::to_string(sequential_limit) + " two-body impacts (inelastic collapse?)");
        const S e = restitution(i), p = -(S(1) + e) * rate[i] / Wi.row(i).dot(Y.col(i));
        const Vector<S> du = Y.col(i) * p;
        carnot += -((S(1) - e) / (S(1) + e)) * model_.kinetic_energy(du) - p * wi[i];
        u_plus += du;
        P[i] += p;
      }
    } else {
      // Newton's law on the approaching contacts, ġ⁺ ≥ −e ġ⁻, and ġ⁺ ≥ 0 on the closed ones that
      // were already opening (Glocker's form; an opening contact given −e ġ⁻ > 0 of room would be
      // free to approach after the impact and sink through its wall).
      const Matrix<S> G = Wi * model_.solve_mass(Matrix<S>(Wi.transpose()));
      Vector<S> c(ns);
      for (Eigen::Index i = 0; i < ns; ++i)
        c[i] = rate_minus[i] + (rate_minus[i] < S(0) ? restitution(i) * rate_minus[i] : S(0));
      try {
        P = solve_contact_lcp<S>(G, c);
      } catch (const std::runtime_error& e) {
        throw IntegrationError::contact(t, std::size_t(a),
                                        std::string("no impulse satisfies Newton's law on the closed contacts (") +
                                            e.what() + "): contacts that pinch the motion with e > 0");
      }
      const Vector<S> du = model_.solve_mass(Vector<S>(Wi.transpose() * P));
      u_plus = u_minus + du;
      const S e = model_.contact(a).restitution;
      carnot = -((S(1) - e) / (S(1) + e)) * model_.kinetic_energy(du) - P.dot(wi);
    }
    const Vector<S> rate_plus = Wi * u_plus + wi;
    const S dT = model_.kinetic_energy(u_plus) - model_.kinetic_energy(u_minus);
    for (int k = 0; k < n_; ++k) xs[std::size_t(n_ + k)] = u_plus[k];
    for (std::size_t i = 0; i < set.size(); ++i) {
      const Eigen::Index ii = Eigen::Index(i);
      if (set[i] != a && !(P[ii] > S(0))) continue;
      ContactEvent<S>& ev = record(ContactEventKind::impact, set[i], t);
      ev.rate_before = rate_minus[ii];
      ev.rate_after = rate_plus[ii];
      ev.impulse = P[ii];
      ev.energy_change = dT;
      ev.carnot = carnot;
      History& hist = history_[std::size_t(set[i])];
      hist.t.push_back(t);
      hist.x_prev = std::move(hist.x_last);
      hist.x_last = xs;
      hist.sigma = S(8) * eps_ * abs(t) +
                   (S(tol_.rtol) * (S(1) + inf_norm(model_.q())) + S(tol_.atol)) / abs(rate_minus[ii]);
      count_unresolved(t, set[i]);
    }
    return zeno(t, xs, a);
  }

  // Impacts of contact c in a row whose intervals the integration does not resolve, with no
  // geometric series to extrapolate (zeno() clears the history when it takes over): refused.
  void count_unresolved(S t, int c) {
    History& hist = history_[std::size_t(c)];
    const std::size_t k = hist.t.size();
    if (k < 2 || !(hist.t[k - 1] - hist.t[k - 2] <= options_.zeno_resolution * hist.sigma)) {
      hist.unresolved = 0;
      return;
    }
    if (++hist.unresolved >= options_.unresolved_impacts)
      throw IntegrationError::contact(
          t, std::size_t(c),
          std::to_string(hist.unresolved) + " impacts in a row closer together than " +
              IntegrationError::format(options_.zeno_resolution) + " times their own time error (" +
              IntegrationError::format(hist.sigma) +
              ") without forming a geometric series: an accumulation of impacts the integration cannot resolve "
              "(tighten the tolerances, or give the contact some restitution loss)");
  }

  // The constraint qualification of contact c where it closes (ContactModel::qualified).
  void require_qualified(S t, int c) const {
    if (!model_.qualified(c))
      throw IntegrationError::contact(t, std::size_t(c),
                                      "the gradient of the constraint vanishes where it closes (|W| = " +
                                          IntegrationError::format(S(model_.W().row(c).norm())) +
                                          "): the constraint qualification fails, and no finite impulse or "
                                          "reaction holds it; write the row so that its gradient is non-zero on "
                                          "its boundary (y >= 0, not y^3 >= 0)");
  }

  // A located event of contact a at (t, x): a separation, or a gap closing (impact or graze).
  void transition(S& t, State<S>& xs, int a) {
    using std::abs;
    if (active_[std::size_t(a)]) {
      record(ContactEventKind::separation, a, t);
      active_[std::size_t(a)] = false;
      decide_mode(t, xs, a);
      return;
    }
    model_.evaluate(t, xs);
    const S v = model_.rate(a);
    if (!model_.kinematic(a) && v < -rate_tol(abs(v))) {
      observe(t, xs);  // the state as integrated up to the impact, then the one after it
      impact(t, xs, a);
    }
    decide_mode(t, xs, -1);
    check_rows(t, xs);
  }

  // After every transition, every row: no gap below zero beyond the tolerance of a position, no
  // closed contact left approaching (an impact that closed one contact while another was
  // opening, contacts that pinch), where the locator, which waits for a gap to go down through
  // zero, would never see it.
  void check_rows(S t, const State<S>& xs) {
    using std::abs;
    model_.evaluate(t, xs);
    const S gtol = gap_tol() + S(tol_.rtol) * (S(1) + inf_norm(model_.q()));
    for (int a = 0; a < m_; ++a) {
      if (model_.kinematic(a)) continue;
      const S g = model_.g()[a], v = model_.rate(a);
      if (g < -gtol)
        throw IntegrationError::contact(t, std::size_t(a), "the gap is " + IntegrationError::format(g) +
                                                               " after the transition there: the state has left the "
                                                               "admissible set");
      if (!active_[std::size_t(a)] && abs(g) <= gtol && v < -rate_tol(abs(v)))
        throw IntegrationError::contact(t, std::size_t(a), "the closed contact still approaches (rate " +
                                                               IntegrationError::format(v) +
                                                               ") after the transition there");
    }
  }

  void observe(S t, const State<S>& xs) {
    if (options_.on_event)
      for (; reported_ < out_.events.size(); ++reported_) options_.on_event(out_.events[reported_]);
    if (any_active_) model_.accelerations(t, xs, active_, udot_, lambda_);
    else lambda_.setZero(m_);
    observer_(t, xs, static_cast<const Vector<S>&>(lambda_), static_cast<const std::vector<bool>&>(active_));
  }

  // The start: on the bilateral rows, approaching closed gaps collide, then the contact decision.
  // The locator reads its signs there; the observer sees the state.
  void start() {
    using std::abs;
    model_.project(t_, x_, active_);
    model_.evaluate(t_, x_);
    const S gtol = gap_tol();
    for (int a = 0; a < m_; ++a)
      if (!model_.kinematic(a) && abs(model_.g()[a]) <= gtol && model_.rate(a) < -rate_tol(S(0))) {
        observe(t_, x_);  // the initial state, then the one after its impact
        impact(t_, x_, a);
        break;
      }
    decide_mode(t_, x_, -1);
    check_rows(t_, x_);

    std::vector<EventSpec> specs(std::size_t(m_), EventSpec{EventDirection::down, false, EventAction::edit, 0.0});
    specs.insert(specs.end(), options_.events.begin(), options_.events.end());
    locator_.emplace(std::move(specs));
    locator_->resolve_with(tol_.rtol, tol_.atol);  // a gap's dip inside one step is seen (events.hpp)
    auto g = indicator_functions();
    locator_->start(g, t_, static_cast<const State<S>&>(x_));
    checker_.check_state(t_, x_);
    observe(t_, x_);
  }

  // The first step after a transition. A gap just opened by an impact closes again after about
  // 2 ġ⁺ / |g̈|, which can be far shorter than what the error control would take from the smooth
  // motion (a small bounce): a step over the whole flight would hold two sign changes of g and
  // miss the next impact (events.hpp's limitation). The first step ends before the apex, ġ / |g̈|;
  // from there the gap only falls, and one crossing per step is seen.
  S first_step(S t_from) {
    using std::abs;
    auto f = rates_function();
    checker_.check_derivative(t_from, stepper_.prepare(f, x_, t_from));
    S h_first = initial_step(f, t_from, static_cast<const State<S>&>(x_), stepper_.derivative(), S(1),
                             Stepper<S>::error_order, tol_, hmax_, extra_evals_);
    model_.accelerations(t_from, x_, active_, udot_, lambda_);
    const S gtol = gap_tol();
    for (int a = 0; a < m_; ++a) {
      if (active_[std::size_t(a)] || model_.kinematic(a) || !(abs(model_.g()[a]) <= gtol)) continue;
      const S v = model_.rate(a), acc = S(model_.W().row(a).dot(udot_)) + model_.b()[a];
      if (v > S(0) && acc < S(0) && v / -acc < h_first) h_first = v / -acc;
    }
    return h_first;
  }

  // One attempt of the main loop, from (t, x) with the step h. Returns false where the run ends: a
  // terminal scene event, or a transition at t1.
  bool step() {
    if (checker_.underflows(t_, h_)) checker_.check_step_size(t_, h_);
    checker_.count_attempt(t_);
    if (h_ > hmax_) h_ = hmax_;
    const bool last = t_ + h_ >= t1_;
    if (last) h_ = t1_ - t_;
    const S t_old = t_;
    auto f = rates_function();
    if (!stepper_.try_step(f, x_, t_, h_, tol_)) {
      ++out_.stats.rejected;
      return true;
    }
    ++out_.stats.accepted;
    if (last) t_ = t1_;
    checker_.check_state(t_, x_);
    auto g = indicator_functions();
    const auto dense = [&](S tau, State<S>& o) { stepper_.calc_state(tau, o); };
    const bool interrupted = locator_->step(g, t_old, t_, static_cast<const State<S>&>(x_), dense, hits_);
    scene_events();
    if (out_.stopped) {
      t_ = hits_.back().t;
      x_ = hits_.back().x;
      if (any_active_ || model_.bilateral() > 0) model_.project(t_, x_, active_);
      observe(t_, x_);
      return false;
    }
    if (!interrupted) {
      if (any_active_ || model_.bilateral() > 0) model_.project(t_, x_, active_);
      observe(t_, x_);
      return true;
    }
    // A transition: the smooth phase ends at the event; the stepper starts afresh after it.
    t_ = hits_.back().t;
    x_ = hits_.back().x;
    transition(t_, x_, int(hits_.back().index));
    stepper_.reset();
    locator_->restart(g, t_, static_cast<const State<S>&>(x_));
    checker_.check_state(t_, x_);
    observe(t_, x_);
    if (t_ >= t1_) return false;
    h_ = first_step(t_);
    return true;
  }

  // The scene events of this step, in time order (a terminal one ends the list and the run).
  void scene_events() {
    for (EventHit<S>& hit : hits_) {
      if (hit.index < std::size_t(m_)) continue;
      hit.index -= std::size_t(m_);
      if (any_active_) model_.accelerations(hit.t, hit.x, active_, udot_, lambda_);
      else lambda_.setZero(m_);
      if (options_.on_scene_event)
        options_.on_scene_event(static_cast<const EventHit<S>&>(hit), static_cast<const Vector<S>&>(lambda_),
                                static_cast<const std::vector<bool>&>(active_));
      if (hit.terminal) {
        out_.stopped = true;
        out_.stopped_by = hit.index;
      }
    }
  }

  EventDrivenOutcome<S> finish() {
    out_.stats.rhs_evals = stepper_.rhs_evals() - evals0_ + extra_evals_;
    out_.t = t_;
    out_.active = active_;
    out_.lambda = lambda_;
    out_.unresolved = locator_->unresolved();
    out_.first_unresolved = locator_->first_unresolved();
    return std::move(out_);
  }

  Stepper<S>& stepper_;
  State<S>& x_;
  const S t1_;
  const Tolerances& tol_;
  Obs& observer_;
  const EventDrivenOptions<S>& options_;
  const int n_, m_;
  const std::size_t n_events_;
  static constexpr std::size_t sequential_limit = 100000;  // two-body impacts in one sequential impact
  const S eps_ = std::numeric_limits<S>::epsilon();
  ContactModel<S> model_;
  EventDrivenOutcome<S> out_;
  std::vector<bool> active_;  // the active set A
  Vector<S> udot_, lambda_;
  bool any_active_ = false;
  std::size_t impacts_ = 0;   // impacts so far (max_impacts)
  std::size_t reported_ = 0;  // the events passed to options.on_event
  std::vector<History> history_;
  State<S> scene_values_;                   // the scene's event functions at one point
  std::optional<EventLocator<S>> locator_;  // made at the start, after the contact decision
  NoProgressChecker<S> checker_;
  std::vector<EventHit<S>> hits_;  // the events of the last step
  S t_, h_ = S(0), hmax_;
  std::size_t evals0_ = 0, extra_evals_ = 0;  // the stepper's count at the first step; initial_step's
};

}  // namespace detail

// Integrates the system from (t0, x) to t1 > t0, x = (q, u) of 2n, through free flight, impacts,
// contact phases and Zeno accumulations (see the top of this file). stepper: an adaptive stepper
// with dense output (Dopri5, Dop853), reset at every transition. observer(t, x, λ, active) at t0,
// after every accepted step and after every transition (at an impact twice: the state before it,
// then after it, the events reported in between); λ is Vector<S> of m, active a
// std::vector<bool>. Returns the events in time order, the counters and the final mode; x is the
// state at t1. Throws IntegrationError like the other adaptive drivers, and of Kind::contact where
// the motion cannot go on with its contacts (the top of this file).
template <template <class> class Stepper, class S, class Obs>
  requires AdaptiveStepper<Stepper<S>> && DenseOutputStepper<Stepper<S>>
EventDrivenOutcome<S> integrate_event_driven(Stepper<S>& stepper, const ContactSystem<S>& sys, State<S>& x,
                                             std::type_identity_t<S> t0, std::type_identity_t<S> t1,
                                             const Tolerances& tol, Obs&& observer,
                                             const EventDrivenOptions<S>& options = {}, const Limits& limits = {}) {
  validate(tol);
  const int n = sys.dof;
  if (n <= 0 || x.size() != std::size_t(2 * n))
    throw std::invalid_argument("integrate_event_driven: x must hold q and u, 2 dof values");
  if (!(t1 >= t0)) throw std::invalid_argument("integrate_event_driven: t1 must not precede t0");
  if (options.zeno_ratios < 1) throw std::invalid_argument("integrate_event_driven: zeno_ratios must be >= 1");
  for (const Contact<S>& c : sys.contacts)
    if (!(c.restitution >= S(0) && c.restitution <= S(1)))
      throw std::invalid_argument("integrate_event_driven: restitution must lie in [0, 1]");
  for (const EventSpec& spec : options.events)
    if (spec.effective_action() == EventAction::edit)
      throw std::invalid_argument("integrate_event_driven: scene events record or stop; they do not edit the state");
  if (!options.events.empty() && !options.event_functions)
    throw std::invalid_argument("integrate_event_driven: scene events need event_functions");
  return detail::EventDrivenRun<Stepper, S, Obs>(stepper, sys, x, t0, t1, tol, observer, options, limits).run();
}

}  // namespace eomc::runtime::contact
