// `--observe` for `eomc sweep` and `eomc ensemble`: extra columns per member. NAME=EXPR is an
// expression in the scene's own syntax over t, the parameters and the state variables, parsed by
// the scene's expression parser (model/expression_parser.hpp: its bounds and its errors at the
// character) and evaluated in double arithmetic on each member's final state (a subnormal or huge
// value gives what IEEE 754 gives; nothing of CLN's range limits applies); event:NAME is the time of the
// member's first NAME event (empty when it had none). Nothing of the text reaches generated code or a
// shell: an expression becomes a GiNaC expression evaluated in this process.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <ginac/ginac.h>

#include "support/diagnostic.hpp"

namespace eomc::host {

struct Observation {
    std::string column;      // NAME, or t_<event> for event:NAME
    std::string event;       // event:NAME: the event; "" for an expression
    std::string expression;  // NAME=EXPR: EXPR
    SourcePos where;         // "--observe TEXT", column 1 at the start of TEXT
};

// Throws InputError at the flag: not NAME=EXPR or event:NAME, NAME not an identifier.
Observation parse_observation(std::string_view text);

// The observations bound to one kernel's names: events checked, expressions parsed.
class BoundObservations {
public:
    BoundObservations() = default;
    // Throws InputError at an observation's flag: an unknown event (with the nearest name), an
    // expression that does not parse or names something that is not t, a parameter or a state
    // variable, a column named twice or like one the CSV already has (`taken`).
    BoundObservations(const std::vector<Observation>& observations, const std::vector<std::string>& parameters,
                      const std::vector<std::string>& states, const std::vector<std::string>& events,
                      const std::vector<std::string>& taken);

    std::size_t size() const { return columns_.size(); }
    const std::vector<std::string>& columns() const { return columns_; }
    // Observation i's event index into `events`, or -1 for an expression.
    int event(std::size_t i) const { return events_[i]; }
    // Expression i at a final state, in double arithmetic (NaN where it has no real value: a pole,
    // a root of a negative number, a function outside its domain). Never throws. Not thread-safe
    // (it walks GiNaC expressions).
    double evaluate(std::size_t i, double t, const std::vector<double>& parameters, const std::vector<double>& state) const;

private:
    std::vector<std::string> columns_;
    std::vector<int> events_;
    std::vector<GiNaC::ex> expressions_;
    GiNaC::symbol t_;
    std::vector<GiNaC::symbol> parameters_, states_;
};

}  // namespace eomc::host
