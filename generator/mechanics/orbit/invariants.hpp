// The integrals of a perturbed Kepler motion in Cartesian coordinates (Mei, ch. 2): the energy
// H0 − R and the angular momentum about the central body's axis, proposed here and kept only
// where mechanics/invariants' prover (the same for every chapter) shows them constant.
#pragma once

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// Requires model.orbit and eqs from lagrange_equations(model).
void add_orbit_invariants(const model::Model& model, Equations& eqs);

}  // namespace eomc::mechanics
