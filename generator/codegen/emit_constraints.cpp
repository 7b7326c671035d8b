// Bilateral constraint rows (Mei, §6.6): rhs() through M u̇ − Wᵀλ = f, W u̇ = r, solved in
// straight-line code (the saddle-point solve) or by the runtime's Schur complement, the rows'
// residuals, and the project() that puts the state back on them.
#include <string>
#include <vector>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

bool straight_line_constraints(const KernelIR& ir) {
    return !ir.constraint_names.empty() && ir.constraint_plan.method != SolvePlan::Method::eigen_llt &&
           ir.constraint_plan.method != SolvePlan::Method::none;
}

namespace {

// The straight-line path of emit_constrained_rates: u̇, λ and Wᵀλ from the saddle-point solve
// (codegen/solve_plan.hpp), and the projection's corrections, with no Eigen.
std::string straight_line_constraint_functions(const KernelIR& ir, const LocalNames& names) {
    const std::size_t nu = ir.n_velocities, m = ir.constraint_names.size();
    const std::vector<std::string> targets = indexed_arrays({{"udot", nu}, {"lambda", m}, {"reaction", nu}});
    std::string out = fmt::format(
        "    // u̇, λ and Wᵀλ of M u̇ − Wᵀλ = f, W u̇ = r: LDLᵀ of [[M, Wᵀ], [W, 0]] in straight-line code, the\n"
        "    // velocities before the multipliers (the Schur complement: M's pivots, then −W M⁻¹ Wᵀ's).\n"
        "    template <class S>\n"
        "    static void constrained_solution_(S t, const S* x, S* udot, S* lambda, S* reaction, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // ẋ from M u̇ − Wᵀλ = f, W u̇ = r; λ and the generalized reactions Wᵀλ too where lambda and\n"
        "    // reaction are not null.\n"
        "    template <class S>\n"
        "    static void constrained_rates_(S t, const S* x, S* dxdt, S* lambda, S* reaction, const Parameters& p) {{\n"
        "        std::array<S, n_velocities> udot, generalized;\n"
        "        std::array<S, n_constraints> multipliers;\n"
        "        constrained_solution_(t, x, udot.data(), multipliers.data(), generalized.data(), p);\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[std::size_t(k)];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_constraints; ++a) lambda[a] = multipliers[std::size_t(a)];\n"
        "        if (reaction)\n"
        "            for (int k = 0; k < n_velocities; ++k) reaction[k] = generalized[std::size_t(k)];\n"
        "    }}\n",
        indent(function_body(ir, names, ir.solved_constraints, targets), 8));
    const auto correction = [&](const char* name, const char* rows, const Block& block) {
        if (block.outputs.empty()) return std::string();
        return fmt::format(
            "\n    // The projection's step C = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ over {},\n"
            "    // n_velocities × {} row-major.\n"
            "    template <class S>\n"
            "    static void {}(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
            rows, block.outputs.size() / nu, name, indent(function_body(ir, names, block, indexed("out", block.outputs.size())), 8));
    };
    out += correction("position_correction_",
                      ir.velocity_correction.outputs.empty() ? "the projected rows (all holonomic: positions and velocities)"
                                                             : "the projected holonomic rows",
                      ir.position_correction);
    out += correction("velocity_correction_", "every projected row", ir.velocity_correction);
    return out;
}

}  // namespace

Rates emit_constrained_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t nu = ir.n_velocities, m = ir.constraint_names.size();
    const bool straight = straight_line_constraints(ir);
    Rates r;
    r.includes = straight ? "#include <eomc/runtime/constraint_projection.hpp>\n"
                          : "#include <Eigen/Core>\n#include <Eigen/Cholesky>\n#include <eomc/runtime/constraints.hpp>\n";
    r.rhs = "constrained_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = differenced_jacobian("the Schur complement");
    const std::vector<std::string> targets =
        indexed_arrays({{"out_M", nu * nu}, {"out_f", nu}, {"out_W", m * nu}, {"out_r", m}});
    const std::vector<std::string> residuals = indexed_arrays({{"out", m}, {"out_phi", m}});
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M, f, the constraint rows' W (m × n_velocities, row-major) and r = −bias − stabilisation,\n"
        "    // together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_forcing_and_constraints_(S t, const S* x, S* out_M, S* out_f, S* out_W, S* out_r,\n"
        "                                              const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "{}\n"
        "    // The rows' residuals: f (holonomic) or φ (kinematic) to out, φ to out_phi.\n"
        "    template <class S>\n"
        "    static void constraint_residuals_(S t, const S* x, S* out, S* out_phi, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // W alone, m × n_velocities row-major: what the projection needs.\n"
        "    template <class S>\n"
        "    static void constraint_jacobian_(S t, const S* x, S* out_W, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_forcing_and_constraints, targets), 8),
        indent(explicit_rates_body(ir, names), 8),
        straight ? straight_line_constraint_functions(ir, names) : std::string(
        "    // ẋ from M u̇ − Wᵀλ = f, W u̇ = r (runtime/constraints.hpp: the Schur complement on the LDLT of\n"
        "    // M); λ and the generalized reactions Wᵀλ too where lambda and reaction are not null.\n"
        "    template <class S>\n"
        "    static void constrained_rates_(S t, const S* x, S* dxdt, S* lambda, S* reaction, const Parameters& p) {\n"
        "        using Matrix = eomc::runtime::ConstraintMatrix<S>;\n"
        "        using Vector = eomc::runtime::ConstraintVector<S>;\n"
        "        Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n_velocities, n_velocities),\n"
        "            W(n_constraints, n_velocities);\n"
        "        Vector f(n_velocities), r(n_constraints), udot, multipliers;\n"
        "        mass_forcing_and_constraints_(t, x, M.data(), f.data(), W.data(), r.data(), p);\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        eomc::runtime::schur_solve<S>(Matrix(M), f, Matrix(W), r, udot, multipliers);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[k];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_constraints; ++a) lambda[a] = multipliers[a];\n"
        "        if (reaction) {\n"
        "            const Vector generalized = W.transpose() * multipliers;\n"
        "            for (int k = 0; k < n_velocities; ++k) reaction[k] = generalized[k];\n"
        "        }\n"
        "    }\n"),
        indent(function_body(ir, names, ir.constraint_residuals, residuals), 8),
        indent(function_body(ir, names, ir.constraint_jacobian, indexed("out_W", m * nu)), 8));
    r.table = table_row("mass_matrix + forcing + rows", ir.mass_forcing_and_constraints) +
              table_row("explicit rates", ir.explicit_rates) +
              (straight ? table_row("saddle-point solve", ir.solved_constraints) : std::string()) +
              table_row("constraint residuals", ir.constraint_residuals) +
              table_row("constraint jacobian", ir.constraint_jacobian);
    if (straight && !ir.position_correction.outputs.empty())
        r.table += table_row("position correction", ir.position_correction);
    if (straight && !ir.velocity_correction.outputs.empty())
        r.table += table_row("velocity correction", ir.velocity_correction);
    return r;
}

