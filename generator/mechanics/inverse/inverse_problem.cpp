#include "mechanics/inverse/inverse_problem.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "mechanics/kinematics/operators.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics::inverse {

using namespace eomc::symbolic;

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::is_a;
using GiNaC::matrix;
using GiNaC::numeric;
using GiNaC::symbol;

// =======================================================================================
// Algebra

namespace {

std::size_t size_of(const ex& e) {
    std::size_t n = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) n += size_of(e.op(i));
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

// exp(a)·exp(b)^k → exp(a + k b) in every product: GiNaC keeps exponentials apart, so
// e^{γt}·e^{−γt} would otherwise never cancel.
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

ex combine_exponentials(const ex& e) {
    CombineExponentials f;
    return f(e);
}

ex safe_normal(const ex& e) {
    try {
        return GiNaC::normal(e);
    } catch (const std::exception&) {
        return e;
    }
}

}  // namespace

ex simplified(const ex& e) {
    // normal() puts everything over one denominator, treating each square root and exponential
    // as a new variable: on tens of thousands of nodes with several of them (drag's
    // exp(−h/H)·|v_rel| under J2) it ran for minutes without end. Past this size only expansion.
    constexpr std::size_t normal_limit = 8000;
    ex best = e;
    std::size_t best_size = size_of(e);
    auto consider = [&](const ex& c) {
        if (c.is_zero()) return true;
        const std::size_t s = size_of(c);
        if (s < best_size) best = c, best_size = s;
        return false;
    };
    ex a = combine_exponentials(combine_exponentials(e).expand()).expand();
    if (consider(a)) return 0;
    if (size_of(a) > normal_limit) return best;
    if (consider(safe_normal(a))) return 0;
    // sin² + cos² = 1 and cosh² − sinh² = 1: rewrite the even powers of sin and cosh away.
    const ex u = GiNaC::wild(0);
    if (a.has(GiNaC::sin(u)) || a.has(GiNaC::cosh(u))) {
        const ex trig = a.subs(GiNaC::lst{GiNaC::pow(GiNaC::sin(u), 2) == 1 - GiNaC::pow(GiNaC::cos(u), 2),
                                          GiNaC::pow(GiNaC::cosh(u), 2) == 1 + GiNaC::pow(GiNaC::sinh(u), 2)},
                               GiNaC::subs_options::algebraic)
                             .expand();
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

// =======================================================================================
// Forms

ex FundamentalForm::expression(const model::Model& model, std::size_t i) const {
    ex e = B[i];
    for (std::size_t j = 0; j < model.coordinates.size(); ++j) e += A(unsigned(i), unsigned(j)) * model.coordinates[j].q_ddot;
    return e;
}

Forms forms(const model::Model& model, const Equations& equations) {
    const std::size_t n = model.coordinates.size();
    Forms out;
    out.given_fundamental = !(model.newtonian && !model.newtonian->fundamental);
    out.fundamental.A = matrix(unsigned(n), unsigned(n));
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j)
            out.fundamental.A(unsigned(i), unsigned(j)) = simplified(equations.mass_matrix(unsigned(i), unsigned(j)));
        out.fundamental.B.push_back(simplified(-equations.forcing[i]));
    }
    if (!out.given_fundamental) {
        out.kinematic = equations.forcing;
        return out;
    }
    bool identity = true;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (!(out.fundamental.A(unsigned(i), unsigned(j)) - (i == j ? 1 : 0)).is_zero()) identity = false;
    if (identity) {
        for (std::size_t i = 0; i < n; ++i) out.kinematic.push_back(simplified(equations.forcing[i]));
        return out;
    }
    if (n > 4)
        throw std::runtime_error(fmt::format("the kinematic form of {} coordinates needs A⁻¹ symbolically; "
                                             "`eomc inverse` handles up to 4 (or give the kinematic form)",
                                             n));
    const matrix inverse = out.fundamental.A.inverse();
    for (std::size_t i = 0; i < n; ++i) {
        ex f = 0;
        for (std::size_t j = 0; j < n; ++j) f += inverse(unsigned(i), unsigned(j)) * equations.forcing[j];
        out.kinematic.push_back(simplified(f));
    }
    return out;
}

// =======================================================================================
// Santilli's conditions

namespace {

// D = ∂_t + q̇_k ∂/∂q_k (no q̈: A and B are functions of t, q, q̇).
ex D(const model::Model& model, const ex& F) {
    ex d = derivative(F, model.t);
    for (const auto& c : model.coordinates) d += c.q_dot * derivative(F, c.q);
    return d;
}

// d/dt along q̈ = f: ∂_t + q̇_k ∂/∂q_k + f_k ∂/∂q̇_k.
ex along_flow(const model::Model& model, const std::vector<ex>& f, const ex& F) {
    ex d = D(model, F);
    for (std::size_t k = 0; k < model.coordinates.size(); ++k) d += f[k] * derivative(F, model.coordinates[k].q_dot);
    return d;
}

std::vector<symbol> state_symbols(const model::Model& model, bool with_acceleration = false) {
    std::vector<symbol> out{model.t};
    for (const auto& c : model.coordinates) {
        out.push_back(c.q);
        out.push_back(c.q_dot);
        if (with_acceleration) out.push_back(c.q_ddot);
    }
    return out;
}

bool depends_on_state(const ex& e, const std::vector<symbol>& state) {
    return std::any_of(state.begin(), state.end(), [&](const symbol& s) { return e.has(s); });
}

bool has_velocity(const model::Model& model, const ex& e) {
    return std::any_of(model.coordinates.begin(), model.coordinates.end(), [&](const auto& c) { return e.has(c.q_dot); });
}

std::string coordinate(const model::Model& model, std::size_t i) { return model.coordinates[i].name; }

}  // namespace

std::string label(const model::Model& model, const Residual& r) {
    if (r.condition == "S2") return fmt::format("S2({};{},{})", coordinate(model, r.i), coordinate(model, r.j), coordinate(model, *r.k));
    if (r.condition == "S4") return fmt::format("S4({},{};{})", coordinate(model, r.i), coordinate(model, r.j), coordinate(model, *r.k));
    return fmt::format("{}({},{})", r.condition, coordinate(model, r.i), coordinate(model, r.j));
}

