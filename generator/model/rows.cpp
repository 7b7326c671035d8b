// The bilateral and unilateral rows ([[constraint]], [[unilateral]]; Mei, ch. 6): each parsed,
// checked to be linear in the rates where it holds them, and checked at the initial state.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "eomc/runtime/contact/method.hpp"
#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

// The magnitude of what cancels in e's value: Σ|term| over a sum, the product of the factors'
// magnitudes over a product, |base|'s magnitude to a positive power; |value| elsewhere. For
// (x² + y² − l²)² it is (x² + y² + l²)², so a square of a residual at round-off is judged by the
// size of its terms and not by its own (Higham, Accuracy and Stability of Numerical Algorithms,
// 2nd ed., §3.1: the rounding of a computed sum is bounded by ε Σ|term|).
static double magnitude(const ex& e, const GiNaC::exmap& values) {
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
        const bool sum = GiNaC::is_a<GiNaC::add>(e);
        double out = sum ? 0.0 : 1.0;
        for (const ex& term : e) out = sum ? out + magnitude(term, values) : out * magnitude(term, values);
        return out;
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
        const GiNaC::numeric exponent = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
        if (exponent.is_real() && exponent.is_positive()) return std::pow(magnitude(e.op(0), values), exponent.to_double());
    }
    const auto value = real_value(e, values);
    return value ? std::abs(value->to_double()) : std::numeric_limits<double>::quiet_NaN();
}

std::pair<double, double> value_and_magnitude(const ex& e, const GiNaC::exmap& values) {
    const auto value = real_value(e, values);
    return {value ? value->to_double() : std::numeric_limits<double>::quiet_NaN(), magnitude(e, values)};
}

GiNaC::exmap initial_values(const Model& model) {
    GiNaC::exmap values = model.parameter_defaults();
    values[model.t] = 0;
    for (const auto& c : model.coordinates) {
        values[c.q] = GiNaC::numeric(c.initial);
        values[c.q_dot] = GiNaC::numeric(c.rate);
    }
    for (const auto& v : model.quasi_velocities) values[v.symbol] = GiNaC::numeric(v.initial);
    if (model.rigid) {
        for (std::size_t i = 0; i < 3; ++i) {
            values[model.rigid->omega[i]] = GiNaC::numeric(model.rigid->omega0[i]);
            values[model.rigid->gamma[i]] = GiNaC::numeric(model.rigid->vertical0[i]);
        }
        if (model.rigid->attitude)
            for (std::size_t k = 0; k < 4; ++k) values[(*model.rigid->attitude)[k]] = GiNaC::numeric(model.rigid->attitude0[k]);
    }
    return values;
}

// Whether `e` vanishes identically in t, q, q̇ (parameters at their defaults): GiNaC's own zero
// test, else zero to round-off at three fixed pseudo-random states. Numbers, not normal(): a
// scene's power of a sum would make normal() expand it.
static bool vanishes_identically(const ex& e, const Model& model) {
    if (e.is_zero()) return true;
    std::mt19937_64 random(0x11ea4);  // fixed: the same scene gets the same verdict
    std::uniform_real_distribution<double> uniform(0.5, 1.5);
    for (int k = 0; k < 3; ++k) {
        GiNaC::exmap values = model.parameter_defaults();
        values[model.t] = GiNaC::numeric(uniform(random));
        for (const auto& c : model.coordinates) {
            values[c.q] = GiNaC::numeric(uniform(random));
            values[c.q_dot] = GiNaC::numeric(uniform(random));
        }
        for (const auto& v : model.quasi_velocities) values[v.symbol] = GiNaC::numeric(uniform(random));
        const auto [value, size] = value_and_magnitude(e, values);
        // Not finite (a pole, an overflow): not shown to vanish.
        if (!std::isfinite(value) || !std::isfinite(size) || std::abs(value) > 1e-9 * (1.0 + size)) return false;
    }
    return true;
}

// The velocities u (the coordinates' rates, then a free carrier's quasi-velocities).
static std::vector<GiNaC::symbol> velocity_symbols(const Model& model) {
    std::vector<GiNaC::symbol> rates;
    for (const auto& c : model.coordinates) rates.push_back(c.q_dot);
    for (const auto& v : model.quasi_velocities) rates.push_back(v.symbol);
    return rates;
}

