// A rigid-body scene's derivation as the book prints it (Mei, ch. 5): the body, Euler's and
// Poisson's equations, the formulation's state and equations, the integrals proven along the
// motion and those the polynomial search found. Also `eomc integrals`.
#pragma once

#include <ostream>

#include "mechanics/equations.hpp"
#include "mechanics/rigid/integrals.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"

namespace eomc::report {

// `eomc derive` on a rigid-body scene (every formulation but euler_angles, whose Lagrangian
// derivation prints as any other, with this one's body and integrals first).
void print_rigid_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                            std::ostream& out);

// `eomc integrals`: the classical integrals, proven, and the search's result at its degree.
void print_rigid_integrals(const model::Model& model, const mechanics::rigid::RigidIntegrals& integrals,
                           DerivationFormat format, std::ostream& out);

}  // namespace eomc::report
