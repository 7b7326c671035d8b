#include "mechanics/canonical/hamiltonian.hpp"

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

namespace {

std::string text(const ex& e) {
    std::ostringstream os;
    os << e;
    return os.str();
}

// The scenes whose canonical equations this chapter does not derive, refused at their place.
void refuse_unsupported(const model::Model& model) {
    const SourcePos where = model.kinetic_pos;
    if (model.newtonian)
        throw InputError(where, "the canonical equations need a Lagrangian, and a [newtonian] scene gives equations "
                                "instead; `eomc inverse --emit-scene FILE` writes one when the equations admit it");
    // Constrained canonical equations would need the rows in (q, p) and a Dirac bracket; the
    // constraint rows are carried by Lagrange's form only.
    if (!model.constraints.empty())
        throw InputError(model.constraints.front().pos,
                         fmt::format("[[constraint]] '{}' is not supported with [formulation] kind = \"hamiltonian\": "
                                     "constraint rows are carried by Lagrange's equations only; use kind = "
                                     "\"lagrangian\"",
                                     model.constraints.front().name));
    if (!model.unilateral.empty())
        throw InputError(model.unilateral.front().pos,
                         fmt::format("[[unilateral]] '{}' is not supported with Hamilton's equations: unilateral "
                                     "rows are carried by Lagrange's equations only; drop --hamiltonian",
                                     model.unilateral.front().name));
    if (model.free_carrier())
        throw InputError(where, "the canonical equations are not available for a free carrier: its quasi-velocities "
                                "are not derivatives of coordinates, so they have no conjugate momenta");
    if (!std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; }))
        throw InputError(where, "the canonical equations need the full Lagrangian, but [effects] drops terms of the "
                                "equations (they no longer follow from an L); keep every effect or use the "
                                "Lagrangian formulation");
}

// The Legendre transform of L = ½ q̇ᵀ W q̇ + bᵀ q̇ + L₀ into out: p = ∂L/∂q̇, q̇(p) = W⁻¹(p − b),
// H = ½ (p − b)ᵀ q̇(p) − L₀ and Hamilton's rates; returns q̇ ↦ q̇(p).
GiNaC::exmap legendre_transform(const model::Model& model, const Equations& eqs, CanonicalEquations& out) {
    const SourcePos where = model.kinetic_pos;
    const std::size_t n = model.coordinates.size();
    const ex L = eqs.T - eqs.V;
    GiNaC::exmap at_rest;
    for (const auto& c : model.coordinates) at_rest[c.q_dot] = 0;

    // L = ½ q̇ᵀ W q̇ + bᵀ q̇ + L₀: W must not depend on q̇ and must be regular.
    GiNaC::matrix W{unsigned(n), unsigned(n)};
    std::vector<ex> b(n);
    for (std::size_t i = 0; i < n; ++i) {
        const ex dL = derivative(L, model.coordinates[i].q_dot);
        out.momentum.push_back(dL);
        b[i] = dL.subs(at_rest);
        for (std::size_t j = 0; j < n; ++j) {
            const ex w = normalized(derivative(dL, model.coordinates[j].q_dot));
            for (const auto& c : model.coordinates)
                if (w.has(c.q_dot))
                    throw InputError(where, fmt::format("the Legendre transform needs L quadratic in the velocities, "
                                                        "but ∂²L/∂{0}_dot∂{1}_dot = {2} depends on {3}_dot",
                                                        model.coordinates[i].name, model.coordinates[j].name,
                                                        text(w), c.name));
            W(unsigned(i), unsigned(j)) = w;
        }
    }
    const ex det = normalized(W.determinant());
    if (det.is_zero())
        throw InputError(where, "the velocity Hessian ∂²L/∂q̇∂q̇ is singular: p = ∂L/∂q̇ cannot be solved for q̇, "
                                "so there is no Hamiltonian (a degenerate Lagrangian)");
    // W⁻¹ entry by entry in normal form (adjugate over determinant, with sin² + cos² = 1 used),
    // and H = ½ (p − b)ᵀ q̇(p) − L₀ left unexpanded: the kernel's CSE shares the rest.
    GiNaC::matrix W_inv = W.inverse();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) W_inv(unsigned(i), unsigned(j)) = normalized(W_inv(unsigned(i), unsigned(j)));
    const ex L0 = L.subs(at_rest);

    for (const auto& c : model.coordinates) out.p.push_back(GiNaC::symbol("p_" + c.name));
    GiNaC::exmap to_canonical;
    for (std::size_t i = 0; i < n; ++i) {
        ex v = 0;
        for (std::size_t j = 0; j < n; ++j) v += W_inv(unsigned(i), unsigned(j)) * (out.p[j] - b[j]);
        out.velocity.push_back(v);
        to_canonical[model.coordinates[i].q_dot] = v;
    }
    ex H = -L0;
    for (std::size_t i = 0; i < n; ++i) H += (out.p[i] - b[i]) * out.velocity[i] / 2;
    out.H = H;
    for (std::size_t s = 0; s < n; ++s) {
        out.q_rate.push_back(out.velocity[s]);  // ∂H/∂p = W⁻¹(p − b), W⁻¹ symmetric
        out.p_rate.push_back(-derivative(out.H, model.coordinates[s].q) +
                             model.generalized_forces[s].subs(to_canonical));
    }
    return to_canonical;
}

