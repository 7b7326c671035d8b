#include "report/unilateral_printer.hpp"

#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "report/derivation_printer.hpp"
#include "support/json.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::report {

using GiNaC::ex;
using symbolic::latex;
using symbolic::latex_escape;
using symbolic::text;

namespace {

std::string method_name(model::ContactMethod m) { return std::string(runtime::contact::name(m)); }

// What the section shows for one row, as expressions (each printer writes them its own way).
struct RowView {
    const mechanics::UnilateralRow* row = nullptr;
    bool gap = true;
    ex constraint;                    // f (gap) or φ (§6.7)
    ex virtual_work;                  // Σ_s W_s δq_s (≥ 0 on the boundary)
    std::vector<ex> reaction;         // λ W_s, s over the coordinates
    ex lambda, lambda_latex, P, P_latex;  // λ_α and P_α, by their text and LaTeX names
    std::optional<ex> G;              // W M⁻¹ Wᵀ, when M is small enough to invert here
    std::optional<ex> impulse;        // P = −(1 + e) ḟ⁻/G (a single impact)
    std::optional<ex> carnot;         // T⁺ − T⁻ = −(1 − e²)(ḟ⁻)²/(2G) + (1 + e) ḟ⁻ ∂f/∂t / G (a single impact)
    bool moving = false;              // the gap depends on t
};

// ḟ⁻, the approach velocity of a gap, as a symbol in the printed formulas.
const GiNaC::symbol& approach() {
    static const GiNaC::symbol s("fdot_minus", "\\dot f^-");
    return s;
}

struct Section {
    std::vector<GiNaC::symbol> delta;  // δq_s
    std::vector<RowView> rows;
    std::vector<ex> applied;           // per coordinate: Q_s + ε_s(V) + bilateral and unilateral reactions
    std::vector<ex> applied_latex;     // the same with the LaTeX-named multipliers
    std::vector<ex> impulse;           // per coordinate: Σ_gaps P_α W_αs
    std::vector<ex> impulse_latex;
    bool any_gap = false;
};

Section section_of(const model::Model& model, const mechanics::Equations& eqs) {
    Section s;
    const std::size_t n = model.coordinates.size();
    for (const auto& c : model.coordinates)
        s.delta.emplace_back("delta_" + c.name, "\\delta " + latex(c.q));
    // M⁻¹ in closed form for small systems only (as the bilateral multipliers are printed).
    std::optional<GiNaC::matrix> M_inv;
    if (eqs.mass_matrix.rows() == n && n <= 3 && model.quasi_velocities.empty()) try {
            M_inv = eqs.mass_matrix.inverse();
        } catch (const std::exception&) {
        }
    s.applied.assign(n, 0);
    s.impulse.assign(n, 0);
    for (std::size_t k = 0; k < n; ++k) {
        s.applied[k] = display_form(eqs.equations[k].rhs);
        for (const auto& b : eqs.constraints) s.applied[k] += b.lambda * b.W[k];
    }
    s.applied_latex = s.applied;
    s.impulse_latex = s.impulse;
    for (const auto& u : eqs.unilateral) {
        RowView v;
        v.row = &u;
        v.gap = u.row.holonomic;
        s.any_gap = s.any_gap || v.gap;
        v.constraint = display_form(v.gap ? u.row.position : u.row.velocity);
        const std::string escaped = "\\text{" + latex_escape(u.row.name) + "}";
        v.lambda = u.row.lambda;
        v.lambda_latex = GiNaC::symbol(u.row.lambda.get_name(), "\\lambda_{" + escaped + "}");
        v.P = GiNaC::symbol("P_" + u.row.name);
        v.P_latex = GiNaC::symbol("P_" + u.row.name, "P_{" + escaped + "}");
        v.virtual_work = 0;
        for (std::size_t k = 0; k < n; ++k) {
            const ex w = display_form(u.row.W[k]);
            v.virtual_work += w * s.delta[k];
            v.reaction.push_back(v.lambda * w);
            s.applied[k] += v.lambda * w;
            s.applied_latex[k] += v.lambda_latex * w;
            if (v.gap) {
                s.impulse[k] += v.P * w;
                s.impulse_latex[k] += v.P_latex * w;
            }
        }
        if (v.gap && M_inv) try {
                ex G = 0;
                for (unsigned i = 0; i < n; ++i)
                    for (unsigned j = 0; j < n; ++j) G += u.row.W[i] * (*M_inv)(i, j) * u.row.W[j];
                if (symbolic::node_count(G) < 4000) {
                    G = symbolic::normalized(G);
                    if (!G.is_zero()) {
                        v.G = G;
                        const ex& e = u.restitution;
                        v.impulse = symbolic::normalized(-(1 + e) * approach() / G);
                        // A moving gap (w = ∂f/∂t ≠ 0): ḟ = W q̇ + w, and the wall's impulse does the work
                        // −P w, so T⁺ − T⁻ = ½ P (ḟ⁺ + ḟ⁻) − P w gains (1 + e) ḟ⁻ w / G: Carnot's loss holds
                        // in the wall's frame.
                        const ex w = symbolic::derivative(u.row.position, model.t);
                        v.carnot = symbolic::normalized(-(1 - e * e) * GiNaC::pow(approach(), 2) / (2 * G) +
                                                        (1 + e) * approach() * w / G);
                        v.moving = !symbolic::normalized(w).is_zero();
                    }
                }
            } catch (const std::exception&) {
            }
        s.rows.push_back(std::move(v));
    }
    return s;
}

std::string joined_text(const std::vector<ex>& v) {
    std::string out;
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + text(v[k]);
    return out;
}

}  // namespace