// ḟ = ∂_t f + Σ ∂f/∂q_s q̇_s: a holonomic row's velocity form.
static ex velocity_form(const ex& f, const Model& model) {
    ex phi = f.diff(model.t);
    for (const auto& c : model.coordinates) phi += f.diff(c.q) * c.q_dot;
    return phi;
}

// A kinematic row φ (bilateral or unilateral, §6.7) must read B(q, t) u + b(q, t): every second
// derivative in the rates vanishes identically, and it holds at least one rate. `what` names the row
// ("kinematic constraint 'blade'"); `holonomic_key` is the key a relation of the coordinates alone
// is written with.
static void check_linear_in_rates(const ex& phi, const Model& model, const SourcePos& pos, const std::string& what,
                                  const char* holonomic_key) {
    const std::vector<GiNaC::symbol> rates = velocity_symbols(model);
    bool has_rate = false;
    for (std::size_t j = 0; j < rates.size(); ++j) {
        const ex first_derivative = phi.diff(rates[j]);
        if (!vanishes_identically(first_derivative, model)) has_rate = true;
        for (std::size_t k = j; k < rates.size(); ++k)
            if (!vanishes_identically(first_derivative.diff(rates[k]), model))
                throw InputError(pos, fmt::format("the {} is not linear in the rates: its second derivative in '{}' and "
                                                  "'{}' does not vanish (a row must read B(q, t) q_dot + b(q, t) = 0)",
                                                  what, rates[j].get_name(), rates[k].get_name()));
    }
    if (!has_rate)
        throw InputError(pos, fmt::format("the {} holds no rate (q_dot); a relation of the coordinates alone is written "
                                          "{} = \"...\"",
                                          what, holonomic_key));
}

// A row's expression at `values` with its magnitude; refused at `pos` when it is not a real number
// there. `level` names it in the message ("f(q0, 0)").
static std::pair<double, double> row_at(const ex& e, const GiNaC::exmap& values, const SourcePos& pos,
                                        const std::string& name, const char* noun, const char* level) {
    const auto value_size = value_and_magnitude(e, values);
    if (!std::isfinite(value_size.first))
        throw InputError(pos, fmt::format("the {} '{}' does not evaluate to a real number at the initial state ({})", noun,
                                          name, level));
    return value_size;
}

void check_constraint_start(const Model& model, const Constraint& row, const GiNaC::exmap& values,
                            const std::string& at) {
    const auto check = [&](const ex& e, const char* level) {
        const auto [value, size] = row_at(e, values, row.pos, row.name, "constraint", level);
        if (std::abs(value) > 1e-9 * size)
            throw InputError(row.pos, fmt::format("the initial state violates the constraint '{}': {} = {:.6g} "
                                                  "(not 0) {}",
                                                  row.name, level, value, at));
    };
    // The velocity-level row φ: ḟ = ∂_t f + Σ ∂f/∂q_s q̇_s for a holonomic row.
    if (row.holonomic) check(row.expression, "f(q0, 0)");
    check(row.holonomic ? velocity_form(row.expression, model) : row.expression,
          row.holonomic ? "df/dt(q0, q0_dot, 0)" : "phi(q0, q0_dot, 0)");
}

