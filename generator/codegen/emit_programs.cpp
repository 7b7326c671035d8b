// Programs realised by controls (Mei ch. 3): rhs() through M u̇ = f + D λ, Ā u̇ = c, reduced in
// straight-line code or solved on Eigen, and the programs' names, laws and residuals.
#include <string>
#include <vector>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

bool straight_line_programs(const KernelIR& ir) { return !ir.reduced_programs.outputs.empty(); }

namespace {

// The straight-line path of emit_controlled_rates: M's solve and Ā M⁻¹ in generated code, the m × m
// G λ = h by runtime/program/reduced_control.hpp, with no Eigen.
Rates emit_reduced_controlled_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t m = ir.program_names.size();
    Rates r;
    r.includes = "#include <eomc/runtime/constraint_projection.hpp>\n#include <eomc/runtime/program/reduced_control.hpp>\n";
    r.rhs = "controlled_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = differenced_jacobian("the control solve");
    r.private_part = fmt::format(
        "\n private:\n"
        "    using ReducedLayout_ = eomc::runtime::program::ReducedLayout<n_velocities, n_programs>;\n\n"
        "    // z = M⁻¹f, Y = M⁻¹D, G = Ā Y, h = c − Ā z and D (row-major, ReducedLayout_): M's solve and\n"
        "    // Ā M⁻¹ in straight-line code; G λ = h is left to a pivoted LU at run time.\n"
        "    template <class S>\n"
        "    static void reduced_programs_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // ẋ from M u̇ = f + D λ, Ā u̇ = c; λ and Q_c = D λ too where lambda and control are not null.\n"
        "    template <class S>\n"
        "    static void controlled_rates_(S t, const S* x, S* dxdt, S* lambda, S* control, const Parameters& p) {{\n"
        "        std::array<S, ReducedLayout_::size> reduced;\n"
        "        std::array<S, n_velocities> udot, generalized;\n"
        "        std::array<S, n_programs> multipliers;\n"
        "        reduced_programs_(t, x, reduced.data(), p);\n"
        "        eomc::runtime::program::reduced_control_solve<n_velocities, n_programs>(reduced.data(), udot.data(),\n"
        "                                                                              multipliers.data(), generalized.data());\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[std::size_t(k)];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_programs; ++a) lambda[a] = multipliers[std::size_t(a)];\n"
        "        if (control)\n"
        "            for (int k = 0; k < n_velocities; ++k) control[k] = generalized[std::size_t(k)];\n"
        "    }}\n\n"
        "    // det(Ā M⁻¹ D): where it vanishes no control in these directions realises the programs.\n"
        "    template <class S>\n"
        "    static S control_determinant_(S t, const S* x, const Parameters& p) {{\n"
        "        std::array<S, ReducedLayout_::size> reduced;\n"
        "        reduced_programs_(t, x, reduced.data(), p);\n"
        "        return eomc::runtime::program::reduced_control_determinant<n_velocities, n_programs>(reduced.data());\n"
        "    }}\n\n"
        "    template <class S>\n"
        "    static void program_residuals_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.reduced_programs, indexed("out", ir.reduced_programs.outputs.size())), 8),
        indent(explicit_rates_body(ir, names), 8),
        indent(function_body(ir, names, ir.program_residuals, indexed("out", 2 * m)), 8));
    r.table = table_row("programs, reduced", ir.reduced_programs) +
              table_row("explicit rates", ir.explicit_rates) + table_row("program residuals", ir.program_residuals);
    return r;
}

}  // namespace

