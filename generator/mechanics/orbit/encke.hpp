// The encke formulation of an orbit scene: the kernel integrates the deviation δ = r − ρ of the
// orbit from a reference Kepler ellipse ρ(t) (Battin, An Introduction to the Mathematics and
// Methods of Astrodynamics, rev. ed., §9.3), in inertial Cartesian axes:
//     δ̈ = −(μ/ρ³)(δ + f(q) r) + ∇R(r, t) + a(r, ṙ, t),   r = ρ + δ,
//     q = δ·(δ − 2r)/r²,   f(q) = q (3 + 3q + q²)/(1 + (1 + q)^{3/2}).
// With ρ² = |r − δ|² = r²(1 + q), Cowell's r̈ = −μ r/r³ + … minus the reference's ρ̈ = −μ ρ/ρ³
// is (μ/ρ³)(ρ − (ρ³/r³) r) = −(μ/ρ³)(δ + (ρ³/r³ − 1) r), and ρ³/r³ − 1 = (1 + q)^{3/2} − 1 =
// ((1 + q)³ − 1)/((1 + q)^{3/2} + 1) = f(q): the small difference formed without cancellation.
//
// The reference is carried in the state as constants (zero rates): its epoch t_ref and its
// classical elements (a, e, i, Ω, ω, M at t_ref), so ρ(t) is written symbolically through
// E = kepler_E(M_ref(t), e), M_ref(t) = M + n (t − t_ref), n = √(μ/a³). When |δ| exceeds a
// fraction (the scene's [orbit] rectify, 1e-2 by default) of |ρ|, the kernel's project()
// rectifies after the step: the reference becomes the osculating ellipse of the total state at
// that time, and δ is re-expressed in it (≈ 0). The kernel's outputs are the Cartesian state.
#pragma once

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// f(q) = (1 + q)^{3/2} − 1 written without cancellation at small q (the derivation printer shows it).
GiNaC::ex encke_f(const GiNaC::ex& q);

// The model must be an orbit scene with an elliptic initial orbit (build_model refuses the others
// at the formulation key); its invariants (proven on the Cowell equations, so valid in any
// variables) are carried over, written in the total state ρ + δ.
FirstOrderForm encke_form(const model::Model& model, const Equations& cowell);

}  // namespace eomc::mechanics
