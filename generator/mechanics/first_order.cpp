#include "mechanics/first_order.hpp"

#include <algorithm>

#include <fmt/format.h>

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

}  // namespace

FirstOrderForm first_order_form(const model::Model& model, const Equations& eqs) {
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
    form.mass_matrix = eqs.mass_matrix;
    form.forcing = eqs.forcing;
    form.invariants = eqs.invariants;
    form.separable = is_separable(model, form);
    return form;
}

}  // namespace eomc::mechanics
