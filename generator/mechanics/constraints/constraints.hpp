// The model's [[constraint]] rows brought to the acceleration level (Mei, §6.6 and ch. 3;
// Lur'e, Analytical Mechanics, ch. 2): for each row its velocity form φ, the row W of the
// reactions' directions over the velocities of M, and the bias φ̇ − W u̇, so that with ideal
// reactions (Chetaev 1932 for the kinematic rows) the equations read
//     M u̇ − Wᵀ λ = f,   W u̇ = −bias.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mechanics/constraints/rows.hpp"
#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// One row's record from its expression, f(q, t) (holonomic) or φ = B(q, t) u + b(q, t) (kinematic,
// linear in the rates): φ (ḟ for a holonomic row), W = ∂φ/∂u over the velocities of M, the bias
// φ̇ − W u̇ and λ named lambda_<name>; stabilization left at its default. The bilateral rows and
// the unilateral ones (mechanics/unilateral) are built by it.
ConstraintRow constraint_row(const model::Model& model, const std::string& name, bool holonomic,
                             const GiNaC::ex& expression, const SourcePos& pos);

// One row per model constraint, in scene order. Throws InputError when rows are dependent
// (W rank deficient at every probe point), naming the rows involved, at the first one's place.
std::vector<ConstraintRow> constraint_rows(const model::Model& model);

// Whether the energy (Jacobi) integral survives the reactions: their power is
// Σ_α λ_α (W_α · u) = −Σ_α λ_α ∂_t f_α (holonomic) or −Σ_α λ_α b_α (kinematic), which vanishes
// for every λ only when each row is scleronomic and homogeneous in the rates.
bool reactions_do_no_work(const model::Model& model, const std::vector<ConstraintRow>& rows);

// The multipliers in closed form: from M u̇ − Wᵀλ = f and W u̇ = −bias,
//     λ = −G⁻¹ (W M⁻¹ f + bias),   G = W M⁻¹ Wᵀ,
// by GiNaC's exact matrix inverse, normalised. Only for small systems (at most two rows and M at
// most 3×3) and results of moderate size; otherwise nullopt with the reason in `why`.
std::optional<std::vector<GiNaC::ex>> closed_form_multipliers(const Equations& eqs, std::string* why = nullptr);

}  // namespace eomc::mechanics
