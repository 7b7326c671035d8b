#include "mechanics/first_order.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "mechanics/inverse/inverse_problem.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "mechanics/relative/holding_forces.hpp"
#include "mechanics/unilateral/unilateral.hpp"
#include "mechanics/rigid/formulation.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

namespace {

bool depends_on_any(const ex& e, const std::vector<StateComponent>& components) {
    return std::any_of(components.begin(), components.end(), [&](const StateComponent& c) { return e.has(c.symbol); });
}

// Störmer–Verlet and its compositions need q̈ = a(t, q): M free of the state and of t
// (so that the kinetic energy is the same quadratic form everywhere) and f free of q̇.
bool is_separable(const model::Model& model, const FirstOrderForm& form) {
    if (form.state.size() != 2 * form.n_coordinates || form.n_velocities() != form.n_coordinates) return false;
    for (std::size_t i = 0; i < form.mass_matrix.rows(); ++i)
        for (std::size_t j = 0; j < form.mass_matrix.cols(); ++j) {
            const ex m = form.mass_matrix(unsigned(i), unsigned(j));
            if (m.has(model.t) || depends_on_any(m, form.state)) return false;
        }
    const std::vector<StateComponent> velocities(form.state.begin() + std::ptrdiff_t(form.n_coordinates), form.state.end());
    return std::none_of(form.forcing.begin(), form.forcing.end(), [&](const ex& f) { return depends_on_any(f, velocities); });
}

// Unit quaternion e = (e0, e1, e2, e3) of the carrier's attitude (carrier → inertial axes)
// and the pole's inertial position: ė = ½ e ⊗ (0, ω), ṙ_o = R(e) v_o / |e|². R(e) is the
// homogeneous quadratic form of the rotation, so R(e)/|e|² is exactly orthogonal even when
// integration lets |e| drift from 1 by the tolerance.
void add_carrier_kinematics(const model::Model& model, FirstOrderForm& form) {
    const auto& c = *model.carrier;
    const std::size_t first = form.state.size();
    const char* names[] = {"carrier_e0", "carrier_e1", "carrier_e2", "carrier_e3", "carrier_x", "carrier_y", "carrier_z"};
    for (int k = 0; k < 7; ++k) {
        for (const auto& s : form.state)
            if (s.name == names[k])
                throw InputError(SourcePos{model.source, 0, 0},
                                 fmt::format("the name '{}' is needed for the free carrier's attitude or position; "
                                             "rename the coordinate or quasi-velocity that uses it",
                                             names[k]));
        form.state.push_back({names[k], GiNaC::symbol(names[k]), k == 0 ? 1.0 : 0.0});
    }
    const ex e0 = form.state[first].symbol, e1 = form.state[first + 1].symbol, e2 = form.state[first + 2].symbol,
             e3 = form.state[first + 3].symbol;
    const ex& w1 = c.angular_velocity[0];
    const ex& w2 = c.angular_velocity[1];
    const ex& w3 = c.angular_velocity[2];
    const ex half = GiNaC::numeric(1, 2);
    const ex attitude[4] = {-half * (e1 * w1 + e2 * w2 + e3 * w3), half * (e0 * w1 + e2 * w3 - e3 * w2),
                            half * (e0 * w2 + e3 * w1 - e1 * w3), half * (e0 * w3 + e1 * w2 - e2 * w1)};
    const ex R[3][3] = {
        {e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3, 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)},
        {2 * (e1 * e2 + e0 * e3), e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3, 2 * (e2 * e3 - e0 * e1)},
        {2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3}};
    const ex norm2 = e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3;
    for (std::size_t k = 0; k < 4; ++k) form.explicit_rates.emplace_back(first + k, attitude[k]);
    form.unit_quaternions.push_back(first);
    for (std::size_t i = 0; i < 3; ++i) {
        ex v = 0;
        for (std::size_t j = 0; j < 3; ++j) v += R[i][j] * c.pole_velocity[j];
        form.explicit_rates.emplace_back(first + 4 + i, v.is_zero() ? v : v / norm2);
    }
}

}  // namespace

