#include "mechanics/rigid/last_multiplier.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/LU>
#include <fmt/format.h>

#include "symbolic/differentiation.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;
using symbolic::derivative;

namespace {

// det of the rows `rows` and the columns `cols` of A, by expansion along the first row.
ex minor_determinant(const GiNaC::matrix& A, const std::vector<unsigned>& rows, const std::vector<unsigned>& cols) {
    if (rows.empty()) return 1;
    if (rows.size() == 1) return A(rows[0], cols[0]);
    const std::vector<unsigned> rest(rows.begin() + 1, rows.end());
    ex det = 0;
    for (std::size_t j = 0; j < cols.size(); ++j) {
        const ex a = A(rows[0], cols[j]);
        if (a.is_zero()) continue;
        std::vector<unsigned> others;
        for (std::size_t k = 0; k < cols.size(); ++k)
            if (k != j) others.push_back(cols[k]);
        det += (j % 2 == 0 ? 1 : -1) * a * minor_determinant(A, rest, others);
    }
    return det;
}

std::vector<unsigned> all_but(unsigned n, unsigned skip) {
    std::vector<unsigned> out;
    for (unsigned i = 0; i < n; ++i)
        if (i != skip) out.push_back(i);
    return out;
}

bool depends_on_coordinates(const model::Model& model, const ex& e) {
    return std::any_of(model.coordinates.begin(), model.coordinates.end(),
                       [&](const model::Coordinate& c) { return e.has(c.q); });
}

// States at the parameters' defaults, the coordinates spread over [−4, 4] (angles over more than
// a turn), for the sign tests.
std::vector<symbolic::ProbePoint> sign_points(const model::Model& model) {
    auto points = symbolic::probe_points_at_defaults(model, 48, 0x51a9);
    for (auto& p : points)
        for (const auto& c : model.coordinates) p.values[c.q] *= 4.0;
    return points;
}

// Takes both signs over the points (so, being continuous, vanishes between them).
bool changes_sign(const ex& e, const std::vector<symbolic::ProbePoint>& points) {
    bool negative = false, positive = false;
    for (const auto& p : points) {
        const double v = symbolic::evaluate(e, p);
        if (!std::isfinite(v)) continue;
        negative |= v < 0;
        positive |= v > 0;
    }
    return negative && positive;
}

struct Factoring {
    std::vector<std::pair<ex, int>> atoms;  // coordinate-dependent atom, its power common to all terms
    ex cofactor;
    int degree = 0;
};

// The powers of coordinate-dependent atoms common to every term of the expanded e.
Factoring common_atoms(const model::Model& model, const ex& e) {
    Factoring out;
    const std::vector<ex> terms = symbolic::terms_of(e);
    if (terms.empty()) return out;
    std::map<ex, int, GiNaC::ex_is_less> common;
    for (std::size_t i = 0; i < terms.size(); ++i) {
        std::map<ex, int, GiNaC::ex_is_less> powers;
        for (const ex& f : symbolic::factors_of(terms[i])) {
            ex base = f;
            int k = 1;
            if (GiNaC::is_a<GiNaC::power>(f) && f.op(1).info(GiNaC::info_flags::posint)) {
                base = f.op(0);
                k = GiNaC::ex_to<GiNaC::numeric>(f.op(1)).to_int();
            }
            const bool atom = GiNaC::is_a<GiNaC::symbol>(base) || GiNaC::is_a<GiNaC::function>(base);
            if (atom && depends_on_coordinates(model, base)) powers[base] += k;
        }
        if (i == 0) {
            common = powers;
            continue;
        }
        for (auto it = common.begin(); it != common.end();) {
            const auto found = powers.find(it->first);
            if (found == powers.end()) {
                it = common.erase(it);
            } else {
                it->second = std::min(it->second, found->second);
                ++it;
            }
        }
    }
    ex divisor = 1;
    for (const auto& [atom, k] : common) {
        out.atoms.emplace_back(atom, k);
        out.degree += k;
        divisor *= GiNaC::pow(atom, k);
    }
    out.cofactor = (e / divisor).expand();
    return out;
}

ex sin_squared_as_cos(const ex& e) { return symbolic::without_sin_squared(e, false).expand(); }

ex cos_squared_as_sin(const ex& e) {
    const ex u = GiNaC::wild(0);
    return e.subs(GiNaC::pow(GiNaC::cos(u), 2) == 1 - GiNaC::pow(GiNaC::sin(u), 2), GiNaC::subs_options::algebraic)
        .expand();
}

bool is_trigonometric(const ex& e) { return symbolic::is_function(e, "sin") || symbolic::is_function(e, "cos"); }

}  // namespace

