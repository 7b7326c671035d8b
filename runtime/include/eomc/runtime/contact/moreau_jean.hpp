#pragma once

// The Moreau–Jean time-stepping scheme for mechanical systems with unilateral contacts
// (J. J. Moreau, "Unilateral contact and dry friction in finite freedom dynamics", CISM 302,
// Springer 1988, 1–82; M. Jean, "The non-smooth contact dynamics method", Comput. Methods Appl.
// Mech. Engrg. 177 (1999) 235–257; V. Acary, B. Brogliato, Numerical Methods for Nonsmooth
// Dynamical Systems, Springer 2008, the chapter on time-stepping schemes for mechanical systems).
//
// The system: M(t, q) u̇ = f(t, q, u) between impacts, gaps g(t, q) ≥ 0 (m of them) with Jacobian
// W = ∂g/∂q (m × n; q̇ = u), Newton restitution e_α per contact. One step of size h from (q_k, u_k):
//
//   M (u_{k+1} − u_k) = h f_θ + Wᵀ P_{k+1},
//   q_{k+1} = q_k + h (θ u_{k+1} + (1 − θ) u_k),
//   for α in the predicted active set  g_α(q_k) + γ h ḟ_α(u_k) ≤ 0:
//     0 ≤ P_α ⊥ W_α u_{k+1} + e_α W_α u_k ≥ 0,   P_α = 0 otherwise,
//
// with M and W frozen at (t_k, q_k) and f_θ = θ f(t_{k+1}, q_k + h u_k, u_k) + (1 − θ) f(t_k, q_k,
// u_k), the θ-method linearised about the step's start (the scheme is of order one anyway).
// With u_free = u_k + h M⁻¹ f_θ the contact law is the LCP(G, q) of lcp.hpp with G = W_I M⁻¹ W_Iᵀ
// and q = W_I u_free + e W_I u_k: Newton's law of impact.hpp over a step, gravity's impulse h f
// included. P is an impulse over the step: it covers impacts and contact forces (P ≈ h λ) alike,
// so that the scheme needs no event location, passes accumulations of impacts (the bouncing ball's
// Zeno point) in finitely many steps and ends in persistent contact with u = 0 on the contact's
// normal. The price is order one: impact times are resolved to O(h), and the gaps may go O(h)
// negative (the law acts on velocities, not positions).
//
// Energy (the bouncing ball, per unit mass, counted step by step in tests/runtime/contact/
// moreau_jean.cpp): free flight under a constant force is exact for θ = 1/2; an impact step with
// v_k < 0 loses energy; a step that starts separating yet predicted active (0 < v_k < g h/(1 + e))
// gains (1 − e) v_k (g h − (1 + e) v_k)/2 ≤ (1 − e)(g h)²/(8 (1 + e)) for θ = 1/2, and θ = 1 gains up
// to (e g h)²/(2 (1 − e²)) on approaching steps: O(h²) per step near an accumulation of impacts, none
// for e = 0. V. Acary, "Energy conservation and dissipation properties of time-integration methods
// for nonsmooth elastodynamics with contact", Z. Angew. Math. Mech. 96 (2016), analyses this and
// modifies the law to dissipate always; not done here.
//
// Moving gaps g_α(t, q) (options.time_rates): the rate is ḟ_α = W_α u + w_α with w_α = ∂g_α/∂t, and
// Newton's law holds on it, 0 ≤ P_α ⊥ W_α u_{k+1} + w_α(t_{k+1}) + e_α (W_α u_k + w_α(t_k)) ≥ 0 (Acary
// & Brogliato's velocity-level condition for rheonomic constraints: U_{k+1} + e U_k ≥ 0 with U the
// relative normal velocity), w taken at q_k like W; the prediction g_α + γ h ḟ_α(u_k) ≤ 0 uses the
// same rate.
//
// Kinematic rows φ_α(t, q, u) ≥ 0, linear in u (Mei §6.7; options.kinematic): already velocity
// constraints, so each step imposes them at the step's end, 0 ≤ P_α ⊥ φ_α(q_k, u_{k+1}) ≥ 0 with
// φ_α(q_k, u_{k+1}) = W_α u_{k+1} + (φ_α(q_k, u_k) − W_α u_k), W_α = ∂φ_α/∂u: always in the LCP, no
// restitution (they take no impacts).
//
// Bilateral rows (Mei §6.6; options.bilateral): C u_{k+1} = d, C = ∂φ/∂u at the step's start and d
// what keeps φ = 0 there (d = C u_k − φ(q_k, u_k) for a row linear in u), with multipliers of free
// sign: eliminated by the constrained inverse mass M̃⁻¹ = M⁻¹ − M⁻¹Cᵀ(C M⁻¹ Cᵀ)⁻¹C M⁻¹ in u_free and
// in the Delassus matrix, so that the contact impulses leave them holding. options.project then puts
// (q, u) back on the rows' manifold after the step (q_{k+1} drifts O(h²) off a curved one).
//
// On a ContactSystem (system.hpp) the driver also reports what each step did as the event-driven
// driver does (ContactEvent): an impact where a row's impulse turned an approaching rate into a
// separating one by more than the forces change it in a step, with the energy change and Carnot's
// loss; a contact where a row enters the active set (λ ≈ P/h); a separation where it leaves.

