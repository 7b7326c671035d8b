#include "mechanics/kinematics/operators.hpp"

#include <unordered_map>
#include <unordered_set>

#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using symbolic::derivative;

ex total_derivative(const model::Model& model, const ex& F) {
    ex d = derivative(F, model.t);
    for (const auto& c : model.coordinates) d += derivative(F, c.q) * c.q_dot + derivative(F, c.q_dot) * c.q_ddot;
    for (const auto& v : model.quasi_velocities) d += derivative(F, v.symbol) * v.rate;
    return d;
}

ex euler_operator(const model::Model& model, const ex& F, std::size_t s) {
    const auto& c = model.coordinates.at(s);
    return total_derivative(model, derivative(F, c.q_dot)) - derivative(F, c.q);
}

namespace {

// ε_s without its u̇ terms for one s, by the product rule over an expression's DAG; d/dt is
// ḟ = `along` (∂_t + Σ q̇_j ∂_{q_j}, shared by every s).
class EulerRest {
public:
    EulerRest(const model::Coordinate& c, symbolic::DirectionalDerivative& along)
        : q_(c.q), by_q_(c.q), by_q_dot_(c.q_dot), along_(along) {}

    ex operator()(const ex& e) {
        if (GiNaC::is_a<GiNaC::symbol>(e)) return e.is_equal(q_) ? ex(-1) : ex(0);  // ε_s(q_s) = −1
        if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 0;
        if (auto it = memo_.find(e); it != memo_.end()) return it->second;
        ex r = compute(e);
        memo_.emplace(e, r);
        return r;
    }
    symbolic::DirectionalDerivative& by_q_dot() { return by_q_dot_; }

private:
    ex compute(const ex& e) {
        const ex S = by_q_dot_(e);
        if (S.is_zero()) return -by_q_(e);  // free of q̇_s: ε_s(f) = −∂f/∂q_s
        if (GiNaC::is_a<GiNaC::add>(e)) {
            GiNaC::exvector terms;
            for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back((*this)(e.op(i)));
            return GiNaC::add(terms);
        }
        if (GiNaC::is_a<GiNaC::mul>(e)) {
            // ε(Π f) = Σ_j ε(f_j) Π_{k≠j} f_k + Σ_{i≠j} ḟ_i ∂f_j/∂q̇_s Π_{k≠i,j} f_k
            const std::size_t m = e.nops();
            GiNaC::exvector terms, S_j(m), D_i(m);
            for (std::size_t j = 0; j < m; ++j) S_j[j] = by_q_dot_(e.op(j));
            auto product = [&](std::size_t a, const ex& fa, std::size_t b, const ex& fb) {
                GiNaC::exvector factors;
                for (std::size_t k = 0; k < m; ++k) factors.push_back(k == a ? fa : k == b ? fb : e.op(k));
                return GiNaC::mul(factors);
            };
            bool rates_known = false;
            for (std::size_t j = 0; j < m; ++j) {
                const ex Ej = (*this)(e.op(j));
                if (!Ej.is_zero()) terms.push_back(product(j, Ej, j, Ej));
                if (S_j[j].is_zero()) continue;
                if (!rates_known) {
                    for (std::size_t i = 0; i < m; ++i) D_i[i] = along_(e.op(i));
                    rates_known = true;
                }
                for (std::size_t i = 0; i < m; ++i) {
                    if (i == j || D_i[i].is_zero()) continue;
                    // Distributed over ḟ_i's terms, so that they meet the ε(f_j) terms they cancel.
                    if (GiNaC::is_a<GiNaC::add>(D_i[i]))
                        for (std::size_t t = 0; t < D_i[i].nops(); ++t) terms.push_back(product(j, S_j[j], i, D_i[i].op(t)));
                    else
                        terms.push_back(product(j, S_j[j], i, D_i[i]));
                }
            }
            return GiNaC::add(terms);
        }
        if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1))) {
            // ε(b^k) = k b^(k−1) ε(b) + k (k−1) b^(k−2) ḃ ∂b/∂q̇_s
            const ex& b = e.op(0);
            const ex& k = e.op(1);
            return k * GiNaC::pow(b, k - 1) * (*this)(b) + k * (k - 1) * GiNaC::pow(b, k - 2) * along_(b) * by_q_dot_(b);
        }
        ex outer;
        if (GiNaC::is_a<GiNaC::function>(e) && e.nops() == 1 &&
            symbolic::outer_derivative(GiNaC::ex_to<GiNaC::function>(e).get_name(), e.op(0), outer)) {
            // ε(φ(u)) = φ'(u) ε(u) + d/dt φ'(u) ∂u/∂q̇_s
            return outer * (*this)(e.op(0)) + along_(outer) * by_q_dot_(e.op(0));
        }
        return along_(S) - by_q_(e);  // anything else: the definition
    }

    const GiNaC::symbol& q_;
    symbolic::DirectionalDerivative by_q_, by_q_dot_;
    symbolic::DirectionalDerivative& along_;
    std::unordered_map<ex, ex> memo_;
};

}  // namespace

