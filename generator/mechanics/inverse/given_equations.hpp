// The equations of motion of a scene that gives its equations instead of its energies
// ([newtonian]): where the inverse problem (Mei, ch. 4) starts.
//
// The kinematic form q̈ = f(t, q, q̇) gives M = I and the forcing f directly; the fundamental
// form Φ = A(t,q,q̇) q̈ + B(t,q,q̇) gives M_sk = ∂Φ_s/∂q̈_k and f = −Φ|q̈=0. Either way the
// result is the same Equations record the Lagrangian path produces, so lowering, the kernel
// and `eomc simulate` need nothing new.
#pragma once

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// Requires model.newtonian. Throws InputError when A is singular (the equations do not
// determine the accelerations), naming the coordinates involved.
Equations derive_given_equations(const model::Model& model);

}  // namespace eomc::mechanics
