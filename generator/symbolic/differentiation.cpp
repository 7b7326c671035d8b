#include "symbolic/differentiation.hpp"

#include <string>
#include <unordered_map>

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

namespace {

class Differentiator {
public:
    explicit Differentiator(const GiNaC::symbol& s) : s_(s) {}

    ex operator()(const ex& e) {
        if (GiNaC::is_a<GiNaC::symbol>(e)) return e.is_equal(s_) ? ex(1) : ex(0);
        if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 0;
        if (auto it = memo_.find(e); it != memo_.end()) return it->second;
        ex d = compute(e);
        memo_.emplace(e, d);
        return d;
    }

private:
    ex compute(const ex& e) {
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
            if (outer_derivative(GiNaC::ex_to<GiNaC::function>(e).get_name(), e.op(0), outer)) return outer * du;
        }
        if (GiNaC::is_a<GiNaC::function>(e) && GiNaC::ex_to<GiNaC::function>(e).get_name() == model::kepler_E_name) {
            // dE = E_M dM + E_e de (model/kepler_function.hpp)
            const ex dM = (*this)(e.op(0)), de = (*this)(e.op(1));
            ex d = 0;
            if (!dM.is_zero()) d += model::kepler_E_partial_M(e, e.op(1)) * dM;
            if (!de.is_zero()) d += model::kepler_E_partial_e(e, e.op(1)) * de;
            return d;
        }
        return e.diff(s_);
    }

    const GiNaC::symbol& s_;
    std::unordered_map<ex, ex> memo_;
};

}  // namespace

ex derivative(const ex& e, const GiNaC::symbol& s) { return Differentiator(s)(e); }

}  // namespace eomc::symbolic
