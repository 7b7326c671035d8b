// The model's entry point, build_model, with the tables every kind shares ([parameters],
// [[coordinate]], [lagrangian], [forces], [reference], [events], [effects]) and the parsing helpers
// of its steps (build_steps.hpp); each kind's own tables are read in its file.
#include "model/model.hpp"

#include <cstddef>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "model/build_steps.hpp"
#include "model/expression_parser.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

const char* name(Effect e) {
    switch (e) {
        case Effect::relative: return "relative";
        case Effect::translation: return "translation";
        case Effect::euler: return "euler";
        case Effect::centrifugal: return "centrifugal";
        case Effect::coriolis: return "coriolis";
    }
    return "?";
}

GiNaC::lst Model::state_symbols() const {
    GiNaC::lst out{t};
    for (const auto& c : coordinates) out.append(c.q);
    for (const auto& c : coordinates) out.append(c.q_dot);
    for (const auto& v : quasi_velocities) out.append(v.symbol);
    if (rigid) {
        for (std::size_t i = 0; i < 3; ++i) out.append(rigid->omega[i]).append(rigid->gamma[i]);
        if (rigid->attitude)
            for (const auto& e : *rigid->attitude) out.append(e);
    }
    for (const auto& p : parameters) out.append(p.symbol);
    return out;
}

GiNaC::exmap Model::parameter_defaults() const {
    GiNaC::exmap defaults;
    for (const auto& p : parameters) defaults[p.symbol] = GiNaC::numeric(p.value);
    return defaults;
}

std::vector<std::string> Model::velocity_names() const {
    std::vector<std::string> names;
    for (const auto& c : coordinates) names.push_back(c.name);
    for (const auto& v : quasi_velocities) names.push_back(v.name);
    return names;
}

// build_steps.hpp's parsing helpers.

Vec3 parse_vector(const SymbolTable& symbols, const scene::Vec3& v, unsigned allowed, const std::string& what) {
    return {symbols.parse(v[0], allowed, what), symbols.parse(v[1], allowed, what),
            symbols.parse(v[2], allowed, what)};
}

