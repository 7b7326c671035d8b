#include "report/inverse_printer.hpp"

#include <sstream>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using namespace eomc::symbolic;

namespace inv = mechanics::inverse;
using GiNaC::ex;

namespace {

std::string json_ex(const ex& e) { return json_string(text(e)); }

std::string matrix_text(const GiNaC::matrix& m) {
    std::string out = "[";
    for (unsigned i = 0; i < m.rows(); ++i) {
        out += i ? ", [" : "[";
        for (unsigned j = 0; j < m.cols(); ++j) out += (j ? ", " : "") + text(display_form(m(i, j)));
        out += "]";
    }
    return out + "]";
}

std::string matrix_json(const GiNaC::matrix& m) {
    std::string out = "[";
    for (unsigned i = 0; i < m.rows(); ++i) {
        out += i ? ", [" : "[";
        for (unsigned j = 0; j < m.cols(); ++j) out += (j ? ", " : "") + json_ex(m(i, j));
        out += "]";
    }
    return out + "]";
}

// TeX stops with "Dimension too large" on a formula wider than about 5.7 m (16384 pt): a few
// thousand characters of LaTeX on one line. Longer expressions (leo_drag's Φ under drag: 60 000)
// are named by their size instead; the text and JSON outputs have them in full.
constexpr std::size_t latex_limit = 2000;

std::string elided(const std::string& what, std::size_t length) {
    return fmt::format("\\text{{({} of {} characters of \\LaTeX{{}}: too wide to typeset; see the text or JSON "
                       "output)}}",
                       what, length);
}

std::string ex_latex(const ex& e) {
    const std::string out = latex(display_form(e));
    return out.size() <= latex_limit ? out : elided("an expression", out.size());
}

std::string matrix_latex(const GiNaC::matrix& m) {
    std::string out = "\\begin{pmatrix}";
    for (unsigned i = 0; i < m.rows(); ++i) {
        for (unsigned j = 0; j < m.cols(); ++j) out += (j ? " & " : "") + latex(display_form(m(i, j)));
        out += i + 1 < m.rows() ? " \\\\ " : "";
    }
    out += "\\end{pmatrix}";
    return out.size() <= latex_limit ? out : elided(fmt::format("a {}×{} matrix", m.rows(), m.cols()), out.size());
}

// Prose for LaTeX: the Unicode of the step texts kept (inputenc utf8 handles the letters;
// the few mathematical signs are mapped), underscores and braces escaped.
std::string latex_prose(const std::string& s) {
    std::string out = latex_escape(s);
    const std::pair<const char*, const char*> signs[] = {
        {"−", "$-$"},   {"∂", "$\\partial$"}, {"≠", "$\\neq$"}, {"·", "$\\cdot$"}, {"½", "$\\frac12$"},
        {"∇", "$\\nabla$"}, {"Γ", "$\\Gamma$"}, {"Φ", "$\\Phi$"}, {"q̇", "$\\dot q$"}, {"q̈", "$\\ddot q$"},
        {"ε", "$\\varepsilon$"}, {"—", "---"}, {"–", "--"}, {"²", "$^2$"}, {"⁻¹", "$^{-1}$"}, {"ᵀ", "$^T$"}};
    for (const auto& [from, to] : signs) {
        for (std::size_t at = out.find(from); at != std::string::npos; at = out.find(from, at + std::string(to).size()))
            out.replace(at, std::string(from).size(), to);
    }
    return out;
}

const char* verdict_name(inv::Verdict v) {
    switch (v) {
        case inv::Verdict::self_adjoint: return "self-adjoint";
        case inv::Verdict::not_self_adjoint: return "not self-adjoint";
        case inv::Verdict::undecided: return "undecided";
    }
    return "?";
}

std::string point_text(const inv::Decision& d) {
    std::string out;
    for (const auto& [name, value] : d.point) out += fmt::format("{}{} = {:.6g}", out.empty() ? "" : ", ", name, value);
    return out;
}

constexpr const char* santilli_statement[] = {
    "S1  A_ij = A_ji",
    "S2  ∂A_ij/∂q̇_k = ∂A_ik/∂q̇_j",
    "S3  ∂B_i/∂q̇_j + ∂B_j/∂q̇_i = 2 D A_ij",
    "S4  ∂A_ik/∂q_j − ∂A_jk/∂q_i = ½ ∂/∂q̇_k (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)",
    "S5  ∂B_i/∂q_j − ∂B_j/∂q_i = ½ D (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)",
};

constexpr const char* santilli_statement_latex[] = {
    R"(S_1 &:\ A_{ij} = A_{ji})",
    R"(S_2 &:\ \frac{\partial A_{ij}}{\partial\dot q_k} = \frac{\partial A_{ik}}{\partial\dot q_j})",
    R"(S_3 &:\ \frac{\partial B_i}{\partial\dot q_j} + \frac{\partial B_j}{\partial\dot q_i} = 2 D A_{ij})",
    R"(S_4 &:\ \frac{\partial A_{ik}}{\partial q_j} - \frac{\partial A_{jk}}{\partial q_i} = \frac12 \frac{\partial}{\partial\dot q_k}\Big(\frac{\partial B_i}{\partial\dot q_j} - \frac{\partial B_j}{\partial\dot q_i}\Big))",
    R"(S_5 &:\ \frac{\partial B_i}{\partial q_j} - \frac{\partial B_j}{\partial q_i} = \frac12 D\Big(\frac{\partial B_i}{\partial\dot q_j} - \frac{\partial B_j}{\partial\dot q_i}\Big))",
};

std::string residual_latex(const model::Model& model, const inv::Residual& r) {
    auto q = [&](std::size_t k) { return latex(model.coordinates[k].q); };
    const std::string digit = r.condition.substr(1);
    if (r.condition == "S2") return fmt::format("S_{}({};{},{})", digit, q(r.i), q(r.j), q(*r.k));
    if (r.condition == "S4") return fmt::format("S_{}({},{};{})", digit, q(r.i), q(r.j), q(*r.k));
    return fmt::format("S_{}({},{})", digit, q(r.i), q(r.j));
}

std::size_t nonzero(const std::vector<inv::Residual>& residuals) {
    std::size_t k = 0;
    for (const auto& r : residuals) k += r.zero ? 0 : 1;
    return k;
}

// ---------------------------------------------------------------------------------------
// text

void text_forms(const model::Model& model, const inv::Forms& forms, std::ostream& out) {
    const std::size_t n = model.coordinates.size();
    out << "Kinematic form q̈ = f(t, q, q̇)" << (forms.given_fundamental ? " (solved from the fundamental form)" : " (as given)")
        << "\n";
    for (std::size_t i = 0; i < n; ++i)
        out << "  " << model.coordinates[i].name << "_ddot = " << text(display_form(forms.kinematic[i])) << "\n";
    out << "Fundamental form A(t, q, q̇) q̈ + B(t, q, q̇) = 0"
        << (forms.given_fundamental ? (model.newtonian ? " (as given)" : " (E = M q̈ − f of the derived equations)")
                                    : " (A = I, B = −f)")
        << "\n";
    for (std::size_t i = 0; i < n; ++i) {
        out << "  A[" << model.coordinates[i].name << "] = [";
        for (std::size_t j = 0; j < n; ++j)
            out << (j ? ", " : "") << text(display_form(forms.fundamental.A(unsigned(i), unsigned(j))));
        out << "]\n";
    }
    for (std::size_t i = 0; i < n; ++i)
        out << "  B[" << model.coordinates[i].name << "] = " << text(display_form(forms.fundamental.B[i])) << "\n";
}

void text_residuals(const model::Model& model, const std::vector<inv::Residual>& residuals, std::ostream& out) {
    std::size_t width = 0;
    for (const auto& r : residuals) width = std::max(width, inv::label(model, r).size());
    for (const auto& r : residuals)
        out << "  " << fmt::format("{:<{}}", inv::label(model, r), width) << " = " << text(display_form(r.value)) << "\n";
}

void text_steps(const std::vector<inv::Step>& steps, std::ostream& out) {
    for (std::size_t s = 0; s < steps.size(); ++s) {
        out << fmt::format("  {}. {}\n", s + 1, steps[s].text);
        for (const auto& [lhs, value] : steps[s].equations) out << "       " << lhs << " = " << text(display_form(value)) << "\n";
    }
}

void text_construction(const model::Model& model, const inv::Construction& c, const std::string& title,
                       std::ostream& out) {
    out << "\n" << title << "\n";
    if (!c.built) {
        out << "  not built: " << c.reason << "\n";
        return;
    }
    out << fmt::format("  homotopy centres: q̇ = {}, q = {}{}\n", c.v_centre, c.q_centre,
                       c.C_by_coordinates ? " (C by integrating one coordinate after another: singular at every centre)" : "");
    out << "  K = q̇_i q̇_j ∫₀¹ (1−τ) A_ij(t, q, τq̇) dτ = " << text(display_form(c.K)) << "\n";
    out << "  E − ε(K) = α + β q̇:";
    for (std::size_t i = 0; i < c.alpha.size(); ++i)
        out << (i ? ", " : " ") << "α[" << model.coordinates[i].name << "] = " << text(display_form(c.alpha[i]));
    out << "; β = " << matrix_text(c.beta) << "\n";
    for (std::size_t i = 0; i < c.D.size(); ++i)
        out << "  D[" << model.coordinates[i].name << "] = " << text(display_form(c.D[i])) << "\n";
    out << "  C = " << text(display_form(c.C)) << "\n";
    out << "  L = K + D_k q̇_k + C = " << text(display_form(c.L)) << "\n";
    if (c.verified) out << "  verified: ε_s(L) − E_s simplifies to 0 for every s\n";
    else
        out << fmt::format("  NOT verified symbolically: ε_s(L) − E_s does not simplify to 0 (it vanishes at {} random "
                           "points)\n",
                           c.points_agreeing);
}

void print_text(const model::Model& model, const inv::Analysis& a, std::ostream& out) {
    out << "Inverse problem — " << model.name << (model.summary.empty() ? "" : ": " + model.summary) << "\n";
    out << "Coordinates q_s:";
    for (const auto& c : model.coordinates) out << " " << c.name;
    out << "\nParameters:";
    for (const auto& p : model.parameters) out << fmt::format(" {} = {}", p.name, p.value);
    out << "\n\n";
    text_forms(model, a.forms, out);

    out << "\nSantilli's conditions of self-adjointness, D = ∂_t + q̇_k ∂/∂q_k\n";
    for (const char* s : santilli_statement) out << "  " << s << "\n";
    out << "Residuals (left minus right side, simplified)\n";
    text_residuals(model, a.conditions, out);
    out << "Verdict: " << verdict_name(a.decision.verdict);
    switch (a.decision.verdict) {
        case inv::Verdict::self_adjoint: out << " — every residual simplifies to 0\n"; break;
        case inv::Verdict::not_self_adjoint:
            out << fmt::format(" — {} = {:.6g} ≠ 0 at {}\n", inv::label(model, a.conditions[a.decision.witness]),
                               a.decision.witness_value, point_text(a.decision));
            break;
        case inv::Verdict::undecided:
            out << fmt::format(" — {} residual{} GiNaC cannot simplify to 0, but each vanishes to round-off at all {} "
                               "random points tried:",
                               a.decision.unresolved.size(), a.decision.unresolved.size() == 1 ? "" : "s",
                               a.decision.points_tried);
            for (std::size_t r : a.decision.unresolved) out << " " << inv::label(model, a.conditions[r]);
            out << "\n";
            break;
    }

    if (a.multiplier) {
        const auto& m = *a.multiplier;
        out << "\nMultiplier g(t, q, q̇) for the kinematic form (Douglas; Sarlet), d/dt = ∂_t + q̇·∂_q + f·∂_q̇\n"
            << "  N = ∂f/∂q̇ = " << matrix_text(m.N) << "\n"
            << "  Φ = ½ dN/dt − ∂f/∂q − ¼ N² = " << matrix_text(m.Phi) << "\n"
            << "  H1  g Φ symmetric\n  H2  dg/dt + ½ Nᵀ g + ½ g N = 0\n  H3  ∂g_ij/∂q̇_k symmetric in (j, k)\n";
        text_steps(m.steps, out);
        if (m.g) out << "  Multiplier (" << m.kind << "): g = " << matrix_text(*m.g) << "\n";
        else if (m.singular_forced) out << "  No regular Lagrangian exists.\n";
        else if (!m.undecided.empty()) out << "  Undecided: " << m.undecided << ".\n";
        else out << "  No multiplier found.\n";
    }
    if (a.multiplied_form) {
        out << "\nMultiplied equations g (q̈ − f) = 0 in fundamental form\n";
        const std::size_t n = model.coordinates.size();
        out << "  A = g = " << matrix_text(a.multiplied_form->A) << "\n";
        for (std::size_t i = 0; i < n; ++i)
            out << "  B[" << model.coordinates[i].name << "] = " << text(display_form(a.multiplied_form->B[i])) << "\n";
        out << "  Santilli's conditions: " << nonzero(a.multiplied_conditions) << " of " << a.multiplied_conditions.size()
            << " residuals non-zero\n";
        text_residuals(model, a.multiplied_conditions, out);
    }
    if (a.construction)
        text_construction(model, *a.construction, "Lagrangian by Santilli's construction L = K + D_k q̇_k + C", out);
    if (a.alternative) {
        text_construction(model, a.alternative->construction,
                          "A second Lagrangian, from the constant multiplier g = " + matrix_text(a.alternative->g) +
                              " (the equations g (q̈ − f) = 0 have the same solutions)",
                          out);
    }
    out << "\nConclusion: " << a.reason << "\n";
}

// ---------------------------------------------------------------------------------------
// LaTeX

void latex_forms(const model::Model& model, const inv::Forms& forms, std::ostream& out) {
    const std::size_t n = model.coordinates.size();
    out << "\\subsection*{The equations}\nKinematic form $\\ddot q = f(t, q, \\dot q)$:\n\\begin{align*}\n";
    for (std::size_t i = 0; i < n; ++i)
        out << latex(model.coordinates[i].q_ddot) << " &= " << ex_latex(forms.kinematic[i])
            << (i + 1 < n ? "\\\\\n" : "\n");
    out << "\\end{align*}\nFundamental form $A(t,q,\\dot q)\\,\\ddot q + B(t,q,\\dot q) = 0$:\n\\begin{align*}\n"
        << "A &= " << matrix_latex(forms.fundamental.A) << "\\\\\n";
    for (std::size_t i = 0; i < n; ++i)
        out << "B_{" << latex(model.coordinates[i].q) << "} &= " << ex_latex(forms.fundamental.B[i])
            << (i + 1 < n ? "\\\\\n" : "\n");
    out << "\\end{align*}\n";
}

void latex_residuals(const model::Model& model, const std::vector<inv::Residual>& residuals, std::ostream& out) {
    out << "\\begin{align*}\n";
    for (std::size_t k = 0; k < residuals.size(); ++k)
        out << residual_latex(model, residuals[k]) << " &= " << ex_latex(residuals[k].value)
            << (k + 1 < residuals.size() ? "\\\\\n" : "\n");
    out << "\\end{align*}\n";
}

void latex_construction(const model::Model& model, const inv::Construction& c, const std::string& title,
                        std::ostream& out) {
    out << "\\subsection*{" << title << "}\n";
    if (!c.built) {
        out << "Not built: " << latex_prose(c.reason) << ".\n";
        return;
    }
    out << "$L = K + D_k \\dot q_k + C$, homotopy centres $\\dot q = " << c.v_centre << "$, $q = " << c.q_centre
        << "$:\n\\begin{align*}\nK &= " << ex_latex(c.K) << "\\\\\n";
    for (std::size_t i = 0; i < c.D.size(); ++i)
        out << "D_{" << latex(model.coordinates[i].q) << "} &= " << ex_latex(c.D[i]) << "\\\\\n";
    out << "C &= " << ex_latex(c.C) << "\\\\\nL &= " << ex_latex(c.L) << "\n\\end{align*}\n";
    out << (c.verified ? "Verified: $\\varepsilon_s(L) - E_s$ simplifies to $0$ for every $s$.\n"
                       : "Not verified symbolically.\n");
}

void print_latex(const model::Model& model, const inv::Analysis& a, std::ostream& out) {
    out << "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage{amsmath}\n"
        << "\\allowdisplaybreaks\n\\begin{document}\n\\section*{Inverse problem: " << latex_escape(model.name) << "}\n";
    if (!model.summary.empty()) out << latex_escape(model.summary) << "\n\n";
    latex_forms(model, a.forms, out);
    out << "\\subsection*{Santilli's conditions}\nWith $D = \\partial_t + \\dot q_k \\partial/\\partial q_k$:\n"
        << "\\begin{align*}\n";
    for (std::size_t s = 0; s < 5; ++s) out << santilli_statement_latex[s] << (s < 4 ? "\\\\\n" : "\n");
    out << "\\end{align*}\nResiduals (left minus right side, simplified):\n";
    latex_residuals(model, a.conditions, out);
    out << "\\paragraph{Verdict} " << verdict_name(a.decision.verdict);
    if (a.decision.verdict == inv::Verdict::not_self_adjoint)
        out << ": $" << residual_latex(model, a.conditions[a.decision.witness]) << " = "
            << fmt::format("{:.6g}", a.decision.witness_value) << " \\neq 0$ at " << latex_escape(point_text(a.decision));
    if (a.decision.verdict == inv::Verdict::undecided)
        out << fmt::format(": residuals that do not simplify vanish at all {} random points tried", a.decision.points_tried);
    out << ".\n";
    if (a.multiplier) {
        const auto& m = *a.multiplier;
        out << "\\subsection*{Multiplier (Douglas; Sarlet)}\n"
            << "$\\frac{d}{dt} = \\partial_t + \\dot q\\cdot\\partial_q + f\\cdot\\partial_{\\dot q}$, "
            << "$N = \\partial f/\\partial\\dot q$, $\\Phi = \\frac12 \\dot N - \\partial f/\\partial q - \\frac14 N^2$; "
            << "$H_1$: $g\\Phi$ symmetric, $H_2$: $\\dot g + \\frac12 N^T g + \\frac12 g N = 0$, "
            << "$H_3$: $\\partial g_{ij}/\\partial \\dot q_k$ symmetric in $(j,k)$.\n\\begin{align*}\n"
            << "N &= " << matrix_latex(m.N) << "\\\\\n\\Phi &= " << matrix_latex(m.Phi) << "\n\\end{align*}\n"
            << "\\begin{enumerate}\n";
        for (const auto& step : m.steps) {
            out << "\\item " << latex_prose(step.text) << "\n";
            if (!step.equations.empty()) {
                out << "\\begin{align*}\n";
                for (std::size_t k = 0; k < step.equations.size(); ++k)
                    out << "\\text{" << latex_prose(step.equations[k].first) << "} &= "
                        << ex_latex(step.equations[k].second) << (k + 1 < step.equations.size() ? "\\\\\n" : "\n");
                out << "\\end{align*}\n";
            }
        }
        out << "\\end{enumerate}\n";
        if (m.g) out << "Multiplier (" << latex_prose(m.kind) << "): $g = " << matrix_latex(*m.g) << "$.\n";
        else if (m.singular_forced) out << "No regular Lagrangian exists.\n";
        else if (!m.undecided.empty()) out << "Undecided: " << latex_prose(m.undecided) << ".\n";
        else out << "No multiplier found.\n";
    }
    if (a.multiplied_form) {
        out << "\\subsection*{Multiplied equations $g(\\ddot q - f) = 0$}\nSantilli's residuals:\n";
        latex_residuals(model, a.multiplied_conditions, out);
    }
    if (a.construction) latex_construction(model, *a.construction, "Lagrangian (Santilli's construction)", out);
    if (a.alternative)
        latex_construction(model, a.alternative->construction,
                           "A second Lagrangian, from $g = " + matrix_latex(a.alternative->g) + "$", out);
    out << "\\paragraph{Conclusion} " << latex_prose(a.reason) << ".\n\\end{document}\n";
}

// ---------------------------------------------------------------------------------------
// JSON

std::string residuals_json(const std::vector<inv::Residual>& residuals) {
    std::string out = "[";
    for (std::size_t k = 0; k < residuals.size(); ++k) {
        const auto& r = residuals[k];
        out += fmt::format("{}\n    {{\"name\": \"{}\", \"i\": {}, \"j\": {}, ", k ? "," : "", r.condition, r.i, r.j);
        if (r.k) out += fmt::format("\"k\": {}, ", *r.k);
        out += "\"residual\": " + json_ex(r.value) + "}";
    }
    return out + (residuals.empty() ? "]" : "\n  ]");
}

std::string construction_json(const inv::Construction& c) {
    std::string out = fmt::format("{{\"built\": {}", c.built ? "true" : "false");
    if (c.built) {
        out += ", \"K\": " + json_ex(c.K) + ", \"D\": [";
        for (std::size_t i = 0; i < c.D.size(); ++i) out += (i ? ", " : "") + json_ex(c.D[i]);
        out += "], \"C\": " + json_ex(c.C) + ", \"L\": " + json_ex(c.L);
        out += fmt::format(", \"verified\": {}", c.verified ? "true" : "false");
    } else {
        out += ", \"reason\": " + json_string(c.reason);
    }
    return out + "}";
}

void print_json(const model::Model& model, const inv::Analysis& a, std::ostream& out) {
    const std::size_t n = model.coordinates.size();
    out << "{\n  \"scene\": " << json_string(model.name) << ",\n  \"coordinates\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_string(model.coordinates[i].name);
    out << "],\n  \"form\": \"" << (a.forms.given_fundamental ? "fundamental" : "kinematic") << "\",\n  \"kinematic\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_ex(a.forms.kinematic[i]);
    out << "],\n  \"fundamental\": {\"A\": " << matrix_json(a.forms.fundamental.A) << ", \"B\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_ex(a.forms.fundamental.B[i]);
    out << "]},\n  \"conditions\": " << residuals_json(a.conditions) << ",\n  \"self_adjoint\": "
        << (a.decision.verdict == inv::Verdict::self_adjoint       ? "true"
            : a.decision.verdict == inv::Verdict::not_self_adjoint ? "false"
                                                                   : "null");
    if (a.decision.verdict == inv::Verdict::not_self_adjoint) {
        out << ",\n  \"witness\": {\"condition\": " << json_string(inv::label(model, a.conditions[a.decision.witness]))
            << fmt::format(", \"value\": {:.17g}, \"point\": {{", a.decision.witness_value);
        for (std::size_t k = 0; k < a.decision.point.size(); ++k)
            out << (k ? ", " : "") << json_string(a.decision.point[k].first) << fmt::format(": {:.17g}", a.decision.point[k].second);
        out << "}}";
    }
    if (a.decision.verdict == inv::Verdict::undecided) out << ",\n  \"points_tried\": " << a.decision.points_tried;
    out << ",\n  \"multiplier\": " << (a.multiplier && a.multiplier->g ? matrix_json(*a.multiplier->g) : "null");
    if (a.multiplier) {
        const auto& m = *a.multiplier;
        out << ",\n  \"multiplier_search\": {\"N\": " << matrix_json(m.N) << ", \"Phi\": " << matrix_json(m.Phi)
            << ", \"kind\": " << (m.g ? json_string(m.kind) : "null")
            << ", \"singular_forced\": " << (m.singular_forced ? "true" : "false")
            << ", \"undecided\": " << (m.undecided.empty() ? "null" : json_string(m.undecided)) << ", \"steps\": [";
        for (std::size_t s = 0; s < m.steps.size(); ++s) {
            out << (s ? ",\n    " : "\n    ") << "{\"text\": " << json_string(m.steps[s].text) << ", \"equations\": [";
            for (std::size_t k = 0; k < m.steps[s].equations.size(); ++k)
                out << (k ? ", " : "") << "[" << json_string(m.steps[s].equations[k].first) << ", "
                    << json_ex(m.steps[s].equations[k].second) << "]";
            out << "]}";
        }
        out << (m.steps.empty() ? "]}" : "\n  ]}");
    }
    if (a.multiplied_form) out << ",\n  \"multiplied_conditions\": " << residuals_json(a.multiplied_conditions);
    const bool built = a.construction && a.construction->built;
    out << ",\n  \"lagrangian\": " << (built ? json_ex(a.construction->L) : "null");
    if (a.construction) out << ",\n  \"construction\": " << construction_json(*a.construction);
    out << ",\n  \"verified\": " << (built && a.construction->verified ? "true" : "false");
    if (a.alternative)
        out << ",\n  \"alternative\": {\"multiplier\": " << matrix_json(a.alternative->g)
            << ", \"construction\": " << construction_json(a.alternative->construction) << "}";
    out << ",\n  \"reason\": " << json_string(a.reason) << "\n}\n";
}

// ---------------------------------------------------------------------------------------
// `eomc derive` for a [newtonian] scene

void newtonian_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    out << "Scene " << model.name << (model.summary.empty() ? "" : " — " + model.summary) << "\n";
    out << "Coordinates q_s:";
    for (const auto& c : model.coordinates) out << " " << c.name;
    out << "\nParameters:";
    for (const auto& p : model.parameters) out << fmt::format(" {} = {}", p.name, p.value);
    out << "\nGiven by its equations of motion ([newtonian], "
        << (model.newtonian->fundamental ? "fundamental" : "kinematic") << " form)\n\n";
    text_forms(model, inv::forms(model, eqs), out);
    const std::size_t n = model.coordinates.size();
    out << "\nEquations of motion M q̈ = f\n";
    for (std::size_t i = 0; i < n; ++i) {
        out << "  M[" << model.coordinates[i].name << "] = [";
        for (std::size_t j = 0; j < n; ++j)
            out << (j ? ", " : "") << text(display_form(eqs.mass_matrix(unsigned(i), unsigned(j))));
        out << "]\n";
    }
    for (std::size_t i = 0; i < n; ++i)
        out << "  f[" << model.coordinates[i].name << "] = " << text(display_form(eqs.forcing[i])) << "\n";
    out << "\nInvariants\n  none derived (the scene gives equations, not energies; `eomc inverse` looks for a "
           "Lagrangian)\n";
}

