#include "report/derivation_printer.hpp"

#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "codegen/kernel_ir.hpp"
#include "mechanics/constraints/constraints.hpp"
#include "mechanics/first_order.hpp"
#include "mechanics/kinematics/rotations.hpp"
#include "mechanics/orbit/encke.hpp"
#include "mechanics/rigid/cyclic.hpp"
#include "mechanics/rigid/last_multiplier.hpp"
#include "report/inverse_printer.hpp"
#include "report/rigid_printer.hpp"
#include "report/unilateral_printer.hpp"
#include "support/json.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/expression_text.hpp"

namespace eomc::report {

using namespace eomc::symbolic;

using GiNaC::ex;
using model::Effect;

ex display_form(const ex& e) {
    // Expansion can explode (products of long sums); only accept it when it stays small.
    const std::size_t size = codegen::count_operations(e);
    if (size > 4000) return e;
    const ex expanded = e.expand();
    if (codegen::count_operations(expanded) > 2 * size + 8) return e;
    // sin² + cos² = 1, the one identity a reader expects to see used (R² sin²θ θ̇² +
    // R² cos²θ θ̇² is R² θ̇²); kept only when it shortens the expression.
    const GiNaC::ex u = GiNaC::wild(0);
    const ex trig = expanded.subs(GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2),
                                  GiNaC::subs_options::algebraic).expand();
    return codegen::count_operations(trig) < codegen::count_operations(expanded) ? trig : expanded;
}

// The inertial side with u̇ (q̈ and the quasi-velocities' rates) collected, for reading.
ex collected_lhs(const model::Model& model, const ex& lhs) {
    GiNaC::lst accelerations;
    for (const auto& c : model.coordinates) accelerations.append(c.q_ddot);
    for (const auto& v : model.quasi_velocities) accelerations.append(v.rate);
    return display_form(lhs).collect(accelerations, true);
}

namespace {

// Width on a terminal of UTF-8 text: one column per character, none for the combining
// marks that draw the dots of ṙ and q̇ (U+0300–U+036F).
std::size_t display_width(const std::string& s) {
    std::size_t width = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        if ((c & 0xC0) == 0x80) continue;  // continuation byte
        const bool combining = (c == 0xCC || (c == 0xCD && i + 1 < s.size() &&
                                              static_cast<unsigned char>(s[i + 1]) <= 0xAF));
        if (!combining) ++width;
    }
    return width;
}

std::string padded(const std::string& s, std::size_t width) {
    const std::size_t w = display_width(s);
    return w >= width ? s : s + std::string(width - w, ' ');
}

// The inertial term of an effect, in the seed's notation.
const char* effect_formula(Effect e) {
    switch (e) {
        case Effect::relative: return "ε_s(T_r) = Σ m (d*ṙ'/dt)·e_s";
        case Effect::translation: return "Σ m (v̇_o + ω × v_o)·e_s";
        case Effect::euler: return "Σ m (ω̇ × r')·e_s";
        case Effect::centrifugal: return "Σ m (ω × (ω × r'))·e_s";
        case Effect::coriolis: return "Σ m 2(ω × ṙ')·e_s";
    }
    return "";
}

const char* effect_formula_latex(Effect e) {
    switch (e) {
        case Effect::relative: return R"(\varepsilon_s(T_r) = \sum m\, \tilde{a}_r\cdot e_s)";
        case Effect::translation: return R"(\sum m\,(\dot v_o + \omega\times v_o)\cdot e_s)";
        case Effect::euler: return R"(\sum m\,(\dot\omega\times r')\cdot e_s)";
        case Effect::centrifugal: return R"(\sum m\,(\omega\times(\omega\times r'))\cdot e_s)";
        case Effect::coriolis: return R"(\sum m\, 2(\omega\times \dot r')\cdot e_s)";
    }
    return "";
}


// The applied side of a carrier balance: the load, plus the reaction when the component is held.
ex carrier_rhs(const mechanics::CarrierEquation& c) { return c.held ? c.applied + c.reaction : c.applied; }


std::string vector_text(const model::Vec3& v) {
    return fmt::format("({}, {}, {})", text(v[0]), text(v[1]), text(v[2]));
}

// Encke's f(q) on a symbol q, for all three formats.
ex encke_f_of_q() {
    static const GiNaC::symbol q("q");
    return mechanics::encke_f(q);
}

// An orbit scene: the central body, each disturbing function and acceleration, then
// R = Σ R_k and its gradient (the perturbing acceleration +∇R; Mei, ch. 2).
// The formulation's own steps (an element formulation's R in the elements, its partials, the
// equations in named partials); none for Cowell, whose equations follow below.
std::vector<mechanics::NamedExpression> formulation_steps(const model::Model& model, const mechanics::Equations& eqs,
                                                          std::string& description) {
    if (!model.orbit || model.orbit->kind == scene::OrbitFormulationKind::cowell) return {};
    mechanics::FirstOrderForm form = mechanics::first_order_form(model, eqs);
    description = form.description;
    return form.derivation;
}

// A step's name in LaTeX: "da/dt" → \dot{a}, "dR/da" → ∂R/∂a, anything else as text.
std::string latex_step_name(const std::string& name) {
    auto symbol = [](const std::string& s) {
        return s.size() == 1 ? s : "\\text{" + latex_escape(s) + "}";
    };
    if (name.size() >= 5 && name.rfind("d", 0) == 0 && name.substr(name.size() - 3) == "/dt")
        return "\\dot{" + symbol(name.substr(1, name.size() - 4)) + "}";
    if (name.rfind("dR/d", 0) == 0) return "\\frac{\\partial R}{\\partial " + symbol(name.substr(4)) + "}";
    return symbol(name);
}

