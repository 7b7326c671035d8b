// The rows whose crossings the runtime watches: events (scene [events]) and unilateral constraints
// (Mei, ch. 6) with the bilateral rows the contact drivers keep active.
#include <string>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

namespace {

// A kernel with bilateral and unilateral rows hands the contact drivers its bilateral rows too (the
// contact phase, the impacts and the projection keep them active; runtime/contact/event_driven.hpp).
std::string bilateral_rows_for_contacts() {
    return "\n    // The bilateral rows for the contact drivers: the residuals f (holonomic) or φ (kinematic) to out, φ\n"
           "    // to out_phi, W (n_constraints × n_velocities, row-major) to out_W and r of W u̇ = r to out_r.\n"
           "    template <class S>\n"
           "    static void constraint_rows(S t, const S* x, S* out, S* out_phi, S* out_W, S* out_r, const Parameters& p) {\n"
           "        std::array<S, n_velocities * n_velocities> M;\n"
           "        std::array<S, n_velocities> f;\n"
           "        mass_forcing_and_constraints_(t, x, M.data(), f.data(), out_W, out_r, p);\n"
           "        constraint_residuals_(t, x, out, out_phi, p);\n"
           "    }\n";
}

}  // namespace

std::string contacts_part(const KernelIR& ir, const LocalNames& names) {
    if (ir.contact_names.empty()) return "";
    const std::size_t m = ir.contact_names.size();
    std::string kinematic;
    for (std::size_t a = 0; a < m; ++a) kinematic += fmt::format("{}{}", a ? ", " : "", ir.contact_kinematic[a] ? "true" : "false");
    Inputs parameters_only;
    parameters_only.state_array = false;
    parameters_only.time_argument = false;
    return fmt::format(
        "\n    // Unilateral constraints (Mei, Special Topics in Analytical Mechanics, ch. 6): a gap f(q, t) >= 0\n"
        "    // (an impact when it closes) or a kinematic row phi(q, u, t) >= 0 (§6.7), each with Newton's\n"
        "    // restitution e; on the boundary M u̇ = f + Wᵀλ with λ >= 0, and f̈ (φ̇) = W u̇ + bias.\n"
        "    static constexpr int n_contacts = {};\n"
        "    static constexpr std::array<const char*, n_contacts> contact_names{{ {} }};\n"
        "    // Kinematic (velocity-level) rows: gaps() writes phi for them, and they take no impacts.\n"
        "    static constexpr std::array<bool, n_contacts> contact_kinematic{{ {} }};\n\n"
        "    // Newton's coefficients of restitution, one per row.\n"
        "    template <class S>\n"
        "    static void restitutions(const Parameters& p, S* out) {{\n{}\n    }}\n\n"
        "    // One value per row: f (a gap) or phi (a kinematic row).\n"
        "    template <class S>\n"
        "    static void gaps(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // W, n_contacts × n_velocities row-major: ∂f/∂q (a gap, q̇ = u) or ∂phi/∂u (a kinematic row).\n"
        "    template <class S>\n"
        "    static void contact_jacobian(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n\n"
        "    // bias = f̈ − W u̇ (a gap) or φ̇ − W u̇ (a kinematic row), one per row.\n"
        "    template <class S>\n"
        "    static void contact_bias(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        m, literal_list(ir.contact_names), kinematic,
        indent(block_body(ir, names, ir.restitutions, "out", parameters_only), 8),
        indent(block_body(ir, names, ir.contact_gaps, "out"), 8),
        indent(block_body(ir, names, ir.contact_jacobian, "out"), 8),
        indent(block_body(ir, names, ir.contact_bias, "out"), 8)) +
           (ir.contact_time_rates.outputs.empty()
                ? std::string()
                : fmt::format("\n    // w = ∂f/∂t, one per row: a moving gap's rate is ḟ = W u + w (0 for a kinematic row).\n"
                              "    template <class S>\n"
                              "    static void contact_time_rates(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
                              indent(block_body(ir, names, ir.contact_time_rates, "out"), 8))) +
           (ir.constraint_names.empty() ? std::string() : bilateral_rows_for_contacts());
}

std::string events_part(const KernelIR& ir, const LocalNames& names) {
    if (ir.event_names.empty()) return "";
    std::string directions, terminal;
    for (std::size_t k = 0; k < ir.event_names.size(); ++k) {
        directions += fmt::format("{}{}", k ? ", " : "", ir.event_directions[k]);
        terminal += fmt::format("{}{}", k ? ", " : "", ir.event_terminal[k] ? "true" : "false");
    }
    return fmt::format(
        "\n    // Events (scene [events]): g_i(t, x), whose zero crossings the runtime locates.\n"
        "    static constexpr int n_events = {};\n"
        "    static constexpr std::array<const char*, n_events> event_names{{ {} }};\n"
        "    // +1: upward crossings (g from negative to positive) only, -1: downward only, 0: both.\n"
        "    static constexpr std::array<int, n_events> event_directions{{ {} }};\n"
        "    // A terminal event stops the integration at its time.\n"
        "    static constexpr std::array<bool, n_events> event_terminal{{ {} }};\n\n"
        "    template <class S>\n"
        "    static void events(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        ir.event_names.size(), quoted_list(ir.event_names, "an event name"), directions, terminal,
        indent(block_body(ir, names, ir.events, "out"), 8));
}

}  // namespace eomc::codegen