#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "eomc/runtime/constraints.hpp"
#include "eomc/runtime/contact/lcp.hpp"
#include "eomc/runtime/contact/system.hpp"
#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

template <class S>
struct MoreauJeanOptions {
  S theta = S(0.5);  // θ of the velocity integral (1/2: exact on constant forces; 1: backward Euler)
  S gamma = S(0.5);  // γ of the active-set prediction g + γ h ḟ ≤ 0
  // Rows that are kinematic, φ(t, q, u) ≥ 0 (empty: none); gaps() then takes (t, q, u) and writes φ
  // for them, jacobian() ∂φ/∂u.
  std::vector<bool> kinematic;
  // The time rates of moving gaps, time_rates(t, q) -> m vector w = ∂g/∂t (empty: all zero; a
  // kinematic row's entry is ignored).
  std::function<LcpVector<S>(S, const LcpVector<S>&)> time_rates;
  // Bilateral rows (empty: none): bilateral(t, q, u, C, d) writes C (k × n) and d of C u_{k+1} = d.
  std::function<void(S, const LcpVector<S>&, const LcpVector<S>&, LcpMatrix<S>&, LcpVector<S>&)> bilateral;
  // Called after every step with (t_{k+1}, q, u) to edit them (the bilateral rows' projection).
  std::function<void(S, LcpVector<S>&, LcpVector<S>&)> project;
};

// What one step did.
template <class S>
struct MoreauJeanStep {
  LcpVector<S> P;                 // impulse per contact over the step (0 off the active set)
  std::vector<Eigen::Index> active;  // the contacts predicted active
  LcpStatus status = LcpStatus::solved;
};

