// The element formulations of an orbit scene: the state is a set of osculating elements of
// the Kepler orbit (FORMULAS §2), and the same perturbation the Cowell equations carry —
// the disturbing function R and the non-conservative acceleration a — drives them.
//
//   gauss     (a, e, i, Ω, ω, M) by Gauss's equations, the acceleration ∇R + a taken in
//             radial, transverse and normal axes; any force, conservative or not.
//   lagrange  (a, e, i, Ω, ω, M) by Lagrange's planetary equations in the partials of R,
//             R written in the elements through the eccentric anomaly E = kepler_E(M, e)
//             (model/kepler_function.hpp); a non-conservative a enters through Gauss's terms.
//   delaunay  (l, g, h, L, G, H) by the canonical equations of K = −μ²/(2L²) − R, R in the
//             Delaunay variables through a = L²/μ, e = √(1 − G²/L²), cos i = H/G; a
//             non-conservative a enters through Gauss's terms.
//   mean      (a, e, i, Ω, ω, M) by Lagrange's equations in R̄, the average of R over the
//             mean anomaly, computed symbolically (dM = r²/(a²η) dν turns R·dM into a
//             polynomial in cos ν, sin ν for every R that falls off at least as 1/r²: the
//             zonal terms). Secular motion only: fast and approximate by design.
//
// Every kernel's outputs are the Cartesian x … z_dot, written in the elements through E (so
// the kernel calls the runtime's Kepler solver); the Cowell equations' invariants and the
// scene's events are carried over in the elements. The classical elements are singular at
// e = 0 and at i = 0 or 180° (ω̇ and Ṁ carry 1/e, Ω̇ and i̇ 1/sin i): an orbit exactly there
// is refused, one near it warned about (model::build_orbit).
#pragma once

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// The model's formulation must be gauss, lagrange, delaunay or mean.
FirstOrderForm element_form(const model::Model& model, const Equations& cowell);

// R̄(a, e, i, Ω, ω, t): the average of the model's disturbing function over the mean anomaly,
// in the symbols given (the ones element_form uses). Throws InputError (at the formulation)
// when R has no closed-form average by this method.
GiNaC::ex averaged_disturbing_function(const model::Model& model, const GiNaC::symbol& a, const GiNaC::symbol& e,
                                       const GiNaC::symbol& i, const GiNaC::symbol& raan, const GiNaC::symbol& argp);

}  // namespace eomc::mechanics
