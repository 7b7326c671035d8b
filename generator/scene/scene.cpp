#include "scene/scene.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "support/identifier.hpp"

namespace eomc::scene {

namespace {

// ---------------------------------------------------------------------------------------
// Small helpers that need no parser state.

bool is_scene_name(std::string_view s) {
    if (s.empty() || !(s[0] >= 'a' && s[0] <= 'z')) return false;
    return std::all_of(s.begin() + 1, s.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
}

std::string lower_first(std::string s) {
    if (!s.empty()) s[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(s[0])));
    return s;
}

std::string join(std::initializer_list<const char*> names) {
    std::string out;
    for (const char* n : names) {
        if (!out.empty()) out += ", ";
        out += n;
    }
    return out;
}

// "a string", "an integer", ...: the TOML type of a node, for "expected X, got Y".
std::string type_name(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table: return "a table";
        case toml::node_type::array: return "an array";
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a float";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::date: return "a date";
        case toml::node_type::time: return "a time";
        case toml::node_type::date_time: return "a date-time";
        default: return "nothing";
    }
}

// A literal number written as an expression ("2", "-0.5", "1e-3"), if the text is one.
std::optional<double> literal_number(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
    if (!text.empty() && text.front() == '+') text.remove_prefix(1);
    if (text.empty()) return std::nullopt;
    double v = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

bool before(const SourcePos& a, const SourcePos& b) {
    return std::pair(a.line, a.column) < std::pair(b.line, b.column);
}

using Entry = std::pair<const toml::key*, const toml::node*>;

const char* const reserved_functions[] = {"sin", "cos", "tan", "exp", "log", "sqrt", "asin", "acos", "atan"};

// ---------------------------------------------------------------------------------------
// The reader: one scene text, checked section by section.

class Reader {
public:
    Reader(std::string_view text, std::string file) : file_(std::move(file)) {
        // A UTF-8 byte order mark is not part of the first line's columns.
        if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
        split_lines(text);
        try {
            root_ = toml::parse(text, std::string_view(file_));
        } catch (const toml::parse_error& e) {
            fail(at(e.source()), syntax_message(std::string(e.description())));
        }
    }

    Scene read() {
        Scene s;
        check_keys(root_, {"scene", "parameters", "coordinates", "carrier", "body", "lagrangian", "forces",
                           "effects", "simulate", "events", "formulation", "reference", "newtonian", "inverse", "orbit",
                           "constraint", "rigid_body", "unilateral", "contact", "program", "kernel"},
                   "at the top level");
        read_scene(s);
        read_parameters(s);
        read_orbit(s);
        read_rigid_body(s);
        read_coordinates(s);
        check_name_clashes(s);
        read_carrier(s);
        read_bodies(s);
        read_lagrangian(s);
        read_forces(s);
        read_effects(s);
        read_simulate(s);
        read_events(s);
        read_constraints(s);
        read_formulation(s);
        read_kernel(s);
        read_reference(s);
        read_newtonian(s);
        read_inverse(s);
        read_unilateral(s);
        read_contact(s);
        read_programs(s);
        check_orbit_structure();
        check_rigid_structure();
        check_newtonian_structure();
        check_structure();
        return s;
    }

private:
    std::string file_;
    std::vector<std::string> lines_;
    toml::table root_;

    // --- positions --------------------------------------------------------------------

    void split_lines(std::string_view text) {
        std::size_t start = 0;
        while (start <= text.size()) {
            std::size_t nl = text.find('\n', start);
            if (nl == std::string_view::npos) nl = text.size();
            std::string line(text.substr(start, nl - start));
            if (!line.empty() && line.back() == '\r') line.pop_back();
            lines_.push_back(std::move(line));
            start = nl + 1;
        }
    }

    SourcePos at(const toml::source_region& r) const {
        return SourcePos{file_, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
    }
    SourcePos at(const toml::node& n) const { return at(n.source()); }
    SourcePos at(const toml::key& k) const { return at(k.source()); }
    SourcePos top() const { return SourcePos{file_, 1, 1}; }

    // The source text from (line, column) to the end of that line; toml++ counts columns
    // in code points, so step over UTF-8 continuation bytes.
    std::string_view text_from(const SourcePos& p) const {
        if (p.line < 1 || static_cast<std::size_t>(p.line) > lines_.size()) return {};
        std::string_view line = lines_[static_cast<std::size_t>(p.line - 1)];
        std::size_t i = 0;
        for (int col = 1; col < p.column && i < line.size(); ++col) {
            ++i;
            while (i < line.size() && (static_cast<unsigned char>(line[i]) & 0xC0) == 0x80) ++i;
        }
        return line.substr(i);
    }

    // Where the text of a string value starts: after the opening quote(s); a multi-line
    // string that opens with a newline starts on the next line.
    SourcePos string_text_pos(const toml::node& n) const {
        SourcePos p = at(n);
        const std::string_view src = text_from(p);
        if (src.substr(0, 3) == "\"\"\"" || src.substr(0, 3) == "'''") {
            if (src.size() == 3) return SourcePos{file_, p.line + 1, 1};
            return p.shifted(3);
        }
        if (!src.empty() && (src[0] == '"' || src[0] == '\'')) return p.shifted(1);
        return p;
    }

    // The literal of a number value as written, without digit separators or a leading '+'.
    std::string number_text(const toml::node& n) const {
        const std::string_view src = text_from(at(n));
        std::string out;
        for (char c : src) {
            if (std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.') {
                out += c == 'E' ? 'e' : c;
            } else if (c != '_') {
                break;
            }
        }
        if (!out.empty() && out[0] == '+') out.erase(0, 1);
        return out;
    }

    // --- errors ----------------------------------------------------------------------

    [[noreturn]] static void fail(const SourcePos& pos, const std::string& message) {
        throw InputError(pos, message);
    }

    static std::string syntax_message(std::string description) {
        static constexpr std::string_view prefix = "Error while parsing ";
        if (description.rfind(prefix, 0) == 0) {
            const std::string rest = description.substr(prefix.size());
            const std::size_t colon = rest.find(": ");
            if (colon != std::string::npos)
                return fmt::format("invalid TOML in {}: {}", rest.substr(0, colon), rest.substr(colon + 2));
            return "invalid TOML in " + rest;
        }
        return "invalid TOML: " + lower_first(std::move(description));
    }

    // --- tables and keys ---------------------------------------------------------------

    // A table's entries in file order (toml++ keeps them sorted by name).
    static std::vector<Entry> entries(const toml::table& t) {
        std::vector<Entry> out;
        for (const auto& [k, v] : t) out.emplace_back(&k, &v);
        std::stable_sort(out.begin(), out.end(), [](const Entry& a, const Entry& b) {
            const auto& pa = a.first->source().begin;
            const auto& pb = b.first->source().begin;
            return std::pair(pa.line, pa.column) < std::pair(pb.line, pb.column);
        });
        return out;
    }

    void check_keys(const toml::table& t, std::initializer_list<const char*> allowed, const std::string& where) const {
        for (const auto& [key, node] : entries(t)) {
            const std::string name(key->str());
            if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; })) continue;
            const std::string near = nearest_name(name, allowed);
            if (!near.empty())
                fail(at(*key), fmt::format("unknown key '{}' {}; did you mean '{}'?", name, where, near));
            fail(at(*key), fmt::format("unknown key '{}' {}; expected one of: {}", name, where, join(allowed)));
        }
    }