// One step from (t, q, u) to t + h, q and u updated in place. The callables:
//   mass(t, q) -> n × n SPD matrix,  force(t, q, u) -> n vector,
//   gaps(t, q) or gaps(t, q, u) -> m vector (the latter for kinematic rows),
//   jacobian(t, q) -> m × n matrix (∂g/∂q, or ∂φ/∂u for a kinematic row).
template <class S, class Mass, class Force, class Gaps, class Jacobian>
MoreauJeanStep<S> moreau_jean_step(Mass&& mass, Force&& force, Gaps&& gaps, Jacobian&& jacobian,
                                   const LcpVector<S>& restitution, S t, S h, LcpVector<S>& q, LcpVector<S>& u,
                                   const MoreauJeanOptions<S>& options = {}) {
  const S theta = options.theta;
  const LcpMatrix<S> M = mass(t, static_cast<const LcpVector<S>&>(q));
  const LcpMatrix<S> W = jacobian(t, static_cast<const LcpVector<S>&>(q));
  const LcpVector<S> g = [&]() -> LcpVector<S> {
    if constexpr (std::is_invocable_v<Gaps&, S, const LcpVector<S>&, const LcpVector<S>&>)
      return gaps(t, static_cast<const LcpVector<S>&>(q), static_cast<const LcpVector<S>&>(u));
    else
      return gaps(t, static_cast<const LcpVector<S>&>(q));
  }();
  if (W.rows() != restitution.size() || g.size() != restitution.size() || W.cols() != q.size())
    throw std::invalid_argument("Moreau-Jean: gaps, Jacobian rows and restitution must agree");
  if (!options.kinematic.empty() && options.kinematic.size() != std::size_t(g.size()))
    throw std::invalid_argument("Moreau-Jean: kinematic must flag every row or none");
  const auto kinematic = [&](Eigen::Index a) { return !options.kinematic.empty() && options.kinematic[std::size_t(a)]; };
  const LcpVector<S> q_predicted = q + h * u;
  const LcpVector<S> f_theta = theta * LcpVector<S>(force(t + h, static_cast<const LcpVector<S>&>(q_predicted),
                                                          static_cast<const LcpVector<S>&>(u))) +
                               (S(1) - theta) * LcpVector<S>(force(t, static_cast<const LcpVector<S>&>(q),
                                                                   static_cast<const LcpVector<S>&>(u)));
  const Eigen::LDLT<LcpMatrix<S>> ldlt(M);
  LcpVector<S> u_free = u + h * ldlt.solve(f_theta);
  // The bilateral rows: u_free onto C u = d, and M̃⁻¹ in place of M⁻¹ below.
  LcpMatrix<S> C, Yc;
  Eigen::LDLT<LcpMatrix<S>> Gc;
  if (options.bilateral) {
    LcpVector<S> d;
    options.bilateral(t, static_cast<const LcpVector<S>&>(q), static_cast<const LcpVector<S>&>(u), C, d);
    if (C.cols() != q.size() || d.size() != C.rows())
      throw std::invalid_argument("Moreau-Jean: the bilateral rows must be k x n with k values");
    if (C.rows() > 0) {
      Yc = ldlt.solve(C.transpose());
      Gc.compute(C * Yc);
      u_free += Yc * Gc.solve(LcpVector<S>(d - C * u_free));
    }
  }
  const auto solve_mass = [&](const LcpMatrix<S>& B) {
    LcpMatrix<S> out = ldlt.solve(B);
    if (C.rows() > 0) out -= Yc * Gc.solve(LcpMatrix<S>(C * out));
    return out;
  };

  MoreauJeanStep<S> step;
  step.P = LcpVector<S>::Zero(g.size());
  // ḟ at the step's start and the time rates at its end (zero without time_rates).
  LcpVector<S> w0 = LcpVector<S>::Zero(g.size()), w1 = w0;
  if (options.time_rates) {
    w0 = options.time_rates(t, static_cast<const LcpVector<S>&>(q));
    w1 = options.time_rates(t + h, static_cast<const LcpVector<S>&>(q));
    if (w0.size() != g.size() || w1.size() != g.size())
      throw std::invalid_argument("Moreau-Jean: time_rates must give one value per row");
    for (Eigen::Index a = 0; a < g.size(); ++a)
      if (kinematic(a)) w0[a] = w1[a] = S(0);
  }
  const LcpVector<S> Wu = W * u, fdot = Wu + w0;
  for (Eigen::Index a = 0; a < g.size(); ++a)
    if (kinematic(a) || g[a] + options.gamma * h * fdot[a] <= S(0)) step.active.push_back(a);

  LcpVector<S> u_next = u_free;
  if (!step.active.empty()) {
    const Eigen::Index k = Eigen::Index(step.active.size());
    LcpMatrix<S> Wa(k, W.cols());
    // w_α(t_{k+1}) + e_α ḟ_α(u_k) for a gap, φ_α(q_k, u_k) − W_α u_k for a kinematic row
    LcpVector<S> offset(k);
    for (Eigen::Index i = 0; i < k; ++i) {
      const Eigen::Index a = step.active[std::size_t(i)];
      Wa.row(i) = W.row(a);
      offset[i] = kinematic(a) ? S(g[a] - Wu[a]) : S(w1[a] + restitution[a] * fdot[a]);
    }
    const LcpMatrix<S> Y = solve_mass(Wa.transpose());  // M̃⁻¹ W_Iᵀ
    const LcpMatrix<S> G = Wa * Y;
    const LcpVector<S> qlcp = Wa * u_free + offset;
    LcpVector<S> P(k);
    if (k == 1) {
      // The scalar LCP in closed form.
      const S p = -qlcp[0] / G(0, 0);
      P[0] = p > S(0) ? p : S(0);
    } else {
      const LcpResult<S> r = solve_lcp<S>(G, qlcp);
      P = r.z;
      step.status = r.status;
    }
    u_next += Y * P;
    for (Eigen::Index i = 0; i < k; ++i) step.P[step.active[std::size_t(i)]] = P[i];
  }
  q += h * (theta * u_next + (S(1) - theta) * u);
  u = u_next;
  if (options.project) options.project(t + h, q, u);
  return step;
}

