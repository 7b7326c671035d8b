#pragma once

// Newton's impact law for several simultaneous contacts, in Moreau's form (J. J. Moreau,
// "Unilateral contact and dry friction in finite freedom dynamics", in Nonsmooth Mechanics and
// Applications, CISM 302, Springer 1988, 1–82; V. Acary, B. Brogliato, Numerical Methods for
// Nonsmooth Dynamical Systems, Springer 2008, on Newton's law in Moreau's velocity form; Mei
// Fengxiang, Special Topics in Analytical Mechanics, ch. 6, §6.5 on the impulsive Lagrange
// equations).
//
// The m active contacts have gaps f_α(q, t) = 0 with Jacobian rows W (m × n), normal velocities
// ḟ = W u + w, w_α = ∂f_α/∂t the rate of a moving wall (zero for a fixed one; the overloads without
// w take it zero). Over the impact the positions do not move and the impulsive equations of motion give
//
//   M (u⁺ − u⁻) = Wᵀ P,        0 ≤ P ⊥ W u⁺ + e ḟ⁻ ≥ 0       (e ḟ⁻ per contact: e_α ḟ⁻_α),
//
// (W u⁺ + w + e ḟ⁻ ≥ 0 for a moving wall: the law acts on the relative normal velocity)
// with P the normal impulses. Substituting u⁺ = u⁻ + M⁻¹ Wᵀ P, ḟ⁺ + e ḟ⁻ = G P + (1 + e) ḟ⁻:
// the LCP(G, q) of lcp.hpp with the Delassus matrix G = W M⁻¹ Wᵀ (symmetric positive definite
// for independent rows) and q_α = (1 + e_α) ḟ⁻_α. A contact with P_α > 0 leaves with
// ḟ⁺_α = −e_α ḟ⁻_α (Newton's law); one with P_α = 0 separates at least that fast. For one contact
// the LCP is a scalar: P = max(0, −(1 + e) ḟ⁻ / G).
//
// Energy (Carnot's theorem, generalised; Mei §6.5): T⁺ − T⁻ = ½ Pᵀ (ḟ⁺ + ḟ⁻)
// and ½ Δuᵀ M Δu = ½ Pᵀ (ḟ⁺ − ḟ⁻); with complementarity, for one contact or a common e,
//
//   T⁺ − T⁻ = −((1 − e)/(1 + e)) · ½ Δuᵀ M Δu ≤ 0,
//
// the kinetic energy of the lost velocities weighted by (1 − e)/(1 + e) (Carnot for e = 0). A moving
// wall does the work −Pᵀw on top (T⁺ − T⁻ = ½ PᵀW(u⁺ + u⁻) = ½ Pᵀ(ḟ⁺ + ḟ⁻) − Pᵀw), which
// carnot_prediction includes: Carnot's theorem holds in the wall's frame.
//
// Simultaneous and sequential impacts are different laws: for Newton's cradle (three equal balls
// touching, the first at unit speed, e = 1) Moreau's simultaneous law gives (−1/3, 2/3, 2/3),
// while resolving one two-ball impact after another (sequential_impacts, the "impulse propagates
// from contact to contact" reading) gives the observed (0, 0, 1). Both
// conserve energy for e = 1; neither is the physics of all chains (the outcome of multiple
// impacts depends on the contact stiffnesses, as Acary and Brogliato discuss for chains of balls).

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "eomc/runtime/contact/lcp.hpp"

