// Carried bodies (Mei, ch. 1): [carrier] and [[body]], with a body's orientation.
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

void Reader::read_carrier(Scene& s) const {
    const toml::node* node = root_.get("carrier");
    if (!node) return;
    const toml::table& t = as_table(*node, "carrier");
    check_keys(t, {"motion", "angular_velocity", "pole_velocity", "mass", "inertia", "center", "initial"},
               "in [carrier]");
    Carrier c;
    c.pos = at(t);
    c.motion_pos = c.pos;
    if (const toml::node* motion = t.get("motion")) {
        c.motion = read_string(*motion, "carrier.motion");
        c.motion_pos = at(*motion);
        if (c.motion != "prescribed" && c.motion != "free") {
            const std::string near = nearest_name(c.motion, {"prescribed", "free"});
            fail(at(*motion), fmt::format("unknown carrier motion '{}'; {}", c.motion,
                                          near.empty() ? std::string("expected 'prescribed' or 'free'")
                                                       : fmt::format("did you mean '{}'?", near)));
        }
    }
    const toml::node* w = t.get("angular_velocity");
    c.angular_velocity = w ? read_vec3(*w, "carrier.angular_velocity") : zero_vec3(c.pos);
    const toml::node* v = t.get("pole_velocity");
    c.pole_velocity = v ? read_vec3(*v, "carrier.pole_velocity") : zero_vec3(c.pos);
    const bool free = c.motion == "free";
    // The initial quasi-velocities mean something only for a free carrier. Its mass distribution
    // is required there; a prescribed carrier may give it, for the forces that hold it.
    if (const toml::node* n = t.get("initial"); n && !free)
        fail(at(*n), "'carrier.initial' is given only for a free carrier (motion = \"free\"); a prescribed "
                     "carrier has no unknown velocities");
    if (free) c.mass = read_expr(require(t, "mass", "a free [carrier]"), "carrier.mass");
    else if (const toml::node* m = t.get("mass")) c.mass = read_expr(*m, "carrier.mass");
    if (free) c.inertia = read_inertia(require(t, "inertia", "a free [carrier]"), "carrier.inertia");
    else if (const toml::node* in = t.get("inertia")) c.inertia = read_inertia(*in, "carrier.inertia");
    const toml::node* center = t.get("center");
    c.center = center ? read_vec3(*center, "carrier.center") : zero_vec3(c.pos);
    if (free) {
        if (const toml::node* initial = t.get("initial")) {
            for (const auto& [key, value] : entries(as_table(*initial, "carrier.initial")))
                c.initial.push_back(
                    {std::string(key->str()), read_number(*value, "carrier.initial." + std::string(key->str())),
                     at(*key)});
        }
    }
    s.carrier = std::move(c);
}

void Reader::read_bodies(Scene& s) const {
    const toml::node* node = root_.get("body");
    if (!node) return;
    const toml::array* bodies = node->as_array();
    if (!bodies)
        fail(at(*node), fmt::format("'body': expected an array of tables ([[body]]), got {}", type_name(*node)));
    if (bodies->empty())
        fail(at(*node), "'body': expected at least one [[body]]; an empty array declares no body");
    std::map<std::string, SourcePos> seen;
    for (std::size_t i = 0; i < bodies->size(); ++i) {
        const toml::node& element = *bodies->get(i);
        const std::string path = fmt::format("body[{}]", i);
        if (!element.is_table())
            fail(at(element), fmt::format("'{}': expected a table, got {}", path, type_name(element)));
        const toml::table& t = *element.as_table();
        check_keys(t, {"name", "mass", "position", "inertia", "orientation"}, "in [[body]]");
        Body b;
        b.pos = at(t);
        const toml::node& name = require(t, "name", "[[body]]");
        b.name = read_string(name, path + ".name");
        if (!is_scene_identifier(b.name))
            fail(at(name), fmt::format("invalid body name '{}': expected a letter followed by letters, digits or "
                                       "underscores",
                                       b.name));
        if (const auto it = seen.find(b.name); it != seen.end())
            fail(at(name), fmt::format("duplicate body name '{}' (first declared at line {})", b.name,
                                       it->second.line));
        seen.emplace(b.name, at(name));
        b.mass = read_expr(require(t, "mass", "[[body]]"), path + ".mass");
        if (const auto m = literal_number(b.mass.text); m && *m <= 0.0)
            fail(b.mass.pos, fmt::format("'{}.mass': a mass must be positive, got {}", path, b.mass.text));
        b.position = read_vec3(require(t, "position", "[[body]]"), path + ".position");
        if (const toml::node* inertia = t.get("inertia")) {
            b.inertia = read_inertia(*inertia, path + ".inertia");
            b.inertia_pos = at(*inertia);
        }
        if (const toml::node* orientation = t.get("orientation")) {
            if (b.inertia.empty())
                fail(at(*orientation), fmt::format("'{}.orientation' needs '{}.inertia': a particle has no "
                                                   "orientation",
                                                   path, path));
            b.orientation = read_orientation(*orientation, path + ".orientation");
            b.orientation_pos = at(*orientation);
        }
        s.bodies.push_back(std::move(b));
    }
}

// ["z:phi", "x:theta", ...]: an axis letter, a colon, an angle expression.
std::vector<Rotation> Reader::read_orientation(const toml::node& n, const std::string& path) const {
    const toml::array* a = n.as_array();
    if (!a || a->empty())
        fail(at(n), fmt::format("'{}': expected an array of rotations such as \"z:phi\"", path));
    std::vector<Rotation> out;
    for (std::size_t i = 0; i < a->size(); ++i) {
        const Expr e = read_expr(*a->get(i), fmt::format("{}[{}]", path, i));
        const std::size_t colon = e.text.find(':');
        const std::string axis = colon == std::string::npos ? "" : e.text.substr(0, colon);
        if (axis != "x" && axis != "y" && axis != "z")
            fail(e.pos, fmt::format("'{}[{}]': expected \"x:angle\", \"y:angle\" or \"z:angle\", got \"{}\"", path,
                                    i, e.text));
        out.push_back({axis[0], Expr{e.text.substr(colon + 1), e.pos.shifted(int(colon + 1))}});
    }
    return out;
}

}  // namespace eomc::scene
