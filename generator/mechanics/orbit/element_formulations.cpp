#include "mechanics/orbit/element_formulations.hpp"

#include <array>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "eomc/runtime/orbital_elements.hpp"
#include "mechanics/orbit/conic.hpp"
#include "model/kepler_function.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

namespace {

// A Cartesian expression of the model (x, y, z, their rates, r) written on the conic. The
// library writes its potentials in powers of x² + y² + z², which become powers of the conic's
// r rather than square roots of a long sum.
ex on_conic(const ex& value, const model::Model& model, const Conic& k) {
    const ex r2 = model.orbit->r.op(0);  // r = √(x² + y² + z²)
    ex out = value.subs(GiNaC::pow(r2, GiNaC::wild(0)) == GiNaC::pow(k.r, 2 * GiNaC::wild(0)));
    out = out.subs(r2 == k.r * k.r);
    GiNaC::exmap m;
    for (std::size_t j = 0; j < 3; ++j) {
        m[model.coordinates[j].q] = k.X[j];
        m[model.coordinates[j].q_dot] = k.V[j];
    }
    return out.subs(m);
}

// The perturbing acceleration (Cartesian, inertial) in radial, transverse and normal components.
Vec rtn(const Vec& a, const Conic& k) {
    Vec out{0, 0, 0};
    for (std::size_t j = 0; j < 3; ++j) {
        out[0] += a[j] * k.radial[j];
        out[1] += a[j] * k.transverse[j];
        out[2] += a[j] * k.normal[j];
    }
    return out;
}

// Gauss's equations (FORMULAS §2; Vallado eq. 9-24) for the force F = (F_r, F_t, F_n) per
// unit mass: the rates of (a, e, i, Ω, ω, M) less the Kepler motion n of M.
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

// Lagrange's planetary equations (FORMULAS §2) from the partials of R in (a, e, i, Ω, ω, M).
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

double number(const ex& e, const GiNaC::exmap& values) {
    const ex v = e.subs(values).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real())
        throw std::runtime_error("internal: an element formulation's initial value did not evaluate to a number");
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

const char* const classical_names[] = {"a", "e", "i", "raan", "argp", "mean_anomaly"};
const char* const delaunay_names[] = {"l", "g", "h", "L", "G", "H"};
const char* const partial_names[] = {"R_a", "R_e", "R_i", "R_raan", "R_argp", "R_M"};

// ⟨cos^m ν sin^n ν⟩ over a period: (m−1)!!(n−1)!!/(m+n)!! for m and n even, else 0.
GiNaC::numeric mean_of_powers(int m, int n) {
    if (m % 2 || n % 2) return 0;
    auto double_factorial = [](int k) {
        GiNaC::numeric f = 1;
        for (; k > 1; k -= 2) f *= k;
        return f;
    };
    return double_factorial(m - 1) * double_factorial(n - 1) / double_factorial(m + n);
}

}  // namespace

