#include "mechanics/orbit/elements.hpp"

#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics::elements {

using GiNaC::ex;

namespace {

inline constexpr std::array<const char*, 6> partial_names{"R_a", "R_e", "R_i", "R_raan", "R_argp", "R_M"};

// The initial osculating elements of the model's initial state, μ at its default.
runtime::ClassicalElements<double> initial_elements(const model::Model& model) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    const std::string_view kind = scene::name(o.kind);
    const runtime::CartesianState<double> x0{c[0].initial, c[1].initial, c[2].initial, c[0].rate, c[1].rate, c[2].rate};
    runtime::ClassicalElements<double> el0{};
    try {
        el0 = runtime::classical_from_cartesian(x0, o.mu_default);
    } catch (const runtime::KeplerError& error) {
        throw InputError(o.formulation_pos, fmt::format("the initial orbit has no {} elements: {}", kind, error.what()));
    }
    if (!(el0.e < 1))
        throw InputError(o.formulation_pos,
                         fmt::format("the {} formulation needs an elliptic orbit (its Kepler solver is the elliptic "
                                     "one); this orbit has e = {}: use cowell or equinoctial",
                                     kind, el0.e));
    return el0;
}

// The conic, then the non-conservative acceleration on it (for Gauss's terms).
void place(Setting& s, const ex& raan, const ex& argp, const ex& M) {
    const model::Orbit& o = *s.model.orbit;
    s.conic = conic(o.mu, s.a, s.e, s.ci, s.si, raan, argp, M);
    for (std::size_t j = 0; j < 3; ++j) s.nonconservative[j] = s.on_conic(o.acceleration[j]);
    s.has_nonconservative = !(o.acceleration[0].is_zero() && o.acceleration[1].is_zero() && o.acceleration[2].is_zero());
}

}  // namespace

// The library writes its potentials in powers of x² + y² + z², which become powers of the
// conic's r rather than square roots of a long sum.
ex Setting::on_conic(const ex& value) const {
    const ex r2 = model.orbit->r.op(0);  // r = √(x² + y² + z²)
    ex out = value.subs(GiNaC::pow(r2, GiNaC::wild(0)) == GiNaC::pow(conic.r, 2 * GiNaC::wild(0)));
    out = out.subs(r2 == conic.r * conic.r);
    GiNaC::exmap m;
    for (std::size_t j = 0; j < 3; ++j) {
        m[model.coordinates[j].q] = conic.X[j];
        m[model.coordinates[j].q_dot] = conic.V[j];
    }
    return out.subs(m);
}

Setting classical_setting(const model::Model& model) {
    Setting s{model, initial_elements(model), {}, {}, {}, {}, {}, {}, {}, {}, false};
    for (std::size_t j = 0; j < 6; ++j) s.q[j] = GiNaC::symbol(classical_names[j]);
    s.a = s.q[0];
    s.e = s.q[1];
    s.i = s.q[2];
    s.ci = GiNaC::cos(s.q[2]);
    s.si = GiNaC::sin(s.q[2]);
    place(s, s.q[3], s.q[4], s.q[5]);
    return s;
}

// a = L²/μ, e = √(1 − G²/L²), cos i = H/G (Brouwer 1959, §2).
Setting delaunay_setting(const model::Model& model) {
    Setting s{model, initial_elements(model), {}, {}, {}, {}, {}, {}, {}, {}, false};
    for (std::size_t j = 0; j < 6; ++j) s.q[j] = GiNaC::symbol(delaunay_names[j]);
    const ex mu = model.orbit->mu;
    const ex &l = s.q[0], &g = s.q[1], &h = s.q[2], &L = s.q[3], &G = s.q[4], &H = s.q[5];
    s.a = L * L / mu;
    s.e = GiNaC::sqrt(1 - G * G / (L * L));
    s.ci = H / G;
    s.si = GiNaC::sqrt(1 - H * H / (G * G));
    place(s, h, g, l);
    return s;
}

Vec rtn(const Vec& a, const Conic& k) {
    Vec out{0, 0, 0};
    for (std::size_t j = 0; j < 3; ++j) {
        out[0] += a[j] * k.radial[j];
        out[1] += a[j] * k.transverse[j];
        out[2] += a[j] * k.normal[j];
    }
    return out;
}

