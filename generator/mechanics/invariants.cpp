#include "mechanics/invariants.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include <Eigen/LU>

#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

// Σ terms vanishes at the point to the precise evaluation's rounding, relative to Σ |terms|.
// 1e-35 lies a trillion times above that rounding (10^-47 per operation) and ten orders of
// magnitude below the smallest real residual the chapters produce (a third body's tidal terms,
// 1e-25 of the Kepler terms at the probe points).
bool vanishes(const std::vector<GiNaC::numeric>& terms) {
    GiNaC::numeric sum = 0, scale = 0;
    for (const auto& term : terms) {
        sum += term;
        scale += GiNaC::abs(term);
    }
    return GiNaC::abs(sum) <= GiNaC::numeric(1, 10).power(35) * scale;
}

// The terms ∂h/∂x · ẋ of dh/dt at the evaluator's point, over the symbols with a rate: the
// partials from one reverse sweep over h, or symbolically where h holds a node the sweep cannot
// differentiate; nullopt where a term does not evaluate to a real number.
std::optional<std::vector<GiNaC::numeric>> rate_terms(PreciseEvaluator& at, const ex& h, const GiNaC::exmap& rates) {
    std::vector<ex> variables;
    std::vector<GiNaC::numeric> rate;
    for (const auto& [x, r] : rates) {
        variables.push_back(x);
        rate.push_back(GiNaC::ex_to<GiNaC::numeric>(r));
    }
    std::vector<GiNaC::numeric> terms;
    if (const auto partials = at.gradient(h, variables)) {
        for (std::size_t i = 0; i < variables.size(); ++i)
            if (!(*partials)[i].is_zero()) terms.push_back((*partials)[i] * rate[i]);
        return terms;
    }
    for (std::size_t i = 0; i < variables.size(); ++i) {
        const ex dh = derivative(h, GiNaC::ex_to<GiNaC::symbol>(variables[i]));
        if (dh.is_zero()) continue;
        const auto v = at.value(dh);
        if (!v) return std::nullopt;
        terms.push_back(*v * rate[i]);
    }
    return terms;
}

// M x = f by Gaussian elimination with partial pivoting in the numbers' own precision; nullopt
// when M is singular. Not GiNaC's matrix::solve: its normal() makes temporary symbols, and every
// new symbol shifts the hash order, hence the printed order, of everything derived after it.
std::optional<std::vector<GiNaC::numeric>> solve_precise(std::vector<std::vector<GiNaC::numeric>> M,
                                                         std::vector<GiNaC::numeric> f) {
    const std::size_t n = f.size();
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t pivot = k;
        for (std::size_t i = k + 1; i < n; ++i)
            if (GiNaC::abs(M[i][k]) > GiNaC::abs(M[pivot][k])) pivot = i;
        if (M[pivot][k].is_zero()) return std::nullopt;
        std::swap(M[k], M[pivot]);
        std::swap(f[k], f[pivot]);
        for (std::size_t i = k + 1; i < n; ++i) {
            const GiNaC::numeric factor = M[i][k] / M[k][k];
            for (std::size_t j = k; j < n; ++j) M[i][j] -= factor * M[k][j];
            f[i] -= factor * f[k];
        }
    }
    std::vector<GiNaC::numeric> x(n);
    for (std::size_t k = n; k-- > 0;) {
        GiNaC::numeric sum = f[k];
        for (std::size_t j = k + 1; j < n; ++j) sum -= M[k][j] * x[j];
        x[k] = sum / M[k][k];
    }
    return x;
}

}  // namespace

std::vector<std::pair<ex, ex>> velocity_residuals(const model::Model& model, const Equations& eqs) {
    std::vector<std::pair<ex, ex>> out;
    for (std::size_t s = 0; s < eqs.equations.size(); ++s)
        out.emplace_back(model.coordinates[s].q_dot, eqs.equations[s].lhs - eqs.equations[s].rhs);
    for (const auto& v : model.quasi_velocities)
        for (const auto& c : eqs.carrier_equations)
            if (c.quasi_velocity == v.name) out.emplace_back(v.symbol, c.lhs - c.applied);
    return out;
}

