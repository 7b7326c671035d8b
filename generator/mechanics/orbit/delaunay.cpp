// delaunay: the Delaunay variables (l, g, h, L, G, H) by the canonical equations of
// K = −μ²/(2L²) − R (Brouwer 1959, §2; Brouwer & Clemence, Methods of Celestial Mechanics, 1961,
// ch. XI; Mei, ch. 2), R written through a = L²/μ, e = √(1 − G²/L²), cos i = H/G and
// E = kepler_E(l, e); a non-conservative acceleration enters through Gauss's terms.
#include <fmt/format.h>

#include "mechanics/orbit/element_formulations.hpp"
#include "mechanics/orbit/elements.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace elements;

namespace {

// The Delaunay variables' rates from Gauss's: L = √(μa), G = √(μp) (so Ġ = r F_t, the torque),
// H = G cos i.
void add_gauss_terms(const Setting& s, std::array<ex, 6>& rates) {
    const Conic& k = s.conic;
    const ex &L = s.q[3], &G = s.q[4];
    const Vec F = rtn(s.nonconservative, k);
    const auto g = gauss_rates(k, F);
    const ex G_dot = k.r * F[1];
    rates[0] += g[5];
    rates[1] += g[4];
    rates[2] += g[3];
    rates[3] += s.model.orbit->mu / (2 * L) * g[0];
    rates[4] += G_dot;
    rates[5] += G_dot * s.ci - G * s.si * g[2];
}

}  // namespace

FirstOrderForm delaunay_form(const model::Model& model, const Equations& cowell) {
    const Setting s = delaunay_setting(model);
    const ex mu = model.orbit->mu;
    FirstOrderForm form;
    form.description = "The Delaunay variables (l, g, h, L, G, H) by the canonical equations of K = −μ²/(2L²) − R, "
                       "R written through a = L²/μ, e = √(1 − G²/L²), cos i = H/G and E = kepler_E(l, e); a "
                       "non-conservative acceleration enters through Gauss's terms; the outputs are the Cartesian "
                       "state.";
    const ex R = s.on_conic(model.orbit->R);
    form.derivation.push_back({"R", R});
    std::array<ex, 6> dR;
    for (std::size_t j = 0; j < 6; ++j) {
        dR[j] = symbolic::derivative(R, s.q[j]);
        form.derivation.push_back({fmt::format("dR/d{}", delaunay_names[j]), dR[j]});
    }
    const ex& L = s.q[3];
    // dl/dt = ∂K/∂L, dL/dt = −∂K/∂l, …
    std::array<ex, 6> rates{mu * mu / GiNaC::pow(L, 3) - dR[3], -dR[4], -dR[5], dR[0], dR[1], dR[2]};
    std::array<ex, 6> named;
    for (std::size_t j = 0; j < 6; ++j) named[j] = GiNaC::symbol(fmt::format("R_{}", delaunay_names[j]));
    const ex shown[] = {mu * mu / GiNaC::pow(L, 3) - named[3], -named[4], -named[5], named[0], named[1], named[2]};
    for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", delaunay_names[j]), shown[j]});
    if (s.has_nonconservative) add_gauss_terms(s, rates);

    const auto d = runtime::delaunay_from_classical(s.initial, model.orbit->mu_default);
    complete(s, {d.l, d.g, d.h, d.L, d.G, d.H}, rates, form);
    carry_invariants(s, cowell, form);
    return form;
}

}  // namespace eomc::mechanics
