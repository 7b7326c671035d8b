#include "symbolic/closed_form.hpp"

#include <cmath>

namespace eomc::symbolic {

using GiNaC::ex;

namespace {

constexpr std::size_t max_solutions = 64;

// The roots of one factor in its one unknown; periodic when they came through sin/cos
// (then every image q + 2πk is a root too).
struct FactorRoots {
    std::vector<Root> values;
    bool periodic = false;
};

// Roots of a·x + b = 0 or a·x² + b·x + c = 0 in x; nullopt for higher degrees.
std::optional<std::vector<ex>> polynomial_roots(const ex& p, const ex& x) {
    if (!p.is_polynomial(x)) return std::nullopt;
    const int degree = p.degree(x);
    if (degree == 1) return std::vector<ex>{(-p.coeff(x, 0) / p.coeff(x, 1)).normal()};
    if (degree == 2) {
        const ex a = p.coeff(x, 2), b = p.coeff(x, 1), c = p.coeff(x, 0);
        const ex root = GiNaC::sqrt((b * b - 4 * a * c).normal());
        return std::vector<ex>{((-b - root) / (2 * a)).normal(), ((-b + root) / (2 * a)).normal()};
    }
    return std::nullopt;
}

std::optional<FactorRoots> solve_factor(const ex& factor, const ex& q, const GiNaC::symbol& S, const GiNaC::symbol& C) {
    const bool bare = factor.has(q), has_sin = factor.has(S), has_cos = factor.has(C);
    if (bare && !has_sin && !has_cos) {
        auto roots = polynomial_roots(factor, q);
        if (!roots) return std::nullopt;
        FactorRoots out{{}, false};
        for (const ex& r : *roots) out.values.push_back({r, GiNaC::sin(r), GiNaC::cos(r)});
        return out;
    }
    if (bare) return std::nullopt;  // q both bare and inside sin/cos: transcendental
    FactorRoots out{{}, true};
    if (has_sin && !has_cos) {  // sin q = s: q = asin s, π − asin s
        auto roots = polynomial_roots(factor, S);
        if (!roots) return std::nullopt;
        for (const ex& r : *roots) {
            const ex c = GiNaC::sqrt((1 - r * r).normal());
            out.values.push_back({GiNaC::asin(r), r, c});
            out.values.push_back({GiNaC::Pi - GiNaC::asin(r), r, -c});
        }
        return out;
    }
    if (has_cos && !has_sin) {  // cos q = c: q = ±acos c
        auto roots = polynomial_roots(factor, C);
        if (!roots) return std::nullopt;
        for (const ex& r : *roots) {
            const ex s = GiNaC::sqrt((1 - r * r).normal());
            out.values.push_back({GiNaC::acos(r), s, r});
            out.values.push_back({-GiNaC::acos(r), -s, r});
        }
        return out;
    }
    // a sin q + b cos q = 0: tan q = −b/a, two roots a half-turn apart.
    if (factor.is_polynomial(GiNaC::lst{S, C}) && factor.degree(S) == 1 && factor.degree(C) == 1) {
        const ex a = factor.coeff(S, 1), b = factor.coeff(C, 1);
        if (a.has(C) || b.has(S) || !(factor - a * S - b * C).expand().is_zero()) return std::nullopt;
        const ex tangent = (-b / a).normal(), angle = GiNaC::atan(tangent);
        const ex c = 1 / GiNaC::sqrt((1 + tangent * tangent).normal());
        return FactorRoots{{{angle, tangent * c, c}, {angle - GiNaC::Pi, -tangent * c, -c}}, true};
    }
    return std::nullopt;
}

}  // namespace

TrigVariables::TrigVariables(const std::vector<GiNaC::symbol>& unknowns) {
    for (const auto& x : unknowns) {
        sin_of.emplace_back("sin_" + x.get_name());
        cos_of.emplace_back("cos_" + x.get_name());
        to_variables[GiNaC::sin(x)] = sin_of.back();
        to_variables[GiNaC::cos(x)] = cos_of.back();
        to_functions[sin_of.back()] = GiNaC::sin(x);
        to_functions[cos_of.back()] = GiNaC::cos(x);
    }
}

std::optional<double> real_value(const GiNaC::exmap& values, const ex& e) {
    ex v;
    try {
        v = e.subs(values).evalf();
    } catch (const GiNaC::pole_error&) {  // a division by zero: g/(R ω²) at ω = 0 has no value
        return std::nullopt;
    }
    if (!GiNaC::is_a<GiNaC::numeric>(v)) return std::nullopt;
    const GiNaC::numeric n = GiNaC::ex_to<GiNaC::numeric>(v);
    const double re = GiNaC::real(n).to_double(), im = GiNaC::imag(n).to_double();
    if (!std::isfinite(re) || std::abs(im) > 1e-12 * (1 + std::abs(re))) return std::nullopt;
    return re;
}

std::vector<ClosedForm> ClosedFormSolver::solve(const std::vector<ex>& f, const std::vector<bool>& free, bool& complete) {
    complete = true;
    complete_ = &complete;
    solutions_.clear();
    const std::size_t n = unknowns_.size();
    ClosedForm start{std::vector<Root>(n), std::vector<bool>(n, false), {}};
    for (std::size_t k = 0; k < n; ++k)
        if (free[k]) start = with(start, k, Root{0, 0, 1}, false);
    branch(f, std::vector<bool>(f.size(), false), start);
    return solutions_;
}

std::vector<std::size_t> ClosedFormSolver::unknowns_in(const ex& e, const GiNaC::exmap& solved) const {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < unknowns_.size(); ++k) {
        if (solved.count(unknowns_[k])) continue;
        if (e.has(unknowns_[k]) || e.has(trig_.sin_of[k]) || e.has(trig_.cos_of[k])) out.push_back(k);
    }
    return out;
}

