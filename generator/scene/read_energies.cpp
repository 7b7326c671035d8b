// A system's energies and loads: [lagrangian], [forces] and [effects] (a carrier's inertial effects
// or an orbit's perturbations).
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

void Reader::read_lagrangian(Scene& s) const {
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

void Reader::read_forces(Scene& s) const {
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

void Reader::read_effects(Scene& s) const {
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
void Reader::read_custom_effects(Scene& s, const toml::table& t) const {
    check_keys(t, {"disturbing_function", "acceleration"}, "in [effects.custom]");
    if (const toml::node* r = t.get("disturbing_function"))
        s.effects.disturbing_function = read_expr(*r, "effects.custom.disturbing_function");
    if (const toml::node* a = t.get("acceleration"))
        s.effects.acceleration = read_vec3(*a, "effects.custom.acceleration");
    if (!s.effects.disturbing_function && !s.effects.acceleration)
        fail(at(t), "[effects.custom] gives neither 'disturbing_function' nor 'acceleration'");
}

}  // namespace eomc::scene
