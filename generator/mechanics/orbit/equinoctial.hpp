// The equinoctial formulation of an orbit scene: the state is the modified equinoctial
// elements (p, f, g, h, k, L) of the runtime's convention (orbital_elements.hpp: h, k =
// tan(i/2) (cos, sin) raan), integrated by Gauss's equations for an arbitrary perturbing
// acceleration (Betts, Practical Methods for Optimal Control, 2nd ed., eq. 6.37; Walker,
// Ireland & Owens 1985). The acceleration is the same one the Cowell equations carry, ∇R plus
// the non-conservative a, evaluated at the Cartesian state that the kernel computes from the
// elements, and projected on the radial, transverse and normal axes. Non-singular at e = 0 and
// i = 0 (singular only at i = 180°). The kernel's outputs are the Cartesian x … z_dot.
#pragma once

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// The model must be an orbit scene; its invariants (proven on the Cowell equations, so valid in
// any variables) are carried over, written in the elements.
FirstOrderForm equinoctial_form(const model::Model& model, const Equations& cowell);

}  // namespace eomc::mechanics
