// Unilateral constraints (Mei, ch. 6): [[unilateral]] and how they are passed, [contact].
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

// [[unilateral]]: name = "floor", exactly one of gap = "f(q, t)" (Mei, §6.2) or velocity =
// "B(q, t) q̇ + b(q, t)" (§6.7), and restitution = "e" (Newton's coefficient; "0" when absent).
// Read as [[constraint]] rows are; names are unique among both kinds. Only a system given by its
// energies in coordinates takes them: not an orbit, a rigid body about a point, given equations,
// a free carrier or Hamilton's form (whose kernels carry no rows).
void Reader::read_unilateral(Scene& s) const {
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

// [contact]: method = "event_driven" (default) | "moreau_jean", theta = θ in [0.5, 1]
// (Moreau–Jean's θ-method; Acary & Brogliato 2008), impact_law = "simultaneous" (default) |
// "sequential" (event_driven only). Only beside [[unilateral]] rows.
void Reader::read_contact(Scene& s) const {
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

}  // namespace eomc::scene
