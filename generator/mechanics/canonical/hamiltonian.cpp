#include "mechanics/canonical/hamiltonian.hpp"

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

namespace {

std::size_t nodes(const ex& e) {
    std::size_t n = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) n += nodes(e.op(i));
    return n;
}

// A smaller but equal form for the expressions the kernel and the printer will see: the
// rational normal form, with sin² = 1 − cos² used where that shortens it (the inverse of a
// mass matrix is full of sin² + cos²).
ex tidy(const ex& e) {
    const ex plain = GiNaC::normal(e.expand());
    const ex u = GiNaC::wild(0);
    const ex trig = GiNaC::normal(
        e.expand().subs(GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2), GiNaC::subs_options::algebraic).expand());
    return nodes(trig) < nodes(plain) ? trig : plain;
}

std::string text(const ex& e) {
    std::ostringstream os;
    os << e;
    return os.str();
}

}  // namespace

CanonicalEquations canonical_equations(const model::Model& model, const Equations& eqs) {
    const SourcePos where = model.kinetic_pos;
    if (model.newtonian)
        throw InputError(where, "the canonical equations need a Lagrangian, and a [newtonian] scene gives equations "
                                "instead; `eomc inverse --emit-scene FILE` writes one when the equations admit it");
    if (model.free_carrier())
        throw InputError(where, "the canonical equations are not available for a free carrier: its quasi-velocities "
                                "are not derivatives of coordinates, so they have no conjugate momenta");
    if (!std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; }))
        throw InputError(where, "the canonical equations need the full Lagrangian, but [effects] drops terms of the "
                                "equations (they no longer follow from an L); keep every effect or use the "
                                "Lagrangian formulation");
    const std::size_t n = model.coordinates.size();
    const ex L = eqs.T - eqs.V;
    GiNaC::exmap at_rest;
    for (const auto& c : model.coordinates) at_rest[c.q_dot] = 0;

    // L = ½ q̇ᵀ W q̇ + bᵀ q̇ + L₀: W must not depend on q̇ and must be regular.
    CanonicalEquations out;
    GiNaC::matrix W{unsigned(n), unsigned(n)};
    std::vector<ex> b(n);
    for (std::size_t i = 0; i < n; ++i) {
        const ex dL = derivative(L, model.coordinates[i].q_dot);
        out.momentum.push_back(dL);
        b[i] = dL.subs(at_rest);
        for (std::size_t j = 0; j < n; ++j) {
            const ex w = tidy(derivative(dL, model.coordinates[j].q_dot));
            for (const auto& c : model.coordinates)
                if (w.has(c.q_dot))
                    throw InputError(where, fmt::format("the Legendre transform needs L quadratic in the velocities, "
                                                        "but ∂²L/∂{0}_dot∂{1}_dot = {2} depends on {3}_dot",
                                                        model.coordinates[i].name, model.coordinates[j].name,
                                                        text(w), c.name));
            W(unsigned(i), unsigned(j)) = w;
        }
    }
    const ex det = tidy(W.determinant());
    if (det.is_zero())
        throw InputError(where, "the velocity Hessian ∂²L/∂q̇∂q̇ is singular: p = ∂L/∂q̇ cannot be solved for q̇, "
                                "so there is no Hamiltonian (a degenerate Lagrangian)");
    // W⁻¹ entry by entry in normal form (adjugate over determinant, with sin² + cos² = 1 used),
    // and H = ½ (p − b)ᵀ q̇(p) − L₀ left unexpanded: the kernel's CSE shares the rest.
    GiNaC::matrix W_inv = W.inverse();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) W_inv(unsigned(i), unsigned(j)) = tidy(W_inv(unsigned(i), unsigned(j)));
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
    // h(q, q̇) = Σ q̇ ∂L/∂q̇ − L is H(q, p(q, q̇)) identically; it is an integral exactly when
    // the Lagrangian side proved it one.
    out.conserved = std::any_of(eqs.invariants.begin(), eqs.invariants.end(),
                                [](const Invariant& i) { return i.name == "energy"; });

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
    for (const auto& e : model.events)
        form.events.push_back({e.name, e.when.subs(to_canonical), e.direction, e.terminal});
    if (out.conserved)
        form.invariants.push_back({"energy", out.H, "H(q, p), the Legendre transform of L (the Jacobi integral)"});
    // Every other integral proven on the Lagrangian side (an orbit's h_z) is one of the same
    // motion, written in (q, p).
    for (const auto& inv : eqs.invariants)
        if (inv.name != "energy") form.invariants.push_back({inv.name, inv.value.subs(to_canonical), inv.description});
    return out;
}

}  // namespace eomc::mechanics
