// The canonical equations of (relative) motion (Mei §1.9): momenta p = ∂L/∂q̇, the
// Hamiltonian H(q, p, t) by a symbolic Legendre transform, and Hamilton's equations
//   q̇ = ∂H/∂p,   ṗ = −∂H/∂q + Q,
// with Q the non-potential generalized forces expressed in (q, p). L = T − V must be
// quadratic in q̇ (true for every carried-particle model, whatever the carrier's motion):
// L = ½ q̇ᵀ W q̇ + bᵀ q̇ + L₀, so q̇ = W⁻¹(p − b) and H = ½ (p − b)ᵀ W⁻¹ (p − b) − L₀.
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

struct CanonicalEquations {
    std::vector<GiNaC::symbol> p;       // one momentum per coordinate, named p_<q>
    std::vector<GiNaC::ex> momentum;    // p_s = ∂L/∂q̇_s, in (q, q̇, t)
    std::vector<GiNaC::ex> velocity;    // q̇_s in (q, p, t)
    GiNaC::ex H;                        // H(q, p, t)
    std::vector<GiNaC::ex> q_rate;      // ∂H/∂p_s
    std::vector<GiNaC::ex> p_rate;      // −∂H/∂q_s + Q_s
    bool conserved = false;             // H is an integral (the Lagrangian side's was proven)
    FirstOrderForm form;                // state (q, p), every rate explicit
};

// Throws InputError when the Legendre transform does not exist or is not what the equations
// integrate: a velocity Hessian that is singular or depends on q̇, a free carrier (its
// quasi-velocities are not canonical), or dropped effects (the kept equations have no L).
CanonicalEquations canonical_equations(const model::Model& model, const Equations& equations);

}  // namespace eomc::mechanics