ex averaged_disturbing_function(const model::Model& model, const GiNaC::symbol& a, const GiNaC::symbol& e,
                                const GiNaC::symbol& i, const GiNaC::symbol& raan, const GiNaC::symbol& argp) {
    const model::Orbit& o = *model.orbit;
    const GiNaC::symbol c("cos_nu"), s("sin_nu"), rho("r");
    // The position on the orbit at true anomaly ν: r (cos ν P + sin ν Q).
    const ex cO = GiNaC::cos(raan), sO = GiNaC::sin(raan), cw = GiNaC::cos(argp), sw = GiNaC::sin(argp);
    const ex ci = GiNaC::cos(i), si = GiNaC::sin(i);
    const Vec P{cO * cw - sO * sw * ci, sO * cw + cO * sw * ci, sw * si};
    const Vec Q{-cO * sw - sO * cw * ci, -sO * sw + cO * cw * ci, cw * si};
    const ex r2 = o.r.op(0);
    ex R = o.R.subs(GiNaC::pow(r2, GiNaC::wild(0)) == GiNaC::pow(rho, 2 * GiNaC::wild(0))).subs(r2 == rho * rho);
    GiNaC::exmap on_orbit;
    for (std::size_t j = 0; j < 3; ++j) on_orbit[model.coordinates[j].q] = rho * (c * P[j] + s * Q[j]);
    R = R.subs(on_orbit);
    // ⟨R⟩ = (1/2π) ∫ R r²/(a² η) dν, r = p/(1 + e cos ν).
    const ex eta = GiNaC::sqrt(1 - e * e), p = a * (1 - e * e);
    const ex integrand = (R * rho * rho / (a * a * eta)).subs(rho == p / (1 + e * c)).expand();
    const GiNaC::lst cs{c, s};
    if (!integrand.is_polynomial(cs) || integrand.has(model.t))
        throw InputError(o.formulation_pos,
                         "the mean formulation averages R over the mean anomaly in closed form, which needs R·r² to be "
                         "a polynomial in x, y, z and 1/r with no explicit time (the zonal terms J2, J3, J4 are); this "
                         "scene's R is not: use gauss, lagrange, delaunay or equinoctial");
    ex mean = 0;
    for (int m = 0; m <= integrand.degree(c); ++m) {
        const ex cm = integrand.coeff(c, m);
        for (int n = 0; n <= cm.degree(s); ++n) {
            const GiNaC::numeric w = mean_of_powers(m, n);
            if (!w.is_zero()) mean += w * cm.coeff(s, n);
        }
    }
    return mean.normal();
}

