// The derivation as a textbook prints it (text, LaTeX) or as data (JSON).
//
// Text and LaTeX follow the seed's notation: T = T_e + T_m + T_r, the Euler operator ε_s,
// each effect's generalized inertial term, then M q̈ = f and the invariants. JSON uses
// GiNaC's default syntax (`^` for powers) so that other computer-algebra systems can
// parse every expression back.
#pragma once

#include <ostream>
#include <string>

#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::report {

enum class DerivationFormat { text, latex, json };

// With `canonical`, the Hamiltonian formulation follows the Lagrangian derivation (JSON: a
// "canonical" member).
void print_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                      std::ostream& out, const mechanics::CanonicalEquations* canonical = nullptr);

// Expanded when that makes it smaller or not much larger (what a reader wants to see);
// otherwise as derived.
GiNaC::ex display_form(const GiNaC::ex& e);

// An equation's inertial side in display form with the accelerations u̇ collected, for reading.
GiNaC::ex collected_lhs(const model::Model& model, const GiNaC::ex& lhs);

}  // namespace eomc::report
