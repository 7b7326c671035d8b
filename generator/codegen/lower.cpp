// Lowering: equations of motion → the blocks of straight-line code the kernel needs.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <regex>
#include <set>
#include <stdexcept>
#include <string>

#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "codegen/solve_plan.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/gradient.hpp"

namespace eomc::codegen {

using namespace eomc::symbolic;

using GiNaC::ex;

namespace {

// "w" unless a scene name looks like a temporary (w0, w12, …); then "w_", "w__", ….
std::string temporary_prefix(const model::Model& model, const mechanics::FirstOrderForm& form) {
    std::set<std::string> names;
    for (const auto& p : model.parameters) names.insert(p.name);
    for (const auto& c : form.state) names.insert(c.name);
    for (const auto& c : form.velocity_rates) names.insert(c.name);
    std::string prefix = "w";
    for (;;) {
        const std::regex pattern(prefix + "[0-9]+");
        if (std::none_of(names.begin(), names.end(), [&](const std::string& n) { return std::regex_match(n, pattern); }))
            return prefix;
        prefix += "_";
    }
}

// u̇ = M⁻¹ f in closed form, for one or two velocities only (beyond that the expressions
// swell; the kernel solves M u̇ = f numerically instead).
std::vector<ex> solve_explicitly(const GiNaC::matrix& M, const std::vector<ex>& f) {
    if (f.size() == 1) return {f[0] / M(0, 0)};
    const ex det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    return {(M(1, 1) * f[0] - M(0, 1) * f[1]) / det, (M(0, 0) * f[1] - M(1, 0) * f[0]) / det};
}

const GiNaC::symbol& as_symbol(const ex& e) { return GiNaC::ex_to<GiNaC::symbol>(e); }

// What makes a matrix non-constant for the solve plans: t and the state.
std::vector<ex> varying_symbols(const KernelIR& ir) {
    std::vector<ex> varying{ir.t};
    for (const auto& s : ir.state) varying.push_back(s.symbol);
    return varying;
}

// How rhs and jacobian solve M u̇ = f, from M's structure (codegen/solve_plan.hpp), and the
// straight-line solve appended to the blocks they evaluate (M and f; M and G).
void lower_solve(KernelIR& ir, const GiNaC::matrix& M, const std::string& prefix) {
    const std::vector<ex> varying = varying_symbols(ir);
    ir.solve_plan = plan_solve(M, varying);
    if (ir.solve_plan.method == SolvePlan::Method::eigen_llt) return;
    ir.solved_rates = solve_block(ir.mass_and_forcing, ir.solve_plan, ir.n_velocities, 1, prefix);
    if (!ir.mass_and_jacobian_terms.outputs.empty())
        ir.solved_jacobian_terms =
            solve_block(ir.mass_and_jacobian_terms, ir.solve_plan, ir.n_velocities, ir.state.size(), prefix);
}

// The constraint rows' blocks: M, f, W and r = −bias − stabilisation CSE'd together (what rhs
// evaluates), the residuals f and φ, and W alone (what project() evaluates). Baumgarte's
// stabilisation (J. Baumgarte, Comput. Methods Appl. Mech. Eng. 1 (1972) 1–16) replaces φ̇ = 0 by
// φ̇ + 2α φ + β² f = 0 for a holonomic row and by φ̇ + α φ = 0 for a kinematic one.
void lower_constraints(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::vector<ex>& M,
                       const std::string& prefix) {
    const std::size_t nu = form.n_velocities(), m = form.constraints.size();
    if (m > nu)
        throw std::runtime_error("more constraint rows (" + std::to_string(m) + ") than velocities (" +
                                 std::to_string(nu) + ")");
    std::vector<ex> W, r, residuals(2 * m);
    bool position_projection = false;
    for (std::size_t a = 0; a < m; ++a) {
        const auto& row = form.constraints[a];
        if (row.W.size() != nu)
            throw std::runtime_error("constraint row '" + row.name + "' has " + std::to_string(row.W.size()) +
                                     " entries of W for " + std::to_string(nu) + " velocities");
        ir.constraint_names.push_back(row.name);
        ir.constraint_holonomic.push_back(row.holonomic);
        ir.constraint_projected.push_back(row.stabilization == mechanics::Stabilization::project);
        position_projection = position_projection || (row.holonomic && ir.constraint_projected.back());
        W.insert(W.end(), row.W.begin(), row.W.end());
        ex stabilisation = 0;
        if (row.stabilization == mechanics::Stabilization::baumgarte)
            stabilisation = row.holonomic ? 2 * ex(row.alpha) * row.velocity + ex(row.beta * row.beta) * row.position
                                          : ex(row.alpha) * row.velocity;
        r.push_back(-row.bias - stabilisation);
        residuals[a] = row.holonomic ? row.position : row.velocity;
        residuals[m + a] = row.velocity;
        ir.output_names.push_back("lambda_" + row.name);
    }
    // The position step moves q along M⁻¹Wᵀ: W's holonomic rows are ∂f/∂q only when u = q̇.
    if (position_projection && form.n_coordinates != nu)
        throw std::runtime_error("projecting holonomic constraint rows needs the velocity block to be q̇ (" +
                                 std::to_string(form.n_coordinates) + " coordinates, " + std::to_string(nu) +
                                 " velocities)");
    for (std::size_t k = 0; k < nu; ++k)
        ir.output_names.push_back(
            "reaction_" + (nu == form.n_coordinates ? form.state[k].name : form.state[form.velocity_offset + k].name));
    std::vector<ex> all = M;
    all.insert(all.end(), form.forcing.begin(), form.forcing.end());
    all.insert(all.end(), W.begin(), W.end());
    all.insert(all.end(), r.begin(), r.end());
    ir.mass_forcing_and_constraints = eliminate_common_subexpressions(all, prefix);
    ir.constraint_residuals = eliminate_common_subexpressions(residuals, prefix);
    ir.constraint_jacobian = eliminate_common_subexpressions(W, prefix);

    // The saddle-point solve and the projection's corrections in straight-line code where the
    // coupled unknowns fit; otherwise the runtime's Schur complement (runtime/constraints.hpp).
    const std::vector<ex> varying = varying_symbols(ir);
    ir.constraint_plan = plan_saddle_point(form.mass_matrix, W, m, varying);
    if (ir.constraint_plan.method == SolvePlan::Method::eigen_llt) return;
    ir.solved_constraints = solve_saddle_point(ir.mass_forcing_and_constraints, ir.constraint_plan, nu, m, prefix);
    const auto correction = [&](bool positions) {
        std::vector<ex> rows;
        std::size_t count = 0;
        for (std::size_t a = 0; a < m; ++a)
            if (ir.constraint_projected[a] && (!positions || ir.constraint_holonomic[a])) {
                rows.insert(rows.end(), W.begin() + long(a * nu), W.begin() + long((a + 1) * nu));
                ++count;
            }
        if (count == 0) return Block{};
        std::vector<ex> system = M;
        system.insert(system.end(), rows.begin(), rows.end());
        const SolvePlan plan = plan_saddle_point(form.mass_matrix, rows, count, varying);
        return saddle_point_correction(eliminate_common_subexpressions(system, prefix), plan, nu, count, prefix);
    };
    ir.position_correction = correction(true);
    // Every projected row holonomic: the velocity step uses the same rows, so the same C.
    bool same_rows = true;
    for (std::size_t a = 0; a < m; ++a) same_rows = same_rows && (!ir.constraint_projected[a] || ir.constraint_holonomic[a]);
    if (!same_rows) ir.velocity_correction = correction(false);
}

// The unilateral rows' blocks (Mei ch. 6; Acary, Brogliato, Numerical Methods for Nonsmooth
// Dynamical Systems, Springer 2008): the gaps (f for a gap row, φ for a kinematic row of §6.7), W
// over the velocities and the bias of f̈ = W u̇ + bias, each CSE'd alone (the event-driven driver
// asks for them at different times), and the restitution coefficients, which may depend on the
// parameters only. A gap that moves with t (a driven wall or table) also gets its explicit time rate
// w = ∂f/∂t, so that ḟ = W u + w (the rate on which Newton's impact law acts; Mei §6.5); f̈'s bias
// already holds ∂²f/∂t² and 2 Σ ∂²f/∂q∂t q̇ (constraint_row's total derivative treats t).
void lower_unilateral(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::string& prefix) {
    const std::size_t nu = form.n_velocities();
    std::vector<ex> gaps, W, bias, restitutions, time_rates;
    bool moving = false;
    for (const auto& u : form.unilateral) {
        const auto& row = u.row;
        if (row.W.size() != nu)
            throw std::runtime_error("unilateral row '" + row.name + "' has " + std::to_string(row.W.size()) +
                                     " entries of W for " + std::to_string(nu) + " velocities");
        if (u.restitution.has(ir.t))
            throw std::runtime_error("the restitution of unilateral row '" + row.name + "' depends on the time");
        for (const auto& s : form.state)
            if (u.restitution.has(s.symbol))
                throw std::runtime_error("the restitution of unilateral row '" + row.name + "' depends on the state (" +
                                         s.name + "); it may depend on the parameters only");
        ir.contact_names.push_back(row.name);
        ir.contact_kinematic.push_back(!row.holonomic);
        gaps.push_back(row.holonomic ? row.position : row.velocity);
        W.insert(W.end(), row.W.begin(), row.W.end());
        bias.push_back(row.bias);
        restitutions.push_back(u.restitution);
        // φ of a kinematic row is itself a rate: nothing is added to it.
        const ex w = row.holonomic ? row.position.diff(GiNaC::ex_to<GiNaC::symbol>(ir.t)).expand() : ex(0);
        moving = moving || !w.is_zero();
        time_rates.push_back(w);
    }
    if (moving) ir.contact_time_rates = eliminate_common_subexpressions(time_rates, prefix);
    ir.restitutions = eliminate_common_subexpressions(restitutions, prefix);
    ir.contact_gaps = eliminate_common_subexpressions(gaps, prefix);
    ir.contact_jacobian = eliminate_common_subexpressions(W, prefix);
    ir.contact_bias = eliminate_common_subexpressions(bias, prefix);
}

// The programs' blocks (Mei ch. 3): M, f, Ā, c and D CSE'd together (what rhs evaluates) and the
// residuals with their rates (what the host compares with Erugin's law).
void lower_programs(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::vector<ex>& M,
                    const std::string& prefix) {
    const std::size_t nu = form.n_velocities();
    std::vector<ex> A, c, residuals;
    std::vector<std::vector<ex>> columns;
    for (const auto& p : form.programs) {
        if (p.row.W.size() != nu)
            throw std::runtime_error("program '" + p.name() + "' has " + std::to_string(p.row.W.size()) +
                                     " entries of its row for " + std::to_string(nu) + " velocities");
        ir.program_names.push_back(p.name());
        ir.program_laws.insert(ir.program_laws.end(),
                               {p.configuration ? 1.0 : 0.0, p.closed_loop ? p.alpha : 0.0, p.closed_loop ? p.beta : 0.0,
                                p.closed_loop ? p.kappa : 0.0});
        A.insert(A.end(), p.row.W.begin(), p.row.W.end());
        c.push_back(p.target);
        residuals.push_back(p.residual());
        residuals.push_back(p.configuration ? p.row.velocity : ex(0));
        columns.insert(columns.end(), p.columns.begin(), p.columns.end());
        ir.program_columns.insert(ir.program_columns.end(), p.column_names.begin(), p.column_names.end());
    }
    ir.program_redundant = form.redundant_programs;
    for (const auto& name : ir.program_names) ir.output_names.push_back("program_" + name);
    for (const auto& name : ir.program_columns) ir.output_names.push_back(name);
    for (std::size_t k = 0; k < nu; ++k) ir.output_names.push_back("Qc_" + form.state[k].name);
    std::vector<ex> all = M;
    all.insert(all.end(), form.forcing.begin(), form.forcing.end());
    all.insert(all.end(), A.begin(), A.end());
    all.insert(all.end(), c.begin(), c.end());
    for (std::size_t i = 0; i < nu; ++i)  // D row-major
        for (const auto& column : columns) all.push_back(column[i]);
    ir.mass_forcing_and_programs = eliminate_common_subexpressions(all, prefix);
    ir.program_residuals = eliminate_common_subexpressions(residuals, prefix);

    // M⁻¹ and Ā in straight-line code where M's solve fits it; Udwadia–Kalaba (dependent ideal
    // programs) and larger M keep the runtime's Eigen path (runtime/program/control.hpp).
    if (ir.program_redundant || ir.program_columns.size() != ir.program_names.size()) return;
    const std::vector<ex> varying = varying_symbols(ir);
    ir.program_plan = plan_solve(form.mass_matrix, varying);
    if (ir.program_plan.method == SolvePlan::Method::eigen_llt || ir.program_plan.method == SolvePlan::Method::none) return;
    ir.reduced_programs = reduce_programs(ir.mass_forcing_and_programs, ir.program_plan, nu, ir.program_names.size(),
                                          ir.program_columns.size(), prefix);
}

}  // namespace

namespace {

// The state, invariant and output names are the CSV's columns and the summary's keys, so each
// must be one quantity's: a coordinate the scene calls lambda_rod beside a constraint rod's
// multiplier, or reaction_x beside a reaction, is refused rather than written twice.
void require_distinct_columns(const KernelIR& ir) {
    std::set<std::string> seen;
    const auto add = [&](const std::string& name, const char* what) {
        if (!seen.insert(name).second)
            throw EmitError("the kernel would write two columns named '" + name + "' (the second is " + what +
                            "); rename the scene's coordinate or constraint that takes this name");
    };
    for (const auto& s : ir.state) add(s.name, "a state variable");
    for (const auto& n : ir.invariant_names) add(n, "an invariant");
    for (const auto& n : ir.output_names) add(n, "an output");
    // eomc simulate writes a unilateral row's multiplier as lambda_<row> beside the outputs.
    for (const auto& n : ir.contact_names) add("lambda_" + n, "a unilateral row's multiplier");
}

// The kernel's names and sizes: the scene's, the state's with its initial values and the
// parameters' with their defaults.
void lower_names(const model::Model& model, const mechanics::FirstOrderForm& form, KernelIR& ir) {
    ir.scene_name = model.name;
    ir.struct_name = model.struct_name;
    ir.summary = model.summary;
    // The file name only: the header must not depend on the directory eomc ran in.
    ir.source = std::filesystem::path(model.source).filename().string();
    ir.description = form.description;
    ir.t = model.t;
    ir.n_coordinates = form.n_coordinates;
    ir.velocity_offset = form.velocity_offset;
    ir.n_velocities = form.n_velocities();
    ir.separable = form.separable;
    ir.unit_quaternions = form.unit_quaternions;
    ir.unit_vectors = form.unit_vectors;
    for (const auto& c : form.state) {
        ir.state.push_back({c.name, c.symbol});
        ir.initial_state.push_back(c.initial);
    }
    for (const auto& c : form.velocity_rates) ir.accelerations.push_back({c.name, c.symbol});
    for (const auto& p : model.parameters) {
        ir.parameters.push_back({p.name, p.symbol});
        ir.parameter_defaults.push_back(p.value);
    }
}

// M and f, apart and together, and the rates given in closed form; whether u̇ is solved in closed
// form. `M` is M's entries, row-major.
void lower_mass_and_forcing(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::vector<ex>& M,
                            const std::string& prefix) {
    const std::size_t nu = ir.n_velocities;
    std::vector<ex> M_and_f = M;
    M_and_f.insert(M_and_f.end(), form.forcing.begin(), form.forcing.end());

    ir.mass_matrix = eliminate_common_subexpressions(M, prefix);
    ir.forcing = eliminate_common_subexpressions(form.forcing, prefix);
    // With constraint rows u̇ comes from the Schur complement at run time, never in closed form.
    ir.explicit_solution = nu <= 2 && form.constraints.empty() && form.programs.empty();
    if (!ir.explicit_solution) {
        ir.mass_and_forcing = eliminate_common_subexpressions(M_and_f, prefix);
        std::vector<ex> rates;
        for (const auto& [index, rate] : form.explicit_rates) {
            ir.explicit_index.push_back(index);
            rates.push_back(rate);
        }
        ir.explicit_rates = eliminate_common_subexpressions(rates, prefix);
    }
}

// rhs() in closed form, with its Jacobian where asked; or, for M u̇ = f solved in the kernel, the
// Jacobian's terms where asked and the solve's plan.
void lower_rates_and_jacobian(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::vector<ex>& M,
                              const std::vector<GiNaC::symbol>& state_symbols, symbolic::Gradient& gradient,
                              const std::string& prefix) {
    const std::size_t nu = ir.n_velocities, N = form.state.size();
    if (ir.explicit_solution) {
        std::vector<ex> rates(N);
        for (const auto& [index, rate] : form.explicit_rates) rates[index] = rate;
        const std::vector<ex> acc = nu == 0 ? std::vector<ex>{} : solve_explicitly(form.mass_matrix, form.forcing);
        for (std::size_t k = 0; k < nu; ++k) rates[form.velocity_offset + k] = acc[k];
        ir.rhs_explicit = eliminate_common_subexpressions(rates, prefix);
        if (ir.has_jacobian)
            ir.jacobian_explicit = eliminate_common_subexpressions(symbolic::jacobian(rates, state_symbols), prefix);
    } else if (ir.has_jacobian && form.constraints.empty() && form.programs.empty()) {
        std::vector<ex> rows;
        for (const auto& [index, rate] : form.explicit_rates) {
            const std::vector<ex> g = gradient(rate);
            rows.insert(rows.end(), g.begin(), g.end());
        }
        ir.explicit_rates_jacobian = eliminate_common_subexpressions(rows, prefix);
        // d(M⁻¹f)/dx_j = M⁻¹ ∂(f − M u̇)/∂x_j with u̇ held at the solved value (acc): one
        // derivative of the residual per entry instead of one per entry of M.
        std::vector<ex> terms = M;
        for (std::size_t i = 0; i < nu; ++i) {
            ex residual = form.forcing[i];
            for (std::size_t k = 0; k < nu; ++k)
                residual -= form.mass_matrix(unsigned(i), unsigned(k)) * form.velocity_rates[k].symbol;
            const std::vector<ex> g = gradient(residual);
            terms.insert(terms.end(), g.begin(), g.end());
        }
        ir.mass_and_jacobian_terms = eliminate_common_subexpressions(terms, prefix);
    }
    if (!ir.explicit_solution && form.constraints.empty() && form.programs.empty() && nu > 0)
        lower_solve(ir, form.mass_matrix, prefix);
}

// The invariants and the scene's outputs, by name.
void lower_invariants_and_outputs(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::string& prefix) {
    std::vector<ex> invariants;
    for (const auto& inv : form.invariants) {
        ir.invariant_names.push_back(inv.name);
        invariants.push_back(inv.value);
    }
    ir.invariants = eliminate_common_subexpressions(invariants, prefix);
    std::vector<ex> outputs;
    for (const auto& out : form.outputs) {
        ir.output_names.push_back(out.name);
        outputs.push_back(out.value);
    }
    ir.outputs = eliminate_common_subexpressions(outputs, prefix);
    ir.n_user_outputs = outputs.size();
}

// What only some kernels carry, each where the form has it: events, the indicators of M's
// singular sets, Santilli's residuals and Encke's reference orbit.
void lower_watched_blocks(KernelIR& ir, const mechanics::FirstOrderForm& form, const std::string& prefix) {
    std::vector<ex> events;
    for (const auto& e : form.events) {
        ir.event_names.push_back(e.name);
        ir.event_directions.push_back(e.direction);
        ir.event_terminal.push_back(e.terminal);
        events.push_back(e.value);
    }
    if (!events.empty()) ir.events = eliminate_common_subexpressions(events, prefix);
    std::vector<ex> indicators;
    for (const auto& set : form.singular_sets) {
        ir.singular_set_names.push_back(set.condition);
        ir.singular_set_orders.push_back(set.order);
        indicators.push_back(set.indicator);
    }
    if (!indicators.empty()) ir.singular_sets = eliminate_common_subexpressions(indicators, prefix);
    std::vector<ex> residuals;
    for (const auto& r : form.santilli_residuals) {
        ir.santilli_residual_names.push_back(r.name);
        residuals.push_back(r.value);
    }
    if (!residuals.empty()) ir.santilli_residuals = eliminate_common_subexpressions(residuals, prefix);
    if (form.rectification) {
        const auto& r = *form.rectification;
        ir.rectification = RectificationIR{r.ratio, r.deviation, r.elements, r.count,
                                           eliminate_common_subexpressions(r.reference, prefix)};
    }
}

}  // namespace

KernelIR lower(const model::Model& model, const mechanics::FirstOrderForm& form, LoweringTimes* times,
               LowerOptions options) {
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
    lower_names(model, form, ir);
    const std::size_t nu = ir.n_velocities;
    const std::string prefix = temporary_prefix(model, form);
    ir.has_jacobian = options.jacobian;
    // ∂/∂x over every rate and residual through one memo (forward mode over the DAG): each
    // subexpression's gradient is formed once, not once per state variable.
    std::vector<GiNaC::symbol> state_symbols;
    for (const auto& s : ir.state) state_symbols.push_back(as_symbol(s.symbol));
    symbolic::Gradient gradient(state_symbols);

    std::vector<ex> M;
    for (std::size_t i = 0; i < nu; ++i)
        for (std::size_t j = 0; j < nu; ++j) M.push_back(form.mass_matrix(unsigned(i), unsigned(j)));
    lower_mass_and_forcing(ir, form, M, prefix);
    t.mass_and_forcing = lap();
    lower_rates_and_jacobian(ir, form, M, state_symbols, gradient, prefix);
    t.jacobian = lap();

    lower_invariants_and_outputs(ir, form, prefix);
    if (!form.constraints.empty()) lower_constraints(ir, form, M, prefix);
    if (!form.unilateral.empty()) lower_unilateral(ir, form, prefix);
    if (!form.programs.empty()) lower_programs(ir, form, M, prefix);
    lower_watched_blocks(ir, form, prefix);
    t.invariants = lap();
    require_distinct_columns(ir);
    return ir;
}

KernelIR lower(const model::Model& model, const mechanics::Equations& equations, LoweringTimes* times,
               LowerOptions options) {
    return lower(model, mechanics::first_order_form(model, equations), times, options);
}

}  // namespace eomc::codegen