std::vector<Residual> santilli_conditions(const model::Model& model, const FundamentalForm& form) {
    const std::size_t n = model.coordinates.size();
    const auto& A = form.A;
    const auto& B = form.B;
    auto a = [&](std::size_t i, std::size_t j) { return A(unsigned(i), unsigned(j)); };
    auto qd = [&](std::size_t k) { return model.coordinates[k].q_dot; };
    auto q = [&](std::size_t k) { return model.coordinates[k].q; };
    // ∂B_i/∂q̇_j − ∂B_j/∂q̇_i, used by S4 and S5
    auto curl_B = [&](std::size_t i, std::size_t j) { return derivative(B[i], qd(j)) - derivative(B[j], qd(i)); };

    std::vector<Residual> out;
    auto add = [&](const char* name, std::size_t i, std::size_t j, std::optional<std::size_t> k, const ex& value) {
        Residual r{name, i, j, k, simplified(value), false};
        r.zero = r.value.is_zero();
        out.push_back(std::move(r));
    };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) add("S1", i, j, std::nullopt, a(i, j) - a(j, i));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t k = j + 1; k < n; ++k)
                add("S2", i, j, k, derivative(a(i, j), qd(k)) - derivative(a(i, k), qd(j)));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i; j < n; ++j)
            add("S3", i, j, std::nullopt, derivative(B[i], qd(j)) + derivative(B[j], qd(i)) - 2 * D(model, a(i, j)));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (std::size_t k = 0; k < n; ++k)
                add("S4", i, j, k,
                    derivative(a(i, k), q(j)) - derivative(a(j, k), q(i)) - derivative(curl_B(i, j), qd(k)) / 2);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            add("S5", i, j, std::nullopt,
                derivative(B[i], q(j)) - derivative(B[j], q(i)) - D(model, curl_B(i, j)) / 2);
    return out;
}

namespace {

// Σ |term| at a point: the size against which "zero to round-off" is judged.
double magnitude(const ex& e, const ProbePoint& point) {
    double sum = 0;
    for (const ex& term : terms_of(e.expand())) sum += std::abs(evaluate(term, point));
    return sum;
}

constexpr std::size_t probe_count = 32;

}  // namespace

Decision decide(const model::Model& model, const std::vector<Residual>& residuals) {
    Decision d;
    const auto points = probe_points(model, probe_count, 0x5a17111);
    bool all_zero = true;
    for (std::size_t r = 0; r < residuals.size(); ++r) {
        if (residuals[r].zero) continue;
        all_zero = false;
        std::size_t finite = 0;
        for (const auto& point : points) {
            const double v = evaluate(residuals[r].value, point);
            if (!std::isfinite(v)) continue;
            ++finite;
            // 1e-9 relative: far above round-off of a few hundred operations, far below
            // any genuinely non-zero residual at a random point.
            if (std::abs(v) > 1e-9 * magnitude(residuals[r].value, point) && std::abs(v) > 1e-300) {
                d.verdict = Verdict::not_self_adjoint;
                d.witness = r;
                d.witness_value = v;
                d.point.emplace_back("t", point.values.at(model.t));
                for (const auto& c : model.coordinates) d.point.emplace_back(c.name, point.values.at(c.q));
                for (const auto& c : model.coordinates) d.point.emplace_back(c.name + "_dot", point.values.at(c.q_dot));
                for (const auto& p : model.parameters) d.point.emplace_back(p.name, point.values.at(p.symbol));
                return d;
            }
        }
        d.unresolved.push_back(r);
        d.points_tried = std::max(d.points_tried, finite);
    }
    d.verdict = all_zero ? Verdict::self_adjoint : Verdict::undecided;
    return d;
}

// =======================================================================================
// Multipliers

namespace {

struct FlowMatrices {
    matrix N, Phi;
};

FlowMatrices flow_matrices(const model::Model& model, const std::vector<ex>& f) {
    const unsigned n = unsigned(model.coordinates.size());
    FlowMatrices m{matrix(n, n), matrix(n, n)};
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) m.N(i, j) = simplified(derivative(f[i], model.coordinates[j].q_dot));
    const matrix N2 = m.N.mul(m.N);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
            m.Phi(i, j) = simplified(along_flow(model, f, m.N(i, j)) / 2 - derivative(f[i], model.coordinates[j].q) -
                                     N2(i, j) / 4);
    return m;
}

std::vector<std::pair<std::string, ex>> helmholtz(const model::Model& model, const std::vector<ex>& f,
                                                  const FlowMatrices& m, const matrix& g, bool simplify) {
    const unsigned n = unsigned(model.coordinates.size());
    std::vector<std::pair<std::string, ex>> out;
    auto put = [&](std::string name, const ex& value) { out.emplace_back(std::move(name), simplify ? simplified(value) : value); };
    const matrix gPhi = g.mul(m.Phi);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i + 1; j < n; ++j)
            put(fmt::format("H1({},{})", coordinate(model, i), coordinate(model, j)), gPhi(i, j) - gPhi(j, i));
    const matrix NtG = m.N.transpose().mul(g), GN = g.mul(m.N);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j)
            put(fmt::format("H2({},{})", coordinate(model, i), coordinate(model, j)),
                along_flow(model, f, g(i, j)) + NtG(i, j) / 2 + GN(i, j) / 2);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j)
            for (unsigned k = j + 1; k < n; ++k)
                put(fmt::format("H3({};{},{})", coordinate(model, i), coordinate(model, j), coordinate(model, k)),
                    derivative(g(i, j), model.coordinates[k].q_dot) - derivative(g(i, k), model.coordinates[j].q_dot));
    return out;
}

bool all_zero(const std::vector<std::pair<std::string, ex>>& residuals) {
    return std::all_of(residuals.begin(), residuals.end(), [](const auto& r) { return r.second.is_zero(); });
}

bool regular(const matrix& g) {
    try {
        return !simplified(g.determinant()).is_zero();
    } catch (const std::exception&) {
        return false;
    }
}