// Fixed steps from t0 to t1 (N = ⌈(t1 − t0)/h⌉ steps of (t1 − t0)/N, t_k = t0 + k (t1 − t0)/N
// without accumulated sums); observer(t_k, q_k, u_k, step) after each step. Returns N.
template <class S, class Mass, class Force, class Gaps, class Jacobian, class Observer>
long integrate_moreau_jean(Mass&& mass, Force&& force, Gaps&& gaps, Jacobian&& jacobian,
                           const LcpVector<S>& restitution, S t0, S t1, S h, LcpVector<S>& q, LcpVector<S>& u,
                           Observer&& observer, const MoreauJeanOptions<S>& options = {}) {
  using std::ceil;
  if (!(h > S(0)) || !(t1 >= t0)) throw std::invalid_argument("Moreau-Jean: h > 0 and t1 >= t0 required");
  const long n = static_cast<long>(ceil((t1 - t0) / h - S(1e-9)));
  if (n <= 0) return 0;
  const S dt = (t1 - t0) / S(n);
  for (long k = 0; k < n; ++k) {
    const S t = t0 + S(k) * dt;
    const MoreauJeanStep<S> s = moreau_jean_step<S>(mass, force, gaps, jacobian, restitution, t, dt, q, u, options);
    observer(k + 1 == n ? t1 : t0 + S(k + 1) * dt, static_cast<const LcpVector<S>&>(q),
             static_cast<const LcpVector<S>&>(u), s);
  }
  return n;
}

namespace contact::detail {

// A ContactSystem in the shapes moreau_jean_step takes, the bilateral rows' projection, and the
// classification of each step's impulses into events.
template <class S>
class MoreauJeanModel {
 public:
  explicit MoreauJeanModel(const ContactSystem<S>& sys)
      : sys_(sys), n_(sys.dof), m_(Eigen::Index(sys.contacts.size())),
        k_(static_cast<int>(sys.bilateral_holonomic.size())), zero_u_(LcpVector<S>::Zero(n_)) {
    if (k_ > 0 && !sys.bilateral) throw std::invalid_argument("Moreau-Jean: bilateral rows need bilateral()");
  }

