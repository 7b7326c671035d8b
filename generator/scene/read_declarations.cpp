// The names every scene declares: [scene], [parameters] and [coordinates].
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

void Reader::read_scene(Scene& s) const {
    const toml::node* node = root_.get("scene");
    if (!node) fail(top(), "missing required table [scene]");
    const toml::table& t = as_table(*node, "scene");
    check_keys(t, {"name", "summary"}, "in [scene]");
    const toml::node& name = require(t, "name", "[scene]");
    s.name = read_string(name, "scene.name");
    s.name_pos = at(name);
    if (!is_scene_name(s.name))
        fail(at(name), fmt::format("invalid scene name '{}': expected a lowercase letter followed by lowercase "
                                   "letters, digits or underscores",
                                   s.name));
    if (const toml::node* summary = t.get("summary")) s.summary = read_string(*summary, "scene.summary");
}

void Reader::read_parameters(Scene& s) const {
    const toml::node* node = root_.get("parameters");
    if (!node) return;
    for (const auto& [key, value] : entries(as_table(*node, "parameters"))) {
        const std::string name(key->str());
        check_symbol_name(name, at(*key), "parameter");
        s.parameters.push_back(Parameter{name, read_number(*value, "parameters." + name), at(*key)});
    }
}

void Reader::read_coordinates(Scene& s) const {
    const toml::node* node = root_.get("coordinates");
    if (s.orbit) {
        if (node)
            fail(at(*node), "[coordinates] cannot be combined with [orbit]: an orbit scene's coordinates are the "
                            "inertial x, y, z of the orbiting body");
        return;
    }
    if (s.rigid_body) {
        if (node)
            fail(at(*node), "[coordinates] cannot be combined with [rigid_body]: a rigid body's state is its "
                            "formulation's (ω and γ, a quaternion, Euler angles or Andoyer-Deprit variables)");
        return;
    }
    if (!node) fail(top(), "missing required table [coordinates]: the scene needs at least one coordinate");
    const toml::table& t = as_table(*node, "coordinates");
    if (t.empty()) fail(at(t), "[coordinates] declares no coordinate; the scene needs at least one");
    for (const auto& [key, value] : entries(t)) {
        const std::string name(key->str());
        const std::string path = "coordinates." + name;
        check_symbol_name(name, at(*key), "coordinate");
        const toml::table& c = as_table(*value, path);
        check_keys(c, {"initial", "rate"}, "in '" + path + "'");
        Coordinate coord{name, 0.0, 0.0, at(*key)};
        // A number, or a string: an expression of the parameters (the model checks what it names).
        if (const toml::node* v = c.get("initial")) {
            if (v->is_string()) coord.initial_expr = read_expr(*v, path + ".initial");
            else coord.initial = read_number(*v, path + ".initial");
        }
        if (const toml::node* v = c.get("rate")) {
            if (v->is_string()) coord.rate_expr = read_expr(*v, path + ".rate");
            else coord.rate = read_number(*v, path + ".rate");
        }
        s.coordinates.push_back(std::move(coord));
    }
}

void Reader::check_name_clashes(const Scene& s) const {
    if (s.orbit)
        for (const Parameter& p : s.parameters)
            if (p.name == "x" || p.name == "y" || p.name == "z")
                fail(p.pos, fmt::format("parameter '{}' has the name of a coordinate of the orbit scene (x, y, z)",
                                        p.name));
    for (const Coordinate& c : s.coordinates) {
        for (const Parameter& p : s.parameters) {
            if (p.name != c.name) continue;
            if (before(p.pos, c.pos))
                fail(c.pos, fmt::format("coordinate '{}' has the same name as the parameter declared at line {}",
                                        c.name, p.pos.line));
            fail(p.pos, fmt::format("parameter '{}' has the same name as the coordinate declared at line {}", p.name,
                                    c.pos.line));
        }
    }
}

}  // namespace eomc::scene
