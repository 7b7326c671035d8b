// `eomc equilibria` on a scene with [[unilateral]] gaps: the KKT conditions of Mei §6.4, then each
// equilibrium (interior, on the boundary, degenerate) with its multipliers, closed forms where
// solved, verdict and the rule behind it, and the solutions refused for λ < 0 or f < 0; as text,
// LaTeX (a whole document) or JSON.
#pragma once

#include <ostream>

#include "mechanics/unilateral/equilibria.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"

namespace eomc::report {

void print_unilateral_equilibria(const model::Model& model, const mechanics::unilateral::UnilateralEquilibria& found,
                                 DerivationFormat format, std::ostream& out);

}  // namespace eomc::report