// dh/dt − Σ u_s E_s vanishes identically iff h is conserved along every motion (the
// equations are linear in u̇, so this is an identity in u̇ too). Probed at random points: in
// double first, where a residual far above round-off refutes h at once, then at the same
// points in high precision, where a residual far below double's reach (a perturbation 1e-13 of
// the Kepler terms that does work) still shows.
bool proven_conserved(const model::Model& model, const Equations& eqs, const ex& h) {
    ex power = 0;
    const auto residuals = velocity_residuals(model, eqs);
    for (const auto& [u, E] : residuals) power += u * E;
    const auto points = probe_points(model, 6);
    for (const auto& point : points) {
        const double a = evaluate_rate(h, point), b = evaluate(power, point);
        if (!std::isfinite(a) || !std::isfinite(b)) return false;
        if (std::abs(a - b) > 1e-9 * (1.0 + std::abs(a) + std::abs(b))) return false;
    }
    for (const auto& point : points) {
        PreciseEvaluator at(precise_values(point.values));
        auto terms = rate_terms(at, h, precise_values(point.rates));
        if (!terms) return false;
        for (const auto& [u, E] : residuals) {
            const auto u_value = at.value(u), E_value = at.value(E);
            if (!u_value || !E_value) return false;
            terms->push_back(-*u_value * *E_value);
        }
        if (!vanishes(*terms)) return false;
    }
    return true;
}

// Whether h(t, q, q̇) is constant along the solutions: at random states q̈ is solved from
// M q̈ = f and dh/dt must vanish there, relative to the size of its terms; in double first (a
// rate far above round-off refutes h), then in high precision (a torque 1e-23 of the terms that
// cancel beside it still shows). For coordinates without quasi-velocities only.
bool proven_constant(const model::Model& model, const Equations& eqs, const ex& h) {
    const std::size_t n = model.coordinates.size();
    if (!model.quasi_velocities.empty()) return false;
    const auto points = probe_points(model, 6, 0xc0457);
    for (auto point : points) {
        Eigen::MatrixXd M(n, n);
        Eigen::VectorXd f(n);
        for (std::size_t i = 0; i < n; ++i) {
            f(Eigen::Index(i)) = evaluate(eqs.forcing[i], point);
            for (std::size_t j = 0; j < n; ++j) M(Eigen::Index(i), Eigen::Index(j)) = evaluate(eqs.mass_matrix(unsigned(i), unsigned(j)), point);
        }
        const Eigen::VectorXd a = M.fullPivLu().solve(f);
        double scale = 0;
        for (std::size_t s = 0; s < n; ++s) {
            const auto& c = model.coordinates[s];
            point.values[c.q_ddot] = a(Eigen::Index(s));
            point.rates[c.q_dot] = a(Eigen::Index(s));
            scale += std::abs(evaluate(derivative(h, c.q), point) * point.values[c.q_dot]) +
                     std::abs(evaluate(derivative(h, c.q_dot), point) * a(Eigen::Index(s)));
        }
        scale += std::abs(evaluate(derivative(h, model.t), point));
        const double rate = evaluate_rate(h, point);
        if (!std::isfinite(rate) || !std::isfinite(scale) || std::abs(rate) > 1e-9 * (1.0 + scale)) return false;
    }
    for (const auto& point : points) {
        GiNaC::exmap values = precise_values(point.values);
        PreciseEvaluator at_state(values);
        std::vector<std::vector<GiNaC::numeric>> M(n, std::vector<GiNaC::numeric>(n));
        std::vector<GiNaC::numeric> f(n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto fi = at_state.value(eqs.forcing[i]);
            if (!fi) return false;
            f[i] = *fi;
            for (std::size_t j = 0; j < n; ++j) {
                const auto m = at_state.value(eqs.mass_matrix(unsigned(i), unsigned(j)));
                if (!m) return false;
                M[i][j] = *m;
            }
        }
        const auto q_ddot = solve_precise(std::move(M), std::move(f));
        if (!q_ddot) return false;  // M singular here
        GiNaC::exmap rates;
        rates[model.t] = 1;
        for (unsigned s = 0; s < n; ++s) {
            const auto& c = model.coordinates[s];
            values[c.q_ddot] = (*q_ddot)[s];
            rates[c.q] = values[c.q_dot];
            rates[c.q_dot] = (*q_ddot)[s];
        }
        PreciseEvaluator at(values);  // with q̈
        const auto terms = rate_terms(at, h, rates);
        if (!terms || !vanishes(*terms)) return false;
    }
    return true;
}

}  // namespace eomc::mechanics