std::array<ex, 6> gauss_rates(const Conic& k, const Vec& F) {
    const ex &a = k.a, &e = k.e, &p = k.p, &r = k.r, &h = k.h;
    const ex cw = GiNaC::cos(k.argp), sw = GiNaC::sin(k.argp);
    const ex cos_u = cw * k.cos_nu - sw * k.sin_nu, sin_u = sw * k.cos_nu + cw * k.sin_nu;
    return {
        2 * a * a / h * (e * k.sin_nu * F[0] + p / r * F[1]),
        (p * k.sin_nu * F[0] + ((p + r) * k.cos_nu + r * e) * F[1]) / h,
        r * cos_u * F[2] / h,
        r * sin_u * F[2] / (h * k.si),
        (-p * k.cos_nu * F[0] + (p + r) * k.sin_nu * F[1]) / (h * e) - r * sin_u * k.ci * F[2] / (h * k.si),
        k.eta * ((p * k.cos_nu - 2 * r * e) * F[0] - (p + r) * k.sin_nu * F[1]) / (h * e),
    };
}

std::array<ex, 6> lagrange_rates(const ex& n, const ex& a, const ex& e, const ex& i, const std::array<ex, 6>& R) {
    const ex eta = GiNaC::sqrt(1 - e * e), na2 = n * a * a, ci = GiNaC::cos(i), si = GiNaC::sin(i);
    const ex &Ra = R[0], &Re = R[1], &Ri = R[2], &RO = R[3], &Rw = R[4], &RM = R[5];
    return {
        2 / (n * a) * RM,
        (eta * eta * RM - eta * Rw) / (na2 * e),
        (ci * Rw - RO) / (na2 * eta * si),
        Ri / (na2 * eta * si),
        eta / (na2 * e) * Re - ci / (na2 * eta * si) * Ri,
        n - 2 / (n * a) * Ra - eta * eta / (na2 * e) * Re,
    };
}

std::array<ex, 6> planetary_equations(const Setting& s, const ex& R, const char* shown_name, FirstOrderForm& form) {
    const Conic& k = s.conic;
    form.derivation.push_back({shown_name, R});
    std::array<ex, 6> partials;
    std::array<ex, 6> shown_partials;
    for (std::size_t j = 0; j < 6; ++j) {
        partials[j] = symbolic::derivative(R, s.q[j]);
        shown_partials[j] = GiNaC::symbol(partial_names[j]);
        form.derivation.push_back({fmt::format("dR/d{}", classical_names[j]), partials[j]});
    }
    std::array<ex, 6> rates = lagrange_rates(k.n, s.a, s.e, s.i, partials);
    const auto shown = lagrange_rates(k.n, s.a, s.e, s.i, shown_partials);
    for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", classical_names[j]), shown[j]});
    if (s.has_nonconservative) {
        const auto g = gauss_rates(k, rtn(s.nonconservative, k));
        for (std::size_t j = 0; j < 6; ++j) rates[j] += g[j];
    }
    return rates;
}

// Every kernel's outputs are the Cartesian x … z_dot, written in the elements through E (so the
// kernel calls the runtime's Kepler solver); the scene's events are carried over on the conic.
void complete(const Setting& s, const std::array<double, 6>& initial, const std::array<ex, 6>& rates,
              FirstOrderForm& form) {
    const auto& c = s.model.coordinates;
    for (std::size_t j = 0; j < 6; ++j) form.state.push_back({s.q[j].get_name(), s.q[j], initial[j]});
    form.n_coordinates = 6;
    form.velocity_offset = 6;
    form.mass_matrix = GiNaC::matrix(0, 0);
    for (std::size_t j = 0; j < 6; ++j) form.explicit_rates.emplace_back(j, rates[j]);
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name, s.conic.X[j]});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name + "_dot", s.conic.V[j]});
    for (const auto& ev : s.model.events)
        form.events.push_back({ev.name, s.on_conic(ev.when), ev.direction, ev.terminal});
}

void carry_invariants(const Setting& s, const Equations& cowell, FirstOrderForm& form) {
    for (const auto& inv : cowell.invariants) form.invariants.push_back({inv.name, s.on_conic(inv.value), inv.description});
}

}  // namespace eomc::mechanics::elements
