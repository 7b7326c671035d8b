// `eomc linearize`: the operating point, the independent coordinates and speeds chosen, A, the
// eigenvalues with their modes and the verdict (mechanics/linearize/linearize.hpp), as text, LaTeX or
// JSON.
#pragma once

#include <ostream>
#include <string>

#include "mechanics/linearize/linearize.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"

namespace eomc::report {

// `about`: "equilibrium" or "initial", as the operating point was chosen.
void print_linearization(const model::Model& model, const mechanics::Linearization& lin, const std::string& about,
                         DerivationFormat format, std::ostream& out);

}  // namespace eomc::report
