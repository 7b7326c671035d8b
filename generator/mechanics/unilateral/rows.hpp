// Unilateral constraints as rows (Mei, ch. 6, §6.2–§6.7): a gap f_α(q, t) ≥ 0, or a unilateral
// kinematic constraint φ_α(q, q̇, t) ≥ 0 (§6.7), each with Newton's restitution coefficient. A row
// carries the bilateral record (mechanics/constraints/rows.hpp: W, bias, λ) because on the
// boundary, in the contact phase, it acts as one: the ideal reaction Σ λ_α W_αs with λ_α ≥ 0
// (Signorini: λ_α ≥ 0, f_α ≥ 0, λ_α f_α = 0), and at an impact the percussion P_α enters as
// Δ(∂T/∂q̇_s) = Σ P_α W_αs with 0 ≤ P_α ⊥ (ḟ⁺_α + e_α ḟ⁻_α) ≥ 0 (Moreau's form of Newton's law).
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/constraints/rows.hpp"

namespace eomc::mechanics {

struct UnilateralRow {
    ConstraintRow row;       // name, holonomic (a gap) or not (§6.7), f, φ, W, bias, λ, pos
    GiNaC::ex restitution;   // e_α, an expression of the parameters, 0 ≤ e ≤ 1 at the defaults
};

}  // namespace eomc::mechanics