Rates emit_controlled_rates(const KernelIR& ir, const LocalNames& names) {
    if (straight_line_programs(ir)) return emit_reduced_controlled_rates(ir, names);
    const std::size_t nu = ir.n_velocities, m = ir.program_names.size(), k = ir.program_columns.size();
    Rates r;
    r.includes = "#include <Eigen/Core>\n#include <eomc/runtime/constraints.hpp>\n#include <eomc/runtime/program/control.hpp>\n";
    r.rhs = "controlled_rates_(t, x, dxdt, static_cast<S*>(nullptr), static_cast<S*>(nullptr), p);";
    r.jacobian = differenced_jacobian("the control solve");
    const std::vector<std::string> targets =
        indexed_arrays({{"out_M", nu * nu}, {"out_f", nu}, {"out_A", m * nu}, {"out_c", m}, {"out_D", nu * k}});
    const std::string solve =
        ir.program_redundant ? "eomc::runtime::program::udwadia_kalaba_solve<S>(M, f, A, c, udot, multipliers, generalized);\n"
                             : "eomc::runtime::program::control_solve<S>(M, f, A, D, c, udot, multipliers, generalized);\n";
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M, f, the programs' Ā (m × n_velocities) and c, and the control directions D (n_velocities × k),\n"
        "    // all row-major, together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_forcing_and_programs_(S t, const S* x, S* out_M, S* out_f, S* out_A, S* out_c, S* out_D,\n"
        "                                           const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    template <class S>\n"
        "    struct ControlMatrices_ {{\n"
        "        eomc::runtime::program::Matrix<S> M, A, D;\n"
        "        eomc::runtime::program::Vector<S> f, c;\n"
        "    }};\n\n"
        "    template <class S>\n"
        "    static ControlMatrices_<S> control_matrices_(S t, const S* x, const Parameters& p) {{\n"
        "        using RowMajor = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;\n"
        "        RowMajor M(n_velocities, n_velocities), A(n_programs, n_velocities), D(n_velocities, n_program_controls);\n"
        "        eomc::runtime::program::Vector<S> f(n_velocities), c(n_programs);\n"
        "        mass_forcing_and_programs_(t, x, M.data(), f.data(), A.data(), c.data(), D.data(), p);\n"
        "        return {{M, A, D, f, c}};\n"
        "    }}\n\n"
        "    // ẋ from M u̇ = f + D λ, Ā u̇ = c; λ and Q_c = D λ too where lambda and control are not null.\n"
        "    template <class S>\n"
        "    static void controlled_rates_(S t, const S* x, S* dxdt, S* lambda, S* control, const Parameters& p) {{\n"
        "        const auto [M, A, D, f, c] = control_matrices_(t, x, p);\n"
        "        (void)D;\n"
        "        eomc::runtime::program::Vector<S> udot, multipliers, generalized;\n"
        "        explicit_rates_(t, x, dxdt, p);\n"
        "        {}"
        "        for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = udot[k];\n"
        "        if (lambda)\n"
        "            for (int a = 0; a < n_program_controls; ++a) lambda[a] = multipliers[a];\n"
        "        if (control)\n"
        "            for (int k = 0; k < n_velocities; ++k) control[k] = generalized[k];\n"
        "    }}\n\n"
        "    // det(Ā M⁻¹ D): where it vanishes no control in these directions realises the programs.\n"
        "    template <class S>\n"
        "    static S control_determinant_(S t, const S* x, const Parameters& p) {{\n"
        "        const auto [M, A, D, f, c] = control_matrices_(t, x, p);\n"
        "        (void)f;\n"
        "        (void)c;\n"
        "        return eomc::runtime::program::control_determinant<S>(M, A, D);\n"
        "    }}\n\n"
        "    template <class S>\n"
        "    static void program_residuals_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_forcing_and_programs, targets), 8),
        indent(explicit_rates_body(ir, names), 8),
        solve, indent(function_body(ir, names, ir.program_residuals, indexed("out", 2 * m)), 8));
    r.table = table_row("mass_matrix + forcing + programs", ir.mass_forcing_and_programs) +
              table_row("explicit rates", ir.explicit_rates) + table_row("program residuals", ir.program_residuals);
    return r;
}

std::string programs_part(const KernelIR& ir) {
    if (ir.program_names.empty()) return "";
    return fmt::format(
        "\n    // Programs realised by controls (Mei ch. 3): M u̇ = f + D λ, Ā u̇ = c. Laws: configuration (1) or\n"
        "    // phase (0), then α, β (ω̈ + 2αω̇ + β²ω = 0) and κ (φ̇ + κφ = 0); all 0 for the open loop.\n"
        "    static constexpr int n_programs = {};\n"
        "    static constexpr int n_program_controls = {};\n"
        "    static constexpr std::array<const char*, n_programs> program_names{{ {} }};\n"
        "    static constexpr std::array<double, 4 * n_programs> program_laws{{ {} }};\n\n"
        "    // ω and ω̇ (configuration programs) or φ and 0, two per program.\n"
        "    template <class S>\n"
        "    static void program_residuals(S t, const S* x, S* out, const Parameters& p) {{\n"
        "        program_residuals_(t, x, out, p);\n"
        "    }}\n",
        ir.program_names.size(), ir.program_columns.size(), quoted_list(ir.program_names, "a program name"),
        number_list(ir.program_laws, "a program's gain"));
}

}  // namespace eomc::codegen
