// `eomc control`: a programmed motion and its realising controls as the book presents them (Mei,
// ch. 3; Galiullin, Inverse Problems of Dynamics): the programs, their derivatives, Erugin's law,
// the matrix Ā M⁻¹ D, the control λ and Q_c = D λ, the realisability verdict with the singular
// set, and the law the residual follows. Text, LaTeX or JSON (expressions in GiNaC's syntax).
#pragma once

#include <ostream>

#include "mechanics/control/control.hpp"
#include "mechanics/equations.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"

namespace eomc::report {

void print_control(const model::Model& model, const mechanics::Equations& eqs, const mechanics::Realisation& r,
                   DerivationFormat format, std::ostream& out);

}  // namespace eomc::report
