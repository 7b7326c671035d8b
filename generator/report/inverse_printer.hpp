// The inverse problem as a textbook prints it (text, LaTeX) or as data (JSON): both forms of
// the equations, Santilli's conditions with their residuals and the verdict, the multiplier
// search step by step, the constructed Lagrangian and its verification. Also `eomc derive`
// for a scene given by its equations ([newtonian]): both forms and M q̈ = f.
//
// JSON writes every expression in GiNaC's syntax (`^` for powers), like `eomc derive`.
#pragma once

#include <ostream>
#include <string>

#include "mechanics/equations.hpp"
#include "mechanics/inverse/inverse_problem.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"

namespace eomc::report {

void print_inverse(const model::Model& model, const mechanics::inverse::Analysis& analysis, DerivationFormat format,
                   std::ostream& out);

// `eomc derive` for a [newtonian] scene.
void print_newtonian_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                                std::ostream& out);

// The constructed Lagrangian as a scene with a [lagrangian] table: same parameters,
// coordinates (initial values) and [simulate] settings, named <scene>_lagrangian.
// Requires analysis.construction->built.
std::string lagrangian_scene(const model::Model& model, const mechanics::inverse::Analysis& analysis);

}  // namespace eomc::report
