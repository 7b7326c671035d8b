// The section "Unilateral constraints" of `eomc derive` (text, LaTeX, JSON), in the book's order
// (Mei, ch. 6, §6.2–§6.5, and §6.7 for the velocity rows): per row the gap f ≥ 0, the admissible
// virtual displacements on the boundary, the ideal reaction λ ∂f/∂q with λ ≥ 0; then Lagrange's
// equations with the reactions, Signorini's conditions, the impact equations with Newton's law
// (Moreau's complementarity form for several rows) and Carnot's theorem for the energy lost.
#pragma once

#include <ostream>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::report {

// Nothing when the model has no unilateral rows.
void print_unilateral_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out);
void print_unilateral_latex(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out);
// The JSON member `"unilateral": {...}` (two-space indented, no trailing comma or newline).
void print_unilateral_json(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out);

}  // namespace eomc::report