ex expanded_determinant(const GiNaC::matrix& A) {
    std::vector<unsigned> idx;
    for (unsigned i = 0; i < A.rows(); ++i) idx.push_back(i);
    return minor_determinant(A, idx, idx).expand();
}

std::vector<SingularSet> singular_sets(const model::Model& model, const Equations& eqs) {
    std::vector<SingularSet> out;
    const unsigned n = eqs.mass_matrix.rows();
    if (!model.lagrangian_in_coordinates() || !model.quasi_velocities.empty() || n == 0 || n > 5) return out;
    bool varies = false;
    std::size_t size = 0;
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) {
            varies |= depends_on_coordinates(model, eqs.mass_matrix(i, j));
            size += symbolic::node_count(eqs.mass_matrix(i, j));
        }
    if (!varies || size > 4000) return out;
    const ex det = expanded_determinant(eqs.mass_matrix);
    if (symbolic::node_count(det) > 20000) return out;
    // The form whose common factors are largest: sin²θ appears as 1 − cos²θ after some expansions.
    Factoring best = common_atoms(model, det);
    for (const ex& form : {sin_squared_as_cos(det), cos_squared_as_sin(det)}) {
        Factoring f = common_atoms(model, form);
        if (f.degree > best.degree) best = std::move(f);
    }
    const auto points = sign_points(model);
    for (const auto& [atom, k] : best.atoms) {
        const bool vanishes = (is_trigonometric(atom) && depends_on_coordinates(model, atom.op(0))) ||
                              changes_sign(atom, points);
        if (vanishes) out.push_back({symbolic::text(atom) + " = 0", atom, k});
    }
    if (depends_on_coordinates(model, best.cofactor) && changes_sign(best.cofactor, points))
        out.push_back({symbolic::text(best.cofactor) + " = 0", best.cofactor, 1});
    return out;
}

LastMultiplier last_multiplier(const model::Model& model, const Equations& eqs) {
    LastMultiplier m;
    if (!model.lagrangian_in_coordinates() || !model.quasi_velocities.empty()) {
        m.reason = "a free carrier's quasi-velocities: the state is not (q, q̇)";
        return m;
    }
    if (!eqs.constraints.empty()) {
        m.reason = "constraint rows: the reactions λ(t, x) enter F, which is not (q̇, M⁻¹f)";
        return m;
    }
    if (!eqs.unilateral.empty()) {
        m.reason = "unilateral rows: impacts make the flow discontinuous, and contact reactions λ(t, x) enter F";
        return m;
    }
    const unsigned n = eqs.mass_matrix.rows();
    // A diagonal M (particles in Cartesian coordinates) has det M = Π M_ss and adj(M) diagonal at
    // any size; a full one is expanded only up to 5 × 5.
    bool diagonal = true;
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) diagonal = diagonal && (i == j || eqs.mass_matrix(i, j).is_zero());
    if (n == 0 || (n > 5 && !diagonal)) {
        m.reason = "more than 5 coordinates and M not diagonal: det M not expanded";
        return m;
    }
    const auto product_of_diagonal_but = [&](unsigned skip) {
        ex product = 1;
        for (unsigned j = 0; j < n; ++j)
            if (j != skip) product *= eqs.mass_matrix(j, j);
        return product;
    };
    m.mu = diagonal ? product_of_diagonal_but(n) : expanded_determinant(eqs.mass_matrix);
    // Each summand of ∂μ/∂t + Σ q̇_s ∂μ/∂q_s + Σ_s ∂(adj(M) f)_s/∂q̇_s.
    std::vector<ex> summands{derivative(m.mu, model.t)};
    for (unsigned s = 0; s < n; ++s) {
        const auto& c = model.coordinates[s];
        summands.push_back(c.q_dot * derivative(m.mu, c.q));
        ex g = 0;  // (μ M⁻¹ f)_s = Σ_k adj(M)_sk f_k, adj(M)_sk = (−1)^{s+k} det M without row k, column s
        for (unsigned k = 0; k < n; ++k) {
            if (eqs.forcing[k].is_zero() || (diagonal && k != s)) continue;
            const ex cofactor = diagonal ? product_of_diagonal_but(s)
                                         : minor_determinant(eqs.mass_matrix, all_but(n, k), all_but(n, s));
            g += ((s + k) % 2 == 0 ? 1 : -1) * cofactor * eqs.forcing[k];
        }
        summands.push_back(derivative(g, c.q_dot));
    }
    m.divergence = 0;
    for (const auto& t : summands) m.divergence += t;
    // The fast reject: a residual far above round-off at a sampled state.
    const auto points = symbolic::probe_points_at_defaults(model, 6, 0x1a57);
    for (const auto& p : points) {
        double sum = 0, scale = 0;
        for (const auto& t : summands) {
            const double v = symbolic::evaluate(t, p);
            sum += v;
            scale += std::abs(v);
        }
        if (!std::isfinite(sum)) continue;
        if (std::abs(sum) > 1e-8 * (scale + 1e-300)) {
            m.status = MultiplierStatus::not_multiplier;
            m.reason = "∂μ/∂t + div(μF) = " + symbolic::text(symbolic::simplified(m.divergence)) +
                       " ≠ 0 (nonzero at a sampled state, e.g. " + fmt::format("{:.3g}", sum) + "): forces outside L (Q ≠ 0) "
                       "change phase-space volume";
            return m;
        }
    }
    if (symbolic::simplified(m.divergence).is_zero()) {
        m.status = MultiplierStatus::proven;
        m.reason = "∂μ/∂t + div(μF) simplifies to 0";
    } else {
        m.status = MultiplierStatus::undecided;
        m.reason = "∂μ/∂t + div(μF) vanishes at every sampled state but was not simplified to 0";
    }
    return m;
}

