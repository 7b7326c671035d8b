#include "symbolic/numeric_probe.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "model/kepler_function.hpp"

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
    const PreciseDigits digits;
    const GiNaC::ex v = e.subs(values, GiNaC::subs_options::no_pattern).evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return std::nullopt;
    return GiNaC::ex_to<GiNaC::numeric>(v);
}

double evaluate(const GiNaC::ex& e, const ProbePoint& at) { return Evaluator(at)(e).v; }

double evaluate_rate(const GiNaC::ex& e, const ProbePoint& at) { return Evaluator(at)(e).d; }

}  // namespace eomc::symbolic
