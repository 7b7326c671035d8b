// Lowering: equations of motion → the blocks of straight-line code the kernel needs.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <regex>
#include <set>

#include "codegen/kernel_ir.hpp"
#include "mechanics/differentiation.hpp"
#include "mechanics/inverse_problem.hpp"

namespace eomc::codegen {

using GiNaC::ex;

namespace {

// "w" unless a scene name looks like a temporary (w0, w12, …); then "w_", "w__", ….
std::string temporary_prefix(const model::Model& model) {
    std::set<std::string> names;
    for (const auto& p : model.parameters) names.insert(p.name);
    for (const auto& c : model.coordinates) {
        names.insert(c.name);
        names.insert(c.name + "_dot");
        names.insert(c.name + "_ddot");
    }
    std::string prefix = "w";
    for (;;) {
        const std::regex pattern(prefix + "[0-9]+");
        if (std::none_of(names.begin(), names.end(), [&](const std::string& n) { return std::regex_match(n, pattern); }))
            return prefix;
        prefix += "_";
    }
}

// q̈ = M⁻¹ f in closed form, for one or two coordinates only (beyond that the expressions
// swell; the kernel solves M q̈ = f numerically instead).
std::vector<ex> solve_explicitly(const GiNaC::matrix& M, const std::vector<ex>& f) {
    if (f.size() == 1) return {f[0] / M(0, 0)};
    const ex det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    return {(M(1, 1) * f[0] - M(0, 1) * f[1]) / det, (M(0, 0) * f[1] - M(1, 0) * f[0]) / det};
}

}  // namespace

KernelIR lower(const model::Model& model, const mechanics::Equations& eqs, LoweringTimes* times) {
    using clock = std::chrono::steady_clock;
    auto lap = [last = clock::now()]() mutable {
        const auto now = clock::now();
        const double s = std::chrono::duration<double>(now - last).count();
        last = now;
        return s;
    };
    LoweringTimes local;
    LoweringTimes& t = times ? *times : local;
    KernelIR ir;
    ir.scene_name = model.name;
    ir.struct_name = model.struct_name;
    ir.summary = model.summary;
    // The file name only: the header must not depend on the directory eomc ran in.
    ir.source = std::filesystem::path(model.source).filename().string();
    ir.t = model.t;
    const std::size_t n = model.coordinates.size();
    ir.n_coordinates = n;
    for (const auto& c : model.coordinates) {
        ir.state.push_back({c.name, c.q});
        ir.initial_state.push_back(c.initial);
    }
    for (const auto& c : model.coordinates) {
        ir.state.push_back({c.name + "_dot", c.q_dot});
        ir.initial_state.push_back(c.rate);
    }
    for (const auto& c : model.coordinates) ir.accelerations.push_back({c.name + "_ddot", c.q_ddot});
    for (const auto& p : model.parameters) {
        ir.parameters.push_back({p.name, p.symbol});
        ir.parameter_defaults.push_back(p.value);
    }
    const std::string prefix = temporary_prefix(model);

    std::vector<ex> M, G;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) M.push_back(eqs.mass_matrix(unsigned(i), unsigned(j)));
    std::vector<ex> M_and_f = M;
    M_and_f.insert(M_and_f.end(), eqs.forcing.begin(), eqs.forcing.end());

    ir.mass_matrix = eliminate_common_subexpressions(M, prefix);
    ir.forcing = eliminate_common_subexpressions(eqs.forcing, prefix);
    ir.mass_and_forcing = eliminate_common_subexpressions(M_and_f, prefix);
    t.mass_and_forcing = lap();

    ir.explicit_solution = n <= 2;
    if (ir.explicit_solution) {
        const std::vector<ex> acc = solve_explicitly(eqs.mass_matrix, eqs.forcing);
        ir.accelerations_explicit = eliminate_common_subexpressions(acc, prefix);
        std::vector<ex> J;
        for (std::size_t i = 0; i < 2 * n; ++i)
            for (std::size_t j = 0; j < 2 * n; ++j)
                J.push_back(i < n ? ex(i + n == j ? 1 : 0) : mechanics::derivative(acc[i - n], GiNaC::ex_to<GiNaC::symbol>(ir.state[j].symbol)));
        ir.jacobian_explicit = eliminate_common_subexpressions(J, prefix);
    } else {
        // d(M⁻¹f)/dx_j = M⁻¹ ∂(f − M q̈)/∂x_j with q̈ held at the solved value (acc): one
        // derivative of the residual per entry instead of one per entry of M.
        std::vector<ex> terms = M;
        for (std::size_t i = 0; i < n; ++i) {
            ex residual = eqs.forcing[i];
            for (std::size_t k = 0; k < n; ++k)
                residual -= eqs.mass_matrix(unsigned(i), unsigned(k)) * model.coordinates[k].q_ddot;
            for (std::size_t j = 0; j < 2 * n; ++j)
                terms.push_back(mechanics::derivative(residual, GiNaC::ex_to<GiNaC::symbol>(ir.state[j].symbol)));
        }
        ir.mass_and_jacobian_terms = eliminate_common_subexpressions(terms, prefix);
    }

    t.jacobian = lap();

    std::vector<ex> invariants;
    for (const auto& inv : eqs.invariants) {
        ir.invariant_names.push_back(inv.name);
        invariants.push_back(inv.value);
    }
    ir.invariants = eliminate_common_subexpressions(invariants, prefix);
    t.invariants = lap();

    // A scene given by its equations carries the residuals of its self-adjointness
    // conditions, so that a simulation can watch them along its trajectory.
    if (model.newtonian) {
        std::vector<ex> residuals;
        const auto form = mechanics::inverse::forms(model, eqs).fundamental;
        for (const auto& r : mechanics::inverse::santilli_conditions(model, form)) {
            ir.santilli_residual_names.push_back(mechanics::inverse::label(model, r));
            residuals.push_back(r.value);
        }
        ir.santilli_residuals = eliminate_common_subexpressions(residuals, prefix);
    }
    return ir;
}

}  // namespace eomc::codegen