void print_orbit_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    out << "Orbit (" << scene::name(o.kind) << "): inertial x, y, z about a central body with μ = " << text(o.mu)
        << ", radius " << text(o.radius) << "; r = " << text(o.r) << "\n";
    out << "Disturbing function R (acceleration = −μ r/r³ + ∇R + a)\n";
    if (o.disturbing.empty()) out << "  none\n";
    for (const auto& term : o.disturbing) out << "  R_" << term.effect << " = " << text(display_form(term.value)) << "\n";
    if (!o.disturbing.empty()) {
        for (std::size_t k = 0; k < 3; ++k)
            out << "  ∂R/∂" << c[k].name << " = "
                << text(display_form(symbolic::derivative(o.R, GiNaC::ex_to<GiNaC::symbol>(ex(c[k].q))))) << "\n";
    }
    if (o.kind == scene::OrbitFormulationKind::equinoctial)
        out << "Formulation equinoctial: the kernel integrates (p, f, g, h, k, L) by Gauss's equations (Betts eq. 6.37)\n"
               "  with the acceleration ∇R + a below, evaluated at the Cartesian state of the elements and taken\n"
               "  in radial, transverse and normal axes; the Cowell equations below give the same motion\n";
    if (o.kind == scene::OrbitFormulationKind::encke)
        out << "Formulation encke (Battin §9.3): the kernel integrates the deviation δ = r − ρ from a reference Kepler "
               "ellipse ρ(t)\n"
               "  δ̈ = −(μ/ρ³)(δ + f(q) r) + ∇R(r) + a(r, ṙ),  r = ρ + δ,  q = δ·(δ − 2r)/r²\n"
               "  f(q) = (1 + q)^(3/2) − 1 = "
            << text(encke_f_of_q())
            << "\n"
               "  ρ = a (cos E − e) P + a √(1 − e²) sin E Q,  E = kepler_E(M + n (t − t_ref), e),  n = √(μ/a³),\n"
               "  P, Q the periapsis and its normal in the plane of (i, Ω, ω); the reference (t_ref, a, e, i, Ω, ω, "
               "M)\n"
               "  is reset to the osculating orbit of r, ṙ when |δ| > "
            << o.rectify
            << " |ρ| (rectification); ∇R and a (below) are taken\n"
               "  at r, ṙ; the Cowell equations below give the same motion\n";
    std::string description;
    const auto steps = formulation_steps(model, eqs, description);
    if (!steps.empty()) {
        out << "Formulation " << scene::name(o.kind) << ": " << description << "\n";
        for (const auto& step : steps) out << "  " << step.name << " = " << text(display_form(step.value)) << "\n";
    }
    out << "Non-conservative accelerations a (generalized forces Q = a)\n";
    if (o.accelerations.empty()) out << "  none\n";
    for (const auto& a : o.accelerations)
        out << "  a_" << a.effect << " = " << vector_text({display_form(a.value[0]), display_form(a.value[1]), display_form(a.value[2])})
            << "\n";
}

// Σ_α λ_α W_αs: the reactions' generalized force on velocity s (Mei, §6.6; Lur'e, ch. 2).
ex reaction_term(const mechanics::Equations& eqs, std::size_t s) {
    ex sum = 0;
    for (const auto& row : eqs.constraints) sum += row.lambda * row.W[s];
    return sum;
}

const char* stabilization_name(mechanics::Stabilization s) {
    switch (s) {
        case mechanics::Stabilization::project: return "projection";
        case mechanics::Stabilization::baumgarte: return "Baumgarte";
        case mechanics::Stabilization::none: return "none";
    }
    return "?";
}

// The constraint rows, the equations with their reactions, and λ in closed form when small.
void print_constraints_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    if (eqs.constraints.empty()) return;
    const std::vector<std::string> u = model.velocity_names();
    out << "\nConstraints (ideal reactions: M u̇ − Wᵀλ = f, W u̇ = −bias, W_αs = ∂φ_α/∂u_s)\n";
    for (const auto& row : eqs.constraints) {
        out << "  " << row.name << " (" << (row.holonomic ? "holonomic" : "kinematic") << ", stabilisation "
            << stabilization_name(row.stabilization);
        if (row.stabilization == mechanics::Stabilization::baumgarte)
            out << fmt::format(" α = {}, β = {}", row.alpha, row.beta);
        out << ")\n";
        if (row.holonomic) out << "    f = " << text(display_form(row.position)) << " = 0\n";
        out << "    φ = " << text(display_form(row.velocity)) << (row.holonomic ? "  (= df/dt)" : " = 0") << "\n";
        out << "    W = [";
        for (std::size_t k = 0; k < row.W.size(); ++k) out << (k ? ", " : "") << text(display_form(row.W[k]));
        out << "]\n    bias = " << text(display_form(row.bias)) << "\n";
    }
    out << "  Lagrange's equations with the reactions ε_s(T) = Q_s + ε_s(V) + Σ λ_α W_αs\n";
    for (std::size_t s = 0; s < eqs.equations.size(); ++s) {
        const auto& eq = eqs.equations[s];
        out << "    s = " << eq.coordinate << ": " << text(collected_lhs(model, eq.lhs)) << " = "
            << (eq.rhs.is_zero() ? "" : text(display_form(eq.rhs)) + " + ") << text(reaction_term(eqs, s)) << "\n";
    }
    for (std::size_t s = eqs.equations.size(); s < u.size(); ++s)
        out << "    " << u[s] << ": M u̇ = f + " << text(reaction_term(eqs, s)) << "\n";
    std::string why;
    if (const auto lambda = mechanics::closed_form_multipliers(eqs, &why)) {
        out << "  Multipliers λ = −G⁻¹(W M⁻¹ f + bias), G = W M⁻¹ Wᵀ\n";
        for (std::size_t a = 0; a < lambda->size(); ++a)
            out << "    " << eqs.constraints[a].lambda.get_name() << " = " << text((*lambda)[a]) << "\n";
    } else {
        out << "  Multipliers: no closed form printed (" << why << "); the kernel solves for λ at each step\n";
    }
}