  LcpMatrix<S> mass(S t, const LcpVector<S>& q) const {
    LcpMatrix<S> M(n_, n_);
    sys_.mass(t, q, M);
    return M;
  }
  LcpVector<S> force(S t, const LcpVector<S>& q, const LcpVector<S>& u) const {
    LcpVector<S> f(n_);
    sys_.force(t, q, u, f);
    return f;
  }
  LcpVector<S> gaps(S t, const LcpVector<S>& q, const LcpVector<S>& u) const {
    LcpVector<S> g = LcpVector<S>::Zero(m_);
    sys_.gaps(t, q, u, g);
    return g;
  }
  // W: ∂g/∂q of a gap, ∂φ/∂u of a kinematic row (φ linear in u), at (q, u = 0).
  LcpMatrix<S> jacobian(S t, const LcpVector<S>& q) const {
    LcpMatrix<S> W = LcpMatrix<S>::Zero(m_, n_);
    LcpVector<S> b(m_);
    sys_.rows(t, q, zero_u_, W, b);
    return W;
  }
  // w = ∂g/∂t of moving gaps (zeros for fixed ones): ġ = W u + w.
  LcpVector<S> time_rates(S t, const LcpVector<S>& q) const {
    LcpVector<S> w = LcpVector<S>::Zero(m_);
    if (sys_.time_rates) sys_.time_rates(t, q, w);
    return w;
  }
  // The bilateral rows at (t, q, u): C = ∂φ/∂u and d = C u − φ, so that C u_{k+1} = d puts φ = 0 at
  // the step's end (φ linear in u).
  void bilateral(S t, const LcpVector<S>& q, const LcpVector<S>& u, LcpMatrix<S>& C, LcpVector<S>& d) const {
    LcpVector<S> f, phi, r;
    sys_.bilateral(t, q, u, f, phi, C, r);
    d = C * u - phi;
  }
  // M̃⁻¹ B: M⁻¹ B with the bilateral rows' reaction taken out (M⁻¹ B without them).
  LcpMatrix<S> constrained_solve(S t, const LcpVector<S>& q, const LcpVector<S>& u, const LcpMatrix<S>& M,
                                 const LcpMatrix<S>& B) const {
    const Eigen::LDLT<LcpMatrix<S>> ldlt(M);
    LcpMatrix<S> out = ldlt.solve(B);
    if (k_ == 0) return out;
    LcpVector<S> f, phi, r;
    LcpMatrix<S> C;
    sys_.bilateral(t, q, u, f, phi, C, r);
    const LcpMatrix<S> Y = ldlt.solve(LcpMatrix<S>(C.transpose()));
    out -= Y * (C * Y).ldlt().solve(LcpMatrix<S>(C * out));
    return out;
  }

  // Puts (q, u) on every bilateral row, positions then velocities, in the M-metric (HLW IV.4).
  void project(S t, LcpVector<S>& q, LcpVector<S>& u) const {
    if (k_ == 0) return;
    State<S> x(2 * std::size_t(n_));
    join(q, u, x.data());
    std::unique_ptr<bool[]> all(new bool[std::size_t(k_)]), holonomic(new bool[std::size_t(k_)]);
    for (int i = 0; i < k_; ++i) {
      all[std::size_t(i)] = true;
      holonomic[std::size_t(i)] = sys_.bilateral_holonomic[std::size_t(i)];
    }
    LcpVector<S> qs(n_), us(n_), f, phi, r;
    LcpMatrix<S> C, M(n_, n_);
    const auto rows_at = [&](S tau, const S* y) {
      split(y, qs, us);
      sys_.bilateral(tau, qs, us, f, phi, C, r);
    };
    project_onto_constraints<S>(
        t, x.data(), ConstraintLayout{int(n_), int(n_), int(n_), k_}, all.get(), holonomic.get(),
        [&](S tau, const S* y, S* fo, S* phio) {
          rows_at(tau, y);
          for (int i = 0; i < k_; ++i) fo[i] = f[i], phio[i] = phi[i];
        },
        [&](S tau, const S* y, S* W) {
          rows_at(tau, y);
          for (int i = 0; i < k_; ++i)
            for (Eigen::Index j = 0; j < n_; ++j) W[Eigen::Index(i) * n_ + j] = C(i, j);
        },
        [&](S tau, const S* y, S* out) {
          split(y, qs, us);
          sys_.mass(tau, qs, M);
          for (Eigen::Index i = 0; i < n_; ++i)
            for (Eigen::Index j = 0; j < n_; ++j) out[i * n_ + j] = M(i, j);
        });
    split(x.data(), q, u);
  }