// The unknown constants u of `conditions` (each linear in u, coefficients functions of the
// state) such that every condition vanishes identically in t, q, q̇: each condition's
// numerator is expanded, its terms grouped by their state-dependent factor, and the
// coefficient of each group set to zero (exact; at worst stricter than needed, when groups
// are dependent functions such as sin², cos² and 1). The result maps every unknown to its
// value in terms of the free ones.
std::optional<GiNaC::exmap> solve_identically(const std::vector<ex>& conditions, const std::vector<symbol>& unknowns,
                                              const std::vector<symbol>& state) {
    std::map<ex, ex, GiNaC::ex_is_less> groups;
    for (const ex& c : conditions) {
        ex numerator = c;
        try {
            // Large conditions are grouped term by term as they stand: their terms keep their
            // denominators as part of the state factor, which is still exact (stricter at worst).
            if (size_of(c) <= 8000) numerator = GiNaC::normal(c).numer();
        } catch (const std::exception&) {
        }
        numerator = combine_exponentials(numerator.expand()).expand();
        for (const ex& term : terms_of(numerator)) {
            ex state_part = 1, coefficient = 1;
            for (const ex& f : factors_of(term)) {
                if (depends_on_state(f, state)) state_part *= f;
                else coefficient *= f;
            }
            groups[state_part] += coefficient;
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

std::string text(const ex& e) {
    std::ostringstream os;
    os << GiNaC::dflt << e;
    return os.str();
}

// A regular member of the family g(free): free diagonal constants 1 and the others 0
// first (the plainest member), then each free constant alone, then all of them 1.
std::optional<matrix> regular_member(const matrix& family, const std::vector<symbol>& free,
                                     const std::vector<bool>& on_diagonal) {
    std::vector<GiNaC::exmap> tries;
    GiNaC::exmap diagonal;
    for (std::size_t i = 0; i < free.size(); ++i) diagonal[free[i]] = on_diagonal[i] ? 1 : 0;
    tries.push_back(diagonal);
    for (std::size_t i = 0; i < free.size(); ++i) {
        GiNaC::exmap unit;
        for (std::size_t k = 0; k < free.size(); ++k) unit[free[k]] = k == i ? 1 : 0;
        tries.push_back(unit);
    }
    GiNaC::exmap ones;
    for (const auto& s : free) ones[s] = 1;
    tries.push_back(ones);
    for (const auto& values : tries) {
        matrix g = ex_to<matrix>(family.subs(values));
        for (unsigned i = 0; i < g.rows(); ++i)
            for (unsigned j = 0; j < g.cols(); ++j) g(i, j) = simplified(g(i, j));
        if (regular(g)) return g;
    }
    return std::nullopt;
}

// An ansatz g = Σ (unknown constant) × (known function) solved through the linear conditions.
struct AnsatzResult {
    bool any = false;  // a non-zero family exists
    matrix family;
    std::vector<symbol> free;
    std::optional<matrix> g;
    std::size_t over_budget = 0;  // the size of the conditions when over the budget (then not solved)
};

AnsatzResult solve_ansatz(const model::Model& model, const std::vector<ex>& f, const FlowMatrices& m,
                          const matrix& ansatz, const std::vector<symbol>& unknowns,
                          const std::vector<bool>& unknown_on_diagonal, const SearchBudget& budget) {
    AnsatzResult r;
    std::vector<ex> conditions;
    std::size_t size = 0;
    for (const auto& [name, value] : helmholtz(model, f, m, ansatz, false)) {
        conditions.push_back(value);
        size += size_of(value);
    }
    if (size > budget.nodes) {
        r.over_budget = size;
        return r;
    }
    const auto solution = solve_identically(conditions, unknowns, state_symbols(model));
    if (!solution) return r;
    r.family = ex_to<matrix>(ansatz.subs(*solution));
    std::vector<bool> diagonal;
    for (std::size_t i = 0; i < unknowns.size(); ++i) {
        const ex value = solution->at(unknowns[i]);
        if (value.is_equal(unknowns[i])) {
            r.free.push_back(unknowns[i]);
            diagonal.push_back(unknown_on_diagonal[i]);
        }
    }
    r.any = !r.free.empty();
    if (r.any) r.g = regular_member(r.family, r.free, diagonal);
    return r;
}

std::string matrix_text(const matrix& g) {
    std::string out = "[";
    for (unsigned i = 0; i < g.rows(); ++i) {
        out += i ? ", [" : "[";
        for (unsigned j = 0; j < g.cols(); ++j) out += (j ? ", " : "") + text(g(i, j));
        out += "]";
    }
    return out + "]";
}

// ---- one degree of freedom: H2 is g_t + q̇ g_q + f g_q̇ = −(∂f/∂q̇) g; with g = exp(u),
// u_t + q̇ u_q + f u_q̇ = −∂f/∂q̇, and the separable u = G(t) + H(q) + K(q̇) are tried.

void one_degree_of_freedom(const model::Model& model, const std::vector<ex>& f_, Multiplier& m) {
    const symbol& t = model.t;
    const symbol& q = model.coordinates[0].q;
    const symbol& v = model.coordinates[0].q_dot;
    const ex f = f_[0], N = m.N(0, 0);
    const ex minus_N = simplified(-N);
    const std::string qn = coordinate(model, 0), vn = qn + "_dot";
    m.steps.push_back({fmt::format("One degree of freedom: H1 and H3 are empty; H2 reads dg/dt = −(∂f/∂{}) g along the "
                                   "motion, a linear first-order PDE for g(t, {}, {}). With g = exp(u): "
                                   "u_t + {} u_{} + f u_{} = −∂f/∂{}.",
                                   vn, qn, vn, vn, qn, vn, vn),
                       {{"−∂f/∂" + vn, minus_N}}});

    auto accept = [&](const ex& u, const std::string& kind, const std::string& how) {
        matrix g(1, 1);
        g(0, 0) = simplified(exp_of(u));
        const auto residuals = helmholtz(model, f_, FlowMatrices{m.N, m.Phi}, g, true);
        if (!all_zero(residuals) || !regular(g)) {
            m.steps.push_back({fmt::format("{}: the candidate g = {} fails H2 on substitution; rejected", kind, text(g(0, 0))), {}});
            return false;
        }
        m.steps.push_back({fmt::format("{}: {}; g = exp(u) satisfies H2 identically (checked by substitution).", kind, how),
                           {{"g", g(0, 0)}}});
        m.g = g;
        m.kind = kind;
        return true;
    };
    auto free_of = [](const ex& e, std::initializer_list<const symbol*> syms) {
        return std::none_of(syms.begin(), syms.end(), [&](const symbol* s) { return e.has(*s); });
    };

    // u = G(t) + H(q): G'(t) + q̇ H'(q) = −∂f/∂q̇, so −∂f/∂q̇ must be affine in q̇.
    {
        const ex b = simplified(derivative(minus_N, v));
        const ex a = simplified(minus_N - v * b);  // not −∂f/∂q̇ at q̇ = 0: that may be a pole
        if (free_of(a, {&q, &v}) && free_of(b, {&t, &v})) {
            const auto G = antiderivative(a, t);
            const auto H = antiderivative(b, q);
            const std::string kind = a.is_zero() && b.is_zero() ? "constant" : b.is_zero() ? "g(t)" : a.is_zero() ? "g(q)" : "g(t)h(q)";
            if (G && H &&
                accept(*G + *H, kind,
                       fmt::format("−∂f/∂{} = G'(t) + {} H'({}) with G' = {}, H' = {}", vn, vn, qn, text(a), text(b))))
                return;
        } else {
            m.steps.push_back({fmt::format("g(t)h({}): −∂f/∂{} is not of the form a(t) + {} b({})", qn, vn, vn, qn), {}});
        }
    }
    // u = K(q̇): f K'(q̇) = −∂f/∂q̇, so −(∂f/∂q̇)/f must depend on q̇ alone.
    if (!simplified(f).is_zero()) {
        const ex c = simplified(minus_N / f);
        if (free_of(c, {&t, &q})) {
            if (const auto K = antiderivative(c, v);
                K && accept(*K, "g(" + vn + ")", fmt::format("K'({}) = −(∂f/∂{})/f = {}", vn, vn, text(c))))
                return;
        } else {
            m.steps.push_back({fmt::format("g({}): −(∂f/∂{})/f = {} depends on more than {}", vn, vn, text(c), vn), {}});
        }
    }
    // u = G(t) + K(q̇): differentiating in q gives f_q K' = −∂²f/∂q̇∂q, so K' = −f_{q̇q}/f_q.
    if (const ex fq = simplified(derivative(f, q)); !fq.is_zero()) {
        const ex c = simplified(-derivative(N, q) / fq);
        const ex a = simplified(minus_N - f * c);
        if (free_of(c, {&t, &q}) && free_of(a, {&q, &v})) {
            const auto G = antiderivative(a, t);
            const auto K = antiderivative(c, v);
            if (G && K && accept(*G + *K, "g(t)k(" + vn + ")",
                                 fmt::format("K'({}) = −f_{{{}{}}}/f_{} = {}, G'(t) = {}", vn, vn, qn, qn, text(c), text(a))))
                return;
        } else {
            m.steps.push_back({fmt::format("g(t)k({}): no separation (K' = {}, G' = {})", vn, text(c), text(a)), {}});
        }
    }
    // u = H(q) + K(q̇): differentiating in t gives f_t K' = −∂²f/∂q̇∂t, so K' = −f_{q̇t}/f_t.
    if (const ex ft = simplified(derivative(f, t)); !ft.is_zero()) {
        const ex c = simplified(-derivative(N, t) / ft);
        const ex b = simplified((minus_N - f * c) / v);
        if (free_of(c, {&t, &q}) && free_of(b, {&t, &v})) {
            const auto H = antiderivative(b, q);
            const auto K = antiderivative(c, v);
            if (H && K && accept(*H + *K, "h(q)k(" + vn + ")",
                                 fmt::format("K'({}) = −f_{{{}t}}/f_t = {}, H'({}) = {}", vn, vn, text(c), qn, text(b))))
                return;
        } else {
            m.steps.push_back({fmt::format("h({})k({}): no separation (K' = {}, H' = {})", qn, vn, text(c), text(b)), {}});
        }
    }
    m.steps.push_back({"No multiplier of the separable forms g(t)h(q), g(q̇), g(t)k(q̇), h(q)k(q̇) solves H2. "
                       "(In one degree of freedom a multiplier always exists locally — Darboux — but it need not be "
                       "of these forms.)",
                       {}});
}

// ---- n degrees of freedom

// H1 and its derivatives along the motion under H2: g ∇ᵏΦ symmetric, ∇X = dX/dt + ΓX − XΓ,
// Γ = −½ ∂f/∂q̇. These are pointwise linear conditions on the entries of g. Their rank is taken
// at random points (the generic rank; a non-zero minor at a point proves it is not lower);
// when it reaches the number of entries only g = 0 is left. When the conditions are small
// enough they are also solved symbolically, for the reasoning steps, and a general solution
// with det g ≡ 0 proves singularity as well. Either way no regular multiplier, hence no
// regular Lagrangian, exists.
bool singular_forced(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget, Multiplier& m) {
    const unsigned n = unsigned(model.coordinates.size());
    matrix G(n, n);
    std::vector<symbol> unknowns;
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j) {
            const std::string name = fmt::format("g_{}_{}", coordinate(model, i), coordinate(model, j));
            const std::string tex = fmt::format("g_{{{}{}}}", coordinate(model, i), coordinate(model, j));
            unknowns.emplace_back(name, tex);
            G(i, j) = G(j, i) = unknowns.back();
        }
    const std::size_t u = unknowns.size();
    const matrix Gamma = m.N.mul_scalar(ex(-1) / 2);
    const auto points = probe_points(model, 8, 0xd06145);
    std::vector<std::vector<ex>> rows;  // coefficients of each condition on the unknowns
    std::size_t rows_size = 0;
    constexpr std::size_t symbolic_limit = 600;  // expression nodes up to which the conditions are solved exactly

    auto numeric_rank = [&] {
        Eigen::Index best = 0;
        for (const auto& point : points) {
            Eigen::MatrixXd C(Eigen::Index(rows.size()), Eigen::Index(u));
            for (std::size_t r = 0; r < rows.size(); ++r)
                for (std::size_t c = 0; c < u; ++c) C(Eigen::Index(r), Eigen::Index(c)) = evaluate(rows[r][c], point);
            if (!C.allFinite()) continue;
            Eigen::JacobiSVD<Eigen::MatrixXd> svd(C);
            const Eigen::VectorXd sigma = svd.singularValues();
            Eigen::Index rank = 0;
            for (Eigen::Index k = 0; k < sigma.size(); ++k)
                if (sigma(k) > 1e-9 * sigma(0)) ++rank;
            best = std::max(best, rank);
        }
        return std::size_t(best);
    };

    matrix X = m.Phi;
    std::size_t previous_rank = 0;
    for (std::size_t k = 0; k < u; ++k) {
        const matrix GX = G.mul(X);
        Step step{k == 0 ? "H1: g Φ must be symmetric (pointwise conditions on the entries of g)"
                         : fmt::format("H1 differentiated along the motion {} time{}, with H2 for dg/dt: g ∇{}Φ must be "
                                       "symmetric, ∇X = dX/dt + ΓX − XΓ, Γ = −½ ∂f/∂q̇",
                                       k, k == 1 ? "" : "s", k == 1 ? "" : fmt::format("^{}", k)),
                  {}};
        for (unsigned i = 0; i < n; ++i)
            for (unsigned j = i + 1; j < n; ++j) {
                const ex c = (GX(i, j) - GX(j, i)).expand();
                std::vector<ex> row;
                ex condition = 0;
                for (const auto& unknown : unknowns) {
                    row.push_back(simplified(c.coeff(unknown, 1)));
                    condition += row.back() * unknown;
                    rows_size += size_of(row.back());
                }
                if (std::all_of(row.begin(), row.end(), [](const ex& e) { return e.is_zero(); })) continue;
                step.equations.emplace_back(fmt::format("({0})_{1}{2} − ({0})_{2}{1}", k == 0 ? "gΦ" : "g∇Φ",
                                                        coordinate(model, i), coordinate(model, j)),
                                            condition);
                rows.push_back(std::move(row));
            }
        const std::size_t rank = rows.empty() ? 0 : numeric_rank();
        // The exact solution, when small, for the reasoning; trusted only when its rank agrees
        // with the numeric one (a pivot that is zero but not recognised as zero would not).
        std::optional<GiNaC::exmap> solution;
        if (!rows.empty() && rows_size <= symbolic_limit) {
            GiNaC::lst equations, vars;
            for (const auto& row : rows) {
                ex e = 0;
                for (std::size_t c = 0; c < u; ++c) e += row[c] * unknowns[c];
                equations.append(e == 0);
            }
            for (const auto& unknown : unknowns) vars.append(unknown);
            try {
                const ex s = GiNaC::lsolve(equations, vars);
                GiNaC::exmap sol;
                std::size_t determined = 0;
                for (std::size_t i = 0; i < s.nops(); ++i) {
                    sol[s.op(i).op(0)] = simplified(s.op(i).op(1));
                    if (!sol[s.op(i).op(0)].is_equal(s.op(i).op(0))) ++determined;
                }
                if (s.nops() == u && determined == rank) solution = sol;
            } catch (const std::exception&) {
            }
        }
        if (step.equations.empty() || rank == previous_rank) {
            step.text += step.equations.empty() ? ": nothing new" : ": nothing new (implied by the conditions above)";
            step.equations.clear();
        } else if (solution) {
            std::string forced;
            for (const auto& unknown : unknowns)
                if (!solution->at(unknown).is_equal(unknown))
                    forced += (forced.empty() ? "" : ", ") + text(unknown) + " = " + text(solution->at(unknown));
            step.text += "; so " + forced;
        } else {
            step.text += fmt::format("; the conditions so far have rank {} on the {} entries of g (at random points)", rank, u);
        }
        m.steps.push_back(std::move(step));
        if (rank == u) {
            m.steps.push_back({fmt::format("H1 and H2 leave only g = 0 ({0} independent conditions on the {0} entries), "
                                           "det g = 0. No regular multiplier exists, so no regular Lagrangian (Douglas).",
                                           u),
                               {}});
            return true;
        }
        if (rank == previous_rank) {
            // The conditions close: each level is the derivative of the one before (with H2
            // for dg/dt), so once a level adds nothing every later one adds nothing either
            // (Sarlet, J. Phys. A 15 (1982) 1503, §4; Crampin et al., Inverse Problems 10
            // (1994) 245). H1–H2 then leave a space of g of dimension u − rank at each point.
            m.steps.push_back({fmt::format("The algebraic conditions close at rank {} of {} (at random points): every "
                                           "further derivative along the motion is implied by them, so they leave "
                                           "g free in {} dimension{} at each point.",
                                           rank, u, u - rank, u - rank == 1 ? "" : "s"),
                               {}});
            return false;
        }
        previous_rank = rank;
        if (solution) {
            const matrix general = ex_to<matrix>(G.subs(*solution));
            std::size_t size = 0;
            for (unsigned i = 0; i < n * n; ++i) size += size_of(general(i / n, i % n));
            if (size <= symbolic_limit && simplified(general.determinant()).is_zero()) {
                m.steps.push_back({fmt::format("Every g allowed by H1 and H2 is singular: g = {}, det g = 0. No regular "
                                               "multiplier exists, so no regular Lagrangian (Douglas).",
                                               matrix_text(general)),
                                   {}});
                return true;
            }
        }
        // Each derivative along the motion multiplies the size of ∇ᵏΦ by 10–20 for a
        // non-polynomial force (drag: exp and square roots of the state), so the next level is
        // only formed while the current one is within the budget.
        std::size_t size = 0;
        for (unsigned i = 0; i < n * n; ++i) size += size_of(X(i / n, i % n));
        if (size > budget.nodes) {
            m.undecided = fmt::format("the algebraic consequences of H1–H2 were cut after {}Φ (rank {} of {}): it has "
                                      "{} expression nodes, over the budget of {} for forming the next derivative",
                                      k == 0 ? "" : k == 1 ? "∇" : fmt::format("∇^{}", k), rank, u, size, budget.nodes);
            m.steps.push_back({"Stopped: " + m.undecided, {}});
            return false;
        }
        matrix next(n, n);
        const matrix commutator = Gamma.mul(X).sub(X.mul(Gamma));
        for (unsigned i = 0; i < n; ++i)
            for (unsigned j = 0; j < n; ++j) next(i, j) = simplified(along_flow(model, f, X(i, j)) + commutator(i, j));
        X = next;
    }
    return false;
}

void several_degrees_of_freedom(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget,
                                Multiplier& m) {
    const unsigned n = unsigned(model.coordinates.size());
    m.steps.push_back({"n degrees of freedom: first the algebraic consequences of H1 and H2, then constant and "
                       "diagonal multipliers, whose conditions H1–H3 are linear in unknown constant coefficients "
                       "(solved identically in t, q, q̇).",
                       {}});
    if (singular_forced(model, f, budget, m)) {
        m.singular_forced = true;
        return;
    }
    const FlowMatrices fm{m.N, m.Phi};
    auto finish = [&](const AnsatzResult& r, const std::string& kind) {
        if (r.over_budget) {
            const std::string why = fmt::format("the {} ansatz's conditions H1–H3 have {} expression nodes, over the "
                                                "budget of {}",
                                                kind, r.over_budget, budget.nodes);
            m.undecided += (m.undecided.empty() ? "" : "; ") + why;
            m.steps.push_back({kind + ": not solved: " + why, {}});
            return false;
        }
        if (!r.any) {
            m.steps.push_back({kind + ": H1–H3 leave only g = 0", {}});
            return false;
        }
        if (!r.g) {
            m.steps.push_back({fmt::format("{}: H1–H3 allow g = {} ({} free constant{}), singular for every choice tried",
                                           kind, matrix_text(r.family), r.free.size(), r.free.size() == 1 ? "" : "s"),
                               {}});
            return false;
        }
        if (!all_zero(helmholtz(model, f, fm, *r.g, true))) {
            m.steps.push_back({kind + ": the candidate fails H1–H3 on substitution; rejected", {}});
            return false;
        }
        m.steps.push_back({fmt::format("{}: H1–H3 hold for g = {} ({} free constant{}); the member chosen is regular",
                                       kind, matrix_text(r.family), r.free.size(), r.free.size() == 1 ? "" : "s"),
                           {}});
        m.g = r.g;
        m.kind = kind;
        m.family = r.family;
        m.free_constants = r.free;
        return true;
    };

    // Constant symmetric g.
    {
        matrix g(n, n);
        std::vector<symbol> unknowns;
        std::vector<bool> diagonal;
        for (unsigned i = 0; i < n; ++i)
            for (unsigned j = i; j < n; ++j) {
                unknowns.emplace_back(fmt::format("c_{}_{}", coordinate(model, i), coordinate(model, j)),
                                      fmt::format("c_{{{}{}}}", coordinate(model, i), coordinate(model, j)));
                diagonal.push_back(i == j);
                g(i, j) = g(j, i) = unknowns.back();
            }
        if (finish(solve_ansatz(model, f, fm, g, unknowns, diagonal, budget), "constant")) return;
    }
    // Diagonal g_ii = c_i exp(φ_i(t, q)): the diagonal part of H2 reads dφ_i/dt = −∂f_i/∂q̇_i,
    // so −∂f_i/∂q̇_i must be a_i(t,q) + q̇_k b_ik(t,q) with (a_i, b_i) a gradient in (t, q).
    {
        matrix g(n, n);
        std::vector<symbol> unknowns;
        std::vector<symbol> vars{model.t};
        for (const auto& c : model.coordinates) vars.push_back(c.q);
        bool depends_t = false, depends_q = false, ok = true;
        for (unsigned i = 0; i < n && ok; ++i) {
            const ex minus = simplified(-m.N(i, i));
            std::vector<ex> gradient{minus};  // [0]: the part free of q̇, completed below
            for (const auto& c : model.coordinates) {
                gradient.push_back(simplified(derivative(minus, c.q_dot)));
                gradient[0] -= c.q_dot * gradient.back();
            }
            gradient[0] = simplified(gradient[0]);
            const bool affine = std::none_of(gradient.begin(), gradient.end(), [&](const ex& e) { return has_velocity(model, e); });
            const auto phi = affine ? potential(gradient, vars) : std::nullopt;
            if (!phi) {
                m.steps.push_back({fmt::format("diagonal: −∂f_{0}/∂{0}_dot = {1} is not the rate of change of a function "
                                               "of t and q along the motion",
                                               coordinate(model, i), text(minus)),
                                   {}});
                ok = false;
                break;
            }
            depends_t = depends_t || phi->has(model.t);
            for (const auto& c : model.coordinates) depends_q = depends_q || phi->has(c.q);
            unknowns.emplace_back(fmt::format("c_{}", coordinate(model, i)), fmt::format("c_{{{}}}", coordinate(model, i)));
            g(i, i) = unknowns.back() * simplified(exp_of(*phi));
        }
        if (ok) {
            const std::string kind = depends_t && depends_q ? "diagonal in t and q"
                                     : depends_q            ? "diagonal in q"
                                     : depends_t            ? "diagonal in t"
                                                            : "constant diagonal";
            if (finish(solve_ansatz(model, f, fm, g, unknowns, std::vector<bool>(n, true), budget), kind)) return;
        }
    }
    m.steps.push_back({"No constant or diagonal multiplier satisfies H1–H3; the question is left open (a multiplier "
                       "of another form may exist).",
                       {}});
}

}  // namespace

std::vector<std::pair<std::string, ex>> helmholtz_residuals(const model::Model& model, const std::vector<ex>& f,
                                                            const matrix& g) {
    return helmholtz(model, f, flow_matrices(model, f), g, true);
}

Multiplier search_multiplier(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget) {
    Multiplier m;
    const FlowMatrices fm = flow_matrices(model, f);
    m.N = fm.N;
    m.Phi = fm.Phi;
    try {
        if (model.coordinates.size() == 1) one_degree_of_freedom(model, f, m);
        else several_degrees_of_freedom(model, f, budget, m);
    } catch (const std::exception& e) {  // a pole met while substituting, or a GiNaC limit
        m.g.reset();
        m.undecided = std::string("GiNaC stopped it: ") + e.what();
        m.steps.push_back({std::string("The search stopped: ") + e.what(), {}});
    }
    if (m.g) m.undecided.clear();  // a verified multiplier decides, whatever was cut short before it
    return m;
}

FundamentalForm multiplied(const matrix& g, const std::vector<ex>& f) {
    const unsigned n = g.rows();
    FundamentalForm out{matrix(n, n), {}};
    for (unsigned i = 0; i < n; ++i) {
        ex b = 0;
        for (unsigned j = 0; j < n; ++j) {
            out.A(i, j) = simplified(g(i, j));
            b -= g(i, j) * f[j];
        }
        out.B.push_back(simplified(b));
    }
    return out;
}

// =======================================================================================
// Santilli's construction

namespace {

// ∫₀¹ integrand dτ by an antiderivative; nullopt when none is found or it is singular at an end.
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

// The centres tried for the homotopies, in order: 0 unless the integrands are singular there.
constexpr double centres[] = {0, 1, 2};

}  // namespace

std::vector<ex> euler_lagrange_mismatch(const model::Model& model, const ex& L, const FundamentalForm& form) {
    std::vector<ex> out;
    for (std::size_t i = 0; i < model.coordinates.size(); ++i)
        out.push_back(simplified(euler_operator(model, L, i) - form.expression(model, i)));
    return out;
}

namespace {

Construction construct(const model::Model& model, const FundamentalForm& form) {
    const std::size_t n = model.coordinates.size();
    Construction c;
    const symbol tau("tau", "\\tau");

    // K from A along the ray v₀ + τ(q̇ − v₀).
    bool have_K = false;
    for (double v0 : centres) {
        GiNaC::exmap ray;
        for (const auto& co : model.coordinates) ray[co.q_dot] = v0 + tau * (co.q_dot - v0);
        ex K = 0;
        bool ok = true;
        for (std::size_t i = 0; i < n && ok; ++i)
            for (std::size_t j = 0; j < n && ok; ++j) {
                const ex a = form.A(unsigned(i), unsigned(j));
                if (a.is_zero()) continue;
                const auto I = unit_integral((1 - tau) * a.subs(ray), tau);
                if (!I) ok = false;
                else K += (model.coordinates[i].q_dot - v0) * (model.coordinates[j].q_dot - v0) * *I;
            }
        if (ok) {
            c.K = simplified(K);
            c.v_centre = v0;
            have_K = true;
            break;
        }
    }
    if (!have_K) {
        c.reason = "the integral ∫₀¹ (1−τ) A(t, q, τq̇) dτ for K is out of reach of the integrator";
        return c;
    }

    // E − ε(K) = α + β q̇ (no q̈ left: ∂²K/∂q̇∂q̇ = A).
    c.beta = matrix(unsigned(n), unsigned(n));
    for (std::size_t i = 0; i < n; ++i) {
        ex R = simplified(form.expression(model, i) - euler_operator(model, c.K, i));
        // R is affine in q̈ and its q̈ coefficients A − ∂²K/∂q̇∂q̇ must vanish (they may only
        // look non-zero, e.g. through square roots the simplifier does not merge).
        GiNaC::exmap no_acceleration;
        for (const auto& co : model.coordinates) {
            if (!R.has(co.q_ddot)) continue;
            if (!simplified(derivative(R, co.q_ddot)).is_zero()) {
                c.reason = "E − ε(K) still contains accelerations: A is not the Hessian of K (S1 or S2 fails)";
                return c;
            }
            no_acceleration[co.q_ddot] = 0;
        }
        if (!no_acceleration.empty()) R = simplified(R.subs(no_acceleration));
        // α = R − β q̇ rather than R at q̇ = 0: R may hold terms (log q̇) that cancel only
        // after simplification and cannot be evaluated at rest.
        ex alpha = R;
        bool affine = true;
        for (std::size_t k = 0; k < n; ++k) {
            const ex b = simplified(derivative(R, model.coordinates[k].q_dot));
            c.beta(unsigned(i), unsigned(k)) = b;
            alpha -= b * model.coordinates[k].q_dot;
            affine = affine && !has_velocity(model, b);
        }
        alpha = simplified(alpha);
        // Terms of α that only look velocity-dependent (a factor that is zero but not
        // simplified away) go with a substitution q̇ = 0 once ∂α/∂q̇ is shown to vanish.
        bool velocity_free = !has_velocity(model, alpha);
        if (!velocity_free && affine) {
            velocity_free = std::all_of(model.coordinates.begin(), model.coordinates.end(), [&](const auto& co) {
                return simplified(derivative(alpha, co.q_dot)).is_zero();
            });
            GiNaC::exmap at_rest;
            for (const auto& co : model.coordinates) at_rest[co.q_dot] = 0;
            try {
                if (velocity_free) alpha = simplified(alpha.subs(at_rest));
            } catch (const std::exception&) {  // a pole at rest: keep α as it is
            }
        }
        c.alpha.push_back(alpha);
        if (!affine || !velocity_free) {
            c.reason = fmt::format("E − ε(K) for '{}' is not affine in the velocities (S3–S5 fail)", coordinate(model, i));
            return c;
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < n; ++k)
            if (!simplified(c.beta(unsigned(i), unsigned(k)) + c.beta(unsigned(k), unsigned(i))).is_zero()) {
                c.reason = "the velocity part β of E − ε(K) is not antisymmetric (S3 fails)";
                return c;
            }

    // D, then C, by the homotopy q₀ + τ(q − q₀), each with the first centre that works.
    std::optional<std::vector<ex>> D;
    for (double q0 : centres) {
        GiNaC::exmap ray;
        for (const auto& co : model.coordinates) ray[co.q] = q0 + tau * (co.q - q0);
        std::vector<ex> Dv;
        for (std::size_t i = 0; i < n; ++i) {
            ex integrand = 0;
            for (std::size_t k = 0; k < n; ++k)
                integrand += (model.coordinates[k].q - q0) * c.beta(unsigned(i), unsigned(k)).subs(ray);
            const auto I = simplified(integrand).is_zero() ? std::optional<ex>(ex(0)) : unit_integral(tau * integrand, tau);
            if (!I) break;
            Dv.push_back(*I);
        }
        if (Dv.size() == n) {
            D = Dv;
            break;
        }
    }
    if (!D) {
        c.reason = "the homotopy integral for D is out of reach of the integrator";
        return c;
    }
    c.D = *D;
    std::vector<ex> gradient_C;  // ∂_i C = ∂_t D_i − α_i
    for (std::size_t i = 0; i < n; ++i) gradient_C.push_back(derivative(c.D[i], model.t) - c.alpha[i]);
    std::optional<ex> C;
    for (double q0 : centres) {
        GiNaC::exmap ray;
        for (const auto& co : model.coordinates) ray[co.q] = q0 + tau * (co.q - q0);
        ex integrand = 0;
        for (std::size_t i = 0; i < n; ++i) integrand += (model.coordinates[i].q - q0) * gradient_C[i].subs(ray);
        C = simplified(integrand).is_zero() ? std::optional<ex>(ex(0)) : unit_integral(integrand, tau);
        if (C) {
            c.q_centre = q0;
            break;
        }
    }
    if (!C) {
        // A potential singular at every centre tried (k/|q| in Cartesian coordinates): C by
        // integrating one coordinate after another instead of along rays.
        std::vector<symbol> coordinates;
        for (const auto& co : model.coordinates) coordinates.push_back(co.q);
        C = potential(gradient_C, coordinates);
        c.C_by_coordinates = bool(C);
    }
    if (!C) {
        c.reason = "the integrals for C are out of reach of the integrator";
        return c;
    }
    c.C = *C;

    ex L = c.K + c.C;
    for (std::size_t i = 0; i < n; ++i) L += c.D[i] * model.coordinates[i].q_dot;
    L = simplified(L);
    // Additive constants (from the homotopy centre) change no equation: drop them.
    const auto state = state_symbols(model);
    if (is_a<GiNaC::add>(L)) {
        ex kept = 0;
        for (const ex& term : terms_of(L))
            if (depends_on_state(term, state)) kept += term;
        L = kept;
    }
    c.L = L;
    c.built = true;

    c.check = euler_lagrange_mismatch(model, L, form);
    c.verified = std::all_of(c.check.begin(), c.check.end(), [](const ex& e) { return e.is_zero(); });
    if (!c.verified) {
        for (const auto& point : probe_points(model, probe_count, 0xc0ffee)) {
            bool agree = true;
            for (const ex& e : c.check) {
                const double v = evaluate(e, point);
                if (!std::isfinite(v) || std::abs(v) > 1e-9 * (1 + magnitude(e, point))) agree = false;
            }
            if (agree) ++c.points_agreeing;
        }
    }
    return c;
}

}  // namespace

Construction construct_lagrangian(const model::Model& model, const FundamentalForm& form) {
    try {
        return construct(model, form);
    } catch (const std::exception& e) {  // a pole met while substituting, or a GiNaC limit
        Construction c;
        c.reason = std::string("the construction failed: ") + e.what();
        return c;
    }
}

std::pair<ex, ex> split_lagrangian(const model::Model& model, const ex& L) {
    ex T = 0, V = 0;
    for (const ex& term : terms_of(L.expand())) {
        const bool kinetic = std::any_of(model.coordinates.begin(), model.coordinates.end(),
                                         [&](const auto& c) { return term.has(c.q_dot); });
        if (kinetic) T += term;
        else V -= term;
    }
    return {simplified(T), simplified(V)};
}

// =======================================================================================
// The analysis

namespace {

bool proportional(const matrix& a, const matrix& b) {
    const unsigned n = a.rows();
    for (unsigned i = 0; i < n * n; ++i)
        for (unsigned j = 0; j < n * n; ++j)
            if (!simplified(a(i / n, i % n) * b(j / n, j % n) - a(j / n, j % n) * b(i / n, i % n)).is_zero()) return false;
    return true;
}

// Another Lagrangian for equations already self-adjoint: a regular constant multiplier not
// proportional to A (the multiplier the equations carry as given) gives different equations
// with the same solutions, hence an inequivalent Lagrangian.
std::optional<Alternative> alternative_lagrangian(const model::Model& model, const Forms& forms) {
    const unsigned n = unsigned(model.coordinates.size());
    Multiplier m;
    const FlowMatrices fm = flow_matrices(model, forms.kinematic);
    matrix g(n, n);
    std::vector<symbol> unknowns;
    std::vector<bool> diagonal;
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j) {
            unknowns.emplace_back(fmt::format("c_{}_{}", coordinate(model, i), coordinate(model, j)));
            diagonal.push_back(i == j);
            g(i, j) = g(j, i) = unknowns.back();
        }
    const AnsatzResult r = solve_ansatz(model, forms.kinematic, fm, g, unknowns, diagonal, SearchBudget{});
    if (r.free.size() < 2) return std::nullopt;
    for (std::size_t k = 0; k < r.free.size(); ++k) {
        GiNaC::exmap unit;
        for (std::size_t l = 0; l < r.free.size(); ++l) unit[r.free[l]] = l == k ? 1 : 0;
        matrix member = ex_to<matrix>(r.family.subs(unit));
        if (!regular(member) || proportional(member, forms.fundamental.A)) continue;
        Alternative alt{member, construct_lagrangian(model, multiplied(member, forms.kinematic))};
        if (alt.construction.built && alt.construction.verified) return alt;
    }
    return std::nullopt;
}

}  // namespace

Analysis analyse(const model::Model& model, const Equations& equations, const SearchBudget& budget) {
    Analysis a;
    a.forms = forms(model, equations);
    a.conditions = santilli_conditions(model, a.forms.fundamental);
    a.decision = decide(model, a.conditions);
    const bool construct = model.inverse.construct;

    std::string verdict;
    switch (a.decision.verdict) {
        case Verdict::self_adjoint: verdict = "self-adjoint as given (S1–S5 hold identically)"; break;
        case Verdict::not_self_adjoint:
            verdict = fmt::format("not self-adjoint ({} = {} ≠ 0)", label(model, a.conditions[a.decision.witness]),
                                  text(a.conditions[a.decision.witness].value));
            break;
        case Verdict::undecided:
            verdict = fmt::format("undecided ({} residual{} GiNaC cannot simplify vanish at {} random points)",
                                  a.decision.unresolved.size(), a.decision.unresolved.size() == 1 ? "" : "s",
                                  a.decision.points_tried);
            break;
    }

    const FundamentalForm* target = nullptr;
    std::string how;
    if (a.decision.verdict != Verdict::not_self_adjoint) {
        target = &a.forms.fundamental;
    } else if (model.inverse.multiplier_search) {
        a.multiplier = search_multiplier(model, a.forms.kinematic, budget);
        if (a.multiplier->g) {
            a.multiplied_form = multiplied(*a.multiplier->g, a.forms.kinematic);
            a.multiplied_conditions = santilli_conditions(model, *a.multiplied_form);
            target = &*a.multiplied_form;
            how = fmt::format("; the multiplier g = {} ({}) makes g (q̈ − f) self-adjoint", matrix_text(*a.multiplier->g),
                              a.multiplier->kind);
        } else if (a.multiplier->singular_forced) {
            how = "; H1–H2 force every multiplier to be singular: no regular Lagrangian exists";
        } else if (!a.multiplier->undecided.empty()) {
            how = "; the multiplier search is undecided: " + a.multiplier->undecided +
                  " (no multiplier among the forms it reached)";
        } else {
            how = "; no multiplier of the forms tried";
        }
    } else {
        how = "; multiplier search is off ([inverse] multiplier_search = false)";
    }

    std::string built;
    if (target && construct) {
        a.construction = construct_lagrangian(model, *target);
        if (!a.construction->built) built = "; no Lagrangian built: " + a.construction->reason;
        else if (a.construction->verified) built = "; L constructed and ε(L) = E verified symbolically";
        else
            built = fmt::format("; L constructed but ε(L) = E not proven symbolically (agrees at {} of {} random points)",
                                a.construction->points_agreeing, probe_count);
        if (a.decision.verdict == Verdict::self_adjoint && model.coordinates.size() >= 2)
            a.alternative = alternative_lagrangian(model, a.forms);
        if (a.alternative)
            built += fmt::format("; another Lagrangian from the multiplier {} (verified): the Lagrangian is not unique",
                                 matrix_text(a.alternative->g));
    } else if (target) {
        built = "; construction is off ([inverse] construct = false)";
    }
    a.reason = verdict + how + built;
    return a;
}

}  // namespace eomc::mechanics::inverse