void print_text(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    out << "Scene " << model.name << (model.summary.empty() ? "" : " — " + model.summary) << "\n";
    out << "Coordinates q_s:";
    for (const auto& c : model.coordinates) out << " " << c.name;
    out << "\nParameters:";
    for (const auto& p : model.parameters) out << fmt::format(" {} = {}", p.name, p.value);
    out << "\n";
    if (model.carrier) {
        out << "Carrier frame o x'y'z' (all vectors in carrier axes):\n"
            << "  ω   = " << vector_text(model.carrier->angular_velocity) << "\n"
            << "  v_o = " << vector_text(model.carrier->pole_velocity) << "\n";
    } else if (eqs.from_particles) {
        out << "Frame: inertial (no carrier)\n";
    }
    if (model.free_carrier()) {
        const auto& c = *model.carrier;
        out << "  free carrier: mass " << text(c.mass) << ", inertia about o " << text(c.inertia) << ", mass centre "
            << vector_text(c.center) << "\n  applied: V = " << vector_text(c.resultant) << ", m⁰ = " << vector_text(c.moment)
            << "\n";
    }
    for (const auto& p : model.particles) {
        out << "  body " << p.name << ": m = " << text(p.mass) << ", r' = " << vector_text(p.position) << "\n";
        if (p.rigid) {
            const mechanics::BodyRotation rotation = mechanics::body_rotation(model, p);
            out << "    rigid: inertia about its mass centre " << text(p.inertia) << ", orientation R = " << text(rotation.R)
                << ",\n    angular velocity relative to the carrier (body axes) "
                << vector_text(rotation.relative_angular_velocity) << "\n";
        }
    }

    if (model.orbit) print_orbit_text(model, eqs, out);

    out << "\nKinetic energy\n";
    if (eqs.from_particles) {
        out << "  T = T_e + T_m + T_r\n"
            << "  T_e = ½ Σ m |v_o + ω × r'|²  = " << text(display_form(eqs.T_e)) << "\n"
            << "  T_m = Σ m (v_o + ω × r')·ṙ'  = " << text(display_form(eqs.T_m)) << "\n"
            << "  T_r = ½ Σ m |ṙ'|²            = " << text(display_form(eqs.T_r)) << "\n";
    } else {
        out << "  T = " << text(display_form(eqs.T)) << "\n";
    }
    out << "Potential\n  V = " << text(display_form(eqs.V)) << "\n";

    out << "\nGeneralized momenta ∂T/∂q̇_s\n";
    for (const auto& eq : eqs.equations)
        out << "  ∂T/∂" << eq.coordinate << "_dot = " << text(display_form(eq.dT_dqdot)) << "\n";

    out << "\nLagrange's equations ε_s(T) = Q_s + ε_s(V), ε_s = d/dt ∂/∂q̇_s − ∂/∂q_s\n";
    if (eqs.from_particles && eqs.has_carrier) {
        out << "with ε_s(T_e) + ε_s(T_m) split into the carrier's inertial effects (kept:";
        for (Effect e : model::all_effects)
            if (model.keeps(e)) out << " " << model::name(e);
        out << ")\n";
    }
    for (const auto& eq : eqs.equations) {
        out << "\n  s = " << eq.coordinate << "\n";
        for (const auto& term : eq.effects)
            out << "    " << padded(model::name(term.effect), 12) << " " << padded(effect_formula(term.effect), 34) << " = "
                << text(display_form(term.value)) << "\n";
        out << "    " << text(collected_lhs(model, eq.lhs)) << " = " << text(display_form(eq.rhs)) << "\n";
    }

    if (model.free_carrier()) {
        out << "\nFree carrier: P = ∂T/∂v_o, K = ∂T/∂ω (T of the whole system)\n"
            << "  P = (" << text(display_form(eqs.momentum[0])) << ", " << text(display_form(eqs.momentum[1])) << ", "
            << text(display_form(eqs.momentum[2])) << ")\n"
            << "  K = (" << text(display_form(eqs.angular_momentum[0])) << ", "
            << text(display_form(eqs.angular_momentum[1])) << ", " << text(display_form(eqs.angular_momentum[2]))
            << ")\n"
            << "  dP/dt + ω × P = V (1.1.14),  dK/dt + ω × K + v_o × P = m⁰ (1.1.15);\n"
            << "  a held component's equation gives the reaction R_i / N_i that holds it\n";
        for (const auto& c : eqs.carrier_equations)
            out << "    " << padded(c.name, 9) << (c.held ? "(held)   " : "(" + c.quasi_velocity + ")" + std::string(7 > c.quasi_velocity.size() ? 7 - c.quasi_velocity.size() : 0, ' '))
                << text(collected_lhs(model, c.lhs)) << " = " << text(display_form(carrier_rhs(c))) << "\n";
    }

    const std::vector<std::string> u = model.velocity_names();
    out << "\nEquations of motion M u̇ = f" << (model.free_carrier() ? ", u = (q̇, quasi-velocities)" : ", u = q̇")
        << "\n";
    for (std::size_t i = 0; i < u.size(); ++i) {
        out << "  M[" << u[i] << "] = [";
        for (std::size_t j = 0; j < u.size(); ++j)
            out << (j ? ", " : "") << text(display_form(eqs.mass_matrix(unsigned(i), unsigned(j))));
        out << "]\n";
    }
    for (std::size_t i = 0; i < u.size(); ++i) out << "  f[" << u[i] << "] = " << text(display_form(eqs.forcing[i])) << "\n";

    print_constraints_text(model, eqs, out);
    print_unilateral_text(model, eqs, out);

    out << "\nInvariants\n";
    if (eqs.invariants.empty()) out << "  none proven (L depends on t explicitly, or forces do work)\n";
    for (const auto& inv : eqs.invariants)
        out << "  " << inv.name << ": " << inv.description << "\n    = " << text(display_form(inv.value)) << "\n";
}

