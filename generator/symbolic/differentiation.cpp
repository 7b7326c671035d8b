#include "symbolic/differentiation.hpp"

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "model/kepler_function.hpp"

namespace eomc::symbolic {

using namespace eomc::symbolic;

using GiNaC::ex;

bool outer_derivative(const std::string& f, const ex& u, ex& out) {
    if (f == "sin") out = GiNaC::cos(u);
    else if (f == "cos") out = -GiNaC::sin(u);
    else if (f == "tan") out = 1 + GiNaC::pow(GiNaC::tan(u), 2);
    else if (f == "exp") out = GiNaC::exp(u);
    else if (f == "log") out = GiNaC::pow(u, -1);
    else if (f == "asin") out = GiNaC::pow(1 - GiNaC::pow(u, 2), GiNaC::numeric(-1, 2));
    else if (f == "acos") out = -GiNaC::pow(1 - GiNaC::pow(u, 2), GiNaC::numeric(-1, 2));
    else if (f == "atan") out = GiNaC::pow(1 + GiNaC::pow(u, 2), -1);
    else if (f == "sinh") out = GiNaC::cosh(u);
    else if (f == "cosh") out = GiNaC::sinh(u);
    else if (f == "tanh") out = 1 - GiNaC::pow(GiNaC::tanh(u), 2);
    else return false;
    return true;
}

ex DirectionalDerivative::operator()(const ex& e) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
        const auto it = direction_.find(e);
        return it == direction_.end() ? ex(0) : it->second;
    }
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 0;
    if (auto it = memo_.find(e); it != memo_.end()) return it->second;
    ex d = compute(e);
    memo_.emplace(e, d);
    return d;
}

ex DirectionalDerivative::compute(const ex& e) {
    if (GiNaC::is_a<GiNaC::add>(e)) {
        GiNaC::exvector terms;
        for (std::size_t i = 0; i < e.nops(); ++i) {
            ex d = (*this)(e.op(i));
            if (!d.is_zero()) terms.push_back(d);
        }
        return GiNaC::add(terms);
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) {
        GiNaC::exvector terms;
        for (std::size_t i = 0; i < e.nops(); ++i) {
            ex d = (*this)(e.op(i));
            if (d.is_zero()) continue;
            GiNaC::exvector factors;
            for (std::size_t j = 0; j < e.nops(); ++j) factors.push_back(j == i ? d : e.op(j));
            terms.push_back(GiNaC::mul(factors));
        }
        return GiNaC::add(terms);
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
        const ex db = (*this)(e.op(0));
        if (db.is_zero()) return 0;
        return e.op(1) * GiNaC::pow(e.op(0), e.op(1) - 1) * db;
    }
    if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1) {
        const ex du = (*this)(e.op(0));
        if (du.is_zero()) return 0;
        ex outer;
        if (outer_derivative(GiNaC::ex_to<GiNaC::function>(e).get_name(), e.op(0), outer)) {
            // φ'(u) distributed over the terms of du, as one partial per symbol would give them: a term
            // that cancels against another (ε_s of T's cos(θ₁ − θ₂) terms) is then one GiNaC collects.
            if (GiNaC::is_a<GiNaC::add>(du)) {
                GiNaC::exvector terms;
                for (std::size_t i = 0; i < du.nops(); ++i) terms.push_back(outer * du.op(i));
                return GiNaC::add(terms);
            }
            return outer * du;
        }
    }
    if (GiNaC::is_a<GiNaC::function>(e) && GiNaC::ex_to<GiNaC::function>(e).get_name() == model::kepler_E_name) {
        // dE = E_M dM + E_e de (model/kepler_function.hpp)
        const ex dM = (*this)(e.op(0)), de = (*this)(e.op(1));
        ex d = 0;
        if (!dM.is_zero()) d += model::kepler_E_partial_M(e, e.op(1)) * dM;
        if (!de.is_zero()) d += model::kepler_E_partial_e(e, e.op(1)) * de;
        return d;
    }
    ex d = 0;
    for (const auto& [x, v] : direction_)
        if (e.has(x)) d += v * e.diff(GiNaC::ex_to<GiNaC::symbol>(x));
    return d;
}

ex derivative(const ex& e, const GiNaC::symbol& s) { return DirectionalDerivative(s)(e); }

bool depends_on_any(const ex& e, const GiNaC::exset& symbols) {
    std::unordered_set<ex> seen;
    std::vector<ex> stack{e};
    while (!stack.empty()) {
        const ex x = stack.back();
        stack.pop_back();
        if (GiNaC::is_a<GiNaC::symbol>(x)) {
            if (symbols.count(x)) return true;
            continue;
        }
        if (x.nops() == 0 || !seen.insert(x).second) continue;
        for (std::size_t i = 0; i < x.nops(); ++i) stack.push_back(x.op(i));
    }
    return false;
}

}  // namespace eomc::symbolic