void print_unilateral_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    if (eqs.unilateral.empty()) return;
    const Section s = section_of(model, eqs);
    out << "\nUnilateral constraints (Mei, ch. 6; contact method " << method_name(model.contact_method);
    if (model.contact_method == model::ContactMethod::moreau_jean) out << fmt::format(", θ = {}", model.theta);
    out << ")\n";
    out << "  The rows and their ideal reactions (§6.2–§6.3)\n";
    for (const auto& v : s.rows) {
        const auto& r = v.row->row;
        out << "  " << r.name << " (" << (v.gap ? "gap" : "unilateral kinematic constraint, §6.7")
            << ", restitution e = " << text(v.row->restitution) << ")\n";
        out << "    " << (v.gap ? "f = " : "φ = ") << text(v.constraint) << " ≥ 0\n";
        if (v.gap) {
            out << "    admissible virtual displacements on f = 0: Σ ∂f/∂q_s δq_s = " << text(v.virtual_work) << " ≥ 0\n";
            out << "    ideal reaction λ ∂f/∂q_s = [" << joined_text(v.reaction) << "], " << text(v.lambda) << " ≥ 0\n";
        } else {
            out << "    admissible virtual displacements on φ = 0 (Chetaev): Σ ∂φ/∂q̇_s δq_s = " << text(v.virtual_work)
                << " ≥ 0\n";
            out << "    ideal reaction λ ∂φ/∂q̇_s = [" << joined_text(v.reaction) << "], " << text(v.lambda) << " ≥ 0\n";
        }
        out << "    W = [";
        for (std::size_t k = 0; k < r.W.size(); ++k) out << (k ? ", " : "") << text(display_form(r.W[k]));
        out << "], bias = " << text(display_form(r.bias)) << (v.gap ? "  (f̈ = W q̈ + bias)\n" : "  (φ̇ = W q̈ + bias)\n");
    }
    out << "  Lagrange's equations with the reactions ε_s(T) = Q_s + ε_s(V) + Σ λ_α ∂f_α/∂q_s (§6.4)\n";
    for (std::size_t k = 0; k < eqs.equations.size(); ++k)
        out << "    s = " << eqs.equations[k].coordinate << ": " << text(collected_lhs(model, eqs.equations[k].lhs))
            << " = " << text(s.applied[k]) << "\n";
    out << "  Signorini's conditions (§6.4): the reaction acts only in contact and only pushes\n";
    for (const auto& v : s.rows) {
        const std::string lam = text(v.lambda), f = v.gap ? "f_" + v.row->row.name : "φ_" + v.row->row.name;
        out << "    " << lam << " ≥ 0, " << f << " ≥ 0, " << lam << "·" << f << " = 0\n";
    }
    if (s.any_gap) {
        out << "  Impact equations (§6.5): Δ(∂T/∂q̇_s) = Σ P_α ∂f_α/∂q_s, q unchanged across the impact\n";
        for (std::size_t k = 0; k < eqs.equations.size(); ++k)
            out << "    s = " << eqs.equations[k].coordinate << ": Δ(" << text(display_form(eqs.equations[k].dT_dqdot))
                << ") = " << text(s.impulse[k]) << "\n";
        out << "  Newton's law ḟ⁺ = −e ḟ⁻; for several rows Moreau's form 0 ≤ P_α ⊥ (ḟ⁺_α + e_α ḟ⁻_α) ≥ 0\n";
        for (const auto& v : s.rows) {
            if (!v.gap) continue;
            out << "    " << v.row->row.name << ": ḟ = " << text(display_form(v.row->row.velocity)) << ", ḟ⁺ = −("
                << text(v.row->restitution) << ") ḟ⁻";
            if (v.G) out << "; alone: G = W M⁻¹ Wᵀ = " << text(*v.G) << ", " << text(v.P) << " = " << text(*v.impulse);
            out << "\n";
        }
        out << "  Carnot's theorem: T⁺ − T⁻ = −((1 − e)/(1 + e)) ½ Δq̇ᵀ M Δq̇ ≤ 0 (kept only for e = 1)\n";
        for (const auto& v : s.rows)
            if (v.gap && v.moving)
                out << "    " << v.row->row.name << " moves (∂f/∂t ≠ 0): ḟ = W q̇ + ∂f/∂t, the wall's impulse does the "
                                                    "work −P ∂f/∂t, and the loss holds in the wall's frame\n";
        for (const auto& v : s.rows)
            if (v.gap && v.carnot)
                out << "    " << v.row->row.name << " alone: T⁺ − T⁻ = " << text(*v.carnot) << "  (fdot_minus = ḟ⁻)\n";
    }
    for (const auto& v : s.rows)
        if (!v.gap)
            out << "  " << v.row->row.name << ": a velocity row has no impact (φ is continuous); it enters the contact "
                                                "phase where φ reaches 0 with φ̇ < 0 (§6.7)\n";
}

