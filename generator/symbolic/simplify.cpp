#include "symbolic/simplify.hpp"

#include <exception>

namespace eomc::symbolic {

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;
using GiNaC::numeric;

std::size_t node_count(const ex& e) {
    std::size_t n = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) n += node_count(e.op(i));
    return n;
}

bool is_function(const ex& e, const char* name) {
    return is_a<GiNaC::function>(e) && ex_to<GiNaC::function>(e).get_name() == name;
}

std::vector<ex> terms_of(const ex& e) {
    std::vector<ex> out;
    if (is_a<GiNaC::add>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i) out.push_back(e.op(i));
    } else if (!e.is_zero()) {
        out.push_back(e);
    }
    return out;
}

std::vector<ex> factors_of(const ex& e) {
    std::vector<ex> out;
    if (is_a<GiNaC::mul>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i) out.push_back(e.op(i));
    } else {
        out.push_back(e);
    }
    return out;
}

namespace {

struct CombineExponentials : GiNaC::map_function {
    ex operator()(const ex& e) override {
        const ex x = e.map(*this);
        if (is_a<GiNaC::power>(x) && is_function(x.op(0), "exp") && is_a<numeric>(x.op(1)))
            return GiNaC::exp((x.op(0).op(0) * x.op(1)).expand());
        if (!is_a<GiNaC::mul>(x)) return x;
        ex argument = 0;
        int count = 0;
        GiNaC::exvector rest;
        for (std::size_t i = 0; i < x.nops(); ++i) {
            const ex& f = x.op(i);
            if (is_function(f, "exp")) {
                argument += f.op(0);
                ++count;
            } else {
                rest.push_back(f);
            }
        }
        if (count < 2) return x;
        return GiNaC::mul(rest) * GiNaC::exp(argument.expand());
    }
};

ex safe_normal(const ex& e) {
    try {
        return GiNaC::normal(e);
    } catch (const std::exception&) {
        return e;
    }
}

}  // namespace

ex combine_exponentials(const ex& e) {
    CombineExponentials f;
    return f(e);
}

ex without_sin_squared(const ex& e, bool hyperbolic) {
    const ex u = GiNaC::wild(0);
    GiNaC::lst rules{GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2)};
    if (hyperbolic) rules.append(GiNaC::pow(GiNaC::cosh(u), 2) == 1 + GiNaC::pow(GiNaC::sinh(u), 2));
    return e.subs(rules, GiNaC::subs_options::algebraic);
}

ex simplified(const ex& e) {
    // normal() puts everything over one denominator, treating each square root and exponential
    // as a new variable: on tens of thousands of nodes with several of them (drag's
    // exp(−h/H)·|v_rel| under J2) it ran for minutes without end. Past this size only expansion.
    constexpr std::size_t normal_limit = 8000;
    ex best = e;
    std::size_t best_size = node_count(e);
    auto consider = [&](const ex& c) {
        if (c.is_zero()) return true;
        const std::size_t s = node_count(c);
        if (s < best_size) best = c, best_size = s;
        return false;
    };
    ex a = combine_exponentials(combine_exponentials(e).expand()).expand();
    if (consider(a)) return 0;
    if (node_count(a) > normal_limit) return best;
    if (consider(safe_normal(a))) return 0;
    // sin² + cos² = 1 and cosh² − sinh² = 1: rewrite the even powers of sin and cosh away.
    const ex u = GiNaC::wild(0);
    if (a.has(GiNaC::sin(u)) || a.has(GiNaC::cosh(u))) {
        const ex trig = without_sin_squared(a, true).expand();
        if (consider(trig)) return 0;
        if (consider(safe_normal(trig))) return 0;
    }
    // Last, a zero test only: sines and cosines as complex exponentials make every identity
    // between trigonometric polynomials (double angles, products to sums) an expansion.
    // Each factor doubles the terms, so only for moderate sizes.
    if (best_size < 4000 && (a.has(GiNaC::sin(u)) || a.has(GiNaC::cos(u)) || a.has(GiNaC::sinh(u)) ||
                             a.has(GiNaC::cosh(u)))) {
        const ex i = GiNaC::I;
        const ex exponential =
            a.subs(GiNaC::lst{GiNaC::sin(u) == (GiNaC::exp(i * u) - GiNaC::exp(-i * u)) / (2 * i),
                              GiNaC::cos(u) == (GiNaC::exp(i * u) + GiNaC::exp(-i * u)) / 2,
                              GiNaC::sinh(u) == (GiNaC::exp(u) - GiNaC::exp(-u)) / 2,
                              GiNaC::cosh(u) == (GiNaC::exp(u) + GiNaC::exp(-u)) / 2});
        if (combine_exponentials(combine_exponentials(exponential.expand()).expand()).expand().is_zero()) return 0;
    }
    return best;
}

ex normalized(const ex& e) {
    // The inverse of a mass matrix is full of sin² + cos²: the rewritten form is often shorter.
    const ex plain = GiNaC::normal(e.expand());
    const ex trig = GiNaC::normal(without_sin_squared(e.expand(), false).expand());
    return node_count(trig) < node_count(plain) ? trig : plain;
}

ex exp_of(const ex& phi) {
    ex product = 1, rest = 0;
    for (const ex& term : terms_of(phi.expand())) {
        ex log_factor, others = 1;
        int logs = 0;
        for (const ex& f : factors_of(term)) {
            if (is_function(f, "log")) {
                log_factor = f.op(0);
                ++logs;
            } else {
                others *= f;
            }
        }
        // exp(c log w) = w^c
        if (logs == 1) product *= GiNaC::pow(log_factor, others);
        else rest += term;
    }
    return product * GiNaC::exp(rest);
}

}  // namespace eomc::symbolic
