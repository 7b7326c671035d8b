#include "report/control_printer.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using GiNaC::ex;
using symbolic::latex;
using symbolic::latex_escape;
using symbolic::text;

namespace {

const char* control_kind(model::ProgramControl c) {
    switch (c) {
        case model::ProgramControl::ideal: return "ideal";
        case model::ProgramControl::directions: return "directions";
        case model::ProgramControl::actuated: return "actuated";
        case model::ProgramControl::moment: return "moment";
    }
    return "?";
}

// The name of velocity k (the component of Q_c it carries): a coordinate, or a rigid body's p, q, r
// (Q_c is then the control torque in body axes).
std::string velocity_name(const model::Model& model, std::size_t k) {
    if (model.rigid) return std::array<const char*, 3>{"p", "q", "r"}[k];
    return model.coordinates[k].name;
}

// The law a program's residual follows, as words (the same in every format).
std::string law_text(const mechanics::ProgramRow& p) {
    if (!p.closed_loop) return p.configuration ? "omega_ddot = 0 (open loop)" : "phi_dot = 0 (open loop)";
    if (!p.configuration) return fmt::format("phi_dot + {} phi = 0", p.kappa);
    return fmt::format("omega_ddot + {} omega_dot + {} omega = 0", 2 * p.alpha, p.beta * p.beta);
}

// Erugin's closed-form residual from ω0, ω̇0 (φ0): the law solved (Galiullin's choice is linear).
std::string residual_text(const mechanics::ProgramRow& p) {
    if (!p.closed_loop)
        return p.configuration ? "omega(t) = omega0 + omega_dot0 t (drift grows from integration error)"
                               : "phi(t) = phi0 (drift grows from integration error)";
    if (!p.configuration) return fmt::format("phi(t) = phi0 exp(-{} t)", p.kappa);
    if (p.alpha < p.beta)
        return fmt::format("omega(t) = exp(-{0} t) [omega0 cos({1} t) + (omega_dot0 + {0} omega0)/{1} sin({1} t)]",
                           p.alpha, std::sqrt(p.beta * p.beta - p.alpha * p.alpha));
    if (p.alpha == p.beta) return fmt::format("omega(t) = (omega0 + (omega_dot0 + {0} omega0) t) exp(-{0} t)", p.beta);
    const double s = std::sqrt(p.alpha * p.alpha - p.beta * p.beta);
    return fmt::format("omega(t) = A exp(-{} t) + B exp(-{} t) (overdamped)", p.alpha - s, p.alpha + s);
}

std::string verdict(const mechanics::Realisation& r) {
    if (r.redundant) return "realisable: the ideal programs are dependent; Udwadia-Kalaba's control";
    if (!r.realisable) return "not realisable: det(A M^-1 D) vanishes identically";
    if (!r.determinant) return "realisable where A M^-1 D is regular (checked at run time): " + r.why_not;
    if (r.singular.empty()) return "realisable everywhere: det(A M^-1 D) has no factor that vanishes on a state";
    std::string sets;
    for (std::size_t i = 0; i < r.singular.size(); ++i) sets += (i ? ", " : "") + text(r.singular[i]) + " = 0";
    return "realisable except where " + sets;
}

void print_text(const model::Model& model, const mechanics::Equations& eqs, const mechanics::Realisation& r,
                std::ostream& out) {
    // A rigid body's controls are torques about body axes, acting on Euler's equations in p, q, r.
    if (model.rigid)
        out << fmt::format("Programmed motion of {} (Mei ch. 3): {} program(s), {} body-axis torque(s) on Euler's "
                           "equations in p, q, r\n\n",
                           model.name, r.programs, r.controls);
    else
        out << fmt::format("Programmed motion of {} (Mei ch. 3): {} program(s), {} control(s), {} coordinate(s)\n\n",
                           model.name, r.programs, r.controls, r.velocities);
    out << "1. Programs and their derivatives\n";
    for (const auto& p : eqs.programs) {
        out << fmt::format("  {} ({} space): {} = {} = 0\n", p.name(), p.configuration ? "configuration" : "phase",
                           p.configuration ? "omega" : "phi", text(p.residual()));
        if (p.configuration) out << fmt::format("    omega_dot = {}\n", text(p.row.velocity));
        std::string row;
        for (std::size_t k = 0; k < p.row.W.size(); ++k) row += (k ? ", " : "") + text(p.row.W[k]);
        out << fmt::format("    A row = [{}], bias = {}\n", row, text(p.row.bias));
    }
    out << "\n2. Erugin's law (Galiullin's choice)\n";
    for (const auto& p : eqs.programs) out << fmt::format("  {}: {}\n    c = {}\n", p.name(), law_text(p), text(p.target));
    out << "\n3. Control directions D and A M^-1 D\n";
    for (const auto& p : eqs.programs)
        for (std::size_t j = 0; j < p.columns.size(); ++j) {
            std::string col;
            for (std::size_t k = 0; k < p.columns[j].size(); ++k) col += (k ? ", " : "") + text(p.columns[j][k]);
            out << fmt::format("  {} ({}): [{}]\n", p.column_names[j], control_kind(p.control), col);
        }
    if (r.AMD) {
        for (unsigned i = 0; i < r.AMD->rows(); ++i) {
            std::string row;
            for (unsigned j = 0; j < r.AMD->cols(); ++j) row += (j ? ", " : "") + text((*r.AMD)(i, j));
            out << fmt::format("  A M^-1 D row {}: [{}]\n", i + 1, row);
        }
        out << fmt::format("  det = {}\n", text(*r.determinant));
    }
    out << "\n4. Control lambda = (A M^-1 D)^-1 (c - A M^-1 f) and Q_c = D lambda\n";
    if (r.lambda) {
        std::size_t a = 0;
        for (const auto& p : eqs.programs)
            for (const auto& name : p.column_names) out << fmt::format("  {} = {}\n", name, text((*r.lambda)[a++]));
        for (std::size_t k = 0; k < r.Qc->size(); ++k)
            out << fmt::format("  Qc_{} = {}\n", velocity_name(model, k), text((*r.Qc)[k]));
    } else {
        out << "  not in closed form: " << r.why_not << "\n";
    }
    out << "\n5. Verdict\n  " << verdict(r) << "\n";
    out << "\n6. Residual law\n";
    for (const auto& p : eqs.programs) out << fmt::format("  {}: {}\n", p.name(), residual_text(p));
}

void print_latex(const model::Model& model, const mechanics::Equations& eqs, const mechanics::Realisation& r,
                 std::ostream& out) {
    out << "\\section*{Programmed motion of " << latex_escape(model.name) << "}\n";
    out << "\\subsection*{Programs}\n\\begin{align*}\n";
    for (const auto& p : eqs.programs)
        out << (p.configuration ? "\\omega_{" : "\\varphi_{") << latex_escape(p.name()) << "} &= " << latex(p.residual())
            << " = 0\\\\\n";
    out << "\\end{align*}\n\\subsection*{Erugin's law}\n\\begin{itemize}\n";
    for (const auto& p : eqs.programs) out << "\\item " << latex_escape(p.name() + ": " + law_text(p)) << "\n";
    out << "\\end{itemize}\n\\subsection*{Control}\n";
    if (r.AMD) out << "$\\det \\bar A M^{-1} D = " << latex(*r.determinant) << "$\n\n";
    if (r.lambda) {
        out << "\\begin{align*}\n";
        std::size_t a = 0;
        for (const auto& p : eqs.programs)
            for (std::size_t j = 0; j < p.column_names.size(); ++j, ++a)
                out << "\\lambda_{" << latex_escape(p.name()) << (p.column_names.size() > 1 ? std::to_string(j + 1) : "")
                    << "} &= " << latex((*r.lambda)[a]) << "\\\\\n";
        for (std::size_t k = 0; k < r.Qc->size(); ++k)
            out << "Q_{c," << (model.rigid ? latex(model.rigid->omega[k]) : latex(model.coordinates[k].q)) << "} &= " << latex((*r.Qc)[k]) << "\\\\\n";
        out << "\\end{align*}\n";
    } else {
        out << latex_escape("Not in closed form: " + r.why_not) << "\n\n";
    }
    out << "\\subsection*{Verdict}\n" << latex_escape(verdict(r)) << "\n\n\\subsection*{Residual law}\n\\begin{itemize}\n";
    for (const auto& p : eqs.programs) out << "\\item " << latex_escape(p.name() + ": " + residual_text(p)) << "\n";
    out << "\\end{itemize}\n";
}

void print_json(const model::Model& model, const mechanics::Equations& eqs, const mechanics::Realisation& r,
                std::ostream& out) {
    const auto expressions = [](const std::vector<ex>& v) {
        std::string s = "[";
        for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + json_string(text(v[i]));
        return s + "]";
    };
    std::string s = fmt::format("{{\"scene\": {}, \"programs\": [", json_string(model.name));
    std::size_t a = 0;
    for (std::size_t i = 0; i < eqs.programs.size(); ++i) {
        const auto& p = eqs.programs[i];
        std::string lambdas = "{";
        for (std::size_t j = 0; j < p.column_names.size(); ++j, ++a)
            lambdas += fmt::format("{}{}: {}", j ? ", " : "", json_string(p.column_names[j]),
                                   r.lambda ? json_string(text((*r.lambda)[a])) : std::string("null"));
        lambdas += "}";
        std::string columns = "[";
        for (std::size_t j = 0; j < p.columns.size(); ++j) columns += (j ? ", " : "") + expressions(p.columns[j]);
        columns += "]";
        s += fmt::format("{}{{\"name\": {}, \"space\": \"{}\", \"residual\": {}, \"rate\": {}, \"A\": {}, \"bias\": {}, "
                         "\"law\": {}, \"closed_loop\": {}, \"alpha\": {}, \"beta\": {}, \"kappa\": {}, \"c\": {}, "
                         "\"control\": \"{}\", \"D\": {}, \"lambda\": {}, \"residual_law\": {}}}",
                         i ? ", " : "", json_string(p.name()), p.configuration ? "configuration" : "phase",
                         json_string(text(p.residual())), json_string(text(p.row.velocity)), expressions(p.row.W),
                         json_string(text(p.row.bias)), json_string(law_text(p)), p.closed_loop ? "true" : "false",
                         p.alpha, p.beta, p.kappa, json_string(text(p.target)), control_kind(p.control), columns, lambdas,
                         json_string(residual_text(p)));
    }
    s += "], \"AMD\": ";
    if (r.AMD) {
        s += "[";
        for (unsigned i = 0; i < r.AMD->rows(); ++i) {
            std::vector<ex> row;
            for (unsigned j = 0; j < r.AMD->cols(); ++j) row.push_back((*r.AMD)(i, j));
            s += (i ? ", " : "") + expressions(row);
        }
        s += "]";
    } else {
        s += "null";
    }
    s += fmt::format(", \"determinant\": {}, \"singular_set\": {}, \"Qc\": ",
                     r.determinant ? json_string(text(*r.determinant)) : std::string("null"), expressions(r.singular));
    if (r.Qc) {
        s += "{";
        for (std::size_t k = 0; k < r.Qc->size(); ++k)
            s += fmt::format("{}{}: {}", k ? ", " : "", json_string(velocity_name(model, k)), json_string(text((*r.Qc)[k])));
        s += "}";
    } else {
        s += "null";
    }
    s += fmt::format(", \"redundant\": {}, \"realisable\": {}, \"verdict\": {}, \"why_not_closed_form\": {}}}\n",
                     r.redundant ? "true" : "false", r.realisable ? "true" : "false", json_string(verdict(r)),
                     json_string(r.why_not));
    out << s;
}

}  // namespace

void print_control(const model::Model& model, const mechanics::Equations& eqs, const mechanics::Realisation& r,
                   DerivationFormat format, std::ostream& out) {
    switch (format) {
        case DerivationFormat::text: print_text(model, eqs, r, out); break;
        case DerivationFormat::latex: print_latex(model, eqs, r, out); break;
        case DerivationFormat::json: print_json(model, eqs, r, out); break;
    }
}

}  // namespace eomc::report