void print_latex(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    out << "\\documentclass[10pt]{article}\n\\usepackage[utf8]{inputenc}\n\\usepackage{amsmath}\n"
        << "\\allowdisplaybreaks\n\\begin{document}\n"
        << "\\section*{" << latex_escape(model.name) << "}\n";
    if (!model.summary.empty()) out << latex_escape(model.summary) << "\n\n";
    if (model.carrier) {
        out << "Carrier frame $o x'y'z'$, vectors in carrier axes:\n\\begin{align*}\n"
            << "\\omega &= \\left(" << latex(model.carrier->angular_velocity[0]) << ",\\ "
            << latex(model.carrier->angular_velocity[1]) << ",\\ " << latex(model.carrier->angular_velocity[2])
            << "\\right)\\\\\nv_o &= \\left(" << latex(model.carrier->pole_velocity[0]) << ",\\ "
            << latex(model.carrier->pole_velocity[1]) << ",\\ " << latex(model.carrier->pole_velocity[2])
            << "\\right)\n\\end{align*}\n";
    }
    if (model.orbit) {
        const model::Orbit& o = *model.orbit;
        out << "\\subsection*{Disturbing function}\nAcceleration $= -\\mu\\,\\mathbf r/r^3 + \\nabla R + \\mathbf a$, "
            << "$\\mu = " << latex(o.mu) << "$, $r = " << latex(o.r) << "$.\n\\begin{align*}\n";
        for (const auto& term : o.disturbing)
            out << "R_{\\text{" << latex_escape(term.effect) << "}} &= " << latex(display_form(term.value)) << "\\\\\n";
        for (std::size_t k = 0; k < 3; ++k)
            out << "\\frac{\\partial R}{\\partial " << latex(model.coordinates[k].q) << "} &= "
                << latex(display_form(symbolic::derivative(o.R, GiNaC::ex_to<GiNaC::symbol>(ex(model.coordinates[k].q)))))
                << (k < 2 || !o.accelerations.empty() ? "\\\\\n" : "\n");
        for (const auto& a : o.accelerations)
            out << "\\mathbf a_{\\text{" << latex_escape(a.effect) << "}} &= \\left(" << latex(display_form(a.value[0]))
                << ",\\ " << latex(display_form(a.value[1])) << ",\\ " << latex(display_form(a.value[2])) << "\\right)"
                << (&a == &o.accelerations.back() ? "\n" : "\\\\\n");
        out << "\\end{align*}\n";
        if (o.kind == scene::OrbitFormulationKind::encke)
            out << "\\subsection*{Encke's formulation}\nThe kernel integrates the deviation $\\boldsymbol\\delta = "
                   "\\mathbf r - \\boldsymbol\\rho$ from a reference Kepler ellipse $\\boldsymbol\\rho(t)$ "
                   "(Battin \\S 9.3), rectified when $|\\boldsymbol\\delta| > "
                << o.rectify
                << "\\,|\\boldsymbol\\rho|$:\n\\begin{align*}\n"
                   "\\ddot{\\boldsymbol\\delta} &= -\\frac{\\mu}{\\rho^3}\\left(\\boldsymbol\\delta + f(q)\\,"
                   "\\mathbf r\\right) + \\nabla R(\\mathbf r) + \\mathbf a(\\mathbf r, \\dot{\\mathbf r}), \\quad "
                   "\\mathbf r = \\boldsymbol\\rho + \\boldsymbol\\delta\\\\\n"
                   "q &= \\frac{\\boldsymbol\\delta\\cdot(\\boldsymbol\\delta - 2\\mathbf r)}{r^2}, \\quad "
                   "f(q) = (1 + q)^{3/2} - 1 = "
                << latex(encke_f_of_q())
                << "\\\\\n"
                   "\\boldsymbol\\rho &= a(\\cos E - e)\\,\\mathbf P + a\\sqrt{1 - e^2}\\,\\sin E\\,\\mathbf Q, \\quad "
                   "E - e\\sin E = M + n(t - t_{\\text{ref}}), \\quad n = \\sqrt{\\mu/a^3}\n\\end{align*}\n";
        std::string description;
        const auto steps = formulation_steps(model, eqs, description);
        if (!steps.empty()) {
            out << "\\subsection*{Formulation: " << latex_escape(std::string(scene::name(o.kind))) << "}\n" << latex_escape(description)
                << "\n\\begin{align*}\n";
            for (std::size_t k = 0; k < steps.size(); ++k)
                out << latex_step_name(steps[k].name) << " &= " << latex(display_form(steps[k].value))
                    << (k + 1 < steps.size() ? "\\\\\n" : "\n");
            out << "\\end{align*}\n";
        }
    }
    out << "\\subsection*{Kinetic energy}\n\\begin{align*}\n";
    if (eqs.from_particles) {
        out << "T &= T_e + T_m + T_r\\\\\n"
            << "T_e &= \\tfrac12\\sum m\\,|v_o + \\omega\\times r'|^2 = " << latex(display_form(eqs.T_e)) << "\\\\\n"
            << "T_m &= \\sum m\\,(v_o + \\omega\\times r')\\cdot\\dot r' = " << latex(display_form(eqs.T_m)) << "\\\\\n"
            << "T_r &= \\tfrac12\\sum m\\,|\\dot r'|^2 = " << latex(display_form(eqs.T_r)) << "\\\\\n";
    } else {
        out << "T &= " << latex(display_form(eqs.T)) << "\\\\\n";
    }
    out << "V &= " << latex(display_form(eqs.V)) << "\n\\end{align*}\n";

    out << "\\subsection*{Lagrange's equations}\n"
        << "$\\varepsilon_s(T) = Q_s + \\varepsilon_s(V)$, with "
        << "$\\varepsilon_s = \\frac{d}{dt}\\frac{\\partial}{\\partial\\dot q_s} - \\frac{\\partial}{\\partial q_s}$.\n";
    for (const auto& eq : eqs.equations) {
        out << "\\paragraph{$s = " << latex(model.coordinates[std::size_t(&eq - eqs.equations.data())].q)
            << "$}\n\\begin{align*}\n";
        out << "\\frac{\\partial T}{\\partial \\dot q_s} &= " << latex(display_form(eq.dT_dqdot)) << "\\\\\n";
        for (const auto& term : eq.effects)
            out << "\\text{" << model::name(term.effect) << "}: \\ " << effect_formula_latex(term.effect) << " &= "
                << latex(display_form(term.value)) << "\\\\\n";
        out << latex(collected_lhs(model, eq.lhs)) << " &= " << latex(display_form(eq.rhs)) << "\n\\end{align*}\n";
    }
    if (model.free_carrier()) {
        out << "\\subsection*{Free carrier}\n$P = \\partial T/\\partial v_o$, $K = \\partial T/\\partial\\omega$; "
            << "$\\dot P + \\omega\\times P = V$, $\\dot K + \\omega\\times K + v_o\\times P = m^0$ "
            << "(a held component's equation gives its reaction).\n\\begin{align*}\n";
        for (const auto& c : eqs.carrier_equations)
            out << "\\text{" << latex_escape(c.name) << "}: \\ " << latex(collected_lhs(model, c.lhs)) << " &= "
                << latex(display_form(carrier_rhs(c))) << (&c == &eqs.carrier_equations.back() ? "\n" : "\\\\\n");
        out << "\\end{align*}\n";
    }
    if (!eqs.constraints.empty()) {
        out << "\\subsection*{Constraints}\nIdeal reactions: $M\\dot u - W^T\\lambda = f$, $W\\dot u = "
               "-\\mathrm{bias}$, $W_{\\alpha s} = \\partial\\varphi_\\alpha/\\partial u_s$.\n\\begin{align*}\n";
        for (const auto& row : eqs.constraints) {
            const std::string name = "\\text{" + latex_escape(row.name) + "}";
            if (row.holonomic) out << "f_{" << name << "} &= " << latex(display_form(row.position)) << " = 0\\\\\n";
            out << "\\varphi_{" << name << "} &= " << latex(display_form(row.velocity)) << "\\\\\n";
            out << "W_{" << name << "} &= \\left(";
            for (std::size_t k = 0; k < row.W.size(); ++k) out << (k ? ",\\ " : "") << latex(display_form(row.W[k]));
            out << "\\right)\\\\\n\\mathrm{bias}_{" << name << "} &= " << latex(display_form(row.bias)) << "\\\\\n";
        }
        for (std::size_t s = 0; s < eqs.equations.size(); ++s)
            out << latex(collected_lhs(model, eqs.equations[s].lhs)) << " &= "
                << (eqs.equations[s].rhs.is_zero() ? "" : latex(display_form(eqs.equations[s].rhs)) + " + ")
                << latex(reaction_term(eqs, s)) << "\\\\\n";
        std::string why;
        const auto lambda = mechanics::closed_form_multipliers(eqs, &why);
        if (lambda)
            for (std::size_t a = 0; a < lambda->size(); ++a)
                out << latex(eqs.constraints[a].lambda) << " &= " << latex((*lambda)[a]) << "\\\\\n";
        out << "\\end{align*}\n";
        if (!lambda) out << "No closed form of $\\lambda$ printed (" << latex_escape(why) << ").\n";
    }
    print_unilateral_latex(model, eqs, out);
    out << "\\subsection*{Invariants}\n";
    if (eqs.invariants.empty()) out << "None proven.\n";
    for (const auto& inv : eqs.invariants)
        out << latex_escape(inv.name) << ":\n\\begin{align*}\nh &= " << latex(display_form(inv.value))
            << "\n\\end{align*}\n";
    out << "\\end{document}\n";
}

