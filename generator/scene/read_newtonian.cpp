// Equations given directly (Mei, ch. 4): [newtonian], [inverse] and what they exclude.
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

// [newtonian]: `<coordinate>_ddot = "f"` entries (kinematic form), or a subtable
// [newtonian.fundamental] with `<coordinate> = "Φ"` entries (fundamental form); not both.
void Reader::read_newtonian(Scene& s) const {
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

void Reader::read_inverse(Scene& s) const {
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
void Reader::check_newtonian_structure() const {
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

}  // namespace eomc::scene
