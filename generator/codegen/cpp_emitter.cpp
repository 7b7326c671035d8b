// The kernel header (cpp_emitter.hpp): emit_header fills templates/kernel.hpp.in with the parts
// kernel_parts.hpp lists, and with the small ones every kernel has (parameters, outputs, invariants,
// the Jacobian, the variational equations, the indicators of singular sets).
#include "codegen/cpp_emitter.hpp"

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "codegen/kernel_parts.hpp"
#include "codegen/solve_plan.hpp"
#include "codegen/templates.hpp"
#include "model/functions.hpp"
#include "model/kepler_function.hpp"

namespace eomc::codegen {

namespace {

// Each step below writes one part of templates/kernel.hpp.in; emit_header fills the template.

// M u̇ = f solved in the kernel's own straight-line code over S (no Eigen), so a SIMD S works.
bool straight_line_solve(const SolvePlan& plan) {
    using M = SolvePlan::Method;
    return plan.method == M::identity || plan.method == M::diagonal || plan.method == M::block_diagonal ||
           plan.method == M::unrolled_ldlt;
}

bool uses_kepler_solver(const KernelIR& ir) {
    for (const Block* b : {&ir.mass_matrix, &ir.forcing, &ir.rhs_explicit, &ir.jacobian_explicit, &ir.mass_and_forcing,
                           &ir.explicit_rates, &ir.explicit_rates_jacobian, &ir.mass_and_jacobian_terms, &ir.invariants,
                           &ir.outputs, &ir.events, &ir.santilli_residuals, &ir.singular_sets,
                           &ir.mass_forcing_and_constraints, &ir.constraint_residuals, &ir.constraint_jacobian,
                           &ir.restitutions, &ir.contact_gaps, &ir.contact_jacobian, &ir.contact_bias,
                           &ir.contact_time_rates, &ir.mass_forcing_and_programs, &ir.program_residuals}) {
        for (const auto& t : b->temporaries)
            if (model::has_kepler_E(t.value)) return true;
        for (const auto& o : b->outputs)
            if (model::has_kepler_E(o)) return true;
    }
    return false;
}

// The members of the Parameters aggregate, with the scene's defaults; PT is double but for a
// batched ensemble's (one value per lane).
std::string parameter_members(const KernelIR& ir, const LocalNames& names) {
    std::string members;
    for (std::size_t i = 0; i < ir.parameters.size(); ++i)
        members += fmt::format("        PT {} = {};\n", names[ir.parameters[i].symbol],
                               double_literal(ir.parameter_defaults[i], "the default of parameter " + ir.parameters[i].name));
    if (!members.empty()) members.pop_back();
    return members;
}

// The body of outputs(). They may read u̇: computed once by rhs and handed over as `acc`.
std::string outputs_body(const KernelIR& ir, const LocalNames& names) {
    if (!ir.program_names.empty()) {
        // The residuals (program_<name>), λ (lambda_<column>) and Q_c = D λ (Qc_<coordinate>) after the scene's own.
        std::string body = fmt::format(
            "std::array<S, n_state> rate;\n"
            "std::array<S, 2 * n_programs> program_residual_;\n"
            "std::array<S, n_program_controls> program_lambda_;\n"
            "std::array<S, n_velocities> program_control_;\n"
            "controlled_rates_(t, x, rate.data(), program_lambda_.data(), program_control_.data(), p);\n"
            "program_residuals_(t, x, program_residual_.data(), p);\n"
            "for (int a = 0; a < n_programs; ++a) out[{0} + a] = program_residual_[std::size_t(2 * a)];\n"
            "for (int a = 0; a < n_program_controls; ++a) out[{0} + n_programs + a] = program_lambda_[std::size_t(a)];\n"
            "for (int k = 0; k < n_velocities; ++k) out[{0} + n_programs + n_program_controls + k] = program_control_[std::size_t(k)];\n",
            ir.n_user_outputs);
        if (ir.n_user_outputs == 0) return body;
        return body + "const S* acc = rate.data() + velocity_offset;\n" +
               function_body(ir, names, ir.outputs, indexed("out", ir.n_user_outputs), {true});
    }
    if (!ir.constraint_names.empty()) {
        // λ (lambda_<row>) and the generalized reactions Wᵀλ (reaction_<coordinate>) after the scene's own.
        std::string body = fmt::format(
            "std::array<S, n_state> rate;\n"
            "std::array<S, n_constraints> constraint_lambda_;\n"
            "std::array<S, n_velocities> constraint_reaction_;\n"
            "constrained_rates_(t, x, rate.data(), constraint_lambda_.data(), constraint_reaction_.data(), p);\n"
            "for (int a = 0; a < n_constraints; ++a) out[{0} + a] = constraint_lambda_[std::size_t(a)];\n"
            "for (int k = 0; k < n_velocities; ++k) out[{0} + n_constraints + k] = constraint_reaction_[std::size_t(k)];\n",
            ir.n_user_outputs);
        if (ir.n_user_outputs == 0) return body;
        return body + "const S* acc = rate.data() + velocity_offset;\n" +
               function_body(ir, names, ir.outputs, indexed("out", ir.n_user_outputs), {true});
    }
    if (ir.output_names.empty()) return "(void)t;\n(void)x;\n(void)out;\n(void)p;";
    return "std::array<S, n_state> rate;\nrhs(t, x, rate.data(), p);\nconst S* acc = rate.data() + velocity_offset;\n" +
           function_body(ir, names, ir.outputs, indexed("out", ir.output_names.size()), {true});
}

// acceleration(t, q) of a separable system, for the splitting methods.
std::string acceleration_function(const KernelIR& ir) {
    if (!ir.separable) return "";
    return "\n    // q̈ = a(t, q): the velocities do not enter the forces, so they are left at zero.\n"
           "    template <class S>\n"
           "    static void acceleration(S t, const S* q, S* a, const Parameters& p) {\n"
           "        std::array<S, n_state> x{}, rate;\n"
           "        for (int i = 0; i < n_coordinates; ++i) x[i] = q[i];\n"
           "        rhs(t, x.data(), rate.data(), p);\n"
           "        for (int i = 0; i < n_coordinates; ++i) a[i] = rate[velocity_offset + i];\n"
           "    }\n";
}

// ∂ẋ/∂x, only in kernels lowered with it (LowerOptions::jacobian): the rest keep their compile
// time and size.
std::string jacobian_function(const std::string& body) {
    return fmt::format(
        "\n    // ∂ẋ/∂x, row-major n_state×n_state.\n"
        "    template <class S>\n"
        "    static void jacobian(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(body, 8));
}

// The variational equations ride on the kernel's own rhs and symbolic Jacobian
// (runtime/variational.hpp); only on request, so that other kernels keep their bytes.
std::string variational_function(const KernelIR& ir) {
    return fmt::format(
        "\n    // Variational equations (runtime/variational.hpp): y = (x, Φ), Φ row-major n_state × n_state,\n"
        "    // with Φ̇ = (∂ẋ/∂x) Φ through jacobian(). From Φ(t0) = I, δx(t) = Φ(t) δx(t0) to first order.\n"
        "    static constexpr int n_variational = n_state + n_state * n_state;\n\n"
        "    template <class S>\n"
        "    static void variational_rhs(S t, const S* y, S* dydt, const Parameters& p) {{\n"
        "        eomc::runtime::variational_rhs<Basic{}>(t, y, dydt, p);\n"
        "    }}\n",
        checked_identifier(ir.struct_name, "the kernel's name"));
}

// One accessor per invariant, by its name.
std::string invariant_accessors(const KernelIR& ir) {
    std::string accessors;
    for (std::size_t k = 0; k < ir.invariant_names.size(); ++k) {
        accessors += fmt::format(
            "\n    template <class S>\n    static S {}(S t, const S* x, const Parameters& p) {{\n"
            "        std::array<S, n_invariants> all;\n        invariants(t, x, all.data(), p);\n"
            "        return all[{}];\n    }}\n",
            checked_identifier(ir.invariant_names[k], "an invariant name"), k);
    }
    return accessors;
}

// Newtonian scenes only, so that no other kernel changes: the self-adjointness residuals.
std::string santilli_residuals(const KernelIR& ir, const LocalNames& names) {
    if (ir.santilli_residual_names.empty()) return "";
    return fmt::format(
        "\n    // Santilli's conditions S1–S5 of variational self-adjointness of the fundamental form\n"
        "    // A(t,q,q̇) q̈ + B(t,q,q̇) = 0 (D = ∂_t + q̇_k ∂/∂q_k), one residual each; all vanish\n"
        "    // identically iff the equations as given are Euler–Lagrange equations (`eomc inverse`).\n"
        "    static constexpr int n_santilli_residuals = {};\n"
        "    static constexpr std::array<const char*, n_santilli_residuals> santilli_residual_names{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void santilli_residuals(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        ir.santilli_residual_names.size(), literal_list(ir.santilli_residual_names),
        indent(block_body(ir, names, ir.santilli_residuals, "out"), 8));
}

// Only kernels whose mass matrix has a singular set carry it, so that no other kernel changes.
std::string singular_sets_part(const KernelIR& ir, const LocalNames& names) {
    // A kernel with programs watches det(Ā M⁻¹ D) too, as one more indicator (computed at run time).
    const bool control = !ir.program_names.empty() && !ir.program_redundant;
    if (ir.singular_set_names.empty() && !control) return "";
    std::vector<std::string> set_names = ir.singular_set_names;
    std::vector<int> set_orders = ir.singular_set_orders;
    std::string body = ir.singular_set_names.empty() ? std::string() : block_body(ir, names, ir.singular_sets, "out");
    if (control) {
        set_names.push_back("det(A M^-1 D) = 0");
        set_orders.push_back(1);
        body += fmt::format("{}out[{}] = control_determinant_(t, x, p);", body.empty() || body.back() == '\n' ? "" : "\n",
                            ir.singular_set_names.size());
    }
    std::string orders;
    for (std::size_t k = 0; k < set_orders.size(); ++k) orders += fmt::format("{}{}", k ? ", " : "", set_orders[k]);
    return fmt::format(
        "\n    // Where det M = 0 (a coordinate singularity, as the gimbal lock of Euler angles){}: indicators\n"
        "    // s_k(t, x) of the sets s_k = 0, each with its power in det M; a simulation stops before them.\n"
        "    static constexpr int n_singular_sets = {};\n"
        "    static constexpr std::array<const char*, n_singular_sets> singular_set_names{{ {} }};\n"
        "    static constexpr std::array<int, n_singular_sets> singular_set_orders{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void singular_sets(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        control ? ",\n    // or where the programs' control matrix Ā M⁻¹ D is singular" : "", set_names.size(),
        literal_list(set_names), orders, indent(body, 8));
}

}  // namespace

std::string emit_header(const KernelIR& ir, const EmitOptions& options) {
    const LocalNames names(ir);
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;

    std::vector<std::string> state_names, parameter_names;
    for (const auto& s : ir.state) state_names.push_back(s.name);
    for (const auto& s : ir.parameters) parameter_names.push_back(s.name);

    const Rates rates = emit_rates(ir, names);
    std::string includes = uses_kepler_solver(ir) ? fmt::format("#include <{}>\n", model::kepler_E_header) : "";
    includes += rates.includes;
    const std::string table = [&] {
        std::string t = table_row("mass_matrix", ir.mass_matrix) + table_row("forcing", ir.forcing) + rates.table +
                        table_row("invariants", ir.invariants);
        if (!ir.output_names.empty()) t += table_row("outputs", ir.outputs);
        if (!ir.event_names.empty()) t += table_row("events", ir.events);
        if (!ir.singular_set_names.empty()) t += table_row("singular_sets", ir.singular_sets);
        if (!ir.program_names.empty()) t += table_row("program residuals", ir.program_residuals);
        if (!ir.contact_names.empty())
            t += table_row("contact gaps", ir.contact_gaps) + table_row("contact jacobian", ir.contact_jacobian) +
                 table_row("contact bias", ir.contact_bias);
        if (!ir.contact_time_rates.outputs.empty()) t += table_row("contact time rates", ir.contact_time_rates);
        t.pop_back();
        return t;
    }();

    // What the runtime's drivers call after every accepted step: a quaternion renormalised, or
    // Encke's rectification.
    // A kernel with constraint rows prints its project() with them (constraints_part).
    std::string projection = ir.constraint_names.empty() ? unit_projection(ir) : std::string(),
                private_part = rates.private_part;
    if (ir.rectification && !ir.constraint_names.empty())
        throw std::runtime_error("a kernel with both constraint rows and a rectification");
    if (ir.rectification) {
        if (!projection.empty()) throw std::runtime_error("a kernel with both a unit quaternion and a rectification");
        const Rectification r = rectification(ir, names);
        projection = r.project;
        private_part += (private_part.empty() ? "\n private:\n" : "\n") + r.private_part;
        includes += "#include <eomc/runtime/orbit/encke.hpp>\n";
    }
    std::string variational;
    if (options.variational && !ir.has_jacobian)
        throw std::logic_error("variational_rhs needs jacobian(): lower the kernel with LowerOptions::jacobian");
    if (options.variational) {
        variational = variational_function(ir);
        includes += "#include <eomc/runtime/variational.hpp>\n";
    }

    const std::string solve_note = nu == 0 ? "Every rate is explicit."
                                   : straight_line_constraints(ir)
                                       ? "M u̇ − Wᵀλ = f, W u̇ = r is solved in straight-line code (LDLᵀ of [[M, Wᵀ], [W, 0]], the "
                                         "velocities first: the Schur complement), and so are the projection's corrections."
                                   : !ir.constraint_names.empty()
                                       ? "M u̇ − Wᵀλ = f, W u̇ = r is solved at run time (the Schur complement on Eigen's LDLT)."
                                   : straight_line_programs(ir)
                                       ? "M u̇ = f + D λ, Ā u̇ = c: z = M⁻¹f, Y = M⁻¹D, G = Ā Y and h = c − Ā z in straight-line "
                                         "code, G λ = h by LU with partial pivoting at run time. " +
                                             describe(ir.program_plan, nu)
                                   : !ir.program_names.empty()
                                       ? "M u̇ = f + D λ, Ā u̇ = c is solved at run time (runtime/program/control.hpp)."
                                   : ir.explicit_solution ? "u̇ is solved in closed form (n_velocities ≤ 2)."
                                                        : describe(ir.solve_plan, nu);
    const std::string jacobian_note = ir.has_jacobian ? "jacobian() gives ∂ẋ/∂x."
                                                      : "No jacobian() (eomc generate --jacobian adds it).";
    const std::vector<std::pair<std::string, std::string>> fields{
        {"version", options.generator_version},
        {"source", comment_text(ir.source)},
        {"summary", comment_text(ir.summary.empty() ? ir.scene_name : ir.summary)},
        {"description", comment(ir.description + " " + solve_note + " " + jacobian_note)},
        {"operation_table", table},
        {"includes", includes},
        {"runtime_version", "1"},
        {"struct_name", checked_identifier(ir.struct_name, "the kernel's name")},
        {"scene_name", checked_identifier(ir.scene_name, "the scene name")},
        {"n", std::to_string(ir.n_coordinates)},
        {"n_state", std::to_string(N)},
        {"velocity_offset", std::to_string(ir.velocity_offset)},
        {"n_velocities", std::to_string(nu)},
        {"n_parameters", std::to_string(ir.parameters.size())},
        {"n_invariants", std::to_string(ir.invariant_names.size())},
        {"n_outputs", std::to_string(ir.output_names.size())},
        {"separable", ir.separable ? "true" : "false"},
        // Straight-line rates: nothing solved by a library at run time (a closed form, or a solve
        // unrolled from M's structure), no iteration (Kepler's equation), no rows.
        {"batchable", (nu == 0 || ir.explicit_solution || straight_line_solve(ir.solve_plan)) &&
                              ir.constraint_names.empty() && ir.program_names.empty() &&
                              ir.contact_names.empty() && !ir.rectification && !uses_kepler_solver(ir)
                          ? "true"
                          : "false"},
        {"state_names", quoted_list(state_names, "a state name")},
        {"parameter_names", quoted_list(parameter_names, "a parameter name")},
        {"invariant_names", quoted_list(ir.invariant_names, "an invariant name")},
        {"output_names", quoted_list(ir.output_names, "an output name")},
        {"initial_state", number_list(ir.initial_state, "an initial value")},
        {"parameter_members", parameter_members(ir, names)},
        {"mass_matrix_body", indent(block_body(ir, names, ir.mass_matrix, "out"), 8)},
        {"forcing_body", indent(block_body(ir, names, ir.forcing, "out"), 8)},
        {"rhs_body", indent(rates.rhs, 8)},
        {"has_jacobian", ir.has_jacobian ? "true" : "false"},
        {"jacobian", ir.has_jacobian ? jacobian_function(rates.jacobian) : std::string()},
        {"invariants_body", indent(block_body(ir, names, ir.invariants, "out"), 8)},
        {"outputs_note", ir.output_names.empty() ? "none for this model" : "functions of t, x and u̇"},
        {"outputs_body", indent(outputs_body(ir, names), 8)},
        {"acceleration", acceleration_function(ir)},
        {"events", events_part(ir, names)},
        {"constraints", constraints_part(ir) + contacts_part(ir, names) + programs_part(ir)},
        {"variational", projection + variational},
        {"invariant_accessors",
         invariant_accessors(ir) + santilli_residuals(ir, names) + singular_sets_part(ir, names)},
        {"private_part", private_part},
    };
    return fill_template(kernel_template(), fields);
}

std::string emit_reference_body(const KernelIR& ir, const std::vector<GiNaC::ex>& reference) {
    if (reference.size() != ir.state.size())
        throw std::runtime_error(fmt::format("the reference has {} values for {} state variables", reference.size(),
                                             ir.state.size()));
    Block block;
    block.outputs = reference;
    Inputs inputs;
    inputs.state_array = false;
    return function_body(ir, LocalNames(ir), block, indexed("out", reference.size()), inputs);
}

}  // namespace eomc::codegen