std::string json_ex(const ex& e) { return json_string(text(e)); }

void print_json(const model::Model& model, const mechanics::Equations& eqs, std::ostream& out) {
    const std::size_t n = model.coordinates.size();
    const std::vector<std::string> u = model.velocity_names();
    out << "{\n  \"scene\": " << json_string(model.name) << ",\n  \"coordinates\": [";
    for (std::size_t i = 0; i < n; ++i) out << (i ? ", " : "") << json_string(model.coordinates[i].name);
    out << "],\n  \"parameters\": {";
    for (std::size_t i = 0; i < model.parameters.size(); ++i)
        out << (i ? ", " : "") << json_string(model.parameters[i].name) << ": "
            << fmt::format("{}", model.parameters[i].value);
    out << "},\n  \"kinetic_energy\": {\"T\": " << json_ex(eqs.T);
    if (eqs.from_particles)
        out << ", \"T_e\": " << json_ex(eqs.T_e) << ", \"T_m\": " << json_ex(eqs.T_m) << ", \"T_r\": " << json_ex(eqs.T_r);
    out << "},\n  \"potential\": " << json_ex(eqs.V) << ",\n";
    if (model.orbit) {
        const model::Orbit& o = *model.orbit;
        out << "  \"orbit\": {\"formulation\": " << json_string(std::string(scene::name(o.kind))) << ", \"mu\": " << json_ex(o.mu)
            << ", \"radius\": " << json_ex(o.radius) << ", \"disturbing_function\": {";
        for (std::size_t k = 0; k < o.disturbing.size(); ++k)
            out << (k ? ", " : "") << json_string(o.disturbing[k].effect) << ": " << json_ex(o.disturbing[k].value);
        out << "}, \"R\": " << json_ex(o.R) << ", \"gradient\": [";
        for (std::size_t k = 0; k < 3; ++k)
            out << (k ? ", " : "")
                << json_ex(symbolic::derivative(o.R, GiNaC::ex_to<GiNaC::symbol>(ex(model.coordinates[k].q))));
        out << "], \"accelerations\": {";
        for (std::size_t k = 0; k < o.accelerations.size(); ++k)
            out << (k ? ", " : "") << json_string(o.accelerations[k].effect) << ": [" << json_ex(o.accelerations[k].value[0])
                << ", " << json_ex(o.accelerations[k].value[1]) << ", " << json_ex(o.accelerations[k].value[2]) << "]";
        std::string description;
        const auto steps = formulation_steps(model, eqs, description);
        out << "}, \"formulation_steps\": [";
        for (std::size_t k = 0; k < steps.size(); ++k)
            out << (k ? ", " : "") << "{\"name\": " << json_string(steps[k].name) << ", \"value\": " << json_ex(steps[k].value)
                << "}";
        out << "]";
        if (o.kind == scene::OrbitFormulationKind::encke)
            out << ", \"encke\": {\"equation\": "
                << json_string("delta_ddot = -(mu/rho^3)*(delta + f(q)*r) + grad R(r) + a(r, r_dot), r = rho + delta")
                << ", \"q\": " << json_string("delta.(delta - 2*r)/r^2") << ", \"f\": " << json_ex(encke_f_of_q())
                << ", \"reference\": "
                << json_string("rho = a*(cos(E) - e)*P + a*sqrt(1 - e^2)*sin(E)*Q, E = kepler_E(M + n*(t - t_ref), e), "
                               "n = sqrt(mu/a^3)")
                << ", \"rectify\": " << fmt::format("{}", o.rectify) << "}";
        out << "},\n";
    }
    out << "  \"equations\": [\n";
    for (std::size_t s = 0; s < n; ++s) {
        const auto& eq = eqs.equations[s];
        out << "    {\"name\": " << json_string(eq.coordinate) << ", \"lhs\": " << json_ex(eq.lhs)
            << ", \"rhs\": " << json_ex(eq.rhs) << ", \"effects\": {";
        for (std::size_t k = 0; k < eq.effects.size(); ++k)
            out << (k ? ", " : "") << json_string(model::name(eq.effects[k].effect)) << ": "
                << json_ex(eq.effects[k].value);
        out << "}}" << (s + 1 < n || !eqs.carrier_equations.empty() ? "," : "") << "\n";
    }
    // A free carrier's balances: lhs the inertial side, rhs the applied side with the
    // reaction symbol of a held component.
    for (std::size_t k = 0; k < eqs.carrier_equations.size(); ++k) {
        const auto& c = eqs.carrier_equations[k];
        out << "    {\"name\": " << json_string(c.name) << ", \"lhs\": " << json_ex(c.lhs) << ", \"rhs\": "
            << json_ex(carrier_rhs(c)) << ", \"held\": " << (c.held ? "true" : "false");
        if (c.held) out << ", \"reaction\": " << json_string(c.reaction.get_name());
        else out << ", \"quasi_velocity\": " << json_string(c.quasi_velocity);
        out << "}" << (k + 1 < eqs.carrier_equations.size() ? "," : "") << "\n";
    }
    out << "  ],\n  \"velocities\": [";
    for (std::size_t i = 0; i < u.size(); ++i) out << (i ? ", " : "") << json_string(u[i]);
    out << "],\n  \"mass_matrix\": [";
    for (std::size_t i = 0; i < u.size(); ++i) {
        out << (i ? ", " : "") << "[";
        for (std::size_t j = 0; j < u.size(); ++j) out << (j ? ", " : "") << json_ex(eqs.mass_matrix(unsigned(i), unsigned(j)));
        out << "]";
    }
    out << "],\n  \"forcing\": [";
    for (std::size_t i = 0; i < u.size(); ++i) out << (i ? ", " : "") << json_ex(eqs.forcing[i]);
    if (!eqs.constraints.empty()) {
        const auto lambda = mechanics::closed_form_multipliers(eqs);
        out << "],\n  \"constraints\": [";
        for (std::size_t a = 0; a < eqs.constraints.size(); ++a) {
            const auto& row = eqs.constraints[a];
            out << (a ? ",\n    " : "\n    ") << "{\"name\": " << json_string(row.name) << ", \"kind\": "
                << json_string(row.holonomic ? "holonomic" : "kinematic") << ", \"expression\": "
                << json_ex(row.holonomic ? row.position : row.velocity) << ", \"W\": [";
            for (std::size_t k = 0; k < row.W.size(); ++k) out << (k ? ", " : "") << json_ex(row.W[k]);
            out << "], \"bias\": " << json_ex(row.bias);
            if (lambda) out << ", \"lambda\": " << json_ex((*lambda)[a]);
            out << "}";
        }
        out << "\n  ";
    }
    out << "],\n  \"invariants\": {";
    for (std::size_t k = 0; k < eqs.invariants.size(); ++k)
        out << (k ? ", " : "") << json_string(eqs.invariants[k].name) << ": " << json_ex(eqs.invariants[k].value);
    out << "}\n}\n";
}