JacobiCount jacobi_count(const model::Model& model, const Equations& eqs, const LastMultiplier& multiplier,
                         std::size_t proven_cyclic) {
    JacobiCount j;
    const std::size_t n = model.coordinates.size();
    j.equations = 2 * n;
    for (const auto& f : eqs.forcing) j.autonomous &= !f.has(model.t);
    for (unsigned a = 0; a < eqs.mass_matrix.rows(); ++a)
        for (unsigned b = 0; b < eqs.mass_matrix.cols(); ++b) j.autonomous &= !eqs.mass_matrix(a, b).has(model.t);
    j.multiplier = multiplier.status == MultiplierStatus::proven;
    // Independent integrals, by the rank of their gradients in (q, q̇) at sampled states.
    const auto points = symbolic::probe_points_at_defaults(model, 3, 0x1d3b);
    std::vector<std::vector<ex>> kept_gradients;
    auto rank = [&](const std::vector<std::vector<ex>>& gradients) {
        Eigen::Index best = 0;
        for (const auto& p : points) {
            Eigen::MatrixXd G(Eigen::Index(gradients.size()), Eigen::Index(2 * n));
            for (std::size_t i = 0; i < gradients.size(); ++i)
                for (std::size_t k = 0; k < 2 * n; ++k) G(Eigen::Index(i), Eigen::Index(k)) = symbolic::evaluate(gradients[i][k], p);
            if (!G.allFinite()) continue;
            Eigen::FullPivLU<Eigen::MatrixXd> lu(G);
            lu.setThreshold(1e-9);
            best = std::max(best, lu.rank());
        }
        return std::size_t(best);
    };
    std::size_t cyclic_used = 0;
    for (const auto& inv : eqs.invariants) {
        if (j.autonomous && inv.value.has(model.t)) continue;
        std::vector<ex> gradient;
        for (const auto& c : model.coordinates) gradient.push_back(derivative(inv.value, c.q));
        for (const auto& c : model.coordinates) gradient.push_back(derivative(inv.value, c.q_dot));
        auto candidate = kept_gradients;
        candidate.push_back(gradient);
        if (rank(candidate) <= kept_gradients.size()) continue;
        kept_gradients = std::move(candidate);
        j.integrals.push_back(inv.name);
        if (inv.name.rfind("momentum_", 0) == 0) ++cyclic_used;
    }
    j.cyclic = std::min(cyclic_used, proven_cyclic);
    const std::size_t lost = j.autonomous ? 2 : 1;
    j.needed = j.equations >= lost ? j.equations - lost : 0;
    j.missing = j.integrals.size() >= j.needed ? 0 : j.needed - j.integrals.size();
    j.reduced_equations = 2 * (n - j.cyclic);
    j.reduced_needed = j.reduced_equations >= lost ? j.reduced_equations - lost : 0;
    const std::size_t others = j.integrals.size() - j.cyclic;
    j.reduced_missing = others >= j.reduced_needed ? 0 : j.reduced_needed - others;
    j.integrable = j.multiplier && (j.missing == 0 || j.reduced_missing == 0);
    return j;
}

}  // namespace eomc::mechanics::rigid
