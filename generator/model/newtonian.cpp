// The given-equations kind ([newtonian]; the inverse problem, Mei, ch. 4): the equations as the
// scene writes them, one per coordinate.
#include <fmt/format.h>

#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

using GiNaC::ex;

// [newtonian]: one equation per coordinate, each naming a declared coordinate once; the
// fundamental form must be affine in the accelerations (A q̈ + B).
Newtonian build_newtonian(const SymbolTable& symbols, const scene::Newtonian& given, const Model& model) {
    Newtonian n;
    n.fundamental = given.fundamental;
    n.pos = given.pos;
    const std::size_t count = model.coordinates.size();
    n.expressions.assign(count, ex(0));
    n.positions.assign(count, given.pos);
    std::vector<bool> seen(count, false);
    std::vector<std::string> names;
    for (const auto& c : model.coordinates) names.push_back(given.fundamental ? c.name : c.name + "_ddot");
    for (const auto& eq : given.equations) {
        const std::string key = given.fundamental ? eq.coordinate : eq.coordinate + "_ddot";
        std::size_t s = 0;
        while (s < count && model.coordinates[s].name != eq.coordinate) ++s;
        if (s == count) {
            const std::string near = nearest_name(key, names);
            throw InputError(eq.pos, fmt::format("'{}' names no declared coordinate{}", key,
                                                 near.empty() ? "" : fmt::format("; did you mean '{}'?", near)));
        }
        if (seen[s]) throw InputError(eq.pos, fmt::format("a second equation for coordinate '{}'", eq.coordinate));
        seen[s] = true;
        const std::string what = given.fundamental ? fmt::format("the fundamental form's equation for '{}'", eq.coordinate)
                                                   : fmt::format("the acceleration '{}'", key);
        n.expressions[s] = symbols.parse(eq.value, given.fundamental ? any_symbol : phase, what);
        n.positions[s] = eq.value.pos;
        if (given.fundamental) {
            for (const auto& c : model.coordinates) {
                if (!n.expressions[s].has(c.q_ddot)) continue;
                if (!n.expressions[s].diff(c.q_ddot).expand().has(c.q_ddot)) continue;
                throw InputError(eq.value.pos, fmt::format("{} is not linear in the accelerations ('{}' appears "
                                                           "non-linearly); the fundamental form is A(t,q,q̇) q̈ + "
                                                           "B(t,q,q̇)",
                                                           what, c.name + "_ddot"));
            }
        }
    }
    for (std::size_t s = 0; s < count; ++s)
        if (!seen[s])
            throw InputError(given.pos, fmt::format("[newtonian{}] gives no equation for coordinate '{}' (expected "
                                                    "'{} = \"...\"')",
                                                    given.fundamental ? ".fundamental" : "", model.coordinates[s].name,
                                                    names[s]));
    return n;
}

}  // namespace eomc::model
