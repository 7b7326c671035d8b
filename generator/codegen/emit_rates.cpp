// rhs() and jacobian() through M u̇ = f (kernel_parts.hpp's emit_rates): u̇ in closed form, solved
// in straight-line code (codegen/solve_plan.hpp), or by Eigen's LLT past the unrolled sizes; kernels
// with rows go to emit_constraints.cpp and emit_programs.cpp.
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

std::pair<std::vector<std::string>, std::vector<std::string>> explicit_rate_targets(const KernelIR& ir) {
    const std::size_t N = ir.state.size();
    std::vector<std::string> rates, rate_rows;
    for (std::size_t i : ir.explicit_index) {
        rates.push_back(fmt::format("dxdt[{}]", i));
        for (std::size_t j = 0; j < N; ++j) rate_rows.push_back(fmt::format("out[{}]", i * N + j));
    }
    return {rates, rate_rows};
}

std::string explicit_rates_body(const KernelIR& ir, const LocalNames& names) {
    const std::vector<std::string> rates = explicit_rate_targets(ir).first;
    return (rates.empty() ? "(void)dxdt;\n" : std::string()) + function_body(ir, names, ir.explicit_rates, rates);
}

std::string differenced_jacobian(std::string_view through) {
    return fmt::format("// The rates go through {}: differenced, not derived.\n"
                       "eomc::runtime::central_difference_jacobian(t, x, out, n_state,\n"
                       "                                           [&p](S tau, const S* y, S* dydt) {{ rhs(tau, y, dydt, p); }});",
                       through);
}

namespace {

// rhs() and jacobian() with M u̇ = f solved in straight-line code (codegen/solve_plan.hpp): M, f
// and the solve in one function, with no Eigen and no arrays for M.
Rates emit_straight_line_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;
    Rates r;
    r.rhs = "explicit_rates_(t, x, dxdt, p);\n"
            "velocity_rates_(t, x, dxdt + velocity_offset, p);";
    r.jacobian = "std::array<S, n_velocities> acc;\n"
                 "velocity_rates_(t, x, acc.data(), p);\n"
                 "explicit_rates_jacobian_(t, x, out, p);\n"
                 "// d(M⁻¹f)/dx = M⁻¹ (∂f/∂x − (∂M/∂x) u̇): the velocity block's rows\n"
                 "velocity_jacobian_(t, x, acc.data(), out + velocity_offset * n_state, p);";
    r.table = table_row("mass_matrix + forcing", ir.mass_and_forcing) + table_row("explicit rates", ir.explicit_rates) +
              table_row("M u̇ = f solved", ir.solved_rates) +
              table_row("mass_matrix + jacobian terms", ir.mass_and_jacobian_terms) +
              table_row("M⁻¹ (jacobian terms)", ir.solved_jacobian_terms) +
              table_row("explicit rates jacobian", ir.explicit_rates_jacobian);
    const auto [rates, rate_rows] = explicit_rate_targets(ir);
    const SplitBody velocity_jacobian =
        split_function(ir, names, ir.solved_jacobian_terms, indexed("out", nu * N), {true}, "velocity_jacobian_",
                       "S t, const S* x, const S* acc, S* out, const Parameters& p", "t, x, acc, out, p", {"out"});
    r.private_part = fmt::format(
        "\n private:\n"
        "    // u̇ = M⁻¹f to out[0 .. n_velocities): M and f together (they share most of their\n"
        "    // subexpressions), then the solve the banner names.\n"
        "    template <class S>\n"
        "    static void velocity_rates_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // M⁻¹G, G = ∂f/∂x − (∂M/∂x) u̇ with u̇ = acc, row-major n_velocities × n_state.\n"
        "    template <class S>\n"
        "    static void velocity_jacobian_(S t, const S* x, const S* acc, S* out, const Parameters& p) {{\n{}\n    }}\n{}\n"
        "    // The rows of ∂ẋ/∂x of the closed-form rates.\n"
        "    template <class S>\n"
        "    static void explicit_rates_jacobian_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.solved_rates, indexed("out", nu)), 8),
        indent(function_body(ir, names, ir.explicit_rates, rates), 8),
        indent(velocity_jacobian.body, 8), velocity_jacobian.parts,
        indent(function_body(ir, names, ir.explicit_rates_jacobian, rate_rows), 8));
    return r;
}

}  // namespace

