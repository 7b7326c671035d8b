#include "model/model.hpp"

#include <fmt/format.h>

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
    for (const auto& p : parameters) out.append(p.symbol);
    return out;
}

namespace {

constexpr unsigned time_and_parameters = SymbolKind::time | SymbolKind::parameter;
constexpr unsigned configuration = time_and_parameters | SymbolKind::coordinate;
constexpr unsigned phase = configuration | SymbolKind::velocity;

Vec3 parse_vector(const SymbolTable& symbols, const scene::Vec3& v, unsigned allowed, const std::string& what) {
    return {symbols.parse(v[0], allowed, what), symbols.parse(v[1], allowed, what),
            symbols.parse(v[2], allowed, what)};
}

// A mass must be a positive constant: evaluate it at the parameters' defaults.
ex parse_mass(const SymbolTable& symbols, const scene::Body& body, const Model& model) {
    const std::string what = fmt::format("the mass of body '{}'", body.name);
    ex mass = symbols.parse(body.mass, unsigned(SymbolKind::parameter), what);
    GiNaC::exmap defaults;
    for (const auto& p : model.parameters) defaults[p.symbol] = GiNaC::numeric(p.value);
    const ex value = mass.subs(defaults).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(value) || !GiNaC::ex_to<GiNaC::numeric>(value).is_real())
        throw InputError(body.mass.pos, fmt::format("{} does not evaluate to a real number", what));
    if (GiNaC::ex_to<GiNaC::numeric>(value).to_double() <= 0.0)
        throw InputError(body.mass.pos, fmt::format("{} must be positive, but '{}' = {} with the default parameters",
                                                    what, body.mass.text,
                                                    GiNaC::ex_to<GiNaC::numeric>(value).to_double()));
    return mass;
}

// [newtonian]: one equation per coordinate, each naming a declared coordinate once; the
// fundamental form must be affine in the accelerations (A q̈ + B).
Newtonian build_newtonian(const SymbolTable& symbols, const scene::Newtonian& given, const Model& model) {
    Newtonian n;
    n.fundamental = given.fundamental;
    n.pos = given.pos;
    const std::size_t count = model.coordinates.size();
    n.expressions.assign(count, ex(0));
    n.positions.assign(count, given.pos);
    std::vector<bool> seen(count, false);
    std::vector<std::string> names;
    for (const auto& c : model.coordinates) names.push_back(given.fundamental ? c.name : c.name + "_ddot");
    for (const auto& eq : given.equations) {
        const std::string key = given.fundamental ? eq.coordinate : eq.coordinate + "_ddot";
        std::size_t s = 0;
        while (s < count && model.coordinates[s].name != eq.coordinate) ++s;
        if (s == count) {
            const std::string near = nearest_name(key, names);
            throw InputError(eq.pos, fmt::format("'{}' names no declared coordinate{}", key,
                                                 near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (seen[s]) throw InputError(eq.pos, fmt::format("a second equation for coordinate '{}'", eq.coordinate));
        seen[s] = true;
        const std::string what = given.fundamental ? fmt::format("the fundamental form's equation for '{}'", eq.coordinate)
                                                   : fmt::format("the acceleration '{}'", key);
        n.expressions[s] = symbols.parse(eq.value, given.fundamental ? any_symbol : phase, what);
        n.positions[s] = eq.value.pos;
        if (given.fundamental) {
            for (const auto& c : model.coordinates) {
                if (!n.expressions[s].has(c.q_ddot)) continue;
                if (!n.expressions[s].diff(c.q_ddot).expand().has(c.q_ddot)) continue;
                throw InputError(eq.value.pos, fmt::format("{} is not linear in the accelerations ('{}' appears "
                                                           "non-linearly); the fundamental form is A(t,q,q̇) q̈ + "
                                                           "B(t,q,q̇)",
                                                           what, c.name + "_ddot"));
            }
        }
    }
    for (std::size_t s = 0; s < count; ++s)
        if (!seen[s])
            throw InputError(given.pos, fmt::format("[newtonian{}] gives no equation for coordinate '{}' (expected "
                                                    "'{} = \"...\"')",
                                                    given.fundamental ? ".fundamental" : "", model.coordinates[s].name,
                                                    names[s]));
    return n;
}

}  // namespace

Model build_model(const scene::Scene& scene) {
    Model model;
    model.name = scene.name;
    model.struct_name = scene::struct_name(scene.name);
    model.summary = scene.summary;
    model.source = scene.path;
    model.simulate = scene.simulate;
    model.inverse = scene.inverse;

    SymbolTable symbols;
    model.t = symbols.declare("t", SymbolKind::time);
    for (const auto& p : scene.parameters)
        model.parameters.push_back({p.name, symbols.declare(p.name, SymbolKind::parameter), p.value});
    for (const auto& c : scene.coordinates) {
        model.coordinates.push_back({c.name, symbols.declare(c.name, SymbolKind::coordinate),
                                     symbols.declare(c.name + "_dot", SymbolKind::velocity),
                                     symbols.declare(c.name + "_ddot", SymbolKind::acceleration), c.initial,
                                     c.rate});
    }

    if (scene.carrier) {
        const auto& c = *scene.carrier;
        if (c.motion == "free")
            throw InputError(c.motion_pos, "a free carrier (motion = \"free\") is not yet supported; "
                                           "give its motion as functions of t with motion = \"prescribed\"");
        model.carrier = Carrier{
            parse_vector(symbols, c.angular_velocity, time_and_parameters, "the carrier's angular velocity"),
            parse_vector(symbols, c.pole_velocity, time_and_parameters, "the carrier's pole velocity")};
    }
    for (const auto& b : scene.bodies) {
        model.particles.push_back(
            {b.name, parse_mass(symbols, b, model),
             parse_vector(symbols, b.position, configuration, fmt::format("the position of body '{}'", b.name))});
    }
    if (!scene.bodies.empty()) model.kinetic_pos = scene.bodies.front().pos;

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

    if (scene.newtonian) {
        model.newtonian = build_newtonian(symbols, *scene.newtonian, model);
        model.kinetic_pos = scene.newtonian->pos;
    }

    if (scene.effects.given) {
        model.keep.fill(false);
        for (const auto& e : scene.effects.keep)
            for (Effect k : all_effects)
                if (e == name(k)) model.keep[static_cast<int>(k)] = true;
    }
    return model;
}

}  // namespace eomc::model
