// The model's [[unilateral]] rows brought to the acceleration level (Mei, ch. 6, §6.2–§6.7): for
// each row the record a bilateral row has (mechanics/constraints/rows.hpp: the gap f, its velocity
// form ḟ or the §6.7 row φ itself, W over the velocities of M and the bias φ̇ − W u̇, so that on the
// boundary f̈ = W u̇ + bias), with Newton's restitution coefficient. On the boundary the admissible
// virtual displacements satisfy Σ_s W_s δq_s ≥ 0 and the ideal reaction Σ_s λ W_s has λ ≥ 0
// (Signorini: λ ≥ 0, f ≥ 0, λ f = 0); at an impact the percussion P enters the momenta as
// Δ(∂T/∂q̇_s) = P W_s with 0 ≤ P ⊥ (ḟ⁺ + e ḟ⁻) ≥ 0 (Moreau 1988; Pfeiffer & Glocker 1996;
// Acary & Brogliato 2008).
#pragma once

#include <vector>

#include "mechanics/unilateral/rows.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// One row per model unilateral constraint, in scene order, each built as the bilateral rows are
// (mechanics/constraints: constraint_row). Rows may be dependent (several contacts of one body): the
// LCPs of the contact phase and of the impact take them as they are. A row whose W vanishes
// identically (a gap that no motion can close or open) is refused at its expression.
std::vector<UnilateralRow> unilateral_rows(const model::Model& model);

// Whether a row is scleronomic and, for a §6.7 row, homogeneous in the rates: then its reaction
// does no work in the contact phase (as for bilateral rows, mechanics/constraints:
// reactions_do_no_work), and the energy is kept between impacts.
bool unilateral_reactions_do_no_work(const model::Model& model, const std::vector<UnilateralRow>& rows);

}  // namespace eomc::mechanics
