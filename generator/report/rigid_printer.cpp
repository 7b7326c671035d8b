#include "report/rigid_printer.hpp"

#include <fmt/format.h>

#include "mechanics/first_order.hpp"
#include "mechanics/rigid/euler_poisson.hpp"
#include "mechanics/rigid/formulation.hpp"
#include "support/json.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

const char* const state_names[6] = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};

std::string vec_text(const model::Vec3& v) { return fmt::format("({}, {}, {})", text(v[0]), text(v[1]), text(v[2])); }
std::string vec_latex(const model::Vec3& v) {
    return fmt::format("\\left({},\\ {},\\ {}\\right)", latex(v[0]), latex(v[1]), latex(v[2]));
}
std::string vec_json(const model::Vec3& v) {
    return fmt::format("[{}, {}, {}]", json_string(text(v[0])), json_string(text(v[1])), json_string(text(v[2])));
}
model::Vec3 diagonal_or_row(const GiNaC::matrix& I, unsigned row) { return {I(row, 0), I(row, 1), I(row, 2)}; }

void integrals_text(const mechanics::rigid::RigidIntegrals& found, std::ostream& out) {
    out << "\nPolynomial first integrals of degree ≤ " << found.degree
        << " (undetermined coefficients in p, q, r, gamma1..3 at the parameters' values; new ones only, not "
           "polynomials in the energy, area and geometric integrals)\n";
    if (!found.not_searched.empty()) {
        out << "  not searched: " << found.not_searched << "\n";
        return;
    }
    if (!found.undecided.empty()) out << "  " << found.undecided << "\n";
    if (found.found.empty()) out << (found.undecided.empty() ? "  none\n" : "  none below that degree\n");
    for (std::size_t k = 0; k < found.found.size(); ++k) {
        const auto& f = found.found[k];
        out << "  " << found.names[k] << " (degree " << f.degree << ")"
            << (f.conditional ? ", " + f.condition_name + " only: dF/dt = (" + text(f.cofactor) + ")·(area)" : "")
            << (found.tracked[k] ? "" : "; the motion does not start there, so it is not tracked") << "\n    = "
            << text(f.value) << "\n";
    }
}

void integrals_json(const mechanics::rigid::RigidIntegrals& found, std::ostream& out) {
    out << "{\"degree\": " << found.degree << ", \"not_searched\": " << json_string(found.not_searched)
        << ", \"undecided\": " << json_string(found.undecided) << ", \"work\": " << found.work << ", \"found\": [";
    for (std::size_t k = 0; k < found.found.size(); ++k) {
        const auto& f = found.found[k];
        out << (k ? ", " : "") << "{\"name\": " << json_string(found.names[k]) << ", \"degree\": " << f.degree
            << ", \"value\": " << json_string(text(f.value)) << ", \"conditional\": " << (f.conditional ? "true" : "false")
            << ", \"condition\": " << json_string(f.condition_name) << ", \"cofactor\": " << json_string(text(f.cofactor))
            << ", \"tracked\": " << (found.tracked[k] ? "true" : "false") << "}";
    }
    out << "]}";
}

void integrals_latex(const mechanics::rigid::RigidIntegrals& found, std::ostream& out) {
    out << "\\subsection*{Polynomial first integrals of degree $\\le " << found.degree << "$}\n";
    if (!found.not_searched.empty()) {
        out << "Not searched: " << latex_escape(found.not_searched) << "\n";
        return;
    }
    if (!found.undecided.empty()) out << latex_escape(found.undecided) << ".\n\n";
    if (found.found.empty()) out << "None beyond the energy, area and geometric integrals.\n";
    for (std::size_t k = 0; k < found.found.size(); ++k) {
        const auto& f = found.found[k];
        out << "\\begin{align*}\n\\text{" << latex_escape(found.names[k]) << "} &= " << latex(f.value) << "\n\\end{align*}\n";
        if (f.conditional)
            out << latex_escape(f.condition_name) << " only: $\\dot F = (" << latex(f.cofactor) << ")\\,K\\cdot\\gamma$.\n";
    }
}

}  // namespace

