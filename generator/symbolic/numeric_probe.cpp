#include "symbolic/numeric_probe.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "model/kepler_function.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::symbolic {

using namespace eomc::symbolic;

namespace {

std::vector<ProbePoint> make_points(const model::Model& model, std::size_t count, std::uint64_t seed,
                                    bool perturb_parameters) {
    std::mt19937_64 rng(seed);
    // Drawn by hand from the raw generator: std::uniform_real_distribution's output is not
    // specified bit-for-bit across standard libraries.
    auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 11) * 0x1.0p-53; };
    std::vector<ProbePoint> points(count);
    for (auto& point : points) {
        auto& v = point.values;
        v[model.t] = uniform(-1, 1);
        point.rates[model.t] = 1;
        for (const auto& c : model.coordinates) {
            v[c.q] = uniform(-1, 1);
            v[c.q_dot] = uniform(-1, 1);
            v[c.q_ddot] = uniform(-1, 1);
        }
        for (const auto& c : model.coordinates) {
            point.rates[c.q] = v[c.q_dot];
            point.rates[c.q_dot] = v[c.q_ddot];
        }
        for (const auto& p : model.parameters) {
            if (!perturb_parameters) v[p.symbol] = p.value;
            else if (p.value == 0.0) v[p.symbol] = uniform(0.3, 1.3);
            else v[p.symbol] = p.value * uniform(0.8, 1.25);
        }
        for (const auto& q : model.quasi_velocities) {
            v[q.symbol] = uniform(-1, 1);
            v[q.rate] = uniform(-1, 1);
            point.rates[q.symbol] = v[q.rate];
        }
    }
    return points;
}

// A dual number a + b·ε with ε² = 0: value and time derivative together.
struct Dual {
    double v = 0, d = 0;
};
Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }

Dual apply_function(const std::string& f, Dual x) {
    const double v = x.v;
    if (f == "sin") return {std::sin(v), std::cos(v) * x.d};
    if (f == "cos") return {std::cos(v), -std::sin(v) * x.d};
    if (f == "tan") return {std::tan(v), x.d / (std::cos(v) * std::cos(v))};
    if (f == "exp") return {std::exp(v), std::exp(v) * x.d};
    if (f == "log") return {std::log(v), x.d / v};
    if (f == "asin") return {std::asin(v), x.d / std::sqrt(1 - v * v)};
    if (f == "acos") return {std::acos(v), -x.d / std::sqrt(1 - v * v)};
    if (f == "atan") return {std::atan(v), x.d / (1 + v * v)};
    if (f == "sinh") return {std::sinh(v), std::cosh(v) * x.d};
    if (f == "cosh") return {std::cosh(v), std::sinh(v) * x.d};
    if (f == "tanh") return {std::tanh(v), x.d / (std::cosh(v) * std::cosh(v))};
    return {std::numeric_limits<double>::quiet_NaN(), 0};
}

class Evaluator {
public:
    explicit Evaluator(const ProbePoint& at) : at_(at) {}

    Dual operator()(const GiNaC::ex& e) {
        if (auto it = memo_.find(e); it != memo_.end()) return it->second;
        const Dual value = compute(e);
        memo_.emplace(e, value);
        return value;
    }

private:
    Dual compute(const GiNaC::ex& e) {
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        if (GiNaC::is_a<GiNaC::numeric>(e)) {
            const auto& x = GiNaC::ex_to<GiNaC::numeric>(e);
            return {x.is_real() ? x.to_double() : nan, 0};
        }
        if (GiNaC::is_a<GiNaC::constant>(e)) {
            const GiNaC::ex v = e.evalf();
            return {GiNaC::is_a<GiNaC::numeric>(v) ? GiNaC::ex_to<GiNaC::numeric>(v).to_double() : nan, 0};
        }
        if (GiNaC::is_a<GiNaC::symbol>(e)) {
            auto v = at_.values.find(e);
            if (v == at_.values.end()) return {nan, 0};
            auto r = at_.rates.find(e);
            return {v->second, r == at_.rates.end() ? 0.0 : r->second};
        }
        if (GiNaC::is_a<GiNaC::add>(e)) {
            Dual sum;
            for (std::size_t i = 0; i < e.nops(); ++i) sum = sum + (*this)(e.op(i));
            return sum;
        }
        if (GiNaC::is_a<GiNaC::mul>(e)) {
            Dual product{1, 0};
            for (std::size_t i = 0; i < e.nops(); ++i) product = product * (*this)(e.op(i));
            return product;
        }
        if (GiNaC::is_a<GiNaC::power>(e)) {
            const Dual b = (*this)(e.op(0)), k = (*this)(e.op(1));
            const double value = std::pow(b.v, k.v);
            // d(b^k) = k b^(k−1) db + b^k log(b) dk (the second term only when k varies)
            double d = k.v * std::pow(b.v, k.v - 1) * b.d;
            if (k.d != 0) d += value * std::log(b.v) * k.d;
            return {value, d};
        }
        if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1)
            return apply_function(GiNaC::ex_to<GiNaC::function>(e).get_name(), (*this)(e.op(0)));
        if (GiNaC::is_a<GiNaC::function>(e) && GiNaC::ex_to<GiNaC::function>(e).get_name() == model::kepler_E_name) {
            const Dual M = (*this)(e.op(0)), ecc = (*this)(e.op(1));
            if (!(ecc.v >= 0 && ecc.v < 1 && std::isfinite(M.v))) return {nan, 0};
            const double E = model::kepler_E_value(M.v, ecc.v);
            return {E, (M.d + std::sin(E) * ecc.d) / (1 - ecc.v * std::cos(E))};
        }
        return {nan, 0};
    }

    const ProbePoint& at_;
    // Keyed by structure, never by address: GiNaC re-points equal subtrees at one another
    // when it compares them, so an address can be freed and reused while a memo holds it.
    std::unordered_map<GiNaC::ex, Dual> memo_;
};

}  // namespace

