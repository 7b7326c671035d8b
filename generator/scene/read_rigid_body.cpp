// A rigid body about a fixed point (Mei, ch. 5): [rigid_body] and what it excludes.
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

// [rigid_body]: the body's inertia at O, mass centre, weight and optional gyrostatic moment as
// expressions of the parameters; ω(0), and γ(0) or a ZXZ attitude, as numbers.
void Reader::read_rigid_body(Scene& s) const {
    const toml::node* node = root_.get("rigid_body");
    if (!node) return;
    const toml::table& t = as_table(*node, "rigid_body");
    check_keys(t, {"inertia", "center", "weight", "gyrostatic_moment", "formulation", "initial"}, "in [rigid_body]");
    RigidBody r;
    r.pos = at(t);
    const toml::node& inertia = require(t, "inertia", "[rigid_body]");
    r.inertia = read_inertia(inertia, "rigid_body.inertia");
    r.inertia_pos = at(inertia);
    const toml::node* center = t.get("center");
    r.center = center ? read_vec3(*center, "rigid_body.center") : zero_vec3(r.pos);
    const toml::node* weight = t.get("weight");
    r.weight = weight ? read_expr(*weight, "rigid_body.weight") : Expr{"0", r.pos};
    if (const toml::node* k = t.get("gyrostatic_moment")) r.gyrostatic_moment = read_vec3(*k, "rigid_body.gyrostatic_moment");
    r.formulation_pos = r.pos;
    if (const toml::node* f = t.get("formulation")) {
        r.formulation_pos = at(*f);
        r.formulation = parse_rigid_formulation(read_string(*f, "rigid_body.formulation"), r.formulation_pos);
    }
    const toml::table& init = as_table(require(t, "initial", "[rigid_body]"), "rigid_body.initial");
    check_keys(init, {"omega", "vertical", "attitude"}, "in 'rigid_body.initial'");
    r.omega = read_numbers3(require(init, "omega", "'rigid_body.initial'"), "rigid_body.initial.omega");
    const toml::node* vertical = init.get("vertical");
    const toml::node* attitude = init.get("attitude");
    if (vertical && attitude)
        fail(at(*attitude), "'rigid_body.initial' gives both 'vertical' and 'attitude'; give one initial attitude");
    if (!vertical && !attitude)
        fail(at(init), "missing required key 'vertical' (γ(0), the upward vertical in body axes) or 'attitude' "
                       "in 'rigid_body.initial'");
    if (vertical) {
        r.initial_pos = at(*vertical);
        const auto g = read_numbers3(*vertical, "rigid_body.initial.vertical");
        const double norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        // A direction typed to the digits a scene shows (0.6, 0.48, 0.64): unit to 1e-9, the
        // relative accuracy of ten significant digits; it is then normalised exactly.
        if (!(std::abs(norm - 1.0) <= 1e-9))
            fail(at(*vertical), fmt::format("'rigid_body.initial.vertical' is the unit upward vertical in body "
                                            "axes; its length is {:.17g}, not 1",
                                            norm));
        // Unit already to the double's rounding: kept as written (dividing by 1 ± 1 ulp would move it).
        r.vertical = std::abs(norm - 1.0) <= 4 * std::numeric_limits<double>::epsilon()
                         ? g
                         : std::array<double, 3>{g[0] / norm, g[1] / norm, g[2] / norm};
    } else {
        r.initial_pos = at(*attitude);
        const toml::table& a = as_table(*attitude, "rigid_body.initial.attitude");
        check_keys(a, {"zxz"}, "in 'rigid_body.initial.attitude'");
        r.zxz = read_numbers3(require(a, "zxz", "'rigid_body.initial.attitude'"), "rigid_body.initial.attitude.zxz");
    }
    s.rigid_body = std::move(r);
}

// A rigid-body scene describes its body by [rigid_body] alone.
void Reader::check_rigid_structure() const {
    const toml::node* rigid = root_.get("rigid_body");
    if (!rigid) return;
    const std::pair<const char*, const char*> others[] = {
        {"body", "[[body]]"},       {"lagrangian", "[lagrangian]"}, {"newtonian", "[newtonian]"},
        {"carrier", "[carrier]"},   {"forces", "[forces]"},         {"reference", "[reference]"},
        {"orbit", "[orbit]"},       {"effects", "[effects]"},       {"constraint", "[[constraint]]"},
        {"formulation", "[formulation]"}};
    for (const auto& [key, title] : others) {
        const toml::node* other = root_.get(key);
        if (!other) continue;
        const bool rigid_later = before(at(*other), at(*rigid));
        fail(at(rigid_later ? *rigid : *other),
             fmt::format("{} cannot be combined with {} (line {}); a rigid-body scene describes its body by "
                         "[rigid_body], and its formulation by [rigid_body] formulation",
                         rigid_later ? "[rigid_body]" : title, rigid_later ? title : "[rigid_body]",
                         at(rigid_later ? *other : *rigid).line));
    }
}

}  // namespace eomc::scene