void print_canonical_text(const model::Model& model, const mechanics::CanonicalEquations& c, std::ostream& out) {
    out << "\nCanonical equations (Hamilton), p = ∂L/∂q̇, H = Σ p q̇ − L\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << "  " << c.p[s].get_name() << " = " << text(display_form(c.momentum[s])) << ",   "
            << model.coordinates[s].name << "_dot = " << text(display_form(c.velocity[s])) << "\n";
    out << "  H = " << text(display_form(c.H)) << "\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << "  d" << model.coordinates[s].name << "/dt = ∂H/∂" << c.p[s].get_name() << " = "
            << text(display_form(c.q_rate[s])) << "\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << "  d" << c.p[s].get_name() << "/dt = −∂H/∂" << model.coordinates[s].name << " + Q = "
            << text(display_form(c.p_rate[s])) << "\n";
    out << "  H is " << (c.conserved ? "conserved (the Jacobi integral)" : "not proven conserved") << "\n";
}

void print_canonical_latex(const model::Model& model, const mechanics::CanonicalEquations& c, std::ostream& out) {
    out << "\\subsection*{Canonical equations}\n\\begin{align*}\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << c.p[s].get_name() << " &= " << latex(display_form(c.momentum[s])) << "\\\\\n";
    out << "H &= " << latex(display_form(c.H)) << "\\\\\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << "\\dot{" << latex(model.coordinates[s].q) << "} &= " << latex(display_form(c.q_rate[s])) << "\\\\\n";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << "\\dot p_{" << latex_escape(model.coordinates[s].name) << "} &= " << latex(display_form(c.p_rate[s]))
            << (s + 1 < c.p.size() ? "\\\\\n" : "\n");
    out << "\\end{align*}\n";
}

void print_canonical_json(const mechanics::CanonicalEquations& c, std::ostream& out) {
    out << "  \"canonical\": {\"momenta\": {";
    for (std::size_t s = 0; s < c.p.size(); ++s)
        out << (s ? ", " : "") << json_string(c.p[s].get_name()) << ": " << json_ex(c.momentum[s]);
    out << "}, \"H\": " << json_ex(c.H) << ", \"q_rates\": [";
    for (std::size_t s = 0; s < c.p.size(); ++s) out << (s ? ", " : "") << json_ex(c.q_rate[s]);
    out << "], \"p_rates\": [";
    for (std::size_t s = 0; s < c.p.size(); ++s) out << (s ? ", " : "") << json_ex(c.p_rate[s]);
    out << "], \"conserved\": " << (c.conserved ? "true" : "false") << "}\n";
}


// The section "Integrals and reduction" (Mei, ch. 5), for a model given by its energies: the
// cyclic coordinates and their momenta, Routh's reduction, Jacobi's last multiplier and count,
// the singular sets of M. Computed here, for the report only: Routh's β symbols and the
// simplifications make symbols, which must not precede the kernel's lowering.
struct Reduction {
    std::vector<mechanics::rigid::CyclicCoordinate> cyclic;
    mechanics::rigid::RouthReduction routh;
    mechanics::rigid::LastMultiplier multiplier;
    mechanics::rigid::JacobiCount count;
};

Reduction reduction_of(const model::Model& model, const mechanics::Equations& eqs) {
    Reduction r;
    r.cyclic = mechanics::rigid::cyclic_coordinates(model, eqs);
    r.routh = mechanics::rigid::routh_reduction(model, eqs, r.cyclic);
    r.multiplier = mechanics::rigid::last_multiplier(model, eqs);
    std::size_t proven = 0;
    for (const auto& c : r.cyclic) proven += c.proven ? 1 : 0;
    r.count = mechanics::rigid::jacobi_count(model, eqs, r.multiplier, proven);
    return r;
}

const char* multiplier_verdict(mechanics::rigid::MultiplierStatus s) {
    switch (s) {
        case mechanics::rigid::MultiplierStatus::proven: return "a last multiplier (proven)";
        case mechanics::rigid::MultiplierStatus::not_multiplier: return "not a last multiplier";
        case mechanics::rigid::MultiplierStatus::undecided: return "not proven a last multiplier (undecided)";
        case mechanics::rigid::MultiplierStatus::not_applicable: return "not examined";
    }
    return "";
}

