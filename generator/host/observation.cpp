#include "host/observation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "model/expression_parser.hpp"
#include "scene/scene.hpp"
#include "support/identifier.hpp"

namespace eomc::host {

Observation parse_observation(std::string_view text) {
    Observation o;
    o.where = SourcePos{fmt::format("--observe {}", text), 1, 1};
    const auto refuse = [&](const std::string& why) { throw InputError(o.where, why); };
    if (text.starts_with("event:")) {
        o.event = std::string(text.substr(6));
        if (!is_identifier(o.event)) refuse(fmt::format("'{}' is not an event name (expected event:NAME)", o.event));
        o.column = "t_" + o.event;
        return o;
    }
    const std::size_t eq = text.find('=');
    if (eq == std::string_view::npos)
        refuse("expected NAME=EXPR (a column NAME and an expression over t, the parameters and the state) or event:NAME");
    o.column = std::string(text.substr(0, eq));
    if (!is_identifier(o.column)) refuse(fmt::format("'{}' is not a column name (letters, digits, _)", o.column));
    o.expression = std::string(text.substr(eq + 1));
    o.where.column = static_cast<int>(eq) + 2;  // the expression's first character
    if (o.expression.empty()) refuse("the expression is empty");
    return o;
}

BoundObservations::BoundObservations(const std::vector<Observation>& observations,
                                     const std::vector<std::string>& parameters, const std::vector<std::string>& states,
                                     const std::vector<std::string>& events, const std::vector<std::string>& taken) {
    model::SymbolTable table;
    t_ = table.declare("t", model::SymbolKind::time);
    for (const auto& p : parameters) parameters_.push_back(table.declare(p, model::SymbolKind::parameter));
    for (const auto& s : states) states_.push_back(table.declare(s, model::SymbolKind::coordinate));
    const unsigned allowed = model::SymbolKind::time | model::SymbolKind::parameter | model::SymbolKind::coordinate;
    for (const auto& o : observations) {
        const SourcePos at{o.where.file};
        if (std::find(taken.begin(), taken.end(), o.column) != taken.end() ||
            std::find(columns_.begin(), columns_.end(), o.column) != columns_.end())
            throw InputError(at, fmt::format("the column '{}' is already in the CSV", o.column));
        columns_.push_back(o.column);
        if (!o.event.empty()) {
            const auto it = std::find(events.begin(), events.end(), o.event);
            if (it == events.end()) {
                const std::string near = nearest_name(o.event, events);
                throw InputError(at, events.empty() ? fmt::format("the scene has no events (no event '{}')", o.event)
                                                    : fmt::format("no event '{}'{} (events: {})", o.event,
                                                                  near.empty() ? "" : "; did you mean '" + near + "'?",
                                                                  fmt::join(events, ", ")));
            }
            events_.push_back(static_cast<int>(it - events.begin()));
            expressions_.emplace_back(0);
            continue;
        }
        events_.push_back(-1);
        expressions_.push_back(table.parse(scene::Expr{o.expression, o.where}, allowed, "an --observe expression"));
    }
}

double BoundObservations::evaluate(std::size_t i, double t, const std::vector<double>& parameters,
                                   const std::vector<double>& state) const {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    GiNaC::exmap at{{t_, t}};
    for (std::size_t k = 0; k < parameters_.size() && k < parameters.size(); ++k) at[parameters_[k]] = parameters[k];
    for (std::size_t k = 0; k < states_.size() && k < state.size(); ++k) at[states_[k]] = state[k];
    GiNaC::ex v;
    try {
        v = expressions_[i].subs(at).evalf();
    } catch (const GiNaC::pole_error&) {  // a division by zero there
        return nan;
    }
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return nan;
    const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(v);
    if (!n.is_real()) return nan;
    return n.to_double();
}

}  // namespace eomc::host