  // The events of the step from (t_prev, q_prev, u_prev) to (t, u_next) with impulses P, in row
  // order (an impact before the row's contact or separation), passed to on_event; updates the
  // active set and λ = P/h. An impulse that turns an approaching rate into a separating one is an
  // impact (ΔT over the step, Carnot's loss of the impulsive Δu = M̃⁻¹W_αᵀP_α); a bounce slower than
  // twice what the forces change in one step is the scheme's own chatter at rest (order h), and the
  // row counts as in contact; an impulse on a kinematic row is its reaction over the step.
  template <class OnEvent>
  void classify(S t_prev, const LcpVector<S>& q_prev, const LcpVector<S>& u_prev, S t, const LcpVector<S>& u_next,
                const LcpVector<S>& P, std::vector<bool>& active, LcpVector<S>& lambda, OnEvent&& on_event) const {
    using std::abs;
    const S dt = t - t_prev;
    const S scale = S(1e-9) * (S(1) + u_next.cwiseAbs().maxCoeff() + u_prev.cwiseAbs().maxCoeff());
    bool any = false;
    for (Eigen::Index a = 0; a < m_; ++a) any = any || P[a] > S(0);
    LcpMatrix<S> W, M;
    LcpVector<S> kick;  // the velocity the forces add over one step, h M̃⁻¹ f
    LcpVector<S> w0 = LcpVector<S>::Zero(m_), w1 = w0;  // ∂g/∂t at t_prev, t
    if (any && sys_.time_rates) {
      w0 = time_rates(t_prev, q_prev);
      w1 = time_rates(t, q_prev);
    }
    if (any) {
      W = jacobian(t_prev, q_prev);
      M = mass(t_prev, q_prev);
      kick = dt * constrained_solve(t_prev, q_prev, u_prev, M, LcpMatrix<S>(force(t_prev, q_prev, u_prev)));
    }
    for (Eigen::Index a = 0; a < m_; ++a) {
      const Contact<S>& row = sys_.contacts[std::size_t(a)];
      bool now = false;
      if (P[a] > S(0) && row.level == GapLevel::velocity) {
        now = true;
      } else if (P[a] > S(0)) {
        const S before = W.row(a).dot(u_prev) + w0[a], after = W.row(a).dot(u_next) + w1[a];
        const S vtol = scale + 2 * abs(W.row(a).dot(kick));
        if (before < -vtol && after > vtol) {
          ContactEvent<S> e{.kind = ContactEventKind::impact, .contact = std::size_t(a), .t = t};
          e.rate_before = before;
          e.rate_after = after;
          e.impulse = P[a];
          e.energy_change = S(0.5) * u_next.dot(M * u_next) - S(0.5) * u_prev.dot(M * u_prev);
          const LcpVector<S> du =
              constrained_solve(t_prev, q_prev, u_prev, M, LcpMatrix<S>(W.row(a).transpose() * P[a]));
          // Carnot's loss in the wall's frame, less the moving wall's work P w.
          const S e_a = row.restitution;
          e.carnot = -((S(1) - e_a) / (S(1) + e_a)) * S(0.5) * du.dot(M * du) - P[a] * w0[a];
          on_event(static_cast<const ContactEvent<S>&>(e));
        } else {
          now = true;
        }
      }
      if (now && !active[std::size_t(a)])
        on_event(ContactEvent<S>{.kind = ContactEventKind::contact, .contact = std::size_t(a), .t = t,
                                 .lambda = P[a] / dt});
      else if (!now && active[std::size_t(a)])
        on_event(ContactEvent<S>{.kind = ContactEventKind::separation, .contact = std::size_t(a), .t = t});
      active[std::size_t(a)] = now;
      lambda[a] = P[a] / dt;
    }
  }

  void join(const LcpVector<S>& q, const LcpVector<S>& u, S* x) const {
    for (Eigen::Index j = 0; j < n_; ++j) x[j] = q[j], x[n_ + j] = u[j];
  }
  void split(const S* x, LcpVector<S>& q, LcpVector<S>& u) const {
    for (Eigen::Index j = 0; j < n_; ++j) q[j] = x[j], u[j] = x[n_ + j];
  }
  Eigen::Index dof() const { return n_; }
  Eigen::Index contacts() const { return m_; }
  int bilateral_rows() const { return k_; }

