// What keeps a prescribed carrier on its motion (Mei 1988, §1.1): with v_o(t) and ω(t) given,
// the balance equations (1.1.14)–(1.1.15) no longer determine the carrier's motion; read the
// other way round they give the external resultant V (1.1.17) and its moment m⁰ about the pole
// o (1.1.24) that the motion requires.
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics {

struct HoldingOutput {
    std::string name;  // holding_force_1 … holding_force_3, holding_moment_1 … holding_moment_3
    GiNaC::ex value;   // a function of (t, q, q̇, q̈) and the parameters
};

// For a prescribed carrier (model.carrier present, not free), in carrier axes, the pole o as
// moment point:
//   holding_force_i  = (dP/dt + ω × P)_i − V_i^given,
//   holding_moment_i = (dK/dt + ω × K + v_o × P)_i − m⁰_i^given,
// P = ∂T/∂v_o and K = ∂T/∂ω of the carried bodies' and the carrier's own (if the scene gives
// its mass or inertia) kinetic energy, and V^given, m⁰^given the scene's [forces] resultant and
// moment (zero when not given). That is the force and moment about o that whatever drives the
// carrier must apply to the system (carrier + carried bodies) for the prescribed motion; the
// loads of [forces] potential and generalized, which act along the coordinates only, are not
// resolved into vectors and so are part of it (e.g. the support of the bodies' weight).
// Empty for a model without a carrier, with a free one, or whose [effects] drop any term.
std::vector<HoldingOutput> holding_forces(const model::Model& model);

}  // namespace eomc::mechanics
