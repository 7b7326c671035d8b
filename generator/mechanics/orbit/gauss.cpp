// gauss: the classical elements (a, e, i, Ω, ω, M) by Gauss's equations, the acceleration
// ∇R + a taken in radial, transverse and normal axes: any force, conservative or not (Vallado,
// Fundamentals of Astrodynamics and Applications, 4th ed., §9.3, eq. 9-24; Mei, ch. 2).
#include <fmt/format.h>

#include "mechanics/orbit/element_formulations.hpp"
#include "mechanics/orbit/elements.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace elements;

FirstOrderForm gauss_form(const model::Model& model, const Equations& cowell) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    const Setting s = classical_setting(model);
    const Conic& k = s.conic;
    FirstOrderForm form;
    form.description = "The classical elements (a, e, i, raan, argp, mean_anomaly) by Gauss's equations, the "
                       "perturbing acceleration ∇R + a in radial, transverse and normal axes at the Cartesian "
                       "state of the elements (E from the runtime's Kepler solver); the outputs are the "
                       "Cartesian state.";
    Vec F;
    for (std::size_t j = 0; j < 3; ++j) F[j] = s.on_conic(symbolic::derivative(o.R, c[j].q) + o.acceleration[j]);
    const Vec Frtn = rtn(F, k);
    std::array<ex, 6> rates = gauss_rates(k, Frtn);
    rates[5] += k.n;
    // The derivation shows the equations in named components, then what the components are.
    const GiNaC::symbol Fr("F_r"), Ft("F_t"), Fn("F_n");
    form.derivation.push_back({"F_r", Frtn[0]});
    form.derivation.push_back({"F_t", Frtn[1]});
    form.derivation.push_back({"F_n", Frtn[2]});
    auto shown = gauss_rates(k, Vec{Fr, Ft, Fn});
    shown[5] += k.n;
    for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", classical_names[j]), shown[j]});

    const runtime::ClassicalElements<double>& el0 = s.initial;
    complete(s, {el0.a, el0.e, el0.i, el0.raan, el0.argp, el0.mean_anomaly}, rates, form);
    carry_invariants(s, cowell, form);
    return form;
}

}  // namespace eomc::mechanics