void print_rigid_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                            std::ostream& out) {
    const model::RigidBody& body = *model.rigid;
    const auto system = mechanics::rigid::euler_poisson(body);
    const auto found = mechanics::rigid::search_rigid_integrals(model, system, mechanics::rigid::default_search_degree);
    const auto& formulation = mechanics::rigid::rigid_formulation(body.formulation);
    const mechanics::FirstOrderForm form = formulation.build(model, eqs);
    switch (format) {
        case DerivationFormat::text: {
            out << "Scene " << model.name << (model.summary.empty() ? "" : " — " + model.summary) << "\n";
            out << "Rigid body about a fixed point O (Mei, ch. 5), body axes; ω = (p, q, r), γ = the upward vertical\n";
            out << "  I = [" << vec_text(diagonal_or_row(body.inertia, 0)) << ", " << vec_text(diagonal_or_row(body.inertia, 1))
                << ", " << vec_text(diagonal_or_row(body.inertia, 2)) << "]\n";
            out << "  r_c = " << vec_text(body.center) << ", P = " << text(body.weight);
            if (body.gyrostat != model::Vec3{0, 0, 0}) out << ", k = " << vec_text(body.gyrostat);
            out << "\nParameters:";
            for (const auto& p : model.parameters) out << " " << p.name << " = " << fmt::format("{}", p.value);
            out << "\n\nEuler's equations  I ω̇ − (Iω + k) × ω = P γ × r_c\n";
            for (const auto& e : eqs.equations) out << "  " << text(e.lhs) << " = " << text(e.rhs) << "\n";
            out << "Poisson's equations  γ̇ = γ × ω\n";
            for (std::size_t i = 0; i < 3; ++i)
                out << "  d" << state_names[3 + i] << "/dt = " << text(system.gamma_rate[i]) << "\n";
            out << "\nFormulation " << formulation.name << ": " << formulation.summary << "\n  state (";
            for (std::size_t i = 0; i < form.state.size(); ++i) out << (i ? ", " : "") << form.state[i].name;
            out << ")\n";
            if (body.formulation != scene::RigidFormulationKind::euler_poisson)
                for (const auto& [index, rate] : form.explicit_rates)
                    out << "  d" << form.state[index].name << "/dt = " << text(rate) << "\n";
            for (const auto& step : form.derivation)
                if (body.formulation != scene::RigidFormulationKind::euler_poisson) out << "  " << step.name << " = " << text(step.value) << "\n";
            out << "\nFirst integrals, proven along the equations\n";
            for (const auto& inv : eqs.invariants) out << "  " << inv.name << ": " << inv.description << "\n    = " << text(inv.value) << "\n";
            // Jacobi's theorem: n = 6 autonomous equations, a last multiplier and n − 2 = 4 integrals.
            out << "Jacobi's last multiplier: "
                << (system.divergence.is_zero() ? "μ = 1, proven: div of the Euler–Poisson field ≡ 0"
                                                : "μ = 1 is not one: div = " + text(system.divergence))
                << "\n  6 equations need the multiplier and 4 independent integrals for quadratures; proven here: "
                << eqs.invariants.size()
                << (eqs.invariants.size() >= 4 ? " (integrable by quadratures, when independent)\n"
                                               : fmt::format(" (missing {})\n", 4 - eqs.invariants.size()));
            integrals_text(found, out);
            return;
        }
        case DerivationFormat::latex: {
            out << "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage{amsmath}\n"
                << "\\allowdisplaybreaks\n\\begin{document}\n\\section*{" << latex_escape(model.name) << "}\n";
            if (!model.summary.empty()) out << latex_escape(model.summary) << "\n\n";
            out << "Rigid body about a fixed point, body axes: $r_c = " << vec_latex(body.center) << "$, $P = "
                << latex(body.weight) << "$.\n\\subsection*{Euler's and Poisson's equations}\n\\begin{align*}\n";
            for (const auto& e : eqs.equations) out << latex(e.lhs) << " &= " << latex(e.rhs) << "\\\\\n";
            for (std::size_t i = 0; i < 3; ++i)
                out << "\\dot\\gamma_" << i + 1 << " &= " << latex(system.gamma_rate[i]) << (i < 2 ? "\\\\\n" : "\n");
            out << "\\end{align*}\n\\subsection*{First integrals}\n\\begin{align*}\n";
            for (std::size_t k = 0; k < eqs.invariants.size(); ++k)
                out << "\\text{" << latex_escape(eqs.invariants[k].name) << "} &= " << latex(eqs.invariants[k].value)
                    << (k + 1 < eqs.invariants.size() ? "\\\\\n" : "\n");
            out << "\\end{align*}\n";
            integrals_latex(found, out);
            out << "\\end{document}\n";
            return;
        }
        case DerivationFormat::json: {
            out << "{\n  \"scene\": " << json_string(model.name) << ",\n  \"rigid_body\": {\"inertia\": ["
                << vec_json(diagonal_or_row(body.inertia, 0)) << ", " << vec_json(diagonal_or_row(body.inertia, 1)) << ", "
                << vec_json(diagonal_or_row(body.inertia, 2)) << "], \"center\": " << vec_json(body.center)
                << ", \"weight\": " << json_string(text(body.weight)) << ", \"gyrostatic_moment\": " << vec_json(body.gyrostat)
                << ", \"formulation\": " << json_string(std::string(formulation.name)) << "},\n  \"euler\": [";
            for (std::size_t i = 0; i < eqs.equations.size(); ++i)
                out << (i ? ", " : "") << "{\"lhs\": " << json_string(text(eqs.equations[i].lhs))
                    << ", \"rhs\": " << json_string(text(eqs.equations[i].rhs)) << "}";
            out << "],\n  \"poisson\": " << vec_json(system.gamma_rate) << ",\n  \"state\": [";
            for (std::size_t i = 0; i < form.state.size(); ++i) out << (i ? ", " : "") << json_string(form.state[i].name);
            out << "],\n  \"invariants\": [";
            for (std::size_t k = 0; k < eqs.invariants.size(); ++k)
                out << (k ? ", " : "") << "{\"name\": " << json_string(eqs.invariants[k].name)
                    << ", \"value\": " << json_string(text(eqs.invariants[k].value)) << "}";
            out << "],\n  \"last_multiplier\": \"1\",\n  \"integral_search\": ";
            integrals_json(found, out);
            out << "\n}\n";
            return;
        }
    }
}

