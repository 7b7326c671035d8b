#include "symbolic/integrate.hpp"

#include <exception>
#include <functional>
#include <set>
#include <string>

#include "symbolic/differentiation.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::symbolic {

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;
using GiNaC::numeric;
using GiNaC::symbol;

namespace {

// u = a v + b with a ≠ 0 free of v.
bool linear_in(const ex& u, const symbol& v, ex& a) {
    if (!u.has(v)) return false;
    a = simplified(derivative(u, v));
    return !a.is_zero() && !a.has(v);
}

class Integrator {
public:
    explicit Integrator(const symbol& v) : v_(v) {}

    std::optional<ex> operator()(const ex& e, int depth = 0) const {
        if (depth > 12) return std::nullopt;
        if (!e.has(v_)) return e * v_;
        if (e.is_equal(v_)) return GiNaC::pow(v_, 2) / 2;
        if (is_a<GiNaC::add>(e)) {
            ex sum = 0;
            bool all = true;
            for (std::size_t i = 0; i < e.nops() && all; ++i) {
                const auto r = (*this)(e.op(i), depth + 1);
                if (r) sum += *r;
                else all = false;
            }
            if (all) return sum;
        } else if (is_a<GiNaC::power>(e)) {
            if (auto linear = linearized_trig(e)) return (*this)(*linear, depth + 1);
            if (e.op(0).is_equal(v_) && !e.op(1).has(v_)) {
                if (e.op(1).is_equal(-1)) return GiNaC::log(v_);
                return GiNaC::pow(v_, e.op(1) + 1) / (e.op(1) + 1);
            }
            if (auto r = laurent(e, depth)) return r;
        } else if (is_a<GiNaC::function>(e)) {
            if (auto r = elementary(e)) return r;
        } else if (is_a<GiNaC::mul>(e)) {
            ex constant = 1, dependent = 1;
            int count = 0;
            for (std::size_t i = 0; i < e.nops(); ++i) {
                if (e.op(i).has(v_)) {
                    dependent *= e.op(i);
                    ++count;
                } else {
                    constant *= e.op(i);
                }
            }
            if (count == 1 && !is_trig_power(dependent)) {
                if (auto r = (*this)(dependent, depth + 1)) return constant * *r;
            } else {
                if (auto linear = linearized_trig(dependent)) return (*this)(constant * *linear, depth + 1);
                if (auto r = by_parts(dependent, depth)) return constant * *r;
                if (auto r = laurent(dependent, depth)) return constant * *r;
            }
        }
        const ex x = e.expand();
        if (!x.is_equal(e)) return (*this)(x, depth + 1);
        return odd(e, depth);
    }

private:
    static bool is_trig(const ex& f) { return is_function(f, "sin") || is_function(f, "cos"); }
    static bool is_trig_power(const ex& e) {
        return is_a<GiNaC::power>(e) && is_trig(e.op(0)) && is_a<numeric>(e.op(1)) &&
               ex_to<numeric>(e.op(1)).is_pos_integer();
    }

    // A product of sines and cosines (positive integer powers included) of arguments in v,
    // rewritten by the product-to-sum formulas into a sum with one such factor per term:
    // sin a cos b = (sin(a+b) + sin(a−b))/2, sin a sin b = (cos(a−b) − cos(a+b))/2,
    // cos a cos b = (cos(a−b) + cos(a+b))/2. nullopt when there is nothing to combine.
    std::optional<ex> linearized_trig(const ex& e) const {
        std::vector<ex> trig;
        ex rest = 1;
        for (const ex& f : factors_of(e)) {
            if (is_trig(f) && f.has(v_)) {
                trig.push_back(f);
            } else if (is_trig_power(f) && f.op(0).has(v_)) {
                for (long k = 0; k < ex_to<numeric>(f.op(1)).to_long(); ++k) trig.push_back(f.op(0));
            } else {
                rest *= f;
            }
        }
        if (trig.size() < 2) return std::nullopt;
        // Combine the first two; the rest stays as factors of each new term (recursion does them).
        const ex a = trig[0].op(0), b = trig[1].op(0);
        const bool sa = is_function(trig[0], "sin"), sb = is_function(trig[1], "sin");
        ex combined;
        if (sa && sb) combined = (GiNaC::cos(a - b) - GiNaC::cos(a + b)) / 2;
        else if (!sa && !sb) combined = (GiNaC::cos(a - b) + GiNaC::cos(a + b)) / 2;
        else if (sa) combined = (GiNaC::sin(a + b) + GiNaC::sin(a - b)) / 2;
        else combined = (GiNaC::sin(a + b) + GiNaC::sin(b - a)) / 2;
        for (std::size_t k = 2; k < trig.size(); ++k) rest *= trig[k];
        return (combined * rest).expand();
    }

    // ∫ v h(v²) dv = ½ ∫ h(w) dw, w = v²: radicals of a + b v² (a central force along a ray).
    std::optional<ex> odd(const ex& e, int depth) const {
        if (depth > 8 || e.is_polynomial(v_)) return std::nullopt;
        const ex h = e / v_;
        if (!simplified(h.subs(v_ == -v_) - h).is_zero()) return std::nullopt;
        const symbol w("w");
        const ex in_w = h.subs(v_ == GiNaC::sqrt(w));
        const auto r = Integrator(w)(in_w, depth + 1);
        if (!r) return std::nullopt;
        return r->subs(w == GiNaC::pow(v_, 2)) / 2;
    }

