#include "symbolic/solve.hpp"

#include <algorithm>
#include <exception>
#include <map>

#include "symbolic/simplify.hpp"

namespace eomc::symbolic {

using GiNaC::ex;

namespace {

bool depends_on(const ex& e, const std::vector<GiNaC::symbol>& variables) {
    return std::any_of(variables.begin(), variables.end(), [&](const GiNaC::symbol& s) { return e.has(s); });
}

}  // namespace

std::optional<GiNaC::exmap> solve_identically(const std::vector<ex>& conditions, const std::vector<GiNaC::symbol>& unknowns,
                                              const std::vector<GiNaC::symbol>& variables) {
    std::map<ex, ex, GiNaC::ex_is_less> groups;
    for (const ex& c : conditions) {
        ex numerator = c;
        try {
            // Large conditions are grouped term by term as they stand: their terms keep their
            // denominators as part of the variable factor, which is still exact (stricter at worst).
            if (node_count(c) <= 8000) numerator = GiNaC::normal(c).numer();
        } catch (const std::exception&) {
        }
        numerator = combine_exponentials(numerator.expand()).expand();
        for (const ex& term : terms_of(numerator)) {
            ex variable_part = 1, coefficient = 1;
            for (const ex& f : factors_of(term)) {
                if (depends_on(f, variables)) variable_part *= f;
                else coefficient *= f;
            }
            groups[variable_part] += coefficient;
        }
    }
    GiNaC::lst equations, vars;
    for (const auto& [key, coefficient] : groups)
        if (!coefficient.expand().is_zero()) equations.append(coefficient == 0);
    for (const auto& u : unknowns) vars.append(u);
    GiNaC::exmap solution;
    if (equations.nops() == 0) {
        for (const auto& u : unknowns) solution[u] = u;
        return solution;
    }
    try {
        const ex s = GiNaC::lsolve(equations, vars);
        if (s.nops() != unknowns.size()) return std::nullopt;
        for (std::size_t i = 0; i < s.nops(); ++i) solution[s.op(i).op(0)] = s.op(i).op(1);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    return solution;
}

}  // namespace eomc::symbolic
