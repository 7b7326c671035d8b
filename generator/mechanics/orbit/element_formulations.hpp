// The element formulations of an orbit scene: the state is a set of osculating elements of the
// Kepler orbit (Mei, ch. 2), and the same perturbation the Cowell equations carry — the
// disturbing function R and the non-conservative acceleration a — drives them. One file each:
//
//   gauss     gauss.cpp               (a, e, i, Ω, ω, M) by Gauss's equations in ∇R + a
//   lagrange  lagrange_planetary.cpp  (a, e, i, Ω, ω, M) by Lagrange's planetary equations in ∂R
//   delaunay  delaunay.cpp            (l, g, h, L, G, H) by the canonical equations of −μ²/(2L²) − R
//   mean      mean.cpp                (a, e, i, Ω, ω, M) by Lagrange's equations in R̄, R averaged
//                                     over the mean anomaly: secular motion only
//
// and what they share in elements.hpp. Every kernel's outputs are the Cartesian x … z_dot,
// written in the elements through E = kepler_E(M, e) (so the kernel calls the runtime's Kepler
// solver); the Cowell equations' invariants and the scene's events are carried over in the
// elements (mean: its own, of R̄). The classical elements are singular at e = 0 and at i = 0 or
// 180° (ω̇ and Ṁ carry 1/e, Ω̇ and i̇ 1/sin i): an orbit exactly there is refused, one near it
// warned about (model::build_model).
#pragma once

#include "mechanics/equations.hpp"
#include "mechanics/first_order.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// Each needs an orbit model in its formulation with an elliptic initial orbit (InputError at the
// formulation otherwise); `cowell` gives the invariants carried over.
FirstOrderForm gauss_form(const model::Model& model, const Equations& cowell);
FirstOrderForm lagrange_planetary_form(const model::Model& model, const Equations& cowell);
FirstOrderForm delaunay_form(const model::Model& model, const Equations& cowell);
// Also refuses a non-conservative acceleration and an R with no closed-form average.
FirstOrderForm mean_elements_form(const model::Model& model, const Equations& cowell);

// R̄(a, e, i, Ω, ω, t): the average of the model's disturbing function over the mean anomaly,
// in the symbols given (the ones mean_elements_form uses). Throws InputError (at the
// formulation) when R has no closed-form average by this method.
GiNaC::ex averaged_disturbing_function(const model::Model& model, const GiNaC::symbol& a, const GiNaC::symbol& e,
                                       const GiNaC::symbol& i, const GiNaC::symbol& raan, const GiNaC::symbol& argp);

}  // namespace eomc::mechanics