void newtonian_latex(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    out << "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage{amsmath}\n"
        << "\\allowdisplaybreaks\n\\begin{document}\n\\section*{" << latex_escape(model.name) << "}\n";
    if (!model.summary.empty()) out << latex_escape(model.summary) << "\n\n";
    out << "Given by its equations of motion (" << (model.newtonian->fundamental ? "fundamental" : "kinematic")
        << " form).\n";
    latex_forms(model, inv::forms(model, eqs), out);
    out << "\\end{document}\n";
}

void newtonian_json(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    const std::size_t n = model.coordinates.size();
    const inv::Forms forms = inv::forms(model, eqs);
    out << "{\n  \"scene\": " << json_string(model.name) << ",\n  \"coordinates\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_string(model.coordinates[i].name);
    out << "],\n  \"parameters\": {";
    for (std::size_t i = 0; i < model.parameters.size(); ++i)
        out << (i ? ", " : "") << json_string(model.parameters[i].name) << ": " << fmt::format("{}", model.parameters[i].value);
    out << "},\n  \"form\": \"" << (model.newtonian->fundamental ? "fundamental" : "kinematic") << "\",\n  \"kinematic\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_ex(forms.kinematic[i]);
    out << "],\n  \"fundamental\": {\"A\": " << matrix_json(forms.fundamental.A) << ", \"B\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_ex(forms.fundamental.B[i]);
    out << "]},\n  \"mass_matrix\": " << matrix_json(eqs.mass_matrix) << ",\n  \"forcing\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_ex(eqs.forcing[i]);
    out << "],\n  \"invariants\": {}\n}\n";
}