std::string joined(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

// Jacobi's count in words (the same sentence in every format).
std::string jacobi_sentence(const mechanics::rigid::JacobiCount& j, const mechanics::rigid::LastMultiplier& m) {
    if (m.status == mechanics::rigid::MultiplierStatus::not_applicable) return "not formed (" + m.reason + ")";
    std::string s = fmt::format(
        "{} first-order equations ({}); {} independent integral{} known ({}); with a last multiplier Jacobi's "
        "theorem asks {} (2n − {}): {} missing",
        j.equations, j.autonomous ? "autonomous" : "F depends on t", j.integrals.size(),
        j.integrals.size() == 1 ? "" : "s", joined(j.integrals), j.needed, j.autonomous ? 2 : 1, j.missing);
    if (j.cyclic > 0)
        s += fmt::format("; Routh's reduction by the {} cyclic coordinate{} leaves {} equations, which ask {} with "
                         "the {} other integral{}: {} missing (the cyclic coordinates then follow by quadratures)",
                         j.cyclic, j.cyclic == 1 ? "" : "s", j.reduced_equations, j.reduced_needed,
                         j.integrals.size() - j.cyclic, j.integrals.size() - j.cyclic == 1 ? "" : "s",
                         j.reduced_missing);
    s += !j.multiplier ? "; no last multiplier is known, so the count gives no quadrature"
         : j.integrable ? "; integrable by quadratures"
                        : "; not shown integrable by quadratures";
    return s;
}

void print_reduction_text(const model::Model& model, const mechanics::Equations& eqs, const Reduction& r,
                          std::ostream& out) {
    out << "\nIntegrals and reduction (Mei, ch. 5)\n";
    out << "  Cyclic coordinates (absent from L = T − V and the forces, Q_c = 0):";
    if (r.cyclic.empty()) out << " none";
    out << "\n";
    for (const auto& c : r.cyclic)
        out << "    " << c.coordinate << ": p_" << c.coordinate << " = ∂L/∂" << c.coordinate
            << "_dot = " << text(display_form(c.momentum)) << "  ("
            << (c.proven ? "conserved, proven along the equations" : "not proven constant: not kept") << ")\n";
    if (r.routh.done) {
        out << "  Routh's reduction, R = L − Σ β_c q̇_c with q̇_c from p_c = β_c (Whittaker §38's sign):\n";
        for (std::size_t k = 0; k < r.routh.cyclic.size(); ++k)
            out << "    " << r.routh.cyclic[k].coordinate << "_dot = " << text(display_form(r.routh.velocities[k]))
                << "\n";
        out << "    R = " << text(r.routh.routhian) << "\n"
            << "    reduced equations d/dt ∂R/∂q̇_r − ∂R/∂q_r = Q_r:\n";
        for (const auto& e : r.routh.equations)
            out << "      " << e.coordinate << ": " << text(e.lhs) << " = " << text(display_form(e.rhs)) << "\n";
    } else if (!r.cyclic.empty()) {
        out << "  Routh's reduction: not formed (" << r.routh.reason << ")\n";
    }
    out << "  Jacobi's last multiplier μ = det M";
    if (r.multiplier.status == mechanics::rigid::MultiplierStatus::not_applicable) {
        out << ": " << multiplier_verdict(r.multiplier.status) << " (" << r.multiplier.reason << ")\n";
    } else {
        out << " = " << text(display_form(r.multiplier.mu)) << "\n    " << multiplier_verdict(r.multiplier.status)
            << ": " << r.multiplier.reason << "\n";
    }
    out << "  Jacobi's count: " << jacobi_sentence(r.count, r.multiplier) << "\n";
    out << "  Singular sets of M (det M = 0; the coordinates fail there, a simulation stops before them):";
    if (eqs.singular_sets.empty()) out << " none";
    out << "\n";
    for (const auto& set : eqs.singular_sets)
        out << "    " << set.condition << "  (" << text(set.indicator) << " to the power " << set.order
            << " divides det M)\n";
    (void)model;
}

void print_reduction_latex(const model::Model& model, const mechanics::Equations& eqs, const Reduction& r,
                           std::ostream& out) {
    out << "\\subsection*{Integrals and reduction}\nCyclic coordinates (absent from $L = T - V$ and the forces):";
    if (r.cyclic.empty()) out << " none.\n";
    else out << "\n\\begin{align*}\n";
    for (const auto& c : r.cyclic)
        out << "p_{" << latex(model.coordinates[c.index].q) << "} &= " << latex(display_form(c.momentum))
            << " &&\\text{" << (c.proven ? "conserved (proven)" : "not proven constant") << "}"
            << (&c == &r.cyclic.back() ? "\n" : "\\\\\n");
    if (!r.cyclic.empty()) out << "\\end{align*}\n";
    if (r.routh.done) {
        out << "Routh's function $R = L - \\sum_c \\beta_c \\dot q_c$, $\\dot q_c$ from $p_c = \\beta_c$:\n"
               "\\begin{align*}\n";
        for (std::size_t k = 0; k < r.routh.cyclic.size(); ++k)
            out << "\\dot{" << latex(model.coordinates[r.routh.cyclic[k].index].q) << "} &= "
                << latex(display_form(r.routh.velocities[k])) << "\\\\\n";
        out << "R &= " << latex(r.routh.routhian);
        for (const auto& e : r.routh.equations)
            out << "\\\\\n\\varepsilon_{" << latex_escape(e.coordinate) << "}(R) = " << latex(e.lhs) << " &= "
                << latex(display_form(e.rhs));
        out << "\n\\end{align*}\n";
    } else if (!r.cyclic.empty()) {
        out << "Routh's reduction not formed (" << latex_escape(r.routh.reason) << ").\n";
    }
    out << "\nJacobi's last multiplier $\\mu = \\det M$";
    if (r.multiplier.status != mechanics::rigid::MultiplierStatus::not_applicable)
        out << "$\\; = " << latex(display_form(r.multiplier.mu)) << "$";
    out << ": " << latex_escape(multiplier_verdict(r.multiplier.status)) << " (" << latex_escape(r.multiplier.reason)
        << ").\n\nJacobi's count: " << latex_escape(jacobi_sentence(r.count, r.multiplier)) << ".\n\nSingular sets of $M$:";
    if (eqs.singular_sets.empty()) out << " none.\n";
    else out << "\n\\begin{align*}\n";
    for (const auto& set : eqs.singular_sets)
        out << latex(set.indicator) << " &= 0 &&\\text{(order " << set.order << " in $\\det M$)}"
            << (&set == &eqs.singular_sets.back() ? "\n" : "\\\\\n");
    if (!eqs.singular_sets.empty()) out << "\\end{align*}\n";
}

void print_reduction_json(const mechanics::Equations& eqs, const Reduction& r, std::ostream& out) {
    out << "  \"reduction\": {\"cyclic\": [";
    for (std::size_t k = 0; k < r.cyclic.size(); ++k)
        out << (k ? ", " : "") << "{\"coordinate\": " << json_string(r.cyclic[k].coordinate)
            << ", \"momentum\": " << json_string(text(r.cyclic[k].momentum))
            << ", \"proven\": " << (r.cyclic[k].proven ? "true" : "false") << "}";
    out << "], \"routhian\": ";
    if (r.routh.done) {
        out << "{\"R\": " << json_string(text(r.routh.routhian)) << ", \"beta\": [";
        for (std::size_t k = 0; k < r.routh.beta.size(); ++k) out << (k ? ", " : "") << json_string(r.routh.beta[k].get_name());
        out << "], \"velocities\": {";
        for (std::size_t k = 0; k < r.routh.cyclic.size(); ++k)
            out << (k ? ", " : "") << json_string(r.routh.cyclic[k].coordinate + "_dot") << ": "
                << json_string(text(r.routh.velocities[k]));
        out << "}, \"equations\": [";
        for (std::size_t k = 0; k < r.routh.equations.size(); ++k)
            out << (k ? ", " : "") << "{\"coordinate\": " << json_string(r.routh.equations[k].coordinate)
                << ", \"lhs\": " << json_string(text(r.routh.equations[k].lhs))
                << ", \"rhs\": " << json_string(text(r.routh.equations[k].rhs)) << "}";
        out << "]}";
    } else {
        out << "null";
    }
    const char* status = "";
    switch (r.multiplier.status) {
        case mechanics::rigid::MultiplierStatus::proven: status = "proven"; break;
        case mechanics::rigid::MultiplierStatus::not_multiplier: status = "not_multiplier"; break;
        case mechanics::rigid::MultiplierStatus::undecided: status = "undecided"; break;
        case mechanics::rigid::MultiplierStatus::not_applicable: status = "not_applicable"; break;
    }
    out << ", \"last_multiplier\": {\"mu\": "
        << (r.multiplier.status == mechanics::rigid::MultiplierStatus::not_applicable ? std::string("null")
                                                                                        : json_string(text(r.multiplier.mu)))
        << ", \"status\": " << json_string(status) << ", \"reason\": " << json_string(r.multiplier.reason) << "}";
    const auto& j = r.count;
    out << ", \"jacobi_count\": {\"equations\": " << j.equations << ", \"autonomous\": " << (j.autonomous ? "true" : "false")
        << ", \"integrals\": [";
    for (std::size_t k = 0; k < j.integrals.size(); ++k) out << (k ? ", " : "") << json_string(j.integrals[k]);
    out << "], \"needed\": " << j.needed << ", \"missing\": " << j.missing << ", \"cyclic\": " << j.cyclic
        << ", \"reduced_equations\": " << j.reduced_equations << ", \"reduced_needed\": " << j.reduced_needed
        << ", \"reduced_missing\": " << j.reduced_missing << ", \"multiplier\": " << (j.multiplier ? "true" : "false")
        << ", \"integrable\": " << (j.integrable ? "true" : "false") << "}, \"singular_sets\": [";
    for (std::size_t k = 0; k < eqs.singular_sets.size(); ++k)
        out << (k ? ", " : "") << "{\"condition\": " << json_string(eqs.singular_sets[k].condition)
            << ", \"indicator\": " << json_string(text(eqs.singular_sets[k].indicator))
            << ", \"order\": " << eqs.singular_sets[k].order << "}";
    out << "]}\n";
}

}  // namespace