// An equation with the solved coordinates substituted, as a polynomial where possible:
// its numerator, with sin² q = 1 − cos² q.
ex ClosedFormSolver::reduce(const ex& e, const GiNaC::exmap& solved) const {
    ex out = GiNaC::numer(e.subs(solved).normal());
    for (std::size_t k = 0; k < unknowns_.size(); ++k)
        out = out.expand().subs(GiNaC::pow(trig_.sin_of[k], 2) == 1 - GiNaC::pow(trig_.cos_of[k], 2),
                                GiNaC::subs_options::algebraic);
    return out.expand();
}

void ClosedFormSolver::branch(const std::vector<ex>& f, const std::vector<bool>& done, const ClosedForm& partial) {
    if (solutions_.size() >= max_solutions) {
        *complete_ = false;
        return;
    }
    const GiNaC::exmap& solved = partial.substitution;
    for (std::size_t i = 0; i < f.size(); ++i) {
        if (done[i]) continue;
        const ex reduced = reduce(f[i], solved);
        if (reduced.is_zero()) continue;
        std::vector<bool> next_done = done;
        next_done[i] = true;
        if (unknowns_in(reduced, solved).empty()) {
            // A condition on the parameters alone: the branch lives only where it holds.
            if (holds_at_defaults(reduced)) branch(f, next_done, partial);
            return;
        }
        // The equation holds where any of its factors vanishes: one branch per factor, each
        // solved for one of its unknowns (the others stay symbolic until solved later).
        const ex factored = GiNaC::factor(reduced);
        std::vector<ex> factors;
        if (GiNaC::is_a<GiNaC::mul>(factored))
            for (const ex& op : factored) factors.push_back(op);
        else
            factors.push_back(factored);
        for (ex factor : factors) {
            if (GiNaC::is_a<GiNaC::power>(factor) && factor.op(1).info(GiNaC::info_flags::posint)) factor = factor.op(0);
            const auto unknowns = unknowns_in(factor, solved);
            if (unknowns.empty()) continue;  // a factor of parameters: non-zero for generic values
            bool solvable = false;
            for (std::size_t k : unknowns) {
                const auto roots = solve_factor(factor, unknowns_[k], trig_.sin_of[k], trig_.cos_of[k]);
                if (!roots) continue;
                solvable = true;
                for (const Root& root : roots->values) branch(f, next_done, with(partial, k, root, roots->periodic));
                break;
            }
            if (!solvable) *complete_ = false;
        }
        return;
    }
    // Every equation holds: a solution when every coordinate is fixed, a continuum otherwise.
    if (solved.size() == 3 * unknowns_.size()) solutions_.push_back(partial);
    else *complete_ = false;
}

// `partial` with q_k = root, substituted into the values found earlier.
ClosedForm ClosedFormSolver::with(const ClosedForm& partial, std::size_t k, const Root& root, bool periodic) const {
    const GiNaC::exmap fixed{{unknowns_[k], root.q}, {trig_.sin_of[k], root.sin}, {trig_.cos_of[k], root.cos}};
    ClosedForm next = partial;
    for (auto& [key, value] : next.substitution) value = value.subs(fixed);
    next.substitution.insert(fixed.begin(), fixed.end());
    next.periodic[k] = periodic;
    for (auto& [key, value] : next.substitution) value = value.normal();
    for (std::size_t j = 0; j < next.q.size(); ++j) {
        const ex& q = unknowns_[j];
        if (next.substitution.count(q))
            next.q[j] = {next.substitution.at(q), next.substitution.at(trig_.sin_of[j]), next.substitution.at(trig_.cos_of[j])};
    }
    return next;
}

bool ClosedFormSolver::holds_at_defaults(const ex& e) const {
    const auto v = real_value(defaults_, e);
    return v && std::abs(*v) < 1e-12;
}

}  // namespace eomc::symbolic
