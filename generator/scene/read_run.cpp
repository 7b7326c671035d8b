// How a scene is run and checked: [formulation], [kernel], [simulate], [events] and [reference].
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "scene/reader.hpp"
#include "support/identifier.hpp"

namespace eomc::scene {

void Reader::read_formulation(Scene& s) const {
    const toml::node* node = root_.get("formulation");
    if (!node) return;
    const toml::table& t = as_table(*node, "formulation");
    check_keys(t, {"kind"}, "in [formulation]");
    const toml::node& kind = require(t, "kind", "[formulation]");
    s.formulation = read_string(kind, "formulation.kind");
    s.formulation_pos = at(kind);
    const std::vector<std::string> names(formulation_names.begin(), formulation_names.end());
    if (std::find(names.begin(), names.end(), s.formulation) == names.end()) {
        const std::string near = nearest_name(s.formulation, names);
        fail(at(kind), fmt::format("unknown formulation '{}'; {}", s.formulation,
                                   near.empty() ? std::string("expected 'lagrangian' or 'hamiltonian'")
                                                : fmt::format("did you mean '{}'?", near)));
    }
}

void Reader::read_kernel(Scene& s) const {
    const toml::node* node = root_.get("kernel");
    if (!node) return;
    const toml::table& t = as_table(*node, "kernel");
    check_keys(t, {"jacobian"}, "in [kernel]");
    if (const toml::node* v = t.get("jacobian")) s.kernel_jacobian = read_bool(*v, "kernel.jacobian");
}

void Reader::read_simulate(Scene& s) const {
    const toml::node* node = root_.get("simulate");
    Simulate& sim = s.simulate;
    if (!node) return;
    const toml::table& t = as_table(*node, "simulate");
    check_keys(t, {"t_end", "integrator", "rtol", "atol", "step", "compensated"}, "in [simulate]");
    sim.integrator_pos = at(t);
    if (const toml::node* v = t.get("t_end")) sim.t_end = read_positive(*v, "simulate.t_end");
    if (const toml::node* v = t.get("integrator")) {
        sim.integrator = read_string(*v, "simulate.integrator");
        sim.integrator_pos = at(*v);
        if (!runtime::is_integrator(sim.integrator)) {
            const std::vector<std::string> names(runtime::integrator_names.begin(), runtime::integrator_names.end());
            const std::string near = nearest_name(sim.integrator, names);
            fail(at(*v), fmt::format("unknown integrator '{}'; {}", sim.integrator,
                                     near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                  : fmt::format("did you mean '{}'?", near)));
        }
    }
    if (const toml::node* v = t.get("rtol")) sim.rtol = read_positive(*v, "simulate.rtol");
    if (const toml::node* v = t.get("atol")) sim.atol = read_positive(*v, "simulate.atol");
    if (const toml::node* v = t.get("step")) sim.step = read_positive(*v, "simulate.step");
    if (const toml::node* v = t.get("compensated")) sim.compensated = read_bool(*v, "simulate.compensated");
}

// [events]: name = "g" (direction both, not terminal) or name = { when = "g", direction =
// "up" | "down" | "both", terminal = true | false }.
void Reader::read_events(Scene& s) const {
    const toml::node* node = root_.get("events");
    if (!node) return;
    const toml::table& t = as_table(*node, "events");
    for (const auto& [key, value] : entries(t)) {
        Event e;
        e.name = std::string(key->str());
        e.pos = at(*key);
        const std::string path = "events." + e.name;
        if (!is_scene_identifier(e.name))
            fail(at(*key), fmt::format("invalid event name '{}': expected a letter followed by letters, digits or "
                                       "underscores",
                                       e.name));
        if (const toml::table* spec = value->as_table()) {
            check_keys(*spec, {"when", "direction", "terminal"}, "in '" + path + "'");
            e.when = read_expr(require(*spec, "when", "'" + path + "'"), path + ".when");
            if (const toml::node* d = spec->get("direction")) {
                e.direction = read_string(*d, path + ".direction");
                const std::vector<std::string> names(event_directions.begin(), event_directions.end());
                if (std::find(names.begin(), names.end(), e.direction) == names.end()) {
                    const std::string near = nearest_name(e.direction, names);
                    fail(at(*d), fmt::format("unknown direction '{}' in '{}'; {}", e.direction, path,
                                             near.empty() ? std::string("expected 'up', 'down' or 'both'")
                                                          : fmt::format("did you mean '{}'?", near)));
                }
            }
            if (const toml::node* v = spec->get("terminal")) e.terminal = read_bool(*v, path + ".terminal");
        } else {
            e.when = read_expr(*value, path);
        }
        s.events.push_back(std::move(e));
    }
}

// [reference]: state name = expression, for every state variable (q and q_dot of each coordinate).
void Reader::read_reference(Scene& s) const {
    const toml::node* node = root_.get("reference");
    if (!node) return;
    const toml::table& t = as_table(*node, "reference");
    std::vector<std::string> states;
    for (const Coordinate& c : s.coordinates) states.push_back(c.name);
    for (const Coordinate& c : s.coordinates) states.push_back(c.name + "_dot");
    Reference r;
    r.pos = at(t);
    for (const auto& [key, value] : entries(t)) {
        const std::string name(key->str());
        if (std::find(states.begin(), states.end(), name) == states.end()) {
            const std::string near = nearest_name(name, states);
            fail(at(*key), fmt::format("'reference.{}': {} is not a state variable; {}", name, name,
                                       near.empty() ? fmt::format("expected one of {}", fmt::join(states, ", "))
                                                    : fmt::format("did you mean '{}'?", near)));
        }
        r.values.push_back(ReferenceValue{name, read_expr(*value, "reference." + name), at(*key)});
    }
    for (const std::string& name : states) {
        const bool given = std::any_of(r.values.begin(), r.values.end(),
                                       [&](const ReferenceValue& v) { return v.state == name; });
        if (!given)
            fail(r.pos, fmt::format("[reference] gives no value for '{}'; a reference gives the whole state ({})",
                                    name, fmt::join(states, ", ")));
    }
    s.reference = std::move(r);
}

}  // namespace eomc::scene