std::vector<ProbePoint> probe_points(const model::Model& model, std::size_t count, std::uint64_t seed) {
    return make_points(model, count, seed, true);
}

std::vector<ProbePoint> probe_points_at_defaults(const model::Model& model, std::size_t count, std::uint64_t seed) {
    return make_points(model, count, seed, false);
}

namespace {

// GiNaC's working precision (a global) raised for one evaluation and restored after.
class PreciseDigits {
public:
    PreciseDigits() : saved_(GiNaC::Digits) { GiNaC::Digits = precise_digits; }
    ~PreciseDigits() { GiNaC::Digits = saved_; }
    PreciseDigits(const PreciseDigits&) = delete;
    PreciseDigits& operator=(const PreciseDigits&) = delete;

private:
    long saved_;
};

// x = m · 2^k with m a 53-bit integer: the double's value as an exact rational.
GiNaC::numeric exact(double x) {
    int k = 0;
    const double m = std::frexp(x, &k);
    return GiNaC::numeric(static_cast<long>(std::ldexp(m, 53))) * GiNaC::numeric(2).power(k - 53);
}

}  // namespace

GiNaC::exmap precise_values(const std::map<GiNaC::ex, double, GiNaC::ex_is_less>& values) {
    const PreciseDigits digits;
    GiNaC::exmap out;
    for (const auto& [symbol, value] : values) out[symbol] = GiNaC::ex_to<GiNaC::numeric>(exact(value).evalf());
    return out;
}

std::optional<GiNaC::numeric> evaluate_precise(const GiNaC::ex& e, const GiNaC::exmap& values) {
    return PreciseEvaluator(values).value(e);
}

namespace {

bool has_operands(const GiNaC::ex& e) {
    return GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::power>(e) ||
           GiNaC::is_a<GiNaC::function>(e);
}

// A numeric result of evalf, or nothing (a symbol without a value, a function evalf leaves alone).
bool as_number(const GiNaC::ex& v, GiNaC::numeric& out) {
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return false;
    out = GiNaC::ex_to<GiNaC::numeric>(v);
    return true;
}

}  // namespace

std::size_t PreciseEvaluator::visit(const GiNaC::ex& e) {
    if (auto it = index_.find(e); it != index_.end()) return it->second;
    std::vector<std::size_t> children;
    if (has_operands(e))
        for (std::size_t i = 0; i < e.nops(); ++i) children.push_back(visit(e.op(i)));
    bool ok = true;
    GiNaC::numeric value = compute(e, children, ok);
    nodes_.push_back({e, std::move(children), std::move(value), ok});
    index_.emplace(e, nodes_.size() - 1);
    return nodes_.size() - 1;
}

// The node's value from its operands' values, as subs + evalf would form it (the same GiNaC
// evaluation of powers and functions, at the same digits).
GiNaC::numeric PreciseEvaluator::compute(const GiNaC::ex& e, const std::vector<std::size_t>& children, bool& ok) {
    for (const std::size_t c : children)
        if (!nodes_[c].real_number) {
            ok = false;
            return 0;
        }
    GiNaC::numeric out;
    try {
        if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e);
        if (GiNaC::is_a<GiNaC::symbol>(e)) {
            const auto v = values_.find(e);
            ok = v != values_.end() && as_number(v->second, out);
            return out;
        }
        if (GiNaC::is_a<GiNaC::add>(e)) {
            out = 0;
            for (const std::size_t c : children) out += nodes_[c].value;
            return out;
        }
        if (GiNaC::is_a<GiNaC::mul>(e)) {
            out = 1;
            for (const std::size_t c : children) out *= nodes_[c].value;
            return out;
        }
        if (GiNaC::is_a<GiNaC::power>(e)) {
            ok = as_number(GiNaC::pow(nodes_[children[0]].value, nodes_[children[1]].value).evalf(), out);
            return out;
        }
        if (GiNaC::is_a<GiNaC::function>(e)) {
            GiNaC::exvector args;
            for (const std::size_t c : children) args.push_back(nodes_[c].value);
            ok = as_number(GiNaC::function(GiNaC::ex_to<GiNaC::function>(e).get_serial(), args).evalf(), out);
            return out;
        }
        // Constants (π) and anything else: GiNaC's own evaluation of the node.
        ok = as_number(e.subs(values_, GiNaC::subs_options::no_pattern).evalf(), out);
    } catch (const std::exception&) {
        ok = false;  // a pole (1/0, log 0) at this point
    }
    return out;
}