 private:
  const ContactSystem<S>& sys_;
  Eigen::Index n_, m_;
  int k_;
  LcpVector<S> zero_u_;
};

}  // namespace contact::detail

// Moreau–Jean time stepping of a ContactSystem from (t0, x) to t1 ≥ t0, x = (q, u) of 2n, with θ =
// `theta` and the step h (N = ⌈(t1 − t0)/h⌉ steps, as integrate_moreau_jean above): the state is put
// on the bilateral rows first; observer(t, x, λ, active) at t0 and after every step, as the
// event-driven driver calls it (λ = P/h per row, active the rows in contact); on_event(ContactEvent)
// for each step's impacts, contacts and separations just before the observer sees that step. x ends
// at t1. Returns the number of steps.
template <class S, class Observer, class OnEvent>
long integrate_moreau_jean(const contact::ContactSystem<S>& sys, S t0, S t1, S h, S theta, State<S>& x,
                           Observer&& observer, OnEvent&& on_event) {
  const contact::detail::MoreauJeanModel<S> model(sys);
  const Eigen::Index n = model.dof(), m = model.contacts();
  if (x.size() != std::size_t(2 * n)) throw std::invalid_argument("Moreau-Jean: the state must be (q, u) of 2 dof");
  LcpVector<S> q(n), u(n), e(m);
  model.split(x.data(), q, u);
  MoreauJeanOptions<S> options;
  options.theta = theta;
  for (Eigen::Index a = 0; a < m; ++a) {
    e[a] = sys.contacts[std::size_t(a)].restitution;
    options.kinematic.push_back(sys.contacts[std::size_t(a)].level == contact::GapLevel::velocity);
  }
  if (sys.time_rates) options.time_rates = [&](S t, const LcpVector<S>& qs) { return model.time_rates(t, qs); };
  if (model.bilateral_rows() > 0) {
    options.bilateral = [&](S t, const LcpVector<S>& qs, const LcpVector<S>& us, LcpMatrix<S>& C, LcpVector<S>& d) {
      model.bilateral(t, qs, us, C, d);
    };
    options.project = [&](S t, LcpVector<S>& qs, LcpVector<S>& us) { model.project(t, qs, us); };
    model.project(t0, q, u);
    model.join(q, u, x.data());
  }
  std::vector<bool> active(std::size_t(m), false);
  LcpVector<S> lambda = LcpVector<S>::Zero(m);
  observer(t0, static_cast<const State<S>&>(x), static_cast<const LcpVector<S>&>(lambda),
           static_cast<const std::vector<bool>&>(active));
  LcpVector<S> q_prev = q, u_prev = u;
  S t_prev = t0;
  const auto after_step = [&](S t, const LcpVector<S>& qn, const LcpVector<S>& un, const MoreauJeanStep<S>& step) {
    model.classify(t_prev, q_prev, u_prev, t, un, step.P, active, lambda, on_event);
    model.join(qn, un, x.data());
    observer(t, static_cast<const State<S>&>(x), static_cast<const LcpVector<S>&>(lambda),
             static_cast<const std::vector<bool>&>(active));
    q_prev = qn;
    u_prev = un;
    t_prev = t;
  };
  const auto mass = [&](S t, const LcpVector<S>& qs) { return model.mass(t, qs); };
  const auto force = [&](S t, const LcpVector<S>& qs, const LcpVector<S>& us) { return model.force(t, qs, us); };
  const auto gaps = [&](S t, const LcpVector<S>& qs, const LcpVector<S>& us) { return model.gaps(t, qs, us); };
  const auto jacobian = [&](S t, const LcpVector<S>& qs) { return model.jacobian(t, qs); };
  const long steps = integrate_moreau_jean<S>(mass, force, gaps, jacobian, e, t0, t1, h, q, u, after_step, options);
  model.join(q, u, x.data());
  return steps;
}

}  // namespace eomc::runtime
