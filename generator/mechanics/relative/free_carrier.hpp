// A free carrier (Mei, §1.1): the carrier's motion is unknown, given by its six balance
// equations (1.1.14)–(1.1.15) in carrier axes, one per quasi-velocity or held component.
#pragma once

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// Appends the six balance equations force_1 … moment_3 to eqs.carrier_equations and sets the
// carrier's momentum P and angular momentum K; a held component's equation gives its reaction.
void add_free_carrier_equations(const model::Model& model, Equations& eqs);

}  // namespace eomc::mechanics