std::optional<GiNaC::numeric> real_value(const ex& e, const GiNaC::exmap& values) {
    try {
        const ex value = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
        if (GiNaC::is_a<GiNaC::numeric>(value) && GiNaC::ex_to<GiNaC::numeric>(value).is_real())
            return GiNaC::ex_to<GiNaC::numeric>(value);
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

ex parse_mass(const SymbolTable& symbols, const scene::Body& body, const Model& model) {
    const std::string what = fmt::format("the mass of body '{}'", body.name);
    ex mass = symbols.parse(body.mass, unsigned(SymbolKind::parameter), what);
    const auto value = real_value(mass, model.parameter_defaults());
    if (!value) throw InputError(body.mass.pos, fmt::format("{} does not evaluate to a real number", what));
    if (value->to_double() <= 0.0)
        throw InputError(body.mass.pos, fmt::format("{} must be positive, but '{}' = {} with the default parameters",
                                                    what, body.mass.text, value->to_double()));
    return mass;
}

GiNaC::matrix parse_inertia(const SymbolTable& symbols, const std::vector<scene::Expr>& entries, const SourcePos& pos,
                            const std::string& what) {
    GiNaC::matrix I(3, 3);
    for (std::size_t k = 0; k < entries.size(); ++k) {
        const ex value = symbols.parse(entries[k], unsigned(SymbolKind::parameter), what);
        if (entries.size() == 3) I(unsigned(k), unsigned(k)) = value;
        else I(unsigned(k / 3), unsigned(k % 3)) = value;
    }
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = i + 1; j < 3; ++j)
            if (!(I(i, j) - I(j, i)).expand().is_zero())
                throw InputError(pos, fmt::format("{} is not symmetric: entry ({},{}) differs from ({},{})", what, i + 1,
                                                  j + 1, j + 1, i + 1));
    return I;
}

double at_defaults(const ex& e, const Model& model, const scene::Expr& where, const std::string& what) {
    const auto value = real_value(e, model.parameter_defaults());
    if (!value) throw InputError(where.pos, fmt::format("{} does not evaluate to a real number", what));
    return value->to_double();
}

namespace {

// [[coordinate]]: each name with its rate and acceleration, after any the kind declares itself
// (an orbit's x, y, z; a rigid body's Euler angles).
void declare_coordinates(const scene::Scene& scene, SymbolTable& symbols, Model& model) {
    const auto value = [&](const std::optional<scene::Expr>& expr, double number, const std::string& what, ex& kept) {
        if (!expr) return number;
        kept = symbols.parse(*expr, unsigned(SymbolKind::parameter), what);
        return at_defaults(kept, model, *expr, what);
    };
    for (const auto& c : scene.coordinates) {
        model.coordinates.push_back({c.name, symbols.declare(c.name, SymbolKind::coordinate),
                                     symbols.declare(c.name + "_dot", SymbolKind::velocity),
                                     symbols.declare(c.name + "_ddot", SymbolKind::acceleration), c.initial,
                                     c.rate});
        Coordinate& made = model.coordinates.back();
        made.initial = value(c.initial_expr, c.initial, "the initial value of " + c.name, made.initial_expr);
        made.rate = value(c.rate_expr, c.rate, "the initial rate of " + c.name, made.rate_expr);
    }
}

// [lagrangian] T and V, and the potential and generalized forces of [forces].
void build_energies_and_forces(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    if (scene.lagrangian) {
        model.kinetic_energy = symbols.parse(scene.lagrangian->kinetic, phase, "the kinetic energy T");
        model.potential = symbols.parse(scene.lagrangian->potential, phase, "the potential V");
        model.kinetic_pos = scene.lagrangian->kinetic.pos;
    }
    // Potentials from [lagrangian] and [forces] add up.
    if (scene.forces.potential) model.potential += symbols.parse(*scene.forces.potential, phase, "the potential");

    model.generalized_forces.assign(model.coordinates.size(), ex(0));
    for (const auto& q : scene.forces.generalized) {
        std::size_t s = 0;
        while (s < model.coordinates.size() && model.coordinates[s].name != q.coordinate) ++s;
        if (s == model.coordinates.size()) {
            std::vector<std::string> names;
            for (const auto& c : model.coordinates) names.push_back(c.name);
            const std::string near = nearest_name(q.coordinate, names);
            throw InputError(q.pos, fmt::format("generalized force for '{}', which is not a declared coordinate{}",
                                                q.coordinate,
                                                near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        model.generalized_forces[s] =
            symbols.parse(q.value, phase, fmt::format("the generalized force on '{}'", q.coordinate));
    }
    // An orbit's non-conservative accelerations are its generalized forces per unit mass
    // (x, y, z are Cartesian, so Q_s = a · ∂r/∂q_s = a_s).
    if (model.orbit)
        for (std::size_t s = 0; s < 3; ++s) model.generalized_forces[s] = model.orbit->acceleration[s];
}

// [reference]: the exact state at time t, in state order.
void build_reference(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    if (!scene.reference) return;
    // The reference is the Lagrangian state (q, q_dot); kernels of other states would be judged
    // against values of different variables.
    if (model.hamiltonian)
        throw InputError(scene.reference->pos,
                         "[reference] gives q and q_dot, but [formulation] kind = \"hamiltonian\" integrates (q, p)");
    if (model.free_carrier())
        throw InputError(scene.reference->pos,
                         "[reference] is not available with a free carrier (its state also holds the carrier's "
                         "velocities and attitude)");
    // In state order, whatever the file order.
    auto parse_reference = [&](const std::string& state) {
        for (const auto& v : scene.reference->values)
            if (v.state == state)
                return symbols.parse(v.value, time_and_parameters,
                                     fmt::format("the reference value of '{}'", state));
        throw InputError(scene.reference->pos, fmt::format("[reference] gives no value for '{}'", state));
    };
    for (const auto& c : model.coordinates) model.reference.push_back(parse_reference(c.name));
    for (const auto& c : model.coordinates) model.reference.push_back(parse_reference(c.name + "_dot"));
}

// [events], and an orbit's own re_entry.
void build_events(const scene::Scene& scene, const SymbolTable& symbols, Model& model) {
    for (const auto& e : scene.events)
        model.events.push_back({e.name, symbols.parse(e.when, phase, fmt::format("event '{}'", e.name)),
                                e.direction == "up" ? 1 : (e.direction == "down" ? -1 : 0), e.terminal, e.pos});
    // Every orbit ends where it reaches the central body's surface: a terminal event, located
    // like any other, instead of integrating on into the body.
    if (model.orbit) {
        for (const auto& e : model.events)
            if (e.name == "re_entry")
                throw InputError(e.pos, "'re_entry' is the orbit's own event (r = radius); give this event another name");
        model.events.push_back({"re_entry", model.orbit->r - model.orbit->radius, -1, true, scene.orbit->pos});
    }
}

// [effects]: the terms of the relative motion kept (an orbit scene's names are perturbations,
// read by build_orbit).
void keep_effects(const scene::Scene& scene, Model& model) {
    if (!scene.effects.given || scene.orbit) return;
    model.keep.fill(false);
    for (const auto& e : scene.effects.keep)
        for (Effect k : all_effects)
            if (e == name(k)) model.keep[static_cast<int>(k)] = true;
}

}  // namespace

std::vector<std::pair<std::string, double>> initial_overrides(const Model& model,
                                                              const std::vector<std::pair<std::string, double>>& overrides) {
    GiNaC::exmap values = model.parameter_defaults();
    std::set<std::string> given;
    bool any_parameter = false;
    for (const auto& [name, v] : overrides) {
        given.insert(name);
        for (const auto& p : model.parameters)
            if (p.name == name) values[p.symbol] = GiNaC::numeric(v), any_parameter = true;
    }
    std::vector<std::pair<std::string, double>> out;
    if (!any_parameter) return out;  // the scene's own values stand
    // Only expressions that name parameters change; numbers were taken whole by the model.
    const auto add = [&](const ex& e, const std::string& name) {
        if (GiNaC::is_a<GiNaC::numeric>(e) || given.count(name)) return;
        const auto v = real_value(e, values);
        if (!v) {
            std::ostringstream text;
            text << e;
            throw InputError(SourcePos{model.source, 0, 0},
                             fmt::format("{} = {} is not a real number at the parameter values given", name, text.str()));
        }
        out.emplace_back(name, v->to_double());
    };
    for (const auto& c : model.coordinates) {
        add(c.initial_expr, c.name);
        add(c.rate_expr, c.name + "_dot");
    }
    return out;
}

Model build_model(const scene::Scene& scene) {
    Model model;
    model.name = scene.name;
    model.struct_name = scene::struct_name(scene.name);
    model.summary = scene.summary;
    model.source = scene.path;
    model.simulate = scene.simulate;
    model.hamiltonian = scene.formulation == "hamiltonian";
    model.inverse = scene.inverse;

    SymbolTable symbols;
    model.t = symbols.declare("t", SymbolKind::time);
    for (const auto& p : scene.parameters)
        model.parameters.push_back({p.name, symbols.declare(p.name, SymbolKind::parameter), p.value});
    if (scene.orbit) build_orbit(scene, symbols, model);
    if (scene.rigid_body) build_rigid_body(scene, symbols, model);
    declare_coordinates(scene, symbols, model);
    build_carried_bodies(scene, symbols, model);
    build_energies_and_forces(scene, symbols, model);
    build_reference(scene, symbols, model);
    build_events(scene, symbols, model);
    if (scene.newtonian) {
        model.newtonian = build_newtonian(symbols, *scene.newtonian, model);
        model.kinetic_pos = scene.newtonian->pos;
    }

    build_constraints(scene, symbols, model);
    build_unilateral(scene, symbols, model);
    build_programs(scene, symbols, model);
    if (!model.programs.empty()) constraints_as_programs(scene, model);
    keep_effects(scene, model);
    check_inertias(model, initial_values(model), "with the default parameters");
    return model;
}

}  // namespace eomc::model