Rates emit_rates(const KernelIR& ir, const LocalNames& names) {
    const std::size_t N = ir.state.size(), nu = ir.n_velocities;
    Rates r;
    if (!ir.constraint_names.empty()) return emit_constrained_rates(ir, names);
    if (!ir.program_names.empty()) return emit_controlled_rates(ir, names);
    if (ir.explicit_solution) {
        r.rhs = function_body(ir, names, ir.rhs_explicit, indexed("dxdt", N));
        if (ir.has_jacobian) r.jacobian = function_body(ir, names, ir.jacobian_explicit, indexed("out", N * N));
        r.table = table_row("rhs (u̇ in closed form)", ir.rhs_explicit) +
                  (ir.has_jacobian ? table_row("jacobian", ir.jacobian_explicit) : std::string());
        return r;
    }
    if (ir.solve_plan.method != SolvePlan::Method::eigen_llt) return emit_straight_line_rates(ir, names);
    // Past unrolled_limit velocities in one block: Eigen's LLT (M is symmetric positive definite).
    r.includes = "#include <limits>\n#include <Eigen/Core>\n#include <Eigen/Cholesky>\n";  // not Dense: twice the compile time
    // Fixed sizes keep small kernels off the heap; past 4096 entries in G a scalar of 16
    // bytes (float128) would near Eigen's 128 KiB limit on fixed-size objects, which is a
    // static assertion, so large systems use dynamic sizes.
    const bool fixed = nu * N <= 4096;
    const std::string square = fixed ? "Eigen::Matrix<S, n_velocities, n_velocities, Eigen::RowMajor> M;\n"
                                     : "Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M(n_velocities, n_velocities);\n";
    const std::string column = fixed ? "Eigen::Matrix<S, n_velocities, 1> f;\n"
                                     : "Eigen::Matrix<S, Eigen::Dynamic, 1> f(n_velocities);\n";
    const std::string vector_type = fixed ? "Eigen::Matrix<S, n_velocities, 1>" : "Eigen::Matrix<S, Eigen::Dynamic, 1>";
    const std::string wide_type = fixed ? "Eigen::Matrix<S, n_velocities, n_state, Eigen::RowMajor>"
                                        : "Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>";
    const std::string wide_size = fixed ? "" : "(n_velocities, n_state)";
    // A failed factorization (M not positive definite: singular where the coordinates fail) gives
    // NaN, which the runtime's checker stops on, never a finite guess.
    const std::string not_definite = "if (llt.info() != Eigen::Success) {\n"
                                     "    for (int k = 0; k < n_velocities; ++k) dxdt[velocity_offset + k] = std::numeric_limits<S>::quiet_NaN();\n"
                                     "    return;\n"
                                     "}\n";
    r.rhs = square + column +
            "mass_matrix_and_forcing_(t, x, M.data(), f.data(), p);\n"
            "explicit_rates_(t, x, dxdt, p);\n"
            "const auto llt = M.llt();\n" + not_definite +
            "Eigen::Map<" + vector_type + ">(dxdt + velocity_offset" + (fixed ? "" : ", n_velocities") + ") = llt.solve(f);";
    r.jacobian = square + column +
                 "mass_matrix_and_forcing_(t, x, M.data(), f.data(), p);\n"
                 "const auto llt = M.llt();\n"
                 "if (llt.info() != Eigen::Success) {\n"
                 "    for (int k = 0; k < n_state * n_state; ++k) out[k] = std::numeric_limits<S>::quiet_NaN();\n"
                 "    return;\n"
                 "}\n"
                 "const " + vector_type + " acc = llt.solve(f);\n" +
                 wide_type + " G" + wide_size + ";\n"
                 "mass_matrix_and_jacobian_terms_(t, x, acc.data(), M.data(), G.data(), p);\n"
                 "explicit_rates_jacobian_(t, x, out, p);\n"
                 "// d(M⁻¹f)/dx = M⁻¹ (∂f/∂x − (∂M/∂x) u̇)\n"
                 "const " + wide_type + " lower = llt.solve(G);\n"
                 "for (int i = 0; i < n_velocities; ++i)\n"
                 "    for (int j = 0; j < n_state; ++j) out[(velocity_offset + i) * n_state + j] = lower(i, j);";
    r.table = table_row("mass_matrix + forcing", ir.mass_and_forcing) + table_row("explicit rates", ir.explicit_rates);
    if (ir.has_jacobian)
        r.table += table_row("mass_matrix + jacobian terms", ir.mass_and_jacobian_terms) +
                   table_row("explicit rates jacobian", ir.explicit_rates_jacobian);
    const std::vector<std::string> mf = indexed_arrays({{"out_M", nu * nu}, {"out_f", nu}});
    const std::vector<std::string> mg = indexed_arrays({{"out_M", nu * nu}, {"out_G", nu * N}});
    const auto [rates, rate_rows] = explicit_rate_targets(ir);
    r.private_part = fmt::format(
        "\n private:\n"
        "    // M and f together: they share most of their subexpressions.\n"
        "    template <class S>\n"
        "    static void mass_matrix_and_forcing_(S t, const S* x, S* out_M, S* out_f, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // The rates given in closed form (everything outside the velocity block).\n"
        "    template <class S>\n"
        "    static void explicit_rates_(S t, const S* x, S* dxdt, const Parameters& p) {{\n{}\n    }}\n",
        indent(function_body(ir, names, ir.mass_and_forcing, mf), 8),
        indent(function_body(ir, names, ir.explicit_rates, rates), 8));
    if (!ir.has_jacobian) return r;
    const SplitBody terms = split_function(ir, names, ir.mass_and_jacobian_terms, mg, {true}, "mass_matrix_and_jacobian_terms_",
                                           "S t, const S* x, const S* acc, S* out_M, S* out_G, const Parameters& p",
                                           "t, x, acc, out_M, out_G, p", {"out_M", "out_G"});
    r.private_part += fmt::format(
        "\n    // M and G = ∂f/∂x − (∂M/∂x) u̇, with u̇ = acc, both row-major.\n"
        "    template <class S>\n"
        "    static void mass_matrix_and_jacobian_terms_(S t, const S* x, const S* acc, S* out_M, S* out_G, const Parameters& p) {{\n{}\n    }}\n{}\n"
        "    // The rows of ∂ẋ/∂x of the closed-form rates.\n"
        "    template <class S>\n"
        "    static void explicit_rates_jacobian_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(terms.body, 8), terms.parts, indent(function_body(ir, names, ir.explicit_rates_jacobian, rate_rows), 8));
    return r;
}

}  // namespace eomc::codegen
