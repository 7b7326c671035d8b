// Lagrange's equations of a model given by its energies, M(q,t) q̈ = f(q,q̇,t): a scene's
// [lagrangian] T, or carried particles and bodies on a carrier (Mei, ch. 1).
//
// For carried particles the kinetic energy is split T = T_e + T_m + T_r (Mei, §1.1) and the
// inertial side of each equation is written as the sum of named effects (Mei, §1.1–§1.2):
//   relative      ε_s(T_r)                       = Σ m_i a_r,i · e_is
//   translation   Σ m_i (v̇_o + ω × v_o) · e_is
//   euler         Σ m_i (ω̇ × r'_i) · e_is
//   centrifugal   Σ m_i (ω × (ω × r'_i)) · e_is
//   coriolis      Σ m_i 2 (ω × ṙ'_i) · e_is
// with e_is = ∂r'_i/∂q_s. The relative term is formed by projection (d'Alembert–Lagrange);
// it equals ε_s(T_r) identically (tested), and the projection keeps the expressions
// factored, which is what makes the generated code small. Effects the scene does not keep
// are never added, so nothing downstream can emit them.
#pragma once

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// The equations alone, without invariants. Throws InputError when M is singular (naming the
// velocities involved).
Equations lagrange_equations(const model::Model& model);

// The Jacobi-type integral of the kept equations: for the full equations h = Σ u ∂L/∂u − L over
// all velocities, which is T_r − T_e + V for a steadily moving carrier and T + V for a free one.
// A candidate only: conservation is proven by mechanics/invariants, never assumed.
GiNaC::ex jacobi_candidate(const model::Model& model, const Equations& eqs);

// lagrange_equations, with the Jacobi integral among the invariants when it is proven conserved.
Equations derive_lagrange(const model::Model& model);

}  // namespace eomc::mechanics
