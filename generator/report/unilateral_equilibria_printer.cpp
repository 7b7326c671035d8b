#include "report/unilateral_equilibria_printer.hpp"

#include <fmt/format.h>

#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using symbolic::latex;
using symbolic::latex_escape;
using symbolic::text;
namespace u = mechanics::unilateral;

namespace {

std::string active_list(const u::UnilateralEquilibria& found, const u::KktPoint& p, const std::string& none) {
    std::string out;
    for (std::size_t a = 0; a < p.active.size(); ++a)
        if (p.active[a]) out += (out.empty() ? "" : ", ") + found.rows[a];
    return out.empty() ? none : out;
}

// ---- JSON ---------------------------------------------------------------------------------

std::string point_json(const model::Model& model, const u::UnilateralEquilibria& found, const u::KktPoint& p) {
    std::string out = "\"q\": {";
    for (std::size_t k = 0; k < p.q.size(); ++k)
        out += fmt::format("{}{}: {:.17g}", k ? ", " : "", json_string(model.coordinates[k].name), p.q[k]);
    out += "}, \"free\": [";
    for (std::size_t k = 0, listed = 0; k < p.free.size(); ++k)
        if (p.free[k]) out += (listed++ ? ", " : "") + json_string(model.coordinates[k].name);
    out += "], \"active\": [";
    for (std::size_t a = 0, listed = 0; a < p.active.size(); ++a)
        if (p.active[a]) out += (listed++ ? ", " : "") + json_string(found.rows[a]);
    out += "], \"lambda\": {";
    for (std::size_t a = 0; a < p.lambda.size(); ++a)
        out += fmt::format("{}{}: {:.17g}", a ? ", " : "", json_string(found.rows[a]), p.lambda[a]);
    out += "}, \"gaps\": {";
    for (std::size_t a = 0; a < p.gap.size(); ++a)
        out += fmt::format("{}{}: {:.17g}", a ? ", " : "", json_string(found.rows[a]), p.gap[a]);
    // The closed forms, in GiNaC syntax, when the point was solved symbolically.
    out += "}, \"exact\": ";
    if (p.exact_q.empty()) return out + "null";
    out += "{\"q\": {";
    for (std::size_t k = 0, listed = 0; k < p.exact_q.size(); ++k)
        if (!p.free[k]) out += (listed++ ? ", " : "") + json_string(model.coordinates[k].name) + ": " + json_string(text(p.exact_q[k]));
    out += "}, \"lambda\": {";
    for (std::size_t a = 0; a < p.exact_lambda.size(); ++a)
        out += (a ? ", " : "") + json_string(found.rows[a]) + ": " + json_string(text(p.exact_lambda[a]));
    return out + "}}";
}

void print_json(const model::Model& model, const u::UnilateralEquilibria& found, std::ostream& out) {
    out << "{\"unilateral\": true, \"rows\": {";
    for (std::size_t a = 0; a < found.rows.size(); ++a)
        out << (a ? ", " : "") << json_string(found.rows[a]) << ": " << json_string(text(found.gaps[a]));
    out << "},\n \"potential\": " << (found.potential ? json_string(text(*found.potential)) : "null")
        << ",\n \"closed_form_complete\": " << (found.closed_form_complete ? "true" : "false") << ",\n \"equilibria\": [";
    for (std::size_t i = 0; i < found.equilibria.size(); ++i) {
        const auto& e = found.equilibria[i];
        out << (i ? ",\n  {" : "\n  {") << point_json(model, found, e.point) << ", \"kind\": " << json_string(u::name(e.kind))
            << ", \"verdict\": " << json_string(e.verdict) << ", \"reason\": " << json_string(e.reason) << ", \"curvature\": [";
        for (std::size_t k = 0; k < e.curvature.size(); ++k) out << (k ? ", " : "") << fmt::format("{:.17g}", e.curvature[k]);
        out << "]}";
    }
    out << (found.equilibria.empty() ? "]" : "\n ]") << ",\n \"rejected\": [";
    for (std::size_t i = 0; i < found.rejected.size(); ++i)
        out << (i ? ",\n  {" : "\n  {") << point_json(model, found, found.rejected[i].point)
            << ", \"reason\": " << json_string(found.rejected[i].reason) << "}";
    out << (found.rejected.empty() ? "]}\n" : "\n ]}\n");
}

// ---- Text ---------------------------------------------------------------------------------

void print_point_text(const model::Model& model, const u::UnilateralEquilibria& found, const u::KktPoint& p,
                      std::ostream& out) {
    out << "\n ";
    for (std::size_t k = 0; k < p.q.size(); ++k)
        out << (p.free[k] ? fmt::format(" {} = any", model.coordinates[k].name)
                          : fmt::format(" {} = {:.12g}", model.coordinates[k].name, p.q[k]));
    out << "   (active: " << active_list(found, p, "none") << ")";
    for (std::size_t k = 0, listed = 0; k < p.exact_q.size(); ++k)
        if (!p.free[k])
            out << fmt::format("{}{} = {}", listed++ ? ", " : "\n    closed form: ", model.coordinates[k].name, text(p.exact_q[k]));
    for (std::size_t a = 0; a < p.lambda.size(); ++a) {
        out << fmt::format("\n    λ_{} = {:.12g}", found.rows[a], p.lambda[a]);
        if (!p.exact_lambda.empty() && p.active[a]) out << " = " << text(p.exact_lambda[a]);
        out << fmt::format(",  f_{} = {:.12g}", found.rows[a], p.gap[a]);
    }
}

void print_text(const model::Model& model, const u::UnilateralEquilibria& found, std::ostream& out) {
    out << "equilibria of " << model.name
        << " with unilateral gaps (Mei §6.4; q̇ = 0, parameters at their defaults):\n"
           "  ∂V/∂q = Σ λ_α ∂f_α/∂q,  λ_α ≥ 0,  f_α ≥ 0,  λ_α f_α = 0  (Karush–Kuhn–Tucker)\n";
    if (found.potential) out << "  V = " << text(*found.potential) << "\n";
    for (std::size_t a = 0; a < found.rows.size(); ++a)
        out << "  f_" << found.rows[a] << " = " << text(found.gaps[a]) << " ≥ 0\n";
    if (!found.closed_form_complete)
        out << "  (some active sets were not solved in closed form or have a continuum of solutions: those are "
               "Newton's roots from a grid of starts)\n";
    out << fmt::format("\n{} equilibri{}:\n", found.equilibria.size(), found.equilibria.size() == 1 ? "um" : "a");
    for (const auto& e : found.equilibria) {
        print_point_text(model, found, e.point, out);
        out << "\n    " << u::name(e.kind) << ", " << e.verdict << ": " << e.reason;
        if (!e.curvature.empty()) {
            out << "\n    curvature";
            for (double c : e.curvature) out << fmt::format(" {:.9g}", c);
        }
        out << "\n";
    }
    if (found.rejected.empty()) return;
    out << fmt::format("\n{} solution{} of an active set's equations rejected:\n", found.rejected.size(),
                       found.rejected.size() == 1 ? "" : "s");
    for (const auto& r : found.rejected) {
        print_point_text(model, found, r.point, out);
        out << "\n    rejected: " << r.reason << "\n";
    }
}

// ---- LaTeX --------------------------------------------------------------------------------

void print_latex(const model::Model& model, const u::UnilateralEquilibria& found, std::ostream& out) {
    out << "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage{amsmath}\n"
        << "\\allowdisplaybreaks\n\\begin{document}\n\\section*{Equilibria with unilateral constraints: "
        << latex_escape(model.name) << "}\n"
        << "At rest ($\\dot q = 0$, parameters at their defaults) a state is an equilibrium when the "
           "Karush--Kuhn--Tucker conditions hold (Mei, \\S6.4):\n"
        << "\\[ \\frac{\\partial V}{\\partial q_s} = \\sum_\\alpha \\lambda_\\alpha \\frac{\\partial f_\\alpha}{\\partial q_s},"
           "\\quad \\lambda_\\alpha \\ge 0,\\quad f_\\alpha \\ge 0,\\quad \\lambda_\\alpha f_\\alpha = 0, \\]\n"
        << "with\n\\begin{align*}\n";
    if (found.potential) out << "V &= " << latex(*found.potential) << "\\\\\n";
    for (std::size_t a = 0; a < found.rows.size(); ++a)
        out << "f_{\\mathrm{" << latex_escape(found.rows[a]) << "}} &= " << latex(found.gaps[a]) << " \\ge 0"
            << (a + 1 < found.rows.size() ? "\\\\\n" : "\n");
    out << "\\end{align*}\n";
    out << "\\subsection*{" << found.equilibria.size() << " equilibri" << (found.equilibria.size() == 1 ? "um" : "a")
        << "}\n\\begin{enumerate}\n";
    auto point = [&](const u::KktPoint& p) {
        out << "\\item $";
        for (std::size_t k = 0; k < p.q.size(); ++k)
            out << (k ? ",\\ " : "") << latex_escape(model.coordinates[k].name) << " = "
                << (p.free[k] ? std::string("\\text{any}") : fmt::format("{:.12g}", p.q[k]));
        out << "$ (active: " << latex_escape(active_list(found, p, "none")) << ")";
        if (!p.exact_q.empty()) {
            out << "\\\\ closed form: $";
            for (std::size_t k = 0, listed = 0; k < p.exact_q.size(); ++k)
                if (!p.free[k]) out << (listed++ ? ",\\ " : "") << latex_escape(model.coordinates[k].name) << " = " << latex(p.exact_q[k]);
            out << "$";
        }
        for (std::size_t a = 0; a < p.lambda.size(); ++a) {
            out << "\\\\ $\\lambda_{\\mathrm{" << latex_escape(found.rows[a]) << "}} = " << fmt::format("{:.12g}", p.lambda[a]);
            if (!p.exact_lambda.empty() && p.active[a]) out << " = " << latex(p.exact_lambda[a]);
            out << "$, $f_{\\mathrm{" << latex_escape(found.rows[a]) << "}} = " << fmt::format("{:.12g}", p.gap[a]) << "$";
        }
    };
    for (const auto& e : found.equilibria) {
        point(e.point);
        out << "\\\\ " << u::name(e.kind) << ", \\emph{" << e.verdict << "}: " << latex_escape(e.reason) << "\n";
    }
    if (found.equilibria.empty()) out << "\\item[] none\n";
    out << "\\end{enumerate}\n";
    if (!found.rejected.empty()) {
        out << "\\subsection*{Rejected}\n\\begin{enumerate}\n";
        for (const auto& r : found.rejected) {
            point(r.point);
            out << "\\\\ " << latex_escape(r.reason) << "\n";
        }
        out << "\\end{enumerate}\n";
    }
    out << "\\end{document}\n";
}

}  // namespace

void print_unilateral_equilibria(const model::Model& model, const u::UnilateralEquilibria& found,
                                 DerivationFormat format, std::ostream& out) {
    switch (format) {
    case DerivationFormat::json: print_json(model, found, out); break;
    case DerivationFormat::latex: print_latex(model, found, out); break;
    case DerivationFormat::text: print_text(model, found, out); break;
    }
}

}  // namespace eomc::report
