// mean: the mean classical elements (a, e, i, Ω, ω, M) by Lagrange's planetary equations in R̄,
// the average of R over the mean anomaly (Kozai 1959; Brouwer 1959; Mei, ch. 2), computed
// symbolically: dM = r²/(a²η) dν turns R·dM into a polynomial in cos ν, sin ν for every R that
// falls off at least as 1/r² (the zonal terms). Secular motion only: fast and approximate by
// design.
#include <stdexcept>

#include "mechanics/orbit/element_formulations.hpp"
#include "mechanics/orbit/elements.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace elements;

namespace {

double number(const ex& e, const GiNaC::exmap& values) {
    const ex v = e.subs(values).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real())
        throw std::runtime_error("internal: an element formulation's initial value did not evaluate to a number");
    return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

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

// First-order mean semi-major axis: ȧ = 2/(na) ∂R/∂M makes the short-period part of a
// (2a²/μ)(R − R̄) (Kozai 1959); left in, it would change the mean motion and the along-track
// error would grow secularly. The other elements' short-period terms stay in, bounded.
std::array<double, 6> mean_initial_elements(const Setting& s, const ex& R_bar) {
    const runtime::ClassicalElements<double>& el0 = s.initial;
    std::array<double, 6> initial{el0.a, el0.e, el0.i, el0.raan, el0.argp, el0.mean_anomaly};
    GiNaC::exmap at0 = s.model.parameter_defaults();
    for (std::size_t j = 0; j < 6; ++j) at0[s.q[j]] = GiNaC::numeric(initial[j]);
    at0[s.model.t] = 0;
    const double R_osc = number(s.on_conic(s.model.orbit->R), at0);
    const double R_mean = number(R_bar, at0);
    initial[0] -= 2 * el0.a * el0.a / s.model.orbit->mu_default * (R_osc - R_mean);
    return initial;
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

FirstOrderForm mean_elements_form(const model::Model& model, const Equations&) {
    const model::Orbit& o = *model.orbit;
    const Setting s = classical_setting(model);
    if (s.has_nonconservative)
        throw InputError(o.formulation_pos,
                         "the mean formulation averages the disturbing function R; a non-conservative "
                         "acceleration (drag, a custom acceleration) has no such average here: use gauss, "
                         "lagrange, delaunay or equinoctial");
    FirstOrderForm form;
    const ex R_bar = averaged_disturbing_function(model, s.q[0], s.q[1], s.q[2], s.q[3], s.q[4]);
    form.description = "The mean classical elements (a, e, i, raan, argp, mean_anomaly) by Lagrange's "
                       "planetary equations in R averaged over the mean anomaly (secular motion only); the "
                       "outputs are the Cartesian state of the mean orbit.";
    const auto rates = planetary_equations(s, R_bar, "R_mean", form);
    complete(s, mean_initial_elements(s, R_bar), rates, form);

    // The secular equations are canonical in R̄: its energy is conserved when R̄ has no t, and
    // H = G cos i, the polar angular momentum, when R̄ has no Ω (the zonal terms).
    const ex mu = o.mu;
    if (!R_bar.has(model.t))
        form.invariants.push_back({"mean_energy", -mu / (2 * s.a) - R_bar, "−μ/(2a) − R̄, the averaged Hamiltonian"});
    if (!R_bar.has(s.q[3]))
        form.invariants.push_back({"mean_h_z", GiNaC::sqrt(mu * s.a * (1 - s.e * s.e)) * s.ci,
                                   "√(μ a (1 − e²)) cos i: R̄ does not depend on raan"});
    return form;
}

}  // namespace eomc::mechanics
