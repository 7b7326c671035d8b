#include "mechanics/orbit/encke.hpp"

#include <array>
#include <cstddef>
#include <string>

#include <fmt/format.h>

#include "eomc/runtime/orbit/orbital_elements.hpp"
#include "mechanics/orbit/conic.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

ex encke_f(const ex& q) { return q * (3 + 3 * q + q * q) / (1 + GiNaC::pow(1 + q, GiNaC::numeric(3, 2))); }

FirstOrderForm encke_form(const model::Model& model, const Equations& cowell) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    FirstOrderForm form;
    form.description = fmt::format(
        "Encke's formulation (Battin §9.3): the deviation δ = r − ρ from a reference Kepler ellipse ρ(t), "
        "δ̈ = −(μ/ρ³)(δ + f(q) r) + ∇R + a with q = δ·(δ − 2r)/r², f(q) = q(3 + 3q + q²)/(1 + (1 + q)^(3/2)); the "
        "reference's epoch and elements are constant state components, reset to the osculating orbit by project() "
        "when |δ| > {} |ρ|; the outputs are the Cartesian state.",
        o.rectify);

    // The initial reference: the osculating ellipse of the initial state (μ at its default), δ = 0.
    const double mu0 = o.mu_default;
    runtime::ClassicalElements<double> el0{};
    try {
        el0 = runtime::classical_from_cartesian(
            runtime::CartesianState<double>{c[0].initial, c[1].initial, c[2].initial, c[0].rate, c[1].rate, c[2].rate},
            mu0);
    } catch (const runtime::KeplerError& e) {
        throw InputError(o.formulation_pos, fmt::format("the initial orbit has no classical elements: {}", e.what()));
    }
    if (!(el0.e < 1 && el0.a > 0))  // build_model refuses these by the energy; round-off at e ≈ 1 lands here
        throw InputError(o.formulation_pos,
                         fmt::format("the encke formulation needs an elliptic initial orbit, but e = {}", el0.e));
    const double initial[14] = {0, 0, 0, 0, 0, 0, 0, el0.a, el0.e, el0.i, el0.raan, el0.argp, el0.mean_anomaly, 0};
    std::vector<GiNaC::symbol> s;
    const auto names = orbit_formulation(OrbitFormulationKind::encke).state_names;
    for (std::size_t k = 0; k < names.size(); ++k) {
        s.emplace_back(std::string(names[k]));
        form.state.push_back({std::string(names[k]), s.back(), initial[k]});
    }
    form.n_coordinates = 3;
    form.velocity_offset = form.state.size();
    form.mass_matrix = GiNaC::matrix(0, 0);
    const std::array<ex, 3> d{s[0], s[1], s[2]}, d_dot{s[3], s[4], s[5]};
    const ex t_ref = s[6], a = s[7], e = s[8], i = s[9], raan = s[10], argp = s[11], M_ref = s[12];

    // The reference ellipse at t (mechanics/conic.hpp), its mean anomaly advanced from its epoch.
    const ex n = GiNaC::sqrt(o.mu / GiNaC::pow(a, 3));
    const Conic ref = conic(o.mu, a, e, GiNaC::cos(i), GiNaC::sin(i), raan, argp, M_ref + n * (model.t - t_ref));
    const ex& rho = ref.r;  // |ρ|
    const std::array<ex, 3>&ref_r = ref.X, &ref_v = ref.V;
    std::array<ex, 3> r, v;
    for (std::size_t j = 0; j < 3; ++j) {
        r[j] = ref_r[j] + d[j];
        v[j] = ref_v[j] + d_dot[j];
    }
    const ex r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];

    // Cartesian expressions → the total state: r² first, as a whole (the library's potentials are
    // written in x² + y² + z²), so that it is the same subexpression as in q.
    const ex r2_cartesian = c[0].q * c[0].q + c[1].q * c[1].q + c[2].q * c[2].q;
    GiNaC::exmap to_total;
    for (std::size_t j = 0; j < 3; ++j) {
        to_total[c[j].q] = r[j];
        to_total[c[j].q_dot] = v[j];
    }
    auto in_total = [&](const ex& x) { return x.subs(GiNaC::exmap{{r2_cartesian, r2}}).subs(to_total); };

    const ex q = (d[0] * (d[0] - 2 * r[0]) + d[1] * (d[1] - 2 * r[1]) + d[2] * (d[2] - 2 * r[2])) / r2;
    const ex f = encke_f(q);
    const ex k = o.mu / GiNaC::pow(rho, 3);
    for (std::size_t j = 0; j < 3; ++j) form.explicit_rates.emplace_back(j, d_dot[j]);
    for (std::size_t j = 0; j < 3; ++j)
        form.explicit_rates.emplace_back(3 + j, -k * (d[j] + f * r[j]) +
                                                    in_total(derivative(o.R, c[j].q) + o.acceleration[j]));
    for (std::size_t m = 6; m < form.state.size(); ++m) form.explicit_rates.emplace_back(m, ex(0));

    for (const auto& inv : cowell.invariants) form.invariants.push_back({inv.name, in_total(inv.value), inv.description});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name, r[j]});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name + "_dot", v[j]});
    for (const auto& ev : model.events) form.events.push_back({ev.name, in_total(ev.when), ev.direction, ev.terminal});

    Rectification rect;
    rect.ratio = o.rectify;
    rect.deviation = 0;
    rect.elements = 6;
    rect.count = 13;
    rect.reference = {ref_r[0], ref_r[1], ref_r[2], ref_v[0], ref_v[1], ref_v[2], o.mu};
    form.rectification = rect;
    return form;
}

}  // namespace eomc::mechanics