std::string toml_string(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += char(c);
        else if (c < 0x20 || c == 0x7F) out += fmt::format("\\u{:04X}", unsigned(c));  // TOML 1.0: control characters
        else out += char(c);
    }
    return out + "\"";
}

}  // namespace

void print_inverse(const model::Model& model, const inv::Analysis& analysis, DerivationFormat format, std::ostream& out) {
    switch (format) {
        case DerivationFormat::text: return print_text(model, analysis, out);
        case DerivationFormat::latex: return print_latex(model, analysis, out);
        case DerivationFormat::json: return print_json(model, analysis, out);
    }
}

void print_newtonian_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                                std::ostream& out) {
    switch (format) {
        case DerivationFormat::text: return newtonian_text(model, eqs, out);
        case DerivationFormat::latex: return newtonian_latex(model, eqs, out);
        case DerivationFormat::json: return newtonian_json(model, eqs, out);
    }
}

std::string lagrangian_scene(const model::Model& model, const inv::Analysis& a) {
    const inv::Construction& c = *a.construction;
    const auto [T, V] = inv::split_lagrangian(model, c.L);
    std::string multiplier = a.multiplier && a.multiplier->g ? "g = " + matrix_text(*a.multiplier->g) : "no multiplier";
    std::string out = fmt::format(
        "# Generated by eomc inverse from {}: a Lagrangian whose Euler–Lagrange equations are\n"
        "# {} (q̈ − f) = 0 for the scene's q̈ = f ({}; {}).\n",
        codegen::comment_text(model.source.empty() ? model.name : model.source),  // a path may hold a line break
        a.multiplier && a.multiplier->g ? "g" : "the scene's own", multiplier,
        c.verified ? "verified symbolically" : "NOT verified symbolically");
    out += "[scene]\nname = " + toml_string(model.name + "_lagrangian") + "\n";
    out += "summary = " +
           toml_string((model.summary.empty() ? model.name : model.summary) + ", from its constructed Lagrangian") + "\n";
    if (!model.parameters.empty()) {
        out += "\n[parameters]\n";
        for (const auto& p : model.parameters) out += fmt::format("{} = {}\n", p.name, p.value);
    }
    out += "\n[coordinates]\n";
    for (const auto& co : model.coordinates)
        out += fmt::format("{} = {{ initial = {}, rate = {} }}\n", co.name, co.initial, co.rate);
    out += "\n# L = " + text(c.L) + "\n[lagrangian]\nT = " + toml_string(text(T)) + "\nV = " + toml_string(text(V)) + "\n";
    const auto& s = model.simulate;
    out += fmt::format("\n[simulate]\nt_end = {}\nintegrator = {}\nrtol = {}\natol = {}\nstep = {}\n", s.t_end,
                       toml_string(s.integrator), s.rtol, s.atol, s.step);
    return out;
}

}  // namespace eomc::report