std::optional<GiNaC::numeric> PreciseEvaluator::value(const GiNaC::ex& e) {
    const PreciseDigits digits;
    const Node& node = nodes_[visit(e)];
    if (!node.real_number || !node.value.is_real()) return std::nullopt;
    return node.value;
}

// ∂node/∂operand_i for each operand, at the point; false for a node whose partials are not known.
bool PreciseEvaluator::local_partials(const Node& node, std::vector<GiNaC::numeric>& out) {
    const std::size_t m = node.children.size();
    out.assign(m, 0);
    auto value = [&](std::size_t i) -> const GiNaC::numeric& { return nodes_[node.children[i]].value; };
    if (GiNaC::is_a<GiNaC::add>(node.e)) {
        out.assign(m, 1);
        return true;
    }
    if (GiNaC::is_a<GiNaC::mul>(node.e)) {
        // Π_{j≠i} f_j from prefix and suffix products: no division, so a zero factor is no pole.
        GiNaC::numeric prefix = 1;
        for (std::size_t i = 0; i < m; ++i) {
            out[i] = prefix;
            prefix *= value(i);
        }
        GiNaC::numeric suffix = 1;
        for (std::size_t i = m; i-- > 0;) {
            out[i] *= suffix;
            suffix *= value(i);
        }
        return true;
    }
    if (GiNaC::is_a<GiNaC::power>(node.e)) {
        const GiNaC::numeric& b = value(0);
        const GiNaC::numeric& k = value(1);
        // d(b^k) = k b^(k−1) db + b^k log(b) dk, the second only when the exponent is not a number.
        if (!as_number((k * GiNaC::pow(b, k - 1)).evalf(), out[0])) return false;
        if (!GiNaC::is_a<GiNaC::numeric>(node.e.op(1)) && !as_number((node.value * GiNaC::log(b)).evalf(), out[1]))
            return false;
        return true;
    }
    if (GiNaC::is_a<GiNaC::function>(node.e)) {
        const std::string name = GiNaC::ex_to<GiNaC::function>(node.e).get_name();
        GiNaC::ex outer;
        if (m == 1 && outer_derivative(name, value(0), outer)) return as_number(outer.evalf(), out[0]);
        if (name == model::kepler_E_name)
            return as_number(model::kepler_E_partial_M(node.value, value(1)).evalf(), out[0]) &&
                   as_number(model::kepler_E_partial_e(node.value, value(1)).evalf(), out[1]);
    }
    return false;
}

std::optional<std::vector<GiNaC::numeric>> PreciseEvaluator::gradient(const GiNaC::ex& e,
                                                                      const std::vector<GiNaC::ex>& variables) {
    const PreciseDigits digits;
    const std::size_t root = visit(e);
    if (!nodes_[root].real_number || !nodes_[root].value.is_real()) return std::nullopt;
    // The nodes e depends on, parents before children (every child has a smaller index).
    std::vector<char> reached(nodes_.size(), 0);
    std::vector<std::size_t> order{root}, stack{root};
    reached[root] = 1;
    while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        for (const std::size_t c : nodes_[i].children)
            if (!reached[c]) {
                reached[c] = 1;
                order.push_back(c);
                stack.push_back(c);
            }
    }
    std::sort(order.begin(), order.end(), std::greater<>());
    std::vector<GiNaC::numeric> adjoint(nodes_.size());
    adjoint[root] = 1;
    std::vector<GiNaC::numeric> partials;
    try {
        for (const std::size_t i : order) {
            const Node& node = nodes_[i];
            if (node.children.empty() || adjoint[i].is_zero()) continue;
            if (!local_partials(node, partials)) return std::nullopt;
            for (std::size_t k = 0; k < node.children.size(); ++k)
                adjoint[node.children[k]] += adjoint[i] * partials[k];
        }
    } catch (const std::exception&) {
        return std::nullopt;  // a partial with a pole at this point
    }
    std::vector<GiNaC::numeric> out;
    for (const auto& x : variables) {
        const auto it = index_.find(x);
        out.push_back(it != index_.end() && it->second < reached.size() && reached[it->second] ? adjoint[it->second]
                                                                                               : GiNaC::numeric(0));
    }
    return out;
}

double evaluate(const GiNaC::ex& e, const ProbePoint& at) { return Evaluator(at)(e).v; }

double evaluate_rate(const GiNaC::ex& e, const ProbePoint& at) { return Evaluator(at)(e).d; }

}  // namespace eomc::symbolic
