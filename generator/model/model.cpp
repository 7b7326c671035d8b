#include "model/model.hpp"

#include <algorithm>
#include <cctype>

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
    for (const auto& v : quasi_velocities) out.append(v.symbol);
    for (const auto& p : parameters) out.append(p.symbol);
    return out;
}

std::vector<std::string> Model::velocity_names() const {
    std::vector<std::string> names;
    for (const auto& c : coordinates) names.push_back(c.name);
    for (const auto& v : quasi_velocities) names.push_back(v.name);
    return names;
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

// 3 principal moments or 9 entries → a symmetric 3×3 matrix of constants.
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

// A free carrier: each component of v_o and ω is a new name (an unknown quasi-velocity) or
// "0" (held by the constraints); anything else is an error at that component.
void build_free_carrier(const scene::Carrier& c, const scene::Forces& forces, SymbolTable& symbols, Model& model) {
    Carrier carrier;
    carrier.free = true;
    std::map<std::string, SourcePos> declared;
    for (const bool angular : {false, true}) {
        const scene::Vec3& v = angular ? c.angular_velocity : c.pole_velocity;
        Vec3& out = angular ? carrier.angular_velocity : carrier.pole_velocity;
        for (int axis = 0; axis < 3; ++axis) {
            const scene::Expr& e = v[std::size_t(axis)];
            if (e.text == "0") {
                out[std::size_t(axis)] = 0;
                continue;
            }
            const bool identifier = !e.text.empty() && (std::isalpha(static_cast<unsigned char>(e.text[0]))) &&
                                    std::all_of(e.text.begin(), e.text.end(), [](char ch) {
                                        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_';
                                    });
            const std::string what = angular ? "angular_velocity" : "pole_velocity";
            if (!identifier)
                throw InputError(e.pos, fmt::format("a free carrier's {} component must be a new name (an unknown "
                                                    "quasi-velocity) or \"0\" (held by the constraints), got '{}'",
                                                    what, e.text));
            if (symbols.contains(e.text) || symbols.contains(e.text + "_dot") || declared.count(e.text))
                throw InputError(e.pos, fmt::format("the quasi-velocity '{}' clashes with a name already declared "
                                                    "(it needs '{}' and '{}_dot' to be free)",
                                                    e.text, e.text, e.text));
            declared.emplace(e.text, e.pos);
            QuasiVelocity q{e.text, symbols.declare(e.text, SymbolKind::velocity),
                            symbols.declare(e.text + "_dot", SymbolKind::acceleration), 0.0, angular, axis};
            out[std::size_t(axis)] = q.symbol;
            model.quasi_velocities.push_back(std::move(q));
        }
    }
    for (const auto& init : c.initial) {
        auto it = std::find_if(model.quasi_velocities.begin(), model.quasi_velocities.end(),
                               [&](const QuasiVelocity& q) { return q.name == init.name; });
        if (it == model.quasi_velocities.end()) {
            std::vector<std::string> names;
            for (const auto& q : model.quasi_velocities) names.push_back(q.name);
            const std::string near = nearest_name(init.name, names);
            throw InputError(init.pos, fmt::format("'{}' in [carrier.initial] is not a quasi-velocity of the carrier{}",
                                                   init.name, near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        it->initial = init.value;
    }
    scene::Body as_body{"carrier", *c.mass, {}, {}, {}, c.pos, {}, {}};
    carrier.mass = parse_mass(symbols, as_body, model);
    carrier.inertia = parse_inertia(symbols, c.inertia, c.pos, "the carrier's inertia");
    carrier.center = parse_vector(symbols, c.center, unsigned(SymbolKind::parameter), "the carrier's mass centre");
    // The applied loads may depend on the whole motion (a damper, a motor law).
    const unsigned loads = phase;
    if (forces.resultant) carrier.resultant = parse_vector(symbols, *forces.resultant, loads, "the resultant force");
    if (forces.moment) carrier.moment = parse_vector(symbols, *forces.moment, loads, "the resultant moment");
    model.carrier = std::move(carrier);
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
    model.hamiltonian = scene.formulation == "hamiltonian";
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
        if (c.motion == "free") {
            if (scene.effects.given)
                throw InputError(scene.effects.keep_pos.empty() ? c.motion_pos : scene.effects.keep_pos.front(),
                                 "[effects] cannot drop terms of a free carrier's equations: its motion follows from "
                                 "all of them");
            build_free_carrier(c, scene.forces, symbols, model);
        } else {
            Carrier carrier;
            carrier.angular_velocity =
                parse_vector(symbols, c.angular_velocity, time_and_parameters, "the carrier's angular velocity");
            carrier.pole_velocity = parse_vector(symbols, c.pole_velocity, time_and_parameters, "the carrier's pole velocity");
            model.carrier = std::move(carrier);
        }
    }
    for (const auto& b : scene.bodies) {
        Particle body;
        body.name = b.name;
        body.mass = parse_mass(symbols, b, model);
        body.position = parse_vector(symbols, b.position, configuration, fmt::format("the position of body '{}'", b.name));
        if (!b.inertia.empty()) {
            body.rigid = true;
            body.inertia = parse_inertia(symbols, b.inertia, b.inertia_pos, fmt::format("the inertia of body '{}'", b.name));
            for (const auto& r : b.orientation)
                body.orientation.emplace_back(
                    r.axis, symbols.parse(r.angle, configuration,
                                          fmt::format("an orientation angle of body '{}'", b.name)));
        }
        model.particles.push_back(std::move(body));
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

    if (scene.reference) {
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

    for (const auto& e : scene.events)
        model.events.push_back({e.name, symbols.parse(e.when, phase, fmt::format("event '{}'", e.name)),
                                e.direction == "up" ? 1 : (e.direction == "down" ? -1 : 0), e.terminal, e.pos});

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