void print_unilateral_latex(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    if (eqs.unilateral.empty()) return;
    const Section s = section_of(model, eqs);
    out << "\\subsection*{Unilateral constraints}\nContact method: " << latex_escape(method_name(model.contact_method));
    if (model.contact_method == model::ContactMethod::moreau_jean) out << fmt::format(", $\\theta = {}$", model.theta);
    out << ". The rows, the admissible virtual displacements on the boundary and the ideal reactions "
           "$\\lambda\\,\\partial f/\\partial q_s$, $\\lambda \\ge 0$:\n\\begin{align*}\n";
    for (const auto& v : s.rows) {
        const auto& r = v.row->row;
        const std::string name = "\\text{" + latex_escape(r.name) + "}";
        const std::string f = (v.gap ? "f_{" : "\\varphi_{") + name + "}";
        out << f << " &= " << latex(v.constraint) << " \\ge 0, \\quad e_{" << name
            << "} = " << latex(v.row->restitution) << "\\\\\n";
        out << "\\sum_s \\frac{\\partial " << f << "}{\\partial " << (v.gap ? "q_s" : "\\dot q_s")
            << "}\\,\\delta q_s &= " << latex(v.virtual_work) << " \\ge 0 \\quad (" << f << " = 0)\\\\\n";
        out << "W_{" << name << "} &= \\left(";
        for (std::size_t k = 0; k < r.W.size(); ++k) out << (k ? ",\\ " : "") << latex(display_form(r.W[k]));
        out << "\\right), \\quad \\mathrm{bias}_{" << name << "} = " << latex(display_form(r.bias)) << "\\\\\n";
    }
    out << "\\end{align*}\nLagrange's equations with the reactions, "
           "$\\varepsilon_s(T) = Q_s + \\varepsilon_s(V) + \\sum_\\alpha \\lambda_\\alpha\\,\\partial f_\\alpha/"
           "\\partial q_s$:\n\\begin{align*}\n";
    for (std::size_t k = 0; k < eqs.equations.size(); ++k)
        out << latex(collected_lhs(model, eqs.equations[k].lhs)) << " &= " << latex(s.applied_latex[k])
            << (k + 1 == eqs.equations.size() ? "\n" : "\\\\\n");
    out << "\\end{align*}\nSignorini's conditions:\n\\begin{align*}\n";
    for (const auto& v : s.rows) {
        const std::string name = "\\text{" + latex_escape(v.row->row.name) + "}";
        const std::string f = (v.gap ? "f_{" : "\\varphi_{") + name + "}", lam = latex(v.lambda_latex);
        out << lam << " &\\ge 0, \\quad " << f << " \\ge 0, \\quad " << lam << " " << f << " = 0"
            << (&v == &s.rows.back() ? "\n" : "\\\\\n");
    }
    out << "\\end{align*}\n";
    if (!s.any_gap) return;
    out << "Impact equations, $\\Delta(\\partial T/\\partial\\dot q_s) = \\sum_\\alpha P_\\alpha\\,\\partial "
           "f_\\alpha/\\partial q_s$, with Newton's law $\\dot f^+ = -e\\,\\dot f^-$ (for several rows Moreau's "
           "$0 \\le P_\\alpha \\perp \\dot f^+_\\alpha + e_\\alpha \\dot f^-_\\alpha \\ge 0$):\n\\begin{align*}\n";
    for (std::size_t k = 0; k < eqs.equations.size(); ++k)
        out << "\\Delta\\left(" << latex(display_form(eqs.equations[k].dT_dqdot)) << "\\right) &= "
            << latex(s.impulse_latex[k]) << "\\\\\n";
    for (const auto& v : s.rows)
        if (v.gap && v.G)
            out << latex(v.P_latex) << " &= " << latex(*v.impulse) << " \\quad (G = W M^{-1} W^T = " << latex(*v.G)
                << ")\\\\\n";
    out << "T^+ - T^- &= -\\frac{1 - e}{1 + e}\\,\\tfrac12\\,\\Delta\\dot q^T M\\,\\Delta\\dot q";
    for (const auto& v : s.rows)
        if (v.gap && v.carnot)
            out << "\\\\\nT^+ - T^-\\ (\\text{" << latex_escape(v.row->row.name) << "}) &= " << latex(*v.carnot);
    out << "\n\\end{align*}\n";
}