ex EulerOperatorSplit::value(const model::Model& model, std::size_t s) const {
    ex e = rest[s];
    std::size_t k = 0;
    for (const auto& c : model.coordinates) e += rates[s][k++] * c.q_ddot;
    for (const auto& v : model.quasi_velocities) e += rates[s][k++] * v.rate;
    return e;
}

namespace {

// Distinct subexpressions of all of `es` together: what their common-subexpression elimination keeps.
std::size_t distinct_nodes(const std::vector<ex>& es) {
    std::unordered_set<ex> seen;
    std::vector<ex> stack(es.begin(), es.end());
    while (!stack.empty()) {
        const ex x = stack.back();
        stack.pop_back();
        if (!seen.insert(x).second) continue;
        for (std::size_t i = 0; i < x.nops(); ++i) stack.push_back(x.op(i));
    }
    return seen.size();
}

}  // namespace

EulerOperatorSplit euler_operator_split(const model::Model& model, const ex& F) {
    const std::size_t n = model.coordinates.size();
    EulerOperatorSplit split;
    GiNaC::exmap rate_free{{model.t, 1}};
    for (const auto& c : model.coordinates) rate_free[c.q] = c.q_dot;
    symbolic::DirectionalDerivative along(rate_free);
    for (const auto& c : model.coordinates) {
        EulerRest eps(c, along);
        split.momenta.push_back(eps.by_q_dot()(F));
        split.rest.push_back(eps(F));
    }
    // A few coordinates: the per-coordinate form too (O(n² |F|) is nothing there), and whichever
    // is smaller kept.
    if (n <= per_coordinate_limit) {
        std::vector<ex> rest;
        for (std::size_t s = 0; s < n; ++s) {
            const ex& p = split.momenta[s];
            ex r = derivative(p, model.t) - derivative(F, model.coordinates[s].q);
            for (const auto& j : model.coordinates) r += derivative(p, j.q) * j.q_dot;
            rest.push_back(r);
        }
        if (distinct_nodes(rest) < distinct_nodes(split.rest)) split.rest = std::move(rest);
    }
    std::vector<GiNaC::symbol> velocities;
    for (const auto& c : model.coordinates) velocities.push_back(c.q_dot);
    for (const auto& v : model.quasi_velocities) velocities.push_back(v.symbol);
    split.rates.assign(n, std::vector<ex>(velocities.size()));
    // One memo per velocity across all momenta; the q̇ block once, mirrored (∂²F/∂q̇_s∂q̇_k is symmetric).
    for (std::size_t k = 0; k < velocities.size(); ++k) {
        symbolic::DirectionalDerivative by_u(velocities[k]);
        for (std::size_t s = 0; s < n; ++s) {
            if (k < n && s > k) break;
            split.rates[s][k] = by_u(split.momenta[s]);
            if (k < n) split.rates[k][s] = split.rates[s][k];
        }
    }
    return split;
}

}  // namespace eomc::mechanics
