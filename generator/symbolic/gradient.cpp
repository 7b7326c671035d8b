#include "symbolic/gradient.hpp"

#include <map>

#include "model/kepler_function.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::symbolic {

using GiNaC::ex;

Gradient::Gradient(const std::vector<GiNaC::symbol>& variables) : variables_(variables) {
    for (unsigned j = 0; j < variables_.size(); ++j) index_.emplace(ex(variables_[j]), j);
}

std::vector<ex> Gradient::operator()(const ex& e) {
    std::vector<ex> dense(variables_.size(), ex(0));
    for (const auto& [j, d] : of(e)) dense[j] = d;
    return dense;
}

const Gradient::Sparse& Gradient::of(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return none_;
    if (auto it = memo_.find(e); it != memo_.end()) return it->second;
    Sparse g = compute(e);
    // unordered_map keeps references to its elements valid across insertions: the operands'
    // gradients a caller up the recursion still holds stay put.
    return memo_.emplace(e, std::move(g)).first->second;
}

// Each rule builds entry j exactly as symbolic::derivative(e, x_j) does (same operands, same
// order, zero terms left out), so the two give the same expressions.
Gradient::Sparse Gradient::compute(const ex& e) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        if (auto it = index_.find(e); it != index_.end()) return {{it->second, ex(1)}};
        return {};
    }
    if (GiNaC::is_a<GiNaC::add>(e)) {
        std::map<unsigned, GiNaC::exvector> terms;
        for (std::size_t i = 0; i < e.nops(); ++i)
            for (const auto& [j, d] : of(e.op(i))) terms[j].push_back(d);
        Sparse g;
        for (auto& [j, list] : terms)
            if (ex d = GiNaC::add(list); !d.is_zero()) g.emplace_back(j, d);
        return g;
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
        std::map<unsigned, std::vector<std::pair<std::size_t, ex>>> factors_by_variable;
        for (std::size_t i = 0; i < e.nops(); ++i)
            for (const auto& [j, d] : of(e.op(i))) factors_by_variable[j].emplace_back(i, d);
        Sparse g;
        for (const auto& [j, differentiated] : factors_by_variable) {
            GiNaC::exvector terms;
            for (const auto& [i, d] : differentiated) {
                GiNaC::exvector factors;
                for (std::size_t k = 0; k < e.nops(); ++k) factors.push_back(k == i ? d : e.op(k));
                terms.push_back(GiNaC::mul(factors));
            }
            if (ex d = GiNaC::add(terms); !d.is_zero()) g.emplace_back(j, d);
        }
        return g;
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
        const Sparse& base = of(e.op(0));
        if (base.empty()) return {};
        const ex coefficient = e.op(1) * GiNaC::pow(e.op(0), e.op(1) - 1);
        Sparse g;
        for (const auto& [j, db] : base)
            if (ex d = coefficient * db; !d.is_zero()) g.emplace_back(j, d);
        return g;
    }
    if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1) {
        const Sparse& argument = of(e.op(0));
        if (argument.empty()) return {};
        ex outer;
        if (outer_derivative(GiNaC::ex_to<GiNaC::function>(e).get_name(), e.op(0), outer)) {
            Sparse g;
            for (const auto& [j, du] : argument)
                if (ex d = outer * du; !d.is_zero()) g.emplace_back(j, d);
            return g;
        }
    }
    if (GiNaC::is_a<GiNaC::function>(e) && GiNaC::ex_to<GiNaC::function>(e).get_name() == model::kepler_E_name) {
        // dE = E_M dM + E_e de (model/kepler_function.hpp)
        std::map<unsigned, std::pair<ex, ex>> by_variable;  // (dM, de)
        for (const auto& [j, dM] : of(e.op(0))) by_variable[j].first = dM;
        for (const auto& [j, de] : of(e.op(1))) by_variable[j].second = de;
        if (by_variable.empty()) return {};
        const ex E_M = model::kepler_E_partial_M(e, e.op(1)), E_e = model::kepler_E_partial_e(e, e.op(1));
        Sparse g;
        for (const auto& [j, partials] : by_variable) {
            ex d = 0;
            if (!partials.first.is_zero()) d += E_M * partials.first;
            if (!partials.second.is_zero()) d += E_e * partials.second;
            if (!d.is_zero()) g.emplace_back(j, d);
        }
        return g;
    }
    return by_diff(e);
}

// Anything else: GiNaC's own diff, for the variables e contains.
Gradient::Sparse Gradient::by_diff(const ex& e) const {
    Sparse g;
    for (unsigned j = 0; j < variables_.size(); ++j)
        if (e.has(variables_[j]))
            if (ex d = e.diff(variables_[j]); !d.is_zero()) g.emplace_back(j, d);
    return g;
}

std::vector<ex> jacobian(const std::vector<ex>& rows, const std::vector<GiNaC::symbol>& variables) {
    Gradient gradient(variables);
    std::vector<ex> J;
    J.reserve(rows.size() * variables.size());
    for (const ex& row : rows) {
        const std::vector<ex> g = gradient(row);
        J.insert(J.end(), g.begin(), g.end());
    }
    return J;
}

}  // namespace eomc::symbolic