std::string constraints_part(const KernelIR& ir) {
    if (ir.constraint_names.empty()) return "";
    const std::size_t m = ir.constraint_names.size();
    std::string holonomic, projected;
    bool projects = false;
    for (std::size_t a = 0; a < m; ++a) {
        holonomic += fmt::format("{}{}", a ? ", " : "", ir.constraint_holonomic[a] ? "true" : "false");
        projected += fmt::format("{}{}", a ? ", " : "", ir.constraint_projected[a] ? "true" : "false");
        projects = projects || ir.constraint_projected[a];
    }
    std::string out = fmt::format(
        "\n    // Bilateral constraint rows: M u̇ − Wᵀλ = f, W u̇ = −bias − stabilisation; λ is output as\n"
        "    // lambda_<row>, the generalized reactions Wᵀλ as reaction_<coordinate>.\n"
        "    static constexpr int n_constraints = {};\n"
        "    static constexpr std::array<const char*, n_constraints> constraint_names{{ {} }};\n"
        "    // Holonomic rows f(q, t) = 0; the others are kinematic, φ(q, u, t) = 0.\n"
        "    static constexpr std::array<bool, n_constraints> constraint_holonomic{{ {} }};\n"
        "    // Rows that project() puts back on the manifold after every accepted step.\n"
        "    static constexpr std::array<bool, n_constraints> constraint_projected{{ {} }};\n\n"
        "    // One residual per row: f (holonomic) or φ (kinematic).\n"
        "    template <class S>\n"
        "    static void constraint_residuals(S t, const S* x, S* out, const Parameters& p) {{\n"
        "        std::array<S, n_constraints> phi;\n"
        "        constraint_residuals_(t, x, out, phi.data(), p);\n"
        "    }}\n",
        m, quoted_list(ir.constraint_names, "a constraint name"), holonomic, projected);
    if (!projects && ir.unit_quaternions.empty() && ir.unit_vectors.empty()) return out;
    std::string body;
    if (!ir.unit_quaternions.empty() || !ir.unit_vectors.empty())
        body += "        using std::sqrt;\n" + unit_renormalisation(ir);
    if (projects && straight_line_constraints(ir)) {
        const auto correction = [](const Block& block, const char* name) {
            return block.outputs.empty() ? std::string("[](S, const S*, S*) {}")
                                         : fmt::format("[&p](S tau, const S* y, S* C) {{ {}(tau, y, C, p); }}", name);
        };
        body += fmt::format(
            "        eomc::runtime::project_by_corrections(\n"
            "            t, x, eomc::runtime::ConstraintLayout{{n_coordinates, velocity_offset, n_velocities, n_constraints}},\n"
            "            constraint_projected.data(), constraint_holonomic.data(),\n"
            "            [&p](S tau, const S* y, S* f, S* phi) {{ constraint_residuals_(tau, y, f, phi, p); }},\n"
            "            {},\n"
            "            {});\n",
            correction(ir.position_correction, "position_correction_"),
            ir.velocity_correction.outputs.empty() ? correction(ir.position_correction, "position_correction_")
                                                   : correction(ir.velocity_correction, "velocity_correction_"));
    } else if (projects)
        body +=
            "        eomc::runtime::project_onto_constraints(\n"
            "            t, x, eomc::runtime::ConstraintLayout{n_coordinates, velocity_offset, n_velocities, n_constraints},\n"
            "            constraint_projected.data(), constraint_holonomic.data(),\n"
            "            [&p](S tau, const S* y, S* f, S* phi) { constraint_residuals_(tau, y, f, phi, p); },\n"
            "            [&p](S tau, const S* y, S* W) { constraint_jacobian_(tau, y, W, p); },\n"
            "            [&p](S tau, const S* y, S* M) { mass_matrix(tau, y, M, p); });\n";
    else
        body = "        (void)t;\n        (void)p;\n" + body;
    out += "\n    // After every accepted step (the runtime calls it): the M-metric projection onto the projected\n"
           "    // rows, positions then velocities (Hairer, Lubich, Wanner, Geometric Numerical Integration,\n"
           "    // 2nd ed., IV.4, Algorithm 4.2).\n"
           "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
           body + "    }\n";
    return out;
}

}  // namespace eomc::codegen
