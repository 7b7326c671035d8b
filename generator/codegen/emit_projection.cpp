// project() of kernels without constraint rows, which the runtime calls after every accepted step:
// unit quaternions and vectors renormalised, or Encke's rectification.
#include <string>

#include <fmt/format.h>

#include "codegen/kernel_parts.hpp"

namespace eomc::codegen {

std::string unit_renormalisation(const KernelIR& ir) {
    std::string body;
    for (std::size_t k : ir.unit_quaternions) {
        body += fmt::format("        {{\n            const S norm = sqrt(x[{0}] * x[{0}] + x[{1}] * x[{1}] + x[{2}] * x[{2}] + "
                            "x[{3}] * x[{3}]);\n",
                            k, k + 1, k + 2, k + 3);
        body += fmt::format("            for (int i = {}; i < {}; ++i) x[i] /= norm;\n        }}\n", k, k + 4);
    }
    for (std::size_t k : ir.unit_vectors) {
        body += fmt::format("        {{\n            const S norm = sqrt(x[{0}] * x[{0}] + x[{1}] * x[{1}] + x[{2}] * x[{2}]);\n",
                            k, k + 1, k + 2);
        body += fmt::format("            for (int i = {}; i < {}; ++i) x[i] /= norm;\n        }}\n", k, k + 3);
    }
    return body;
}

std::string unit_projection(const KernelIR& ir) {
    if (ir.unit_quaternions.empty() && ir.unit_vectors.empty()) return "";
    const std::string body = "        (void)t;\n        (void)p;\n        using std::sqrt;\n" + unit_renormalisation(ir);
    if (ir.unit_quaternions.empty())
        return "\n    // Puts Poisson's vertical back on |γ| = 1, a Casimir of the equations that integration keeps only\n"
               "    // to its error (the runtime calls it after every accepted step; Hairer, Lubich, Wanner,\n"
               "    // Geometric Numerical Integration, 2nd ed., IV.4, standard projection).\n"
               "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
               body + "    }\n";
    return "\n    // Puts the attitude quaternion back on |e| = 1 (the runtime calls it after every accepted\n"
           "    // step). R(e)/|e|² is orthogonal for any |e|, so this only keeps e well scaled.\n"
           "    template <class S>\n    static void project(S t, S* x, const Parameters& p) {\n" +
           body + "    }\n";
}

Rectification rectification(const KernelIR& ir, const LocalNames& names) {
    const RectificationIR& r = *ir.rectification;
    Rectification out;
    out.project = fmt::format(
        "\n    // Encke's rectification (Battin §9.3; runtime/orbit/encke.hpp), which the runtime calls after\n"
        "    // every accepted step: once |δ| > rectification_ratio |ρ| the reference becomes the osculating\n"
        "    // ellipse of the total state at t, and δ is re-expressed in it.\n"
        "    static constexpr double rectification_ratio = {ratio};\n\n"
        "    template <class S>\n"
        "    static void project(S t, S* x, const Parameters& p) {{\n"
        "        const auto reference = [&p](S tau, const S* y, S* out) {{ reference_orbit_(tau, y, out, p); }};\n"
        "        eomc::runtime::encke_rectify(t, x, eomc::runtime::EnckeLayout{{{deviation}, {elements}, {count}}},\n"
        "                                     rectification_ratio, reference);\n"
        "    }}\n",
        fmt::arg("ratio", fmt::format("{}", r.ratio)), fmt::arg("deviation", r.deviation),
        fmt::arg("elements", r.elements), fmt::arg("count", r.count));
    out.private_part = fmt::format(
        "    // The reference orbit at t: ρ, ρ̇ from the reference elements in the state, then μ.\n"
        "    template <class S>\n"
        "    static void reference_orbit_(S t, const S* x, S* out, const Parameters& p) {{\n{}\n    }}\n",
        indent(block_body(ir, names, r.reference, "out"), 8));
    return out;
}

}  // namespace eomc::codegen
