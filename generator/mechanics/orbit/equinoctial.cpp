#include "mechanics/orbit/equinoctial.hpp"

#include <array>
#include <cmath>

#include <fmt/format.h>

#include "eomc/runtime/orbital_elements.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

FirstOrderForm equinoctial_form(const model::Model& model, const Equations& cowell) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    FirstOrderForm form;
    form.description = "The modified equinoctial elements (p, f, g, h, k, L) of an orbit, integrated by Gauss's "
                       "equations with the perturbing acceleration ∇R + a in radial, transverse and normal axes; "
                       "the outputs are the Cartesian state.";

    // The initial elements from the model's initial Cartesian state (μ at its default).
    const double mu0 = o.mu_default;
    runtime::EquinoctialElements<double> q0{};
    try {
        q0 = runtime::equinoctial_from_cartesian(
            runtime::CartesianState<double>{c[0].initial, c[1].initial, c[2].initial, c[0].rate, c[1].rate, c[2].rate},
            mu0);
    } catch (const runtime::KeplerError& e) {
        throw InputError(o.formulation_pos, fmt::format("the initial orbit has no equinoctial elements: {}", e.what()));
    }
    const GiNaC::symbol p("p"), f("f"), g("g"), h("h"), k("k"), L("L");
    const double initial[] = {q0.p, q0.f, q0.g, q0.h, q0.k, q0.L};
    const GiNaC::symbol* names[] = {&p, &f, &g, &h, &k, &L};
    for (int i = 0; i < 6; ++i) form.state.push_back({names[i]->get_name(), *names[i], initial[i]});
    form.n_coordinates = 6;
    form.velocity_offset = 6;
    form.mass_matrix = GiNaC::matrix(0, 0);

    // The Cartesian state in the elements (the runtime's cartesian_from_equinoctial).
    const ex s2 = 1 + h * h + k * k;
    const std::array<ex, 3> fu{(1 - k * k + h * h) / s2, 2 * h * k / s2, -2 * k / s2};
    const std::array<ex, 3> gu{2 * h * k / s2, (1 + k * k - h * h) / s2, 2 * h / s2};
    const std::array<ex, 3> wu{2 * k / s2, -2 * h / s2, (1 - h * h - k * k) / s2};  // fu × gu, the orbit normal
    const ex cL = GiNaC::cos(L), sL = GiNaC::sin(L);
    const ex w = 1 + f * cL + g * sL;
    const ex r = p / w;
    const ex vs = GiNaC::sqrt(o.mu / p);
    std::array<ex, 3> X, V, radial, transverse;
    for (std::size_t j = 0; j < 3; ++j) {
        radial[j] = cL * fu[j] + sL * gu[j];
        transverse[j] = -sL * fu[j] + cL * gu[j];
        X[j] = r * radial[j];
        V[j] = vs * (-(g + sL) * fu[j] + (f + cL) * gu[j]);
    }
    // Cartesian expressions → elements: r² first, as a whole (the library's potentials are
    // written in x² + y² + z²), so that r is p/w rather than the norm of X.
    const ex r2_cartesian = c[0].q * c[0].q + c[1].q * c[1].q + c[2].q * c[2].q;
    GiNaC::exmap to_elements;
    for (std::size_t j = 0; j < 3; ++j) {
        to_elements[c[j].q] = X[j];
        to_elements[c[j].q_dot] = V[j];
    }
    auto in_elements = [&](const ex& e) { return e.subs(GiNaC::exmap{{r2_cartesian, r * r}}).subs(to_elements); };

    // The perturbing acceleration and its components on (radial, transverse, normal).
    std::array<ex, 3> a;
    for (std::size_t j = 0; j < 3; ++j) a[j] = in_elements(derivative(o.R, c[j].q) + o.acceleration[j]);
    ex dr = 0, dt = 0, dn = 0;
    for (std::size_t j = 0; j < 3; ++j) {
        dr += a[j] * radial[j];
        dt += a[j] * transverse[j];
        dn += a[j] * wu[j];
    }
    const ex q = GiNaC::sqrt(p / o.mu);
    const ex z = h * sL - k * cL;
    const ex rates[] = {
        2 * p / w * q * dt,
        q * (dr * sL + ((w + 1) * cL + f) * dt / w - z * g * dn / w),
        q * (-dr * cL + ((w + 1) * sL + g) * dt / w + z * f * dn / w),
        q * s2 * cL * dn / (2 * w),
        q * s2 * sL * dn / (2 * w),
        GiNaC::sqrt(o.mu * p) * w * w / (p * p) + q * z * dn / w,
    };
    for (std::size_t i = 0; i < 6; ++i) form.explicit_rates.emplace_back(i, rates[i]);

    for (const auto& inv : cowell.invariants) form.invariants.push_back({inv.name, in_elements(inv.value), inv.description});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name, X[j]});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name + "_dot", V[j]});
    for (const auto& e : model.events) form.events.push_back({e.name, in_elements(e.when), e.direction, e.terminal});
    return form;
}

}  // namespace eomc::mechanics