// The kernel's state x = (q, p) with p(0) from q(0), q̇(0), and the rates, events, a rigid body's
// outputs and the invariants in it.
void canonical_form(const model::Model& model, const Equations& eqs, const GiNaC::exmap& to_canonical,
                    CanonicalEquations& out) {
    const SourcePos where = model.kinetic_pos;
    const std::size_t n = model.coordinates.size();
    FirstOrderForm& form = out.form;
    form.description = fmt::format("Hamilton's equations q̇ = ∂H/∂p, ṗ = −∂H/∂q + Q of {} coordinate{}, state "
                                   "x = (q, p) with p = ∂L/∂q̇.",
                                   n, n == 1 ? "" : "s");
    form.n_coordinates = n;
    for (const auto& c : model.coordinates) form.state.push_back({c.name, c.q, c.initial});
    form.velocity_offset = 2 * n;  // no velocity block: every rate is explicit
    form.mass_matrix = GiNaC::matrix(1, 1);
    // p(0) from the scene's q(0), q̇(0), evaluated at the default parameters and t = 0.
    GiNaC::exmap initial{{model.t, 0}};
    for (const auto& c : model.coordinates) {
        initial[c.q] = GiNaC::numeric(c.initial);
        initial[c.q_dot] = GiNaC::numeric(c.rate);
    }
    for (const auto& prm : model.parameters) initial[prm.symbol] = GiNaC::numeric(prm.value);
    for (std::size_t s = 0; s < n; ++s) {
        const ex p0 = out.momentum[s].subs(initial).evalf();
        if (!GiNaC::is_a<GiNaC::numeric>(p0))
            throw InputError(where, fmt::format("the initial momentum p_{} does not evaluate to a number",
                                                model.coordinates[s].name));
        form.state.push_back({"p_" + model.coordinates[s].name, out.p[s], GiNaC::ex_to<GiNaC::numeric>(p0).to_double()});
    }
    for (std::size_t s = 0; s < n; ++s) form.explicit_rates.emplace_back(s, out.q_rate[s]);
    for (std::size_t s = 0; s < n; ++s) form.explicit_rates.emplace_back(n + s, out.p_rate[s]);
    // A rigid body in Euler angles states its events in ω and γ and writes them as outputs
    // (mechanics/rigid/formulation.cpp's euler_angles form): through the angles, then (q, p).
    const GiNaC::exmap no_body;
    const GiNaC::exmap& body = model.rigid ? model.rigid->in_angles : no_body;
    for (const auto& e : model.events)
        form.events.push_back({e.name, e.when.subs(body).subs(to_canonical), e.direction, e.terminal});
    if (model.rigid) {
        const char* names[6] = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};
        for (std::size_t i = 0; i < 6; ++i) {
            const GiNaC::symbol& v = i < 3 ? model.rigid->omega[i] : model.rigid->gamma[i - 3];
            form.outputs.push_back({names[i], v.subs(body).subs(to_canonical)});
        }
    }
    if (out.conserved)
        form.invariants.push_back({"energy", out.H, "H(q, p), the Legendre transform of L (the Jacobi integral)"});
    // Every other integral proven on the Lagrangian side (an orbit's h_z) is one of the same
    // motion, written in (q, p).
    for (const auto& inv : eqs.invariants)
        if (inv.name != "energy") form.invariants.push_back({inv.name, inv.value.subs(to_canonical), inv.description});
}

}  // namespace

CanonicalEquations canonical_equations(const model::Model& model, const Equations& eqs) {
    refuse_unsupported(model);
    CanonicalEquations out;
    const GiNaC::exmap to_canonical = legendre_transform(model, eqs, out);
    // h(q, q̇) = Σ q̇ ∂L/∂q̇ − L is H(q, p(q, q̇)) identically; it is an integral exactly when
    // the Lagrangian side proved it one.
    out.conserved = std::any_of(eqs.invariants.begin(), eqs.invariants.end(),
                                [](const Invariant& i) { return i.name == "energy"; });
    canonical_form(model, eqs, to_canonical, out);
    return out;
}

}  // namespace eomc::mechanics