FirstOrderForm first_order_form(const model::Model& model, const Equations& eqs) {
    switch (model.kind()) {
        case model::ModelKind::energies:
        case model::ModelKind::given_equations: return lagrange_form(model, eqs);
        // An orbit scene's formulation decides what the kernel integrates; the equations derived
        // (Cowell's) are the same either way.
        case model::ModelKind::orbit: return orbit_formulation(model.orbit->kind).build(model, eqs);
        case model::ModelKind::rigid: return rigid::rigid_formulation(model.rigid->formulation).build(model, eqs);
    }
    throw std::logic_error("first_order_form: unknown model kind");
}

FirstOrderForm lagrange_form(const model::Model& model, const Equations& eqs) {
    FirstOrderForm form;
    const std::size_t n = model.coordinates.size();
    form.n_coordinates = n;
    form.description = fmt::format("Lagrange's equations M(q,t) q̈ = f(q,q̇,t) of {} coordinate{}, as the first-order "
                                   "system x = (q, q̇), ẋ = (q̇, M⁻¹f).",
                                   n, n == 1 ? "" : "s");
    for (const auto& c : model.coordinates) form.state.push_back({c.name, c.q, c.initial});
    form.velocity_offset = n;
    for (const auto& c : model.coordinates) form.state.push_back({c.name + "_dot", c.q_dot, c.rate});
    for (const auto& c : model.coordinates) form.velocity_rates.push_back({c.name + "_ddot", c.q_ddot, 0.0});
    for (std::size_t s = 0; s < n; ++s) form.explicit_rates.emplace_back(s, model.coordinates[s].q_dot);
    for (const auto& v : model.quasi_velocities) {
        form.state.push_back({v.name, v.symbol, v.initial});
        form.velocity_rates.push_back({v.name + "_dot", v.rate, 0.0});
    }
    if (model.free_carrier()) {
        form.description = fmt::format(
            "Lagrange's equations in the {} coordinate{} and the free carrier's balance equations (1.1.14)-(1.1.15) "
            "for its {} quasi-velocit{}, M u̇ = f with u = (q̇, quasi-velocities); the state adds the carrier's "
            "attitude quaternion e and the pole's inertial position.",
            n, n == 1 ? "" : "s", model.quasi_velocities.size(), model.quasi_velocities.size() == 1 ? "y" : "ies");
        add_carrier_kinematics(model, form);
        // The reaction that holds each held component: the balance's inertial side minus the applied load.
        for (const auto& c : eqs.carrier_equations)
            if (c.held) form.outputs.push_back({"reaction_" + c.name, c.lhs - c.applied});
    }
    // A prescribed carrier: the force and moment about o that hold it on its motion (Mei,
    // (1.1.14)–(1.1.15) read for V (1.1.17) and m⁰ (1.1.24)), carrier axes.
    for (auto& h : holding_forces(model)) form.outputs.push_back({std::move(h.name), std::move(h.value)});
    form.mass_matrix = eqs.mass_matrix;
    form.forcing = eqs.forcing;
    form.invariants = eqs.invariants;
    form.singular_sets = eqs.singular_sets;
    form.constraints = eqs.constraints;
    form.programs = eqs.programs;
    form.redundant_programs = eqs.redundant_programs;
    // The unilateral rows (Mei, ch. 6) as derived; a caller's Equations built without them get them here.
    form.unilateral = eqs.unilateral.empty() && !model.unilateral.empty() ? unilateral_rows(model) : eqs.unilateral;
    for (const auto& e : model.events) form.events.push_back({e.name, e.when, e.direction, e.terminal});
    // Controls λ(t, q, q̇) make the accelerations depend on the rates. Constraint rows make a kernel
    // no splitting method may step: q̈ = a(q) there would hold no reaction of the rows and no
    // projection back onto them (a Cartesian pendulum under verlet left its rod by 20).
    form.separable = is_separable(model, form) && form.programs.empty() && form.constraints.empty();
    if (model.newtonian) {
        const auto fundamental = inverse::forms(model, eqs).fundamental;
        for (const auto& r : inverse::santilli_conditions(model, fundamental))
            form.santilli_residuals.push_back({inverse::label(model, r), r.value});
    }
    return form;
}

}  // namespace eomc::mechanics
