#include "mechanics/invariants.hpp"

#include <cmath>

#include <Eigen/LU>

#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

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
// equations are linear in u̇, so this is an identity in u̇ too). Probed at random points with
// a relative tolerance far above round-off and far below any real residual.
bool proven_conserved(const model::Model& model, const Equations& eqs, const ex& h) {
    ex power = 0;
    for (const auto& [u, E] : velocity_residuals(model, eqs)) power += u * E;
    for (const auto& point : probe_points(model, 6)) {
        const double a = evaluate_rate(h, point), b = evaluate(power, point);
        if (!std::isfinite(a) || !std::isfinite(b)) return false;
        if (std::abs(a - b) > 1e-9 * (1.0 + std::abs(a) + std::abs(b))) return false;
    }
    return true;
}

// Whether h(t, q, q̇) is constant along the solutions: at random states q̈ is solved from
// M q̈ = f numerically and dh/dt must vanish there, relative to the size of its terms
// (round-off), far below any real rate. For coordinates without quasi-velocities only.
bool proven_constant(const model::Model& model, const Equations& eqs, const ex& h) {
    const std::size_t n = model.coordinates.size();
    if (!model.quasi_velocities.empty()) return false;
    for (auto point : probe_points(model, 6, 0xc0457)) {
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
    return true;
}

}  // namespace eomc::mechanics