void print_rigid_integrals(const model::Model& model, const mechanics::rigid::RigidIntegrals& integrals,
                           DerivationFormat format, std::ostream& out) {
    const auto system = mechanics::rigid::euler_poisson(*model.rigid);
    switch (format) {
        case DerivationFormat::text:
            out << "Scene " << model.name << ": first integrals of the Euler–Poisson equations\n";
            for (const auto& inv : system.integrals) out << "  " << inv.name << " = " << text(inv.value) << "  (proven)\n";
            integrals_text(integrals, out);
            return;
        case DerivationFormat::latex:
            out << "\\documentclass[10pt]{article}\n\\usepackage{amsmath}\n\\begin{document}\n";
            integrals_latex(integrals, out);
            out << "\\end{document}\n";
            return;
        case DerivationFormat::json:
            out << "{\"scene\": " << json_string(model.name) << ", \"classical\": [";
            for (std::size_t k = 0; k < system.integrals.size(); ++k)
                out << (k ? ", " : "") << "{\"name\": " << json_string(system.integrals[k].name)
                    << ", \"value\": " << json_string(text(system.integrals[k].value)) << "}";
            out << "], \"search\": ";
            integrals_json(integrals, out);
            out << "}\n";
            return;
    }
}

}  // namespace eomc::report