FirstOrderForm element_form(const model::Model& model, const Equations& cowell) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    const std::string& kind = o.formulation;
    const bool delaunay = kind == "delaunay", mean = kind == "mean";
    FirstOrderForm form;

    // The initial osculating elements of the model's initial state (parameters at defaults).
    const GiNaC::exmap defaults = model.parameter_defaults();
    const double mu0 = o.mu_default;
    const runtime::CartesianState<double> x0{c[0].initial, c[1].initial, c[2].initial, c[0].rate, c[1].rate, c[2].rate};
    runtime::ClassicalElements<double> el0{};
    try {
        el0 = runtime::classical_from_cartesian(x0, mu0);
    } catch (const runtime::KeplerError& error) {
        throw InputError(o.formulation_pos, fmt::format("the initial orbit has no {} elements: {}", kind, error.what()));
    }
    if (!(el0.e < 1))
        throw InputError(o.formulation_pos,
                         fmt::format("the {} formulation needs an elliptic orbit (its Kepler solver is the elliptic "
                                     "one); this orbit has e = {}: use cowell or equinoctial",
                                     kind, el0.e));

    std::array<GiNaC::symbol, 6> q;
    for (std::size_t j = 0; j < 6; ++j) q[j] = GiNaC::symbol(delaunay ? delaunay_names[j] : classical_names[j]);
    const ex mu = o.mu;
    // The classical elements as expressions of the state, and the conic they describe.
    ex a, e, ci, si, raan, argp, M, i;
    if (delaunay) {
        const ex &l = q[0], &g = q[1], &h = q[2], &L = q[3], &G = q[4], &H = q[5];
        a = L * L / mu;
        e = GiNaC::sqrt(1 - G * G / (L * L));
        ci = H / G;
        si = GiNaC::sqrt(1 - H * H / (G * G));
        raan = h;
        argp = g;
        M = l;
    } else {
        a = q[0];
        e = q[1];
        i = q[2];
        ci = GiNaC::cos(q[2]);
        si = GiNaC::sin(q[2]);
        raan = q[3];
        argp = q[4];
        M = q[5];
    }
    const Conic k = conic(mu, a, e, ci, si, raan, argp, M);
    auto in_elements = [&](const ex& value) { return on_conic(value, model, k); };

    // The non-conservative acceleration in (r, t, n), for Gauss's terms.
    Vec nonconservative;
    for (std::size_t j = 0; j < 3; ++j) nonconservative[j] = in_elements(o.acceleration[j]);
    const bool has_nonconservative = !(o.acceleration[0].is_zero() && o.acceleration[1].is_zero() &&
                                       o.acceleration[2].is_zero());
    std::array<ex, 6> rates;
    ex R_bar;  // mean: the averaged disturbing function

    if (kind == "gauss") {
        form.description = "The classical elements (a, e, i, raan, argp, mean_anomaly) by Gauss's equations, the "
                           "perturbing acceleration ∇R + a in radial, transverse and normal axes at the Cartesian "
                           "state of the elements (E from the runtime's Kepler solver); the outputs are the "
                           "Cartesian state.";
        Vec F;
        for (std::size_t j = 0; j < 3; ++j) F[j] = in_elements(derivative(o.R, c[j].q) + o.acceleration[j]);
        const Vec Frtn = rtn(F, k);
        rates = gauss_rates(k, Frtn);
        rates[5] += k.n;
        const GiNaC::symbol Fr("F_r"), Ft("F_t"), Fn("F_n");
        form.derivation.push_back({"F_r", Frtn[0]});
        form.derivation.push_back({"F_t", Frtn[1]});
        form.derivation.push_back({"F_n", Frtn[2]});
        auto shown = gauss_rates(k, Vec{Fr, Ft, Fn});
        shown[5] += k.n;
        for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", classical_names[j]), shown[j]});
    } else if (kind == "lagrange" || mean) {
        ex R;
        if (mean) {
            if (has_nonconservative)
                throw InputError(o.formulation_pos,
                                 "the mean formulation averages the disturbing function R; a non-conservative "
                                 "acceleration (drag, a custom acceleration) has no such average here: use gauss, "
                                 "lagrange, delaunay or equinoctial");
            R = R_bar = averaged_disturbing_function(model, q[0], q[1], q[2], q[3], q[4]);
            form.description = "The mean classical elements (a, e, i, raan, argp, mean_anomaly) by Lagrange's "
                               "planetary equations in R averaged over the mean anomaly (secular motion only); the "
                               "outputs are the Cartesian state of the mean orbit.";
        } else {
            R = in_elements(o.R);
            form.description = "The classical elements (a, e, i, raan, argp, mean_anomaly) by Lagrange's planetary "
                               "equations in the partials of R(a, e, i, raan, argp, M), written through E = "
                               "kepler_E(M, e) (the runtime's Kepler solver); a non-conservative acceleration enters "
                               "through Gauss's terms; the outputs are the Cartesian state.";
        }
        form.derivation.push_back({mean ? "R_mean" : "R", R});
        std::array<ex, 6> partials;
        std::array<ex, 6> shown_partials;
        for (std::size_t j = 0; j < 6; ++j) {
            partials[j] = derivative(R, q[j]);
            shown_partials[j] = GiNaC::symbol(partial_names[j]);
            form.derivation.push_back({fmt::format("dR/d{}", classical_names[j]), partials[j]});
        }
        rates = lagrange_rates(k.n, a, e, i, partials);
        const auto shown = lagrange_rates(k.n, a, e, i, shown_partials);
        for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", classical_names[j]), shown[j]});
        if (has_nonconservative) {
            const auto g = gauss_rates(k, rtn(nonconservative, k));
            for (std::size_t j = 0; j < 6; ++j) rates[j] += g[j];
        }
    } else if (delaunay) {
        form.description = "The Delaunay variables (l, g, h, L, G, H) by the canonical equations of K = −μ²/(2L²) − R, "
                           "R written through a = L²/μ, e = √(1 − G²/L²), cos i = H/G and E = kepler_E(l, e); a "
                           "non-conservative acceleration enters through Gauss's terms; the outputs are the Cartesian "
                           "state.";
        const ex R = in_elements(o.R);
        form.derivation.push_back({"R", R});
        std::array<ex, 6> dR;
        for (std::size_t j = 0; j < 6; ++j) {
            dR[j] = derivative(R, q[j]);
            form.derivation.push_back({fmt::format("dR/d{}", delaunay_names[j]), dR[j]});
        }
        const ex &L = q[3], &G = q[4];
        // dl/dt = ∂K/∂L, dL/dt = −∂K/∂l, …, K = −μ²/(2L²) − R (FORMULAS §2).
        rates = {mu * mu / GiNaC::pow(L, 3) - dR[3], -dR[4], -dR[5], dR[0], dR[1], dR[2]};
        std::array<ex, 6> s;
        for (std::size_t j = 0; j < 6; ++j) s[j] = GiNaC::symbol(fmt::format("R_{}", delaunay_names[j]));
        const ex shown[] = {mu * mu / GiNaC::pow(L, 3) - s[3], -s[4], -s[5], s[0], s[1], s[2]};
        for (std::size_t j = 0; j < 6; ++j) form.derivation.push_back({fmt::format("d{}/dt", delaunay_names[j]), shown[j]});
        if (has_nonconservative) {
            // The Delaunay variables' rates from Gauss's: L = √(μa), G = √(μp) (so Ġ = r F_t, the
            // torque), H = G cos i.
            const Vec F = rtn(nonconservative, k);
            const auto g = gauss_rates(k, F);
            const ex G_dot = k.r * F[1];
            rates[0] += g[5];
            rates[1] += g[4];
            rates[2] += g[3];
            rates[3] += mu / (2 * L) * g[0];
            rates[4] += G_dot;
            rates[5] += G_dot * ci - G * si * g[2];
        }
    } else {
        throw std::logic_error("element_form: formulation " + kind + " is not an element formulation");
    }

    // The initial state.
    std::array<double, 6> initial{el0.a, el0.e, el0.i, el0.raan, el0.argp, el0.mean_anomaly};
    if (delaunay) {
        const auto d = runtime::delaunay_from_classical(el0, mu0);
        initial = {d.l, d.g, d.h, d.L, d.G, d.H};
    }
    if (mean) {
        // First-order mean semi-major axis: ȧ = 2/(na) ∂R/∂M makes the short-period part of a
        // (2a²/μ)(R − R̄); left in, it would change the mean motion and the along-track error
        // would grow secularly. The other elements' short-period terms stay in, bounded.
        GiNaC::exmap at0 = defaults;
        for (std::size_t j = 0; j < 6; ++j) at0[q[j]] = GiNaC::numeric(initial[j]);
        at0[model.t] = 0;
        const double R_osc = number(in_elements(o.R), at0);
        const double R_mean = number(R_bar, at0);
        initial[0] -= 2 * el0.a * el0.a / mu0 * (R_osc - R_mean);
    }
    for (std::size_t j = 0; j < 6; ++j) form.state.push_back({q[j].get_name(), q[j], initial[j]});
    form.n_coordinates = 6;
    form.velocity_offset = 6;
    form.mass_matrix = GiNaC::matrix(0, 0);
    for (std::size_t j = 0; j < 6; ++j) form.explicit_rates.emplace_back(j, rates[j]);

    if (mean) {
        // The secular equations are canonical in R̄: its energy is conserved when R̄ has no t, and
        // H = G cos i, the polar angular momentum, when R̄ has no Ω (the zonal terms).
        if (!R_bar.has(model.t))
            form.invariants.push_back({"mean_energy", -mu / (2 * a) - R_bar, "−μ/(2a) − R̄, the averaged Hamiltonian"});
        if (!R_bar.has(q[3]))
            form.invariants.push_back(
                {"mean_h_z", GiNaC::sqrt(mu * a * (1 - e * e)) * ci, "√(μ a (1 − e²)) cos i: R̄ does not depend on raan"});
    } else {
        for (const auto& inv : cowell.invariants)
            form.invariants.push_back({inv.name, in_elements(inv.value), inv.description});
    }
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name, k.X[j]});
    for (std::size_t j = 0; j < 3; ++j) form.outputs.push_back({c[j].name + "_dot", k.V[j]});
    for (const auto& ev : model.events) form.events.push_back({ev.name, in_elements(ev.when), ev.direction, ev.terminal});
    return form;
}

}  // namespace eomc::mechanics