namespace eomc::runtime {

template <class S>
struct ImpactResult {
  LcpVector<S> u_plus;  // velocities after the impact
  LcpVector<S> P;       // normal impulse per contact (the total over the impacts for the sequential law)
  S kinetic_energy_before = S(0), kinetic_energy_after = S(0);
  // −((1 − e)/(1 + e)) ½ Δuᵀ M Δu − Pᵀw: Carnot's prediction of T⁺ − T⁻, valid when all contacts
  // share one e (carnot_applies) or there is one contact; 0 and false otherwise.
  S carnot_prediction = S(0);
  bool carnot_applies = false;
  LcpStatus status = LcpStatus::solved;  // of the LCP (solved for the closed forms)
  int impacts = 0;                       // sequential law: two-body impacts resolved
};

namespace detail {

template <class S>
void check_impact_shapes(const LcpMatrix<S>& M, const LcpMatrix<S>& W, const LcpVector<S>& e,
                         const LcpVector<S>& u_minus) {
  if (M.rows() != M.cols() || W.cols() != M.rows() || u_minus.size() != M.rows() || e.size() != W.rows())
    throw std::invalid_argument("impact: M n x n, W m x n, e of m, u of n");
}

// The energies and Carnot's prediction of a result whose u_plus is set.
template <class S>
void impact_energies(const LcpMatrix<S>& M, const LcpVector<S>& e, const LcpVector<S>& u_minus,
                     const LcpVector<S>& w, ImpactResult<S>& r) {
  r.kinetic_energy_before = S(0.5) * u_minus.dot(M * u_minus);
  r.kinetic_energy_after = S(0.5) * r.u_plus.dot(M * r.u_plus);
  r.carnot_applies = e.size() == 0 || (e.array() == e[0]).all();
  if (r.carnot_applies && e.size() > 0) {
    const LcpVector<S> du = r.u_plus - u_minus;
    r.carnot_prediction = -((S(1) - e[0]) / (S(1) + e[0])) * S(0.5) * du.dot(M * du) - r.P.dot(w);
  }
}

}  // namespace detail

// Moreau's simultaneous impact law on all m contacts: M n × n symmetric positive definite, W m × n,
// restitution e_α ∈ [0, 1] per contact, u⁻ of n.
// w: the time rates ∂f_α/∂t of moving walls, ḟ = W u + w.
template <class S>
ImpactResult<S> newton_impact(const LcpMatrix<S>& M, const LcpMatrix<S>& W, const LcpVector<S>& e,
                              const LcpVector<S>& u_minus, const LcpVector<S>& w) {
  detail::check_impact_shapes(M, W, e, u_minus);
  if (w.size() != W.rows()) throw std::invalid_argument("impact: w of m");
  const Eigen::LDLT<LcpMatrix<S>> ldlt(M);
  const LcpMatrix<S> Y = ldlt.solve(W.transpose());  // M⁻¹ Wᵀ
  const LcpMatrix<S> G = W * Y;                      // Delassus matrix
  const LcpVector<S> fdot = W * u_minus + w;
  ImpactResult<S> r;
  if (W.rows() == 1) {
    // The scalar LCP in closed form.
    const S P = -(S(1) + e[0]) * fdot[0] / G(0, 0);
    r.P = LcpVector<S>::Constant(1, P > S(0) ? P : S(0));
  } else {
    const LcpVector<S> q = ((LcpVector<S>::Ones(e.size()) + e).array() * fdot.array()).matrix();
    const LcpResult<S> lcp = solve_lcp<S>(G, q);
    r.P = lcp.z;
    r.status = lcp.status;
  }
  r.u_plus = u_minus + Y * r.P;
  r.impacts = 1;
  detail::impact_energies(M, e, u_minus, w, r);
  return r;
}

// Fixed walls (w = 0).
template <class S>
ImpactResult<S> newton_impact(const LcpMatrix<S>& M, const LcpMatrix<S>& W, const LcpVector<S>& e,
                              const LcpVector<S>& u_minus) {
  return newton_impact<S>(M, W, e, u_minus, LcpVector<S>(LcpVector<S>::Zero(W.rows())));
}

// The sequential law: the contact approaching fastest (most negative ḟ_α) takes a one-contact
// Newton impact, and so on until no contact approaches (ḟ_α ≥ −rounding for all α) or
// max_impacts ran out (status pivot_limit; e < 1 chains can need infinitely many, inelastic
// collapse). P accumulates each contact's impulses.
// w: the time rates of moving walls, ḟ = W u + w.
template <class S>
ImpactResult<S> sequential_impacts(const LcpMatrix<S>& M, const LcpMatrix<S>& W, const LcpVector<S>& e,
                                   const LcpVector<S>& u_minus, const LcpVector<S>& w, int max_impacts = 10000) {
  detail::check_impact_shapes(M, W, e, u_minus);
  if (w.size() != W.rows()) throw std::invalid_argument("impact: w of m");
  const Eigen::LDLT<LcpMatrix<S>> ldlt(M);
  const LcpMatrix<S> Y = ldlt.solve(W.transpose());
  const Eigen::Index m = W.rows();
  const S eps = Eigen::NumTraits<S>::epsilon();
  ImpactResult<S> r;
  r.u_plus = u_minus;
  r.P = LcpVector<S>::Zero(m);
  for (;;) {
    // ḟ_α, and the rounding it carries: 64 ε (Σ_j |W_αj u_j| + |w_α|).
    const LcpVector<S> fdot = W * r.u_plus + w;
    const LcpVector<S> noise = S(64) * eps * (W.cwiseAbs() * r.u_plus.cwiseAbs() + w.cwiseAbs());
    Eigen::Index a = -1;
    for (Eigen::Index k = 0; k < m; ++k)
      if (fdot[k] < -noise[k] && (a < 0 || fdot[k] < fdot[a])) a = k;
    if (a < 0) break;
    if (r.impacts >= max_impacts) {
      r.status = LcpStatus::pivot_limit;
      break;
    }
    const S P = -(S(1) + e[a]) * fdot[a] / W.row(a).dot(Y.col(a));
    r.u_plus += Y.col(a) * P;
    r.P[a] += P;
    ++r.impacts;
  }
  detail::impact_energies(M, e, u_minus, w, r);
  // Carnot holds for each two-body impact, not for their sum (the lost velocities add, their
  // energies do not): no prediction after more than one.
  if (r.impacts > 1) {
    r.carnot_applies = false;
    r.carnot_prediction = S(0);
  }
  return r;
}

// Fixed walls (w = 0).
template <class S>
ImpactResult<S> sequential_impacts(const LcpMatrix<S>& M, const LcpMatrix<S>& W, const LcpVector<S>& e,
                                   const LcpVector<S>& u_minus, int max_impacts = 10000) {
  return sequential_impacts<S>(M, W, e, u_minus, LcpVector<S>(LcpVector<S>::Zero(W.rows())), max_impacts);
}

}  // namespace eomc::runtime
