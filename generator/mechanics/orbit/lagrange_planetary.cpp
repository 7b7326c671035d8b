// lagrange: the classical elements (a, e, i, Ω, ω, M) by Lagrange's planetary equations in the
// partials of R (Brouwer & Clemence, Methods of Celestial Mechanics, 1961, ch. XI; Vallado,
// Fundamentals of Astrodynamics and Applications, 4th ed., eq. 9-12; Mei, ch. 2), R written in
// the elements through the eccentric anomaly E = kepler_E(M, e) (model/kepler_function.hpp); a
// non-conservative acceleration enters through Gauss's terms.
#include <fmt/format.h>

#include "mechanics/orbit/element_formulations.hpp"
#include "mechanics/orbit/elements.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace elements;

FirstOrderForm lagrange_planetary_form(const model::Model& model, const Equations& cowell) {
    const Setting s = classical_setting(model);
    FirstOrderForm form;
    form.description = "The classical elements (a, e, i, raan, argp, mean_anomaly) by Lagrange's planetary "
                       "equations in the partials of R(a, e, i, raan, argp, M), written through E = "
                       "kepler_E(M, e) (the runtime's Kepler solver); a non-conservative acceleration enters "
                       "through Gauss's terms; the outputs are the Cartesian state.";
    const auto rates = planetary_equations(s, s.on_conic(model.orbit->R), "R", form);
    const runtime::ClassicalElements<double>& el0 = s.initial;
    complete(s, {el0.a, el0.e, el0.i, el0.raan, el0.argp, el0.mean_anomaly}, rates, form);
    carry_invariants(s, cowell, form);
    return form;
}

}  // namespace eomc::mechanics