    // f(u) for u linear in v.
    std::optional<ex> elementary(const ex& e) const {
        if (!is_a<GiNaC::function>(e) || e.nops() != 1) return std::nullopt;
        const std::string name = ex_to<GiNaC::function>(e).get_name();
        const ex u = e.op(0);
        ex a;
        if (!linear_in(u, v_, a)) return std::nullopt;
        if (name == "exp") return e / a;
        if (name == "sin") return -GiNaC::cos(u) / a;
        if (name == "cos") return GiNaC::sin(u) / a;
        if (name == "sinh") return GiNaC::cosh(u) / a;
        if (name == "cosh") return GiNaC::sinh(u) / a;
        if (name == "tan") return -GiNaC::log(GiNaC::cos(u)) / a;
        return std::nullopt;
    }

    // ∫ P(v) h(u) dv = P H − ∫ P' H dv, for a polynomial P and h as in elementary().
    std::optional<ex> by_parts(const ex& e, int depth) const {
        ex P = 1, h;
        int functions = 0;
        for (const ex& f : factors_of(e)) {
            if (is_a<GiNaC::function>(f) && f.has(v_)) {
                h = f;
                ++functions;
            } else {
                P *= f;
            }
        }
        if (functions != 1 || !P.is_polynomial(v_)) return std::nullopt;
        const auto H = elementary(h);
        if (!H) return std::nullopt;
        const ex dP = derivative(P, v_);
        if (dP.is_zero()) return P * *H;
        const auto rest = (*this)((dP * *H).expand(), depth + 1);
        if (!rest) return std::nullopt;
        return P * *H - *rest;
    }

    // Powers of one linear form b = a v + b₀ (and polynomials in v): with U = b the integrand
    // is a Laurent polynomial in U, integrated term by term (U⁻¹ → log U).
    std::optional<ex> laurent(const ex& e, int depth) const {
        std::set<ex, GiNaC::ex_is_less> bases;
        bool other = false;
        std::function<void(const ex&)> walk = [&](const ex& x) {
            if (!x.has(v_)) return;
            if (is_a<GiNaC::power>(x) && !x.op(0).is_equal(v_)) {
                if (x.op(1).has(v_)) other = true;
                bases.insert(x.op(0).expand());
                return;
            }
            if (is_a<GiNaC::function>(x)) {
                other = true;
                return;
            }
            for (std::size_t i = 0; i < x.nops(); ++i) walk(x.op(i));
        };
        walk(e);
        if (other || bases.size() != 1) return std::nullopt;
        const ex b = *bases.begin();
        ex a;
        if (!linear_in(b, v_, a)) return std::nullopt;
        const ex b0 = b.subs(v_ == 0);
        const symbol U("U");
        struct ExpandBases : GiNaC::map_function {
            const symbol& v;
            explicit ExpandBases(const symbol& var) : v(var) {}
            ex operator()(const ex& x) override {
                if (is_a<GiNaC::power>(x) && x.op(0).has(v)) return GiNaC::pow(x.op(0).expand(), x.op(1));
                return x.map(*this);
            }
        } expand_bases(v_);
        ex in_U = expand_bases(e).subs(b == U).subs(v_ == (U - b0) / a);
        if (in_U.has(v_)) return std::nullopt;
        in_U = in_U.expand();
        const auto r = Integrator(U)(in_U, depth + 1);
        if (!r) return std::nullopt;
        return r->subs(U == b) / a;
    }

    const symbol& v_;
};

}  // namespace

std::optional<ex> antiderivative(const ex& e, const symbol& v) {
    std::optional<ex> r;
    try {
        r = Integrator(v)(e);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    if (!r) return std::nullopt;
    if (!simplified(derivative(*r, v) - e).is_zero()) return std::nullopt;
    return r;
}

std::optional<ex> potential(const std::vector<ex>& gradient, const std::vector<symbol>& vars) {
    ex phi = 0;
    for (std::size_t k = 0; k < vars.size(); ++k) {
        const ex rest = simplified(gradient[k] - derivative(phi, vars[k]));
        for (std::size_t m = 0; m < k; ++m)
            if (rest.has(vars[m])) return std::nullopt;  // not a gradient
        const auto part = antiderivative(rest, vars[k]);
        if (!part) return std::nullopt;
        phi += *part;
    }
    for (std::size_t k = 0; k < vars.size(); ++k)
        if (!simplified(derivative(phi, vars[k]) - gradient[k]).is_zero()) return std::nullopt;
    return simplified(phi);
}

std::optional<ex> unit_integral(const ex& integrand, const symbol& tau) {
    const auto F = antiderivative(integrand, tau);
    if (!F) return std::nullopt;
    try {
        const ex upper = F->subs(tau == 1), lower = F->subs(tau == 0);
        if (upper.has(tau) || lower.has(tau)) return std::nullopt;
        return simplified(upper - lower);
    } catch (const std::exception&) {  // a pole at an end: log(0), 1/0
        return std::nullopt;
    }
}

}  // namespace eomc::symbolic
