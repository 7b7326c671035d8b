// An orbit scene (Mei, ch. 2): [orbit], its initial state or elements, and what it excludes.
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

// [orbit]: the central body, the initial orbit (classical elements in degrees, or a state),
// and the formulation of the equations.
void Reader::read_orbit(Scene& s) const {
    const toml::node* node = root_.get("orbit");
    if (!node) return;
    const toml::table& t = as_table(*node, "orbit");
    check_keys(t, {"central_body", "elements", "state", "formulation", "rectify"}, "in [orbit]");
    Orbit o;
    o.pos = at(t);
    const toml::node& body = require(t, "central_body", "[orbit]");
    const toml::table& b = as_table(body, "orbit.central_body");
    check_keys(b, {"mu", "radius"}, "in 'orbit.central_body'");
    o.central_body_pos = at(body);
    o.mu = read_expr(require(b, "mu", "'orbit.central_body'"), "orbit.central_body.mu");
    o.radius = read_expr(require(b, "radius", "'orbit.central_body'"), "orbit.central_body.radius");
    const toml::node* elements = t.get("elements");
    const toml::node* state = t.get("state");
    if (elements && state)
        fail(at(before(at(*elements), at(*state)) ? *state : *elements),
             "[orbit] gives both 'elements' and 'state'; give one initial orbit");
    if (!elements && !state)
        fail(o.pos, "missing required key 'elements' (or 'state') in [orbit]");
    if (elements) {
        o.initial_pos = at(*elements);
        o.elements = read_elements(as_table(*elements, "orbit.elements"));
    } else {
        o.initial_pos = at(*state);
        const toml::table& st = as_table(*state, "orbit.state");
        check_keys(st, {"r", "v"}, "in 'orbit.state'");
        std::array<double, 6> x{};
        for (const auto& [key, offset] : {std::pair{"r", 0}, std::pair{"v", 3}}) {
            const std::string path = std::string("orbit.state.") + key;
            const toml::node& n = require(st, key, "'orbit.state'");
            const toml::array* a = n.as_array();
            if (!a) fail(at(n), fmt::format("'{}': expected an array of 3 numbers, got {}", path, type_name(n)));
            if (a->size() != 3) fail(at(n), fmt::format("'{}': expected 3 components, got {}", path, a->size()));
            for (std::size_t i = 0; i < 3; ++i)
                x[std::size_t(offset) + i] = read_number(*a->get(i), fmt::format("{}[{}]", path, i));
        }
        if (x[0] == 0 && x[1] == 0 && x[2] == 0)
            fail(at(require(st, "r", "'orbit.state'")), "'orbit.state.r' is the centre of the central body");
        o.state = x;
    }
    if (const toml::node* f = t.get("formulation")) {
        o.formulation_pos = at(*f);
        o.formulation = parse_orbit_formulation(read_string(*f, "orbit.formulation"), o.formulation_pos);
    }
    // Read whatever the formulation, so that --orbit-formulation encke finds it.
    if (const toml::node* r = t.get("rectify")) {
        o.rectify = read_number(*r, "orbit.rectify");
        if (!(o.rectify > 0 && o.rectify < 1))
            fail(at(*r), fmt::format("'orbit.rectify' is the fraction |δ|/|ρ| at which encke resets its reference "
                                     "orbit; it must lie in (0, 1), got {}",
                                     number_text(*r)));
    }
    s.orbit = std::move(o);
}

// Classical elements: a and e required; the angles (degrees) default to 0.
std::array<double, 6> Reader::read_elements(const toml::table& t) const {
    check_keys(t, {"a", "e", "i", "raan", "argp", "mean_anomaly"}, "in 'orbit.elements'");
    const double a = read_number(require(t, "a", "'orbit.elements'"), "orbit.elements.a");
    const toml::node& en = require(t, "e", "'orbit.elements'");
    const double e = read_number(en, "orbit.elements.e");
    if (e < 0) fail(at(en), fmt::format("'orbit.elements.e' must not be negative, got {}", number_text(en)));
    if (e == 1)
        fail(at(en), "'orbit.elements.e' = 1 is a parabola, which classical elements with a cannot describe; give "
                     "'orbit.state'");
    if ((e < 1) != (a > 0))
        fail(at(*t.get("a")), fmt::format("'orbit.elements.a' = {} does not fit e = {}: an ellipse (e < 1) has a > 0, "
                                          "a hyperbola (e > 1) a < 0",
                                          number_text(*t.get("a")), number_text(en)));
    constexpr double degree = 3.14159265358979323846 / 180.0;
    std::array<double, 6> el{a, e, 0, 0, 0, 0};
    const char* angles[] = {"i", "raan", "argp", "mean_anomaly"};
    for (std::size_t k = 0; k < 4; ++k) {
        if (const toml::node* n = t.get(angles[k])) {
            const double deg = read_number(*n, std::string("orbit.elements.") + angles[k]);
            if (k == 0 && (deg < 0 || deg > 180))
                fail(at(*n), fmt::format("'orbit.elements.i' is an inclination in degrees, 0 to 180; got {}",
                                         number_text(*n)));
            el[2 + k] = deg * degree;
        }
    }
    return el;
}

// An orbit scene describes its body by [orbit] alone: no carried bodies, energies, equations or
// forces beside it (perturbations go in [effects]).
void Reader::check_orbit_structure() const {
    const toml::node* orbit = root_.get("orbit");
    if (!orbit) return;
    const std::pair<const char*, const char*> others[] = {
        {"body", "[[body]]"},   {"lagrangian", "[lagrangian]"}, {"newtonian", "[newtonian]"},
        {"carrier", "[carrier]"}, {"forces", "[forces]"},       {"reference", "[reference]"}};
    for (const auto& [key, title] : others) {
        const toml::node* other = root_.get(key);
        if (!other) continue;
        const bool orbit_later = before(at(*other), at(*orbit));
        fail(at(orbit_later ? *orbit : *other),
             fmt::format("{} cannot be combined with {} (line {}); an orbit scene describes its body by [orbit] and "
                         "its perturbations by [effects]",
                         orbit_later ? "[orbit]" : title, orbit_later ? title : "[orbit]",
                         at(orbit_later ? *other : *orbit).line));
    }
}

}  // namespace eomc::scene
