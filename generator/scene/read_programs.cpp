// Programmed motions (Mei, ch. 3): [[program]].
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

// [[program]]: name, constraint = "ω(q, t)" or "φ(q, q̇, t)", erugin = { alpha, beta } |
// { kappa } (absent: the open loop), control = "ideal" (default) | { coordinate = "direction" }
// | ["coordinate", ...], or on a [rigid_body] { moment = [m1, m2, m3] } (a body-axis torque
// direction, Mei §3.2). Which law fits which kind of relation is the model's to check (it knows
// which symbols the relation holds). A system given by its energies in coordinates, or a rigid
// body, takes programs, and [[constraint]] rows beside them (the model solves both together).
void Reader::read_programs(Scene& s) const {
    const auto rows = table_array("program", "[[program]]", "program");
    if (rows.empty()) return;
    const SourcePos first = at(*rows.front());
    refuse_programs(s, first);
    std::map<std::string, std::pair<SourcePos, std::string>> seen;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const std::string path = fmt::format("program[{}]", i);
        const toml::table& t = *rows[i];
        check_keys(t, {"name", "constraint", "erugin", "control"}, "in [[program]]");
        Program p;
        p.pos = p.erugin_pos = p.control_pos = at(t);
        p.name = read_row_name(t, path, "[[program]]", "program", seen, p.name_pos);
        p.constraint = read_expr(require(t, "constraint", "[[program]] '" + p.name + "'"), path + ".constraint");
        read_erugin(t, path, p);
        read_program_control(t, path, s, p);
        s.programs.push_back(std::move(p));
    }
}

// The scenes that take no programs, refused at the first [[program]] row.
void Reader::refuse_programs(const Scene& s, const SourcePos& first) const {
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
}

// A program's law, erugin = { alpha, beta } | { kappa }; absent: the open loop.
void Reader::read_erugin(const toml::table& t, const std::string& path, Program& p) const {
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
}

// A program's control: "ideal", directions by coordinate, actuated coordinates, or a rigid body's
// torque direction.
void Reader::read_program_control(const toml::table& t, const std::string& path, const Scene& s,
                                  Program& p) const {
    std::vector<std::string> coordinates;
    for (const auto& c : s.coordinates) coordinates.push_back(c.name);
    const auto known_coordinate = [&](const std::string& name, const SourcePos& where, const std::string& path) {
        if (std::find(coordinates.begin(), coordinates.end(), name) != coordinates.end()) return;
        const std::string near = nearest_name(name, coordinates);
        fail(where, fmt::format("unknown coordinate '{}' in '{}'; {}", name, path,
                                near.empty() ? fmt::format("the coordinates are {}", fmt::join(coordinates, ", "))
                                             : fmt::format("did you mean '{}'?", near)));
    };
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
}

}  // namespace eomc::scene