// [[constraint]] rows: parsed with the scene's symbols and checked (Mei, §6.6; Lur'e, ch. 2).
void build_constraints(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    if (scene.constraints.empty()) return;
    const scene::Constraint& first = scene.constraints.front();
    if (scene.newtonian)
        throw InputError(first.expression.pos,
                         "[[constraint]] is not supported in a [newtonian] scene: its equations are given, so there "
                         "are no energies for the reactions to enter; give the constrained system by [lagrangian] "
                         "or [[body]]");
    if (scene.orbit)
        throw InputError(first.expression.pos,
                         "[[constraint]] is not supported in an [orbit] scene: an orbit is a free point mass; give "
                         "a constrained system by [lagrangian] or [[body]]");
    for (const auto& given : scene.constraints) {
        Constraint row;
        row.name = given.name;
        row.holonomic = given.holonomic;
        row.pos = given.expression.pos;
        row.stabilization = given.stabilize == "baumgarte" ? ConstraintStabilization::baumgarte
                            : given.stabilize == "none"    ? ConstraintStabilization::none
                                                           : ConstraintStabilization::project;
        row.alpha = given.alpha;
        row.beta = given.beta;
        const std::string what = fmt::format("the {} constraint '{}'{}", given.holonomic ? "holonomic" : "kinematic",
                                             given.name,
                                             given.holonomic ? " (a function of the coordinates and t only; give a "
                                                               "row in the rates as kinematic = \"...\")"
                                                             : "");
        row.expression = symbols.parse(given.expression, given.holonomic ? configuration : phase, what);
        if (!row.holonomic)
            check_linear_in_rates(row.expression, model, row.pos, fmt::format("kinematic constraint '{}'", given.name),
                                  "holonomic");
        // The initial state must satisfy the row (positions and velocities), at the defaults.
        check_constraint_start(model, row, initial_values(model),
                               "at the initial values and the default parameters");
        model.constraints.push_back(std::move(row));
    }
}

// [[unilateral]] rows (Mei, ch. 6): a gap f(t, q) >= 0 or a velocity row φ(t, q, u) >= 0 (§6.7),
// parsed and checked as the [[constraint]] rows are, with Newton's restitution coefficient (a
// function of the parameters, 0 <= e <= 1 at the defaults), the initial state inside (f >= 0 or
// φ >= 0), and the contact method. The scene has refused the kinds of scene that take no rows.
void build_unilateral(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    model.contact_method = scene.contact.method;
    model.theta = scene.contact.theta;
    model.impact_law = scene.contact.impact_law;
    model.impact_law_pos = scene.contact.impact_law_pos;
    model.contact_method_pos = scene.contact.method_pos;
    for (const auto& given : scene.unilateral) {
        Unilateral row;
        row.name = given.name;
        row.holonomic = given.holonomic;
        row.pos = given.expression.pos;
        row.restitution_pos = given.restitution.pos;
        const std::string what =
            given.holonomic ? fmt::format("the gap of the unilateral constraint '{}' (a function of the coordinates and t "
                                          "only; give a row in the rates as velocity = \"...\")",
                                          given.name)
                            : fmt::format("the unilateral velocity constraint '{}'", given.name);
        row.expression = symbols.parse(given.expression, given.holonomic ? configuration : phase, what);
        if (!given.holonomic)
            check_linear_in_rates(row.expression, model, row.pos,
                                  fmt::format("unilateral velocity constraint '{}'", given.name), "gap");
        // Newton's coefficient: parameters only, in [0, 1] at their defaults.
        row.restitution = symbols.parse(given.restitution, unsigned(SymbolKind::parameter),
                                        fmt::format("the restitution of the unilateral constraint '{}'", given.name));
        row.restitution_default = at_defaults(row.restitution, model, given.restitution,
                                              fmt::format("the restitution of '{}'", given.name));
        if (!runtime::contact::valid_restitution(row.restitution_default))
            throw InputError(given.restitution.pos,
                             fmt::format("the restitution of the unilateral constraint '{}' is {:.6g} at the default "
                                         "parameters; Newton's coefficient must lie between 0 (plastic) and 1 (elastic)",
                                         given.name, row.restitution_default));
        // The initial state inside the admissible set: f(q0, 0) >= 0 (or φ >= 0), to round-off.
        const char* level = given.holonomic ? "f(q0, 0)" : "phi(q0, q0_dot, 0)";
        const auto [value, size] =
            row_at(row.expression, initial_values(model), row.pos, given.name, "unilateral constraint", level);
        if (value < -1e-9 * size)
            throw InputError(row.pos, fmt::format("the initial state violates the unilateral constraint '{}': {} = {:.6g} "
                                                  "(must be >= 0) at the initial values and the default parameters",
                                                  given.name, level, value));
        model.unilateral.push_back(std::move(row));
    }
}

}  // namespace eomc::model