    const toml::table& as_table(const toml::node& n, const std::string& path) const {
        if (const toml::table* t = n.as_table()) return *t;
        fail(at(n), fmt::format("'{}': expected a table, got {}", path, type_name(n)));
    }

    const toml::node& require(const toml::table& t, const char* key, const std::string& where) const {
        if (const toml::node* n = t.get(key)) return *n;
        fail(at(t), fmt::format("missing required key '{}' in {}", key, where));
    }

    // --- values ----------------------------------------------------------------------

    std::string read_string(const toml::node& n, const std::string& path) const {
        if (const auto* s = n.as_string()) return s->get();
        fail(at(n), fmt::format("'{}': expected a string, got {}", path, type_name(n)));
    }

    double read_number(const toml::node& n, const std::string& path) const {
        double v = 0.0;
        if (const auto* i = n.as_integer()) {
            v = static_cast<double>(i->get());
        } else if (const auto* f = n.as_floating_point()) {
            v = f->get();
        } else {
            fail(at(n), fmt::format("'{}': expected a number, got {}", path, type_name(n)));
        }
        if (!std::isfinite(v)) fail(at(n), fmt::format("'{}': expected a finite number, got {}", path, number_text(n)));
        return v;
    }

    bool read_bool(const toml::node& n, const std::string& path) const {
        if (const auto* b = n.as_boolean()) return b->get();
        fail(at(n), fmt::format("'{}': expected true or false, got {}", path, type_name(n)));
    }

    double read_positive(const toml::node& n, const std::string& path) const {
        const double v = read_number(n, path);
        if (!(v > 0.0)) fail(at(n), fmt::format("'{}' must be positive, got {}", path, number_text(n)));
        return v;
    }