void print_derivation(const model::Model& model, const mechanics::Equations& eqs, DerivationFormat format,
                      std::ostream& out, const mechanics::CanonicalEquations* canonical) {
    if (model.newtonian) return print_newtonian_derivation(model, eqs, format, out);  // equations given, not energies
    // A rigid body's own chain (Euler's and Poisson's equations, its integrals); in Euler angles it is
    // a Lagrangian system and prints as one.
    if (model.rigid && model.rigid->formulation != scene::RigidFormulationKind::euler_angles)
        return print_rigid_derivation(model, eqs, format, out);
    std::optional<Reduction> reduction;
    if (model.lagrangian_in_coordinates()) reduction = reduction_of(model, eqs);
    switch (format) {
        case DerivationFormat::text:
            print_text(model, eqs, out);
            if (reduction) print_reduction_text(model, eqs, *reduction, out);
            if (canonical) print_canonical_text(model, *canonical, out);
            return;
        case DerivationFormat::latex: {
            std::ostringstream body;
            print_latex(model, eqs, body);
            std::string doc = body.str();
            if (reduction) {
                std::ostringstream extra;
                print_reduction_latex(model, eqs, *reduction, extra);
                doc.insert(doc.rfind("\\end{document}"), extra.str());
            }
            if (canonical) {
                std::ostringstream extra;
                print_canonical_latex(model, *canonical, extra);
                doc.insert(doc.rfind("\\end{document}"), extra.str());
            }
            out << doc;
            return;
        }
        case DerivationFormat::json: {
            std::ostringstream body;
            print_json(model, eqs, body);
            std::string doc = body.str();
            if (!eqs.unilateral.empty()) {
                std::ostringstream extra;
                print_unilateral_json(model, eqs, extra);
                doc.insert(doc.rfind("\n}"), ",\n" + extra.str());
            }
            if (reduction) {
                std::ostringstream extra;
                print_reduction_json(eqs, *reduction, extra);
                const std::size_t end = doc.rfind("\n}");
                doc.insert(end, ",\n" + extra.str().substr(0, extra.str().size() - 1));
            }
            if (canonical) {
                std::ostringstream extra;
                print_canonical_json(*canonical, extra);
                const std::size_t end = doc.rfind("\n}");
                doc.insert(end, ",\n" + extra.str().substr(0, extra.str().size() - 1));
            }
            out << doc;
            return;
        }
    }
}

}  // namespace eomc::report
