// The energies kind's carried system ([carrier], [[body]]; Mei, ch. 1): the carrier, prescribed or
// free, and the particles and rigid bodies it carries.
#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"
#include "support/identifier.hpp"

namespace eomc::model {

using GiNaC::ex;

namespace {

// The carrier's own mass distribution (required for a free carrier, optional for a prescribed
// one) and the loads [forces] resultant and moment on its system.
void add_carrier_mass_and_loads(const scene::Carrier& c, const scene::Forces& forces, const SymbolTable& symbols,
                                const Model& model, Carrier& carrier) {
    if (c.mass) {
        scene::Body as_body{"carrier", *c.mass, {}, {}, {}, c.pos, {}, {}};
        carrier.mass = parse_mass(symbols, as_body, model);
    }
    carrier.inertia = parse_inertia(symbols, c.inertia, c.pos, "the carrier's inertia");
    carrier.inertia_pos = c.pos;
    carrier.center = parse_vector(symbols, c.center, unsigned(SymbolKind::parameter), "the carrier's mass centre");
    // The applied loads may depend on the whole motion (a damper, a motor law).
    const unsigned loads = phase;
    if (forces.resultant) carrier.resultant = parse_vector(symbols, *forces.resultant, loads, "the resultant force");
    if (forces.moment) carrier.moment = parse_vector(symbols, *forces.moment, loads, "the resultant moment");
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
            const bool identifier = is_scene_identifier(e.text);
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
    add_carrier_mass_and_loads(c, forces, symbols, model, carrier);
    model.carrier = std::move(carrier);
}

// A prescribed carrier: ω and v_o functions of t and the parameters.
void build_prescribed_carrier(const scene::Carrier& c, const scene::Forces& forces, SymbolTable& symbols,
                              Model& model) {
    Carrier carrier;
    carrier.angular_velocity =
        parse_vector(symbols, c.angular_velocity, time_and_parameters, "the carrier's angular velocity");
    carrier.pole_velocity = parse_vector(symbols, c.pole_velocity, time_and_parameters, "the carrier's pole velocity");
    add_carrier_mass_and_loads(c, forces, symbols, model, carrier);
    model.carrier = std::move(carrier);
}

}  // namespace

void build_carried_bodies(const scene::Scene& scene, SymbolTable& symbols, Model& model) {
    if (scene.carrier) {
        const auto& c = *scene.carrier;
        if (c.motion == "free") {
            if (scene.effects.given)
                throw InputError(scene.effects.keep_pos.empty() ? c.motion_pos : scene.effects.keep_pos.front(),
                                 "[effects] cannot drop terms of a free carrier's equations: its motion follows from "
                                 "all of them");
            build_free_carrier(c, scene.forces, symbols, model);
        } else {
            build_prescribed_carrier(c, scene.forces, symbols, model);
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
            body.inertia_pos = b.inertia_pos;
            for (const auto& r : b.orientation)
                body.orientation.emplace_back(
                    r.axis, symbols.parse(r.angle, configuration,
                                          fmt::format("an orientation angle of body '{}'", b.name)));
        }
        model.particles.push_back(std::move(body));
    }
    if (!scene.bodies.empty()) model.kinetic_pos = scene.bodies.front().pos;
}

}  // namespace eomc::model
