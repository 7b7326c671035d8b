// Bilateral constraint rows (Mei, §6.6): [[constraint]].
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

// [[constraint]]: name = "rod", exactly one of holonomic = "f(q, t)" or kinematic =
// "B(q, t) q̇ + b(q, t)", and stabilize = "project" (default) | "none" | { alpha = a, beta = b }
// (Baumgarte). The algebra (which symbols, linearity in the rates, the initial state) is the
// model's to check.
void Reader::read_constraints(Scene& s) const {
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

}  // namespace eomc::scene
