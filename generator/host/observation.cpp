#include "host/observation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <fmt/format.h>

#include "model/expression_parser.hpp"
#include "scene/scene.hpp"
#include "support/identifier.hpp"
#include "symbolic/exact_constants.hpp"

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
        const GiNaC::ex parsed = table.parse(scene::Expr{o.expression, o.where}, allowed, "an --observe expression");
        try {  // sin(10^300) in double arithmetic would be sin of the nearest double, an unrelated value
            expressions_.push_back(symbolic::fold_ill_conditioned_constants(parsed));
        } catch (const symbolic::ConstantOutOfReach& e) {
            throw InputError(at, e.what());
        }
    }
}

namespace {

using Values = std::map<GiNaC::ex, double, GiNaC::ex_is_less>;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// A number of the expression (a literal, a folded constant, π) as the nearest double; NaN when
// it is not real. CLN rounds a value beyond double's range to ±inf or 0 rather than failing.
double to_double(const GiNaC::ex& e) {
    const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(e);
    if (!n.is_real()) return nan;
    try {
        return n.to_double();
    } catch (const std::exception&) {
        return nan;
    }
}

double function_value(const std::string& name, double x) {
    static const std::map<std::string, double (*)(double)> table{
        {"sin", [](double v) { return std::sin(v); }},   {"cos", [](double v) { return std::cos(v); }},
        {"tan", [](double v) { return std::tan(v); }},   {"exp", [](double v) { return std::exp(v); }},
        {"asin", [](double v) { return std::asin(v); }}, {"acos", [](double v) { return std::acos(v); }},
        {"atan", [](double v) { return std::atan(v); }}, {"sinh", [](double v) { return std::sinh(v); }},
        {"cosh", [](double v) { return std::cosh(v); }}, {"tanh", [](double v) { return std::tanh(v); }},
        {"log", [](double v) { return v > 0 ? std::log(v) : nan; }},  // log 0 is a pole: no real value
    };
    const auto f = table.find(name);
    return f == table.end() ? nan : f->second(x);
}

// The expression in double arithmetic over the values of its symbols: every operation is IEEE
// 754's, so a subnormal or huge value gives what double gives and nothing throws (GiNaC's evalf
// hands each value to CLN, which has no subnormal floats and threw "floating point underflow"
// for a member that ended at 7.5e-322). NaN where there is no real value: a pole (x^-1 at 0,
// log 0), a root of a negative number, a function outside its domain.
double value_of(const GiNaC::ex& e, const Values& at) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return to_double(e);
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        const auto v = at.find(e);
        return v == at.end() ? nan : v->second;
    }
    if (GiNaC::is_a<GiNaC::constant>(e)) return to_double(e.evalf());  // Pi
    if (GiNaC::is_a<GiNaC::add>(e)) {
        double v = 0.0;
        for (const auto& term : e) v += value_of(term, at);
        return v;
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {  // the factors b^-k divide by b^k: x/y is x/y, not x·(1/y)
        double numerator = 1.0, denominator = 1.0;
        for (const auto& factor : e) {
            if (GiNaC::is_a<GiNaC::power>(factor) && GiNaC::is_a<GiNaC::numeric>(factor.op(1)) &&
                GiNaC::ex_to<GiNaC::numeric>(factor.op(1)).is_negative())
                denominator *= value_of(GiNaC::pow(factor.op(0), -factor.op(1)), at);
            else
                numerator *= value_of(factor, at);
        }
        return denominator == 0 ? nan : numerator / denominator;  // nan: a division by zero
    }
    if (GiNaC::is_a<GiNaC::power>(e)) {
        const double base = value_of(e.op(0), at), k = value_of(e.op(1), at);
        if (base == 0 && k < 0) return nan;  // a division by zero
        if (k == 0.5) return std::sqrt(base);
        return std::pow(base, k);
    }
    if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1)
        return function_value(GiNaC::ex_to<GiNaC::function>(e).get_name(), value_of(e.op(0), at));
    return nan;
}

}  // namespace

double BoundObservations::evaluate(std::size_t i, double t, const std::vector<double>& parameters,
                                   const std::vector<double>& state) const {
    Values at{{t_, t}};
    for (std::size_t k = 0; k < parameters_.size() && k < parameters.size(); ++k) at[parameters_[k]] = parameters[k];
    for (std::size_t k = 0; k < states_.size() && k < state.size(); ++k) at[states_[k]] = state[k];
    return value_of(expressions_[i], at);
}

}  // namespace eomc::host