void print_unilateral_json(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    if (eqs.unilateral.empty()) return;
    const Section s = section_of(model, eqs);
    const auto js = [](const ex& e) { return json_string(text(e)); };
    out << "  \"unilateral\": {\"contact\": {\"method\": " << json_string(method_name(model.contact_method))
        << ", \"theta\": " << fmt::format("{}", model.theta) << "}, \"rows\": [";
    for (std::size_t a = 0; a < s.rows.size(); ++a) {
        const RowView& v = s.rows[a];
        const auto& r = v.row->row;
        out << (a ? ",\n    " : "\n    ") << "{\"name\": " << json_string(r.name) << ", \"kind\": "
            << json_string(v.gap ? "gap" : "velocity") << ", \"expression\": " << js(v.constraint)
            << ", \"restitution\": " << js(v.row->restitution) << ", \"virtual_displacements\": "
            << json_string(text(v.virtual_work) + " >= 0") << ", \"reaction\": [";
        for (std::size_t k = 0; k < v.reaction.size(); ++k) out << (k ? ", " : "") << js(v.reaction[k]);
        out << "], \"W\": [";
        for (std::size_t k = 0; k < r.W.size(); ++k) out << (k ? ", " : "") << js(r.W[k]);
        out << "], \"bias\": " << js(r.bias) << ", \"velocity\": " << js(r.velocity);
        const std::string lam = text(v.lambda), f = text(v.constraint);
        out << ", \"signorini\": [" << json_string(lam + " >= 0") << ", " << json_string(f + " >= 0") << ", "
            << json_string(lam + "*(" + f + ") = 0") << "]";
        if (v.G) out << ", \"G\": " << js(*v.G) << ", \"impulse\": " << js(*v.impulse) << ", \"carnot\": " << js(*v.carnot);
        out << "}";
    }
    out << "\n  ], \"equations\": [";
    for (std::size_t k = 0; k < eqs.equations.size(); ++k)
        out << (k ? ", " : "") << "{\"name\": " << json_string(eqs.equations[k].coordinate)
            << ", \"lhs\": " << js(eqs.equations[k].lhs) << ", \"rhs\": " << js(s.applied[k]) << "}";
    out << "]";
    if (s.any_gap) {
        out << ", \"impact\": [";
        for (std::size_t k = 0; k < eqs.equations.size(); ++k)
            out << (k ? ", " : "") << "{\"name\": " << json_string(eqs.equations[k].coordinate)
                << ", \"momentum\": " << js(eqs.equations[k].dT_dqdot) << ", \"jump\": " << js(s.impulse[k]) << "}";
        out << "], \"newton\": " << json_string("fdot_plus = -e*fdot_minus; several: 0 <= P _|_ fdot_plus + e*fdot_minus >= 0")
            << ", \"carnot\": " << json_string("T_plus - T_minus = -((1 - e)/(1 + e))*(1/2)*dqdot^T*M*dqdot");
    }
    out << "}";
}

}  // namespace eomc::report