    Expr read_expr(const toml::node& n, const std::string& path) const {
        if (const auto* s = n.as_string()) {
            const std::string& text = s->get();
            if (std::all_of(text.begin(), text.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }))
                fail(at(n), fmt::format("'{}': empty expression", path));
            return Expr{text, string_text_pos(n)};
        }
        if (const auto* i = n.as_integer()) return Expr{std::to_string(i->get()), at(n)};
        if (n.is_floating_point()) {
            if (!std::isfinite(n.as_floating_point()->get()))
                fail(at(n), fmt::format("'{}': expected a finite number, got {}", path, number_text(n)));
            return Expr{number_text(n), at(n)};
        }
        fail(at(n), fmt::format("'{}': expected an expression (a string or a number), got {}", path, type_name(n)));
    }

    Vec3 read_vec3(const toml::node& n, const std::string& path) const {
        const toml::array* a = n.as_array();
        if (!a) fail(at(n), fmt::format("'{}': expected an array of 3 expressions, got {}", path, type_name(n)));
        if (a->size() != 3) fail(at(n), fmt::format("'{}': expected 3 components, got {}", path, a->size()));
        Vec3 v;
        for (std::size_t i = 0; i < 3; ++i) v[i] = read_expr(*a->get(i), fmt::format("{}[{}]", path, i));
        return v;
    }

    static Vec3 zero_vec3(const SourcePos& pos) { return Vec3{Expr{"0", pos}, Expr{"0", pos}, Expr{"0", pos}}; }

    // Parameters and coordinates become symbols: they must not shadow the time, the
    // built-in functions and constants, or the derived names q_dot / q_ddot.
    void check_symbol_name(const std::string& name, const SourcePos& pos, const char* kind) const {
        if (!is_scene_identifier(name))
            fail(pos, fmt::format("invalid {} name '{}': expected a letter followed by letters, digits or underscores",
                                  kind, name));
        if (name == "t") fail(pos, fmt::format("'t' is reserved for the time and cannot name a {}", kind));
        if (name == "Pi") fail(pos, fmt::format("'Pi' is reserved for the constant pi and cannot name a {}", kind));
        for (const char* f : reserved_functions)
            if (name == f)
                fail(pos, fmt::format("'{}' is reserved for a built-in function and cannot name a {}", name, kind));
        const auto ends_with = [&](std::string_view suffix) {
            return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
        };
        if (ends_with("_ddot"))
            fail(pos, fmt::format("{} name '{}' ends in '_ddot', which is reserved for generalized accelerations",
                                  kind, name));
        if (ends_with("_dot"))
            fail(pos, fmt::format("{} name '{}' ends in '_dot', which is reserved for generalized velocities", kind,
                                  name));
    }

    // --- sections --------------------------------------------------------------------

    void read_scene(Scene& s) const {
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

    void read_parameters(Scene& s) const {
        const toml::node* node = root_.get("parameters");
        if (!node) return;
        for (const auto& [key, value] : entries(as_table(*node, "parameters"))) {
            const std::string name(key->str());
            check_symbol_name(name, at(*key), "parameter");
            s.parameters.push_back(Parameter{name, read_number(*value, "parameters." + name), at(*key)});
        }
    }

    void read_coordinates(Scene& s) const {
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
            if (const toml::node* v = c.get("initial")) coord.initial = read_number(*v, path + ".initial");
            if (const toml::node* v = c.get("rate")) coord.rate = read_number(*v, path + ".rate");
            s.coordinates.push_back(std::move(coord));
        }
    }

    void check_name_clashes(const Scene& s) const {
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

    // Bodies (with an optional carrier and effects) or a Lagrangian: one or the other.
    void check_structure() const {
        const toml::node* lagrangian = root_.get("lagrangian");
        const toml::node* body = root_.get("body");
        const toml::node* carrier = root_.get("carrier");
        const toml::node* effects = root_.get("effects");
        if (lagrangian) {
            const std::pair<const toml::node*, const char*> others[] = {
                {body, "[[body]]"}, {carrier, "[carrier]"}, {effects, "[effects]"}};
            for (const auto& [other, title] : others) {
                if (!other) continue;
                const bool lagrangian_later = before(at(*other), at(*lagrangian));
                const toml::node& later = lagrangian_later ? *lagrangian : *other;
                const toml::node& earlier = lagrangian_later ? *other : *lagrangian;
                fail(at(later),
                     fmt::format("{} cannot be combined with {} (line {}); a scene gives either carried bodies "
                                 "([[body]], with an optional [carrier] and [effects]) or a [lagrangian]",
                                 lagrangian_later ? "[lagrangian]" : title, lagrangian_later ? title : "[lagrangian]",
                                 at(earlier).line));
            }
        } else if (!body && !root_.get("newtonian") && !root_.get("orbit") && !root_.get("rigid_body")) {
            fail(top(), "the scene has neither [[body]] nor [lagrangian] nor [newtonian] nor [orbit] nor [rigid_body]; "
                        "give carried bodies, a lagrangian L = T - V, the equations of motion, an orbit or a rigid body "
                        "about a fixed point");
        }
        if (effects && !carrier && !root_.get("orbit"))
            fail(at(*effects), "[effects] requires a [carrier] (inertial effects of a moving frame) or an [orbit] "
                               "(perturbations of an orbit)");
    }

    void read_carrier(Scene& s) const {
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

    // Three principal moments, or a 3×3 matrix as 9 entries or 3 rows of 3.
    std::vector<Expr> read_inertia(const toml::node& n, const std::string& path) const {
        const toml::array* a = n.as_array();
        if (!a) fail(at(n), fmt::format("'{}': expected 3 principal moments or a 3×3 array, got {}", path, type_name(n)));
        std::vector<Expr> out;
        if (a->size() == 3 && a->get(0)->is_array()) {
            for (std::size_t i = 0; i < 3; ++i) {
                const Vec3 row = read_vec3(*a->get(i), fmt::format("{}[{}]", path, i));
                out.insert(out.end(), row.begin(), row.end());
            }
        } else if (a->size() == 3 || a->size() == 9) {
            for (std::size_t i = 0; i < a->size(); ++i) out.push_back(read_expr(*a->get(i), fmt::format("{}[{}]", path, i)));
        } else {
            fail(at(n), fmt::format("'{}': expected 3 principal moments or a 3×3 array, got {} entries", path, a->size()));
        }
        return out;
    }

    void read_bodies(Scene& s) const {
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
    std::vector<Rotation> read_orientation(const toml::node& n, const std::string& path) const {
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

    void read_formulation(Scene& s) const {
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

    void read_kernel(Scene& s) const {
        const toml::node* node = root_.get("kernel");
        if (!node) return;
        const toml::table& t = as_table(*node, "kernel");
        check_keys(t, {"jacobian"}, "in [kernel]");
        if (const toml::node* v = t.get("jacobian")) s.kernel_jacobian = read_bool(*v, "kernel.jacobian");
    }

    void read_lagrangian(Scene& s) const {
        const toml::node* node = root_.get("lagrangian");
        if (!node) return;
        const toml::table& t = as_table(*node, "lagrangian");
        check_keys(t, {"T", "V"}, "in [lagrangian]");
        Lagrangian l;
        l.pos = at(t);
        l.kinetic = read_expr(require(t, "T", "[lagrangian]"), "lagrangian.T");
        const toml::node* v = t.get("V");
        l.potential = v ? read_expr(*v, "lagrangian.V") : Expr{"0", l.pos};
        s.lagrangian = std::move(l);
    }

    void read_forces(Scene& s) const {
        const toml::node* node = root_.get("forces");
        if (!node) return;
        const toml::table& t = as_table(*node, "forces");
        check_keys(t, {"potential", "generalized", "resultant", "moment"}, "in [forces]");
        if (const toml::node* v = t.get("potential")) s.forces.potential = read_expr(*v, "forces.potential");
        for (const auto& [key, target, where] :
             {std::tuple{"resultant", &s.forces.resultant, &s.forces.resultant_pos},
              std::tuple{"moment", &s.forces.moment, &s.forces.moment_pos}}) {
            const toml::node* n = t.get(key);
            if (!n) continue;
            if (!s.carrier)
                fail(at(*n), fmt::format("'forces.{}' acts on a carrier's system; this scene has no [carrier] "
                                         "(use [forces] potential or generalized)",
                                         key));
            *target = read_vec3(*n, std::string("forces.") + key);
            *where = at(*n);
        }
        if (const toml::node* g = t.get("generalized")) {
            for (const auto& [key, value] : entries(as_table(*g, "forces.generalized"))) {
                const std::string name(key->str());
                s.forces.generalized.push_back(
                    GeneralizedForce{name, read_expr(*value, "forces.generalized." + name), at(*key)});
            }
        }
    }

    void read_effects(Scene& s) const {
        const toml::node* node = root_.get("effects");
        if (!node) return;
        const toml::table& t = as_table(*node, "effects");
        s.effects.pos = at(t);
        const bool orbit = s.orbit.has_value();
        if (orbit) check_keys(t, {"keep", "custom"}, "in [effects]");
        else check_keys(t, {"keep"}, "in [effects]");
        if (const toml::node* custom = t.get("custom")) read_custom_effects(s, as_table(*custom, "effects.custom"));
        const toml::node* keep = t.get("keep");
        if (!keep) return;
        const toml::array* a = keep->as_array();
        if (!a) fail(at(*keep), fmt::format("'effects.keep': expected an array of effect names, got {}", type_name(*keep)));
        s.effects.given = true;
        // The two effect vocabularies never mix: an orbit scene keeps perturbations, a carrier
        // scene keeps inertial effects; a name from the other list says which scene it belongs to.
        const std::vector<std::string> own = orbit ? std::vector<std::string>(orbit_effect_names.begin(), orbit_effect_names.end())
                                                   : std::vector<std::string>(effect_names.begin(), effect_names.end());
        const std::vector<std::string> other = orbit ? std::vector<std::string>(effect_names.begin(), effect_names.end())
                                                     : std::vector<std::string>(orbit_effect_names.begin(), orbit_effect_names.end());
        for (std::size_t i = 0; i < a->size(); ++i) {
            const toml::node& entry = *a->get(i);
            const std::string name = read_string(entry, fmt::format("effects.keep[{}]", i));
            if (std::find(own.begin(), own.end(), name) == own.end()) {
                if (std::find(other.begin(), other.end(), name) != other.end())
                    fail(at(entry), orbit ? fmt::format("'{}' in effects.keep is an inertial effect of a [carrier] scene; "
                                                        "an [orbit] scene keeps perturbations: {}",
                                                        name, fmt::join(own, ", "))
                                          : fmt::format("'{}' in effects.keep is a perturbation of an [orbit] scene; this "
                                                        "scene keeps inertial effects of its carrier: {}",
                                                        name, fmt::join(own, ", ")));
                const std::string near = nearest_name(name, own);
                fail(at(entry), fmt::format("unknown effect '{}' in effects.keep; {}", name,
                                            near.empty() ? fmt::format("expected one of: {}", fmt::join(own, ", "))
                                                         : fmt::format("did you mean '{}'?", near)));
            }
            for (std::size_t j = 0; j < s.effects.keep.size(); ++j)
                if (s.effects.keep[j] == name)
                    fail(at(entry), fmt::format("effect '{}' appears twice in effects.keep (first at line {}, column {})",
                                                name, s.effects.keep_pos[j].line, s.effects.keep_pos[j].column));
            s.effects.keep.push_back(name);
            s.effects.keep_pos.push_back(at(entry));
        }
    }

    // [effects.custom] of an orbit scene: a disturbing function and/or an acceleration.
    void read_custom_effects(Scene& s, const toml::table& t) const {
        check_keys(t, {"disturbing_function", "acceleration"}, "in [effects.custom]");
        if (const toml::node* r = t.get("disturbing_function"))
            s.effects.disturbing_function = read_expr(*r, "effects.custom.disturbing_function");
        if (const toml::node* a = t.get("acceleration"))
            s.effects.acceleration = read_vec3(*a, "effects.custom.acceleration");
        if (!s.effects.disturbing_function && !s.effects.acceleration)
            fail(at(t), "[effects.custom] gives neither 'disturbing_function' nor 'acceleration'");
    }

    // [orbit]: the central body, the initial orbit (classical elements in degrees, or a state),
    // and the formulation of the equations.
    void read_orbit(Scene& s) const {
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
    std::array<double, 6> read_elements(const toml::table& t) const {
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

    // [rigid_body]: the body's inertia at O, mass centre, weight and optional gyrostatic moment as
    // expressions of the parameters; ω(0), and γ(0) or a ZXZ attitude, as numbers.
    void read_rigid_body(Scene& s) const {
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

    std::array<double, 3> read_numbers3(const toml::node& n, const std::string& path) const {
        const toml::array* a = n.as_array();
        if (!a) fail(at(n), fmt::format("'{}': expected an array of 3 numbers, got {}", path, type_name(n)));
        if (a->size() != 3) fail(at(n), fmt::format("'{}': expected 3 numbers, got {}", path, a->size()));
        std::array<double, 3> v{};
        for (std::size_t i = 0; i < 3; ++i) v[i] = read_number(*a->get(i), fmt::format("{}[{}]", path, i));
        return v;
    }

    // A rigid-body scene describes its body by [rigid_body] alone.
    void check_rigid_structure() const {
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

    // An orbit scene describes its body by [orbit] alone: no carried bodies, energies, equations or
    // forces beside it (perturbations go in [effects]).
    void check_orbit_structure() const {
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

    void read_simulate(Scene& s) const {
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
    void read_events(Scene& s) const {
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

    // An array of tables [[key]] (`title`): its elements, each checked to be a table. Absent: none.
    std::vector<const toml::table*> table_array(const char* key, const char* title, const char* noun) const {
        std::vector<const toml::table*> out;
        const toml::node* node = root_.get(key);
        if (!node) return out;
        const toml::array* rows = node->as_array();
        if (!rows)
            fail(at(*node), fmt::format("'{}': expected an array of tables ({}), got {}", key, title, type_name(*node)));
        if (rows->empty())
            fail(at(*node), fmt::format("'{}': expected at least one {}; an empty array declares no {}", key, title, noun));
        for (std::size_t i = 0; i < rows->size(); ++i) {
            const toml::node& element = *rows->get(i);
            if (!element.is_table())
                fail(at(element), fmt::format("'{}[{}]': expected a table, got {}", key, i, type_name(element)));
            out.push_back(element.as_table());
        }
        return out;
    }

    // A row's `name`: an identifier not yet in `seen` (which it joins). `noun` names the row's
    // kind in the messages; `duplicate` says what an earlier row of that name was.
    std::string read_row_name(const toml::table& t, const std::string& path, const char* title, const char* noun,
                              std::map<std::string, std::pair<SourcePos, std::string>>& seen, SourcePos& name_pos) const {
        const toml::node& name = require(t, "name", title);
        std::string value = read_string(name, path + ".name");
        name_pos = at(name);
        if (!is_scene_identifier(value))
            fail(at(name), fmt::format("invalid {} name '{}': expected a letter followed by letters, digits or "
                                       "underscores",
                                       noun, value));
        if (const auto it = seen.find(value); it != seen.end())
            fail(at(name), fmt::format("duplicate {} name '{}' (first declared{} at line {})", noun, value,
                                       it->second.second, it->second.first.line));
        seen.emplace(value, std::pair(at(name), std::string()));
        return value;
    }

    // Exactly one of the keys `a` and `b` of a row's table: the node and whether it is `a`. Both are
    // refused at the later one with `both`, neither at the table with `neither`.
    std::pair<const toml::node*, bool> exactly_one(const toml::table& t, const char* a, const char* b,
                                                   const std::string& both, const std::string& neither) const {
        const toml::node* first = t.get(a);
        const toml::node* second = t.get(b);
        if (first && second) {
            const bool second_later = before(at(*first), at(*second));
            fail(at(second_later ? *second : *first), both);
        }
        if (!first && !second) fail(at(t), neither);
        return {first ? first : second, first != nullptr};
    }

    // [[constraint]]: name = "rod", exactly one of holonomic = "f(q, t)" or kinematic =
    // "B(q, t) q̇ + b(q, t)", and stabilize = "project" (default) | "none" | { alpha = a, beta = b }
    // (Baumgarte). The algebra (which symbols, linearity in the rates, the initial state) is the
    // model's to check.
    void read_constraints(Scene& s) const {
        const auto rows = table_array("constraint", "[[constraint]]", "constraint");
        std::map<std::string, std::pair<SourcePos, std::string>> seen;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const std::string path = fmt::format("constraint[{}]", i);
            const toml::table& t = *rows[i];
            check_keys(t, {"name", "holonomic", "kinematic", "stabilize"}, "in [[constraint]]");
            Constraint c;
            c.pos = at(t);
            c.name = read_row_name(t, path, "[[constraint]]", "constraint", seen, c.name_pos);
            const auto [expression, holonomic] = exactly_one(
                t, "holonomic", "kinematic",
                fmt::format("constraint '{}' has both 'holonomic' and 'kinematic'; a row is one or the other (declare "
                            "two [[constraint]] tables for two rows)",
                            c.name),
                fmt::format("constraint '{}' needs 'holonomic = \"f(q, t)\"' or 'kinematic = \"B(q, t) q_dot + b(q, "
                            "t)\"'",
                            c.name));
            c.holonomic = holonomic;
            c.expression = read_expr(*expression, path + (holonomic ? ".holonomic" : ".kinematic"));
            c.stabilize_pos = c.pos;
            if (const toml::node* st = t.get("stabilize")) {
                c.stabilize_pos = at(*st);
                if (const toml::table* spec = st->as_table()) {
                    check_keys(*spec, {"alpha", "beta"}, "in '" + path + ".stabilize'");
                    c.stabilize = "baumgarte";
                    // A rate constant: not negative, and a double the model's exact arithmetic and the
                    // kernel can hold as 2α and β² (CLN has no subnormal floats; 1e150² is near the
                    // largest double).
                    const auto rate_constant = [&](const toml::node& n, const char* key) {
                        const double v = read_number(n, path + ".stabilize." + key);
                        if (v < 0.0 || (v != 0.0 && v < std::numeric_limits<double>::min()) || v > 1e150)
                            fail(at(n), fmt::format("'{}.stabilize.{}' must be 0 or between 2.2e-308 and 1e150, got {}",
                                                    path, key, number_text(n)));
                        return v;
                    };
                    c.alpha = rate_constant(require(*spec, "alpha", "'" + path + ".stabilize'"), "alpha");
                    if (const toml::node* b = spec->get("beta")) {
                        c.beta = rate_constant(*b, "beta");
                    } else if (c.holonomic) {
                        fail(at(*spec), fmt::format("missing required key 'beta' in '{}.stabilize': a holonomic row's "
                                                    "Baumgarte stabilisation needs alpha and beta",
                                                    path));
                    }
                } else if (const auto* str = st->as_string()) {
                    c.stabilize = str->get();
                    if (c.stabilize != "project" && c.stabilize != "none") {
                        const std::string near = nearest_name(c.stabilize, {"project", "none"});
                        fail(at(*st), fmt::format("unknown stabilize value '{}' in '{}'; {}", c.stabilize, path,
                                                  near.empty() ? std::string("expected \"project\", \"none\" or "
                                                                             "{ alpha = ..., beta = ... } (Baumgarte)")
                                                               : fmt::format("did you mean '{}'?", near)));
                    }
                } else {
                    fail(at(*st), fmt::format("'{}.stabilize': expected \"project\", \"none\" or a table "
                                              "{{ alpha = ..., beta = ... }}, got {}",
                                              path, type_name(*st)));
                }
            }
            s.constraints.push_back(std::move(c));
        }
    }

    // [[unilateral]]: name = "floor", exactly one of gap = "f(q, t)" (Mei, §6.2) or velocity =
    // "B(q, t) q̇ + b(q, t)" (§6.7), and restitution = "e" (Newton's coefficient; "0" when absent).
    // Read as [[constraint]] rows are; names are unique among both kinds. Only a system given by its
    // energies in coordinates takes them: not an orbit, a rigid body about a point, given equations,
    // a free carrier or Hamilton's form (whose kernels carry no rows).
    void read_unilateral(Scene& s) const {
        const auto rows = table_array("unilateral", "[[unilateral]]", "unilateral constraint");
        if (rows.empty()) return;
        const SourcePos first = at(*rows.front());
        const std::pair<const char*, const char*> refused[] = {
            {"orbit", "an [orbit] scene: an orbit is a free point mass"},
            {"rigid_body", "a [rigid_body] scene: its formulations carry no constraint rows"},
            {"newtonian", "a [newtonian] scene: its equations are given, so there are no energies for the reactions "
                          "to enter"}};
        for (const auto& [key, why] : refused)
            if (root_.get(key))
                fail(first, fmt::format("[[unilateral]] is not supported in {}; give the system by [lagrangian] or "
                                        "[[body]]",
                                        why));
        if (s.carrier && s.carrier->motion == "free")
            fail(first, fmt::format("[[unilateral]] is not supported with a free carrier ([carrier] motion = \"free\", "
                                    "line {}): its quasi-velocities have no impact equations here; give the carrier's "
                                    "motion (prescribed) or its freedom as coordinates",
                                    s.carrier->pos.line));
        if (s.formulation == "hamiltonian")
            fail(first, fmt::format("[[unilateral]] is not supported with [formulation] kind = \"hamiltonian\" (line "
                                    "{}): the rows are carried by Lagrange's equations only; use kind = \"lagrangian\"",
                                    s.formulation_pos.line));
        std::map<std::string, std::pair<SourcePos, std::string>> seen;
        for (const Constraint& c : s.constraints) seen.emplace(c.name, std::pair(c.name_pos, std::string(" as a [[constraint]]")));
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const std::string path = fmt::format("unilateral[{}]", i);
            const toml::table& t = *rows[i];
            check_keys(t, {"name", "gap", "velocity", "restitution"}, "in [[unilateral]]");
            Unilateral u;
            u.pos = at(t);
            u.name = read_row_name(t, path, "[[unilateral]]", "unilateral constraint", seen, u.name_pos);
            const auto [expression, gap] = exactly_one(
                t, "gap", "velocity",
                fmt::format("unilateral constraint '{}' has both 'gap' and 'velocity'; a row is one or the other "
                            "(declare two [[unilateral]] tables for two rows)",
                            u.name),
                fmt::format("unilateral constraint '{}' needs 'gap = \"f(q, t)\"' (f >= 0) or 'velocity = \"B(q, t) "
                            "q_dot + b(q, t)\"' (phi >= 0)",
                            u.name));
            u.holonomic = gap;
            u.expression = read_expr(*expression, path + (gap ? ".gap" : ".velocity"));
            if (const toml::node* e = t.get("restitution")) u.restitution = read_expr(*e, path + ".restitution");
            else u.restitution = Expr{"0", u.pos};
            s.unilateral.push_back(std::move(u));
        }
    }

    // [[program]]: name, constraint = "ω(q, t)" or "φ(q, q̇, t)", erugin = { alpha, beta } |
    // { kappa } (absent: the open loop), control = "ideal" (default) | { coordinate = "direction" }
    // | ["coordinate", ...], or on a [rigid_body] { moment = [m1, m2, m3] } (a body-axis torque
    // direction, Mei §3.2). Which law fits which kind of relation is the model's to check (it knows
    // which symbols the relation holds). A system given by its energies in coordinates, or a rigid
    // body, takes programs, and [[constraint]] rows beside them (the model solves both together).
    void read_programs(Scene& s) const {
        const auto rows = table_array("program", "[[program]]", "program");
        if (rows.empty()) return;
        const SourcePos first = at(*rows.front());
        const std::pair<const char*, const char*> refused[] = {
            {"orbit", "an [orbit] scene"},
            {"newtonian", "a [newtonian] scene: its equations are given, so there is no mass matrix for the control "
                          "to act through"},
            {"unilateral", "a scene with [[unilateral]] rows"}};
        for (const auto& [key, why] : refused)
            if (root_.get(key))
                fail(first, fmt::format("[[program]] is not supported in {}; give the system by [lagrangian] or [[body]]",
                                        why));
        if (s.carrier && s.carrier->motion == "free")
            fail(first, fmt::format("[[program]] is not supported with a free carrier ([carrier] motion = \"free\", line "
                                    "{}): the controls act on the coordinates' equations only",
                                    s.carrier->pos.line));
        if (s.formulation == "hamiltonian")
            fail(first, fmt::format("[[program]] is not supported with [formulation] kind = \"hamiltonian\" (line {}): "
                                    "the controls enter Lagrange's equations; use kind = \"lagrangian\"",
                                    s.formulation_pos.line));
        std::vector<std::string> coordinates;
        for (const auto& c : s.coordinates) coordinates.push_back(c.name);
        const auto known_coordinate = [&](const std::string& name, const SourcePos& where, const std::string& path) {
            if (std::find(coordinates.begin(), coordinates.end(), name) != coordinates.end()) return;
            const std::string near = nearest_name(name, coordinates);
            fail(where, fmt::format("unknown coordinate '{}' in '{}'; {}", name, path,
                                    near.empty() ? fmt::format("the coordinates are {}", fmt::join(coordinates, ", "))
                                                 : fmt::format("did you mean '{}'?", near)));
        };
        std::map<std::string, std::pair<SourcePos, std::string>> seen;
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const std::string path = fmt::format("program[{}]", i);
            const toml::table& t = *rows[i];
            check_keys(t, {"name", "constraint", "erugin", "control"}, "in [[program]]");
            Program p;
            p.pos = p.erugin_pos = p.control_pos = at(t);
            p.name = read_row_name(t, path, "[[program]]", "program", seen, p.name_pos);
            p.constraint = read_expr(require(t, "constraint", "[[program]] '" + p.name + "'"), path + ".constraint");
            if (const toml::node* e = t.get("erugin")) {
                p.erugin_pos = at(*e);
                const toml::table& law = as_table(*e, path + ".erugin");
                check_keys(law, {"alpha", "beta", "kappa"}, "in '" + path + ".erugin'");
                // Galiullin's choice is stable for α > 0, β > 0 (ω̈ + 2αω̇ + β²ω = 0) and κ > 0; the
                // bound keeps 2α, β² and κ doubles the exact arithmetic can hold.
                const auto gain = [&](const char* key) {
                    const toml::node& n = require(law, key, "'" + path + ".erugin'");
                    const double v = read_number(n, path + ".erugin." + key);
                    if (!(v > 0.0) || v < std::numeric_limits<double>::min() || v > 1e150)
                        fail(at(n), fmt::format("'{}.erugin.{}' must be positive (at most 1e150), got {}; Erugin's law "
                                                "is stable only for positive gains",
                                                path, key, number_text(n)));
                    return v;
                };
                p.closed_loop = true;
                if (const toml::node* k = law.get("kappa")) {
                    if (law.get("alpha") || law.get("beta"))
                        fail(at(*k), fmt::format("'{}.erugin' has both kappa (phi_dot + kappa phi = 0, a phase-space "
                                                 "program) and alpha/beta (omega_ddot + 2 alpha omega_dot + beta^2 "
                                                 "omega = 0, a configuration-space one); give one law",
                                                 path));
                    p.phase_law = true;
                    p.kappa = gain("kappa");
                } else {
                    p.alpha = gain("alpha");
                    p.beta = gain("beta");
                }
            }
            if (const toml::node* c = t.get("control")) {
                p.control_pos = at(*c);
                if (const auto* str = c->as_string()) {
                    if (str->get() != "ideal")
                        fail(at(*c), fmt::format("unknown control '{}' in '{}'; expected \"ideal\", a table "
                                                 "{{ coordinate = \"direction\" }} or a list of actuated coordinates",
                                                 str->get(), path));
                } else if (c->is_table() && s.rigid_body) {
                    // A rigid body (Mei §3.2): the control is a torque about a fixed body-axis direction,
                    // M_c = m λ, entering Euler's equations I ω̇ = (Iω) × ω + M_g + m λ.
                    p.control = "moment";
                    const toml::table& given = *c->as_table();
                    check_keys(given, {"moment"}, "in '" + path + ".control' of a [rigid_body] scene");
                    const toml::node& m = require(given, "moment", "'" + path + ".control'");
                    p.moment = read_vec3(m, path + ".control.moment");
                    const bool zero = std::all_of(p.moment.begin(), p.moment.end(), [](const Expr& e) {
                        char* end = nullptr;
                        const double v = std::strtod(e.text.c_str(), &end);
                        return end && *end == '\0' && v == 0.0;
                    });
                    if (zero)
                        fail(at(m), fmt::format("'{}.control.moment' is the zero vector: it gives no torque direction",
                                                path));
                } else if (const toml::table* given = c->as_table()) {
                    p.control = "directions";
                    if (given->empty()) fail(at(*c), fmt::format("'{}.control': an empty table gives no direction", path));
                    for (const auto& [key, value] : entries(*given)) {
                        const std::string name(key->str());
                        known_coordinate(name, at(*key), path + ".control");
                        p.directions.emplace_back(name, read_expr(*value, path + ".control." + name));
                    }
                } else if (c->is_array() && s.rigid_body) {
                    fail(at(*c), fmt::format("'{}.control': a rigid body has no coordinates to actuate; give a body-axis "
                                             "torque direction, control = {{ moment = [1, 0, 0] }}",
                                             path));
                } else if (const toml::array* list = c->as_array()) {
                    p.control = "actuated";
                    if (list->empty()) fail(at(*c), fmt::format("'{}.control': an empty list actuates nothing", path));
                    for (std::size_t k = 0; k < list->size(); ++k) {
                        const toml::node& n = *list->get(k);
                        const std::string name = read_string(n, fmt::format("{}.control[{}]", path, k));
                        known_coordinate(name, at(n).shifted(1), path + ".control");
                        for (const auto& [other, where] : p.actuated)
                            if (other == name)
                                fail(at(n), fmt::format("coordinate '{}' is actuated twice in '{}.control' (first at "
                                                        "column {})",
                                                        name, path, where.column));
                        p.actuated.emplace_back(name, at(n));
                    }
                } else {
                    fail(at(*c), fmt::format("'{}.control': expected \"ideal\", a table {{ coordinate = \"direction\" }} "
                                             "or a list of coordinates, got {}",
                                             path, type_name(*c)));
                }
            }
            s.programs.push_back(std::move(p));
        }
    }

    // [contact]: method = "event_driven" (default) | "moreau_jean", theta = θ in [0.5, 1]
    // (Moreau–Jean's θ-method; Acary & Brogliato 2008), impact_law = "simultaneous" (default) |
    // "sequential" (event_driven only). Only beside [[unilateral]] rows.
    void read_contact(Scene& s) const {
        const toml::node* node = root_.get("contact");
        if (!node) return;
        const toml::table& t = as_table(*node, "contact");
        Contact& c = s.contact;
        c.pos = c.method_pos = c.theta_pos = c.impact_law_pos = at(t);
        check_keys(t, {"method", "theta", "impact_law"}, "in [contact]");
        if (s.unilateral.empty())
            fail(at(t), "[contact] says how to integrate through unilateral constraints, but the scene declares no "
                        "[[unilateral]] row");
        namespace rc = runtime::contact;
        // A name from the runtime's table, or the error with the nearest one.
        const auto choose = [&](const toml::node& v, const char* key, const char* what, const auto& find,
                                const std::vector<std::string>& names) {
            const std::string text = read_string(v, key);
            if (const auto value = find(text)) return *value;
            const std::string near = nearest_name(text, names);
            fail(at(v), fmt::format("unknown {} '{}'; {}", what, text,
                                    near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                 : fmt::format("did you mean '{}'?", near)));
        };
        if (const toml::node* m = t.get("method")) {
            c.method = choose(*m, "contact.method", "contact method",
                              [](std::string_view n) { return rc::find_contact_method(n); }, rc::contact_method_names());
            c.method_pos = at(*m);
        }
        if (const toml::node* th = t.get("theta")) {
            c.theta = read_number(*th, "contact.theta");
            c.theta_pos = at(*th);
            if (!rc::valid_theta(c.theta))
                fail(at(*th), fmt::format("'contact.theta' must be between 0.5 and 1 (Moreau-Jean's theta-method), got "
                                          "{}",
                                          number_text(*th)));
            if (c.method != rc::ContactMethod::moreau_jean)
                fail(at(*th), fmt::format("'contact.theta' is Moreau-Jean's; it has no meaning with method = \"{}\"",
                                          rc::name(c.method)));
        }
        if (const toml::node* law = t.get("impact_law")) {
            c.impact_law = choose(*law, "contact.impact_law", "impact law",
                                  [](std::string_view n) { return rc::find_impact_law(n); }, rc::impact_law_names());
            c.impact_law_pos = at(*law);
            // Moreau–Jean's step LCP is the simultaneous law by construction.
            if (c.method == rc::ContactMethod::moreau_jean && c.impact_law != rc::ImpactLaw::simultaneous)
                fail(at(*law), fmt::format("'contact.impact_law' = \"{}\" needs method = \"event_driven\"; "
                                           "Moreau-Jean resolves every step's impacts simultaneously",
                                           rc::name(c.impact_law)));
        }
    }

    // [reference]: state name = expression, for every state variable (q and q_dot of each coordinate).
    void read_reference(Scene& s) const {
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

    // [newtonian]: `<coordinate>_ddot = "f"` entries (kinematic form), or a subtable
    // [newtonian.fundamental] with `<coordinate> = "Φ"` entries (fundamental form); not both.
    void read_newtonian(Scene& s) const {
        const toml::node* node = root_.get("newtonian");
        if (!node) return;
        const toml::table& t = as_table(*node, "newtonian");
        Newtonian n;
        n.pos = at(t);
        const toml::node* fundamental = t.get("fundamental");
        for (const auto& [key, value] : entries(t)) {
            const std::string name(key->str());
            if (name == "fundamental") continue;
            const std::string path = "newtonian." + name;
            static constexpr std::string_view suffix = "_ddot";
            if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
                if (name.size() > 4 && name.compare(name.size() - 4, 4, "_dot") == 0)
                    fail(at(*key), fmt::format("'{}': [newtonian] gives accelerations; write '{}_ddot = ...' (or the "
                                               "fundamental form in [newtonian.fundamental])",
                                               path, name.substr(0, name.size() - 4)));
                fail(at(*key), fmt::format("unknown key '{}' in [newtonian]; expected '<coordinate>_ddot = \"...\"' "
                                           "(kinematic form) or a [newtonian.fundamental] table",
                                           name));
            }
            if (fundamental)
                fail(at(*key), fmt::format("'{}': [newtonian] gives the kinematic form (accelerations) or the "
                                           "fundamental form ([newtonian.fundamental], line {}), not both",
                                           path, at(*fundamental).line));
            n.equations.push_back(
                NewtonianEquation{name.substr(0, name.size() - suffix.size()), read_expr(*value, path), at(*key)});
        }
        if (fundamental) {
            const toml::table& f = as_table(*fundamental, "newtonian.fundamental");
            n.fundamental = true;
            n.pos = at(f);
            for (const auto& [key, value] : entries(f)) {
                const std::string name(key->str());
                n.equations.push_back(NewtonianEquation{name, read_expr(*value, "newtonian.fundamental." + name), at(*key)});
            }
        }
        if (n.equations.empty())
            fail(n.pos, "[newtonian] gives no equation; write one '<coordinate>_ddot = \"...\"' per coordinate, or "
                        "one '<coordinate> = \"...\"' per coordinate in [newtonian.fundamental]");
        s.newtonian = std::move(n);
    }

    void read_inverse(Scene& s) const {
        const toml::node* node = root_.get("inverse");
        if (!node) return;
        const toml::table& t = as_table(*node, "inverse");
        check_keys(t, {"construct", "multiplier_search"}, "in [inverse]");
        auto flag = [&](const char* key, bool& out) {
            const toml::node* v = t.get(key);
            if (!v) return;
            const auto* b = v->as_boolean();
            if (!b) fail(at(*v), fmt::format("'inverse.{}': expected a boolean, got {}", key, type_name(*v)));
            out = b->get();
        };
        flag("construct", s.inverse.construct);
        flag("multiplier_search", s.inverse.multiplier_search);
    }

    // The equations replace the energies: nothing that describes energies or forces may
    // come with them (the forces belong inside the equations).
    void check_newtonian_structure() const {
        const toml::node* newtonian = root_.get("newtonian");
        if (!newtonian) return;
        // [newtonian.fundamental] alone defines [newtonian] implicitly, without a position of its own.
        if (!at(*newtonian).known())
            if (const toml::table* t = newtonian->as_table(); t && t->get("fundamental")) newtonian = t->get("fundamental");
        const std::pair<const char*, const char*> others[] = {{"lagrangian", "[lagrangian]"}, {"body", "[[body]]"},
                                                              {"carrier", "[carrier]"},       {"effects", "[effects]"},
                                                              {"forces", "[forces]"},         {"formulation", "[formulation]"}};
        for (const auto& [key, title] : others) {
            const toml::node* other = root_.get(key);
            if (!other) continue;
            const bool newtonian_later = before(at(*other), at(*newtonian));
            const toml::node& later = newtonian_later ? *newtonian : *other;
            const toml::node& earlier = newtonian_later ? *other : *newtonian;
            fail(at(later), fmt::format("{} cannot be combined with {} (line {}); a Newtonian scene gives its "
                                        "equations of motion, forces included, instead of energies or bodies",
                                        newtonian_later ? "[newtonian]" : title,
                                        newtonian_later ? title : "[newtonian]", at(earlier).line));
        }
    }
};

}  // namespace

OrbitFormulationKind parse_orbit_formulation(std::string_view name, const SourcePos& where) {
    for (std::size_t k = 0; k < orbit_formulation_names.size(); ++k)
        if (orbit_formulation_names[k] == name) return static_cast<OrbitFormulationKind>(k);
    const std::vector<std::string> names(orbit_formulation_names.begin(), orbit_formulation_names.end());
    const std::string near = nearest_name(std::string(name), names);
    throw InputError(where, fmt::format("unknown orbit formulation '{}'; {}", name,
                                        near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                     : fmt::format("did you mean '{}'?", near)));
}

void check_orbit_formulation(const std::string& name, const SourcePos& where) { parse_orbit_formulation(name, where); }

void set_orbit_formulation(Scene& scene, const std::string& name, const SourcePos& where) {
    if (!scene.orbit)
        throw InputError(where, fmt::format("{} has no [orbit]; only an orbit scene has a formulation to choose",
                                            scene.path.empty() ? "the scene" : scene.path));
    const OrbitFormulationKind kind = parse_orbit_formulation(name, where);
    scene.name += "_" + name;
    scene.orbit->formulation = kind;
    scene.orbit->formulation_pos = where;
}

RigidFormulationKind parse_rigid_formulation(std::string_view name, const SourcePos& where) {
    for (std::size_t k = 0; k < rigid_formulation_names.size(); ++k)
        if (rigid_formulation_names[k] == name) return static_cast<RigidFormulationKind>(k);
    const std::vector<std::string> names(rigid_formulation_names.begin(), rigid_formulation_names.end());
    const std::string near = nearest_name(std::string(name), names);
    throw InputError(where, fmt::format("unknown rigid-body formulation '{}'; {}", name,
                                        near.empty() ? fmt::format("expected one of {}", fmt::join(names, ", "))
                                                     : fmt::format("did you mean '{}'?", near)));
}

void check_rigid_formulation(const std::string& name, const SourcePos& where) { parse_rigid_formulation(name, where); }

void set_rigid_formulation(Scene& scene, const std::string& name, const SourcePos& where) {
    if (!scene.rigid_body)
        throw InputError(where, fmt::format("{} has no [rigid_body]; only a rigid-body scene has a formulation to "
                                            "choose",
                                            scene.path.empty() ? "the scene" : scene.path));
    const RigidFormulationKind kind = parse_rigid_formulation(name, where);
    scene.name += "_" + name;
    scene.rigid_body->formulation = kind;
    scene.rigid_body->formulation_pos = where;
}

Scene parse_scene_string(std::string_view toml_text, const std::string& path) {
    return Reader(toml_text, path).read();
}

Scene parse_scene_file(const std::string& path) {
    const SourcePos where{path, 0, 0};
    // A scene is a regular file of bounded size: /dev/zero, a FIFO or a huge file would never
    // finish reading (or fill memory) before the first line is checked. O_NONBLOCK keeps the
    // open of a FIFO from waiting for a writer; the type is checked on what was opened.
    constexpr std::size_t max_scene_bytes = 4u << 20;
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int err = errno;
        throw InputError(where, fmt::format("cannot open scene file '{}': {}", path, lower_first(std::strerror(err))));
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat info {};
    if (::fstat(fd, &info) != 0)
        throw InputError(where, fmt::format("cannot read scene file '{}': {}", path, lower_first(std::strerror(errno))));
    if (S_ISDIR(info.st_mode))
        throw InputError(where, fmt::format("cannot read scene file '{}': it is a directory", path));
    if (!S_ISREG(info.st_mode))
        throw InputError(where, fmt::format("cannot read scene file '{}': it is not a regular file", path));
    std::string text;
    char buffer[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw InputError(where, fmt::format("cannot read scene file '{}': read error", path));
        if (n == 0) break;
        text.append(buffer, std::size_t(n));
        if (text.size() > max_scene_bytes)
            throw InputError(where, fmt::format("cannot read scene file '{}': it is larger than {} MiB", path,
                                                max_scene_bytes >> 20));
    }
    Scene s = parse_scene_string(text, path);
    s.path = path;
    return s;
}

std::string struct_name(const std::string& scene_name) {
    std::string out;
    bool upper = true;
    for (char c : scene_name) {
        if (c == '_') {
            upper = true;
            continue;
        }
        out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return out;
}

}  // namespace eomc::scene
