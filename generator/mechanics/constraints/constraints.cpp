#include "mechanics/constraints/constraints.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mechanics/kinematics/operators.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using symbolic::derivative;

namespace {

// The velocities u of M's rows and their rates: the coordinates' q̇ (q̈), then a free carrier's
// quasi-velocities (their rates).
struct Velocities {
    std::vector<GiNaC::symbol> u, rate;
};

Velocities velocities(const model::Model& model) {
    Velocities v;
    for (const auto& c : model.coordinates) {
        v.u.push_back(c.q_dot);
        v.rate.push_back(c.q_ddot);
    }
    for (const auto& q : model.quasi_velocities) {
        v.u.push_back(q.symbol);
        v.rate.push_back(q.rate);
    }
    return v;
}

Stabilization stabilization_of(model::ConstraintStabilization s) {
    switch (s) {
        case model::ConstraintStabilization::project: return Stabilization::project;
        case model::ConstraintStabilization::baumgarte: return Stabilization::baumgarte;
        case model::ConstraintStabilization::none: return Stabilization::none;
    }
    return Stabilization::project;
}

// The generic rank of the rows `which` of W: the largest numeric rank over the probe points
// (a rank that drops only at special points is not a dependence of the rows).
std::size_t generic_rank(const std::vector<Eigen::MatrixXd>& at_points,
                         const std::vector<std::size_t>& which) {
    std::size_t best = 0;
    for (const Eigen::MatrixXd& W : at_points) {
        if (which.empty()) return 0;
        Eigen::MatrixXd rows(static_cast<Eigen::Index>(which.size()), W.cols());
        for (std::size_t i = 0; i < which.size(); ++i) rows.row(Eigen::Index(i)) = W.row(Eigen::Index(which[i]));
        Eigen::FullPivLU<Eigen::MatrixXd> lu(rows);
        lu.setThreshold(1e-9);
        best = std::max(best, static_cast<std::size_t>(lu.rank()));
    }
    return best;
}

// Refuses dependent rows: the reactions of such rows are not determined (G = W M⁻¹ Wᵀ singular).
void check_independent(const model::Model& model, const std::vector<ConstraintRow>& rows) {
    const auto points = symbolic::probe_points(model, 4, 0xc0457a1);
    std::vector<Eigen::MatrixXd> at_points;
    for (const auto& point : points) {
        Eigen::MatrixXd W(Eigen::Index(rows.size()), Eigen::Index(rows.front().W.size()));
        for (std::size_t a = 0; a < rows.size(); ++a)
            for (std::size_t k = 0; k < rows[a].W.size(); ++k) {
                const double value = symbolic::evaluate(rows[a].W[k], point);
                W(Eigen::Index(a), Eigen::Index(k)) = std::isfinite(value) ? value : 0.0;
            }
        // Scale each row to unit size so that the threshold is relative.
        for (Eigen::Index a = 0; a < W.rows(); ++a)
            if (const double n = W.row(a).norm(); n > 0) W.row(a) /= n;
        at_points.push_back(std::move(W));
    }
    std::vector<std::size_t> independent;
    for (std::size_t k = 0; k < rows.size(); ++k) {
        std::vector<std::size_t> with = independent;
        with.push_back(k);
        if (generic_rank(at_points, with) > independent.size()) {
            independent.push_back(k);
            continue;
        }
        if (independent.empty() || generic_rank(at_points, {k}) == 0)
            throw InputError(rows[k].pos, fmt::format("the constraint '{}' is degenerate: its row W of the reactions "
                                                      "vanishes identically, so it constrains no velocity",
                                                      rows[k].name));
        // The rows involved: those without which row k would no longer depend on the others.
        std::vector<std::size_t> involved;
        for (std::size_t j : independent) {
            std::vector<std::size_t> rest;
            for (std::size_t i : independent)
                if (i != j) rest.push_back(i);
            std::vector<std::size_t> rest_with = rest;
            rest_with.push_back(k);
            if (generic_rank(at_points, rest_with) > rest.size()) involved.push_back(j);
        }
        involved.push_back(k);
        std::string names;
        for (std::size_t i = 0; i < involved.size(); ++i) {
            if (i > 0) names += i + 1 == involved.size() ? " and " : ", ";
            names += "'" + rows[involved[i]].name + "'";
        }
        throw InputError(rows[involved.front()].pos,
                         fmt::format("the constraints {} are dependent: their rows W of the reactions are linearly "
                                     "dependent at every probe point, so the reactions are not determined; drop one",
                                     names));
    }
}

}  // namespace

ConstraintRow constraint_row(const model::Model& model, const std::string& name, bool holonomic, const ex& expression,
                             const SourcePos& pos) {
    const Velocities v = velocities(model);
    GiNaC::exmap no_rates;
    for (const auto& r : v.rate) no_rates[r] = 0;
    ConstraintRow row;
    row.name = name;
    row.holonomic = holonomic;
    row.pos = pos;
    row.lambda = GiNaC::symbol("lambda_" + name, "\\lambda_{" + name + "}");
    if (holonomic) {
        // φ = ḟ = ∂_t f + Σ ∂f/∂q_s q̇_s (f holds no rate, so no q̈ appears); W_s = ∂f/∂q_s.
        row.position = expression;
        row.velocity = total_derivative(model, expression).subs(no_rates);
        for (const auto& c : model.coordinates) row.W.push_back(derivative(expression, c.q));
        for (std::size_t k = model.coordinates.size(); k < v.u.size(); ++k) row.W.push_back(0);
    } else {
        // φ = Σ B_k u_k + b, linear in u (checked by the model): W_k = ∂φ/∂u_k = B_k.
        row.position = 0;
        row.velocity = expression;
        for (const auto& u : v.u) row.W.push_back(derivative(expression, u));
    }
    // bias = φ̇ − W u̇: the total derivative along the motion with the accelerations set to zero
    // (φ is linear in u, so φ̇ is affine in u̇ with the coefficients W).
    row.bias = total_derivative(model, row.velocity).subs(no_rates).expand();
    return row;
}

std::vector<ConstraintRow> constraint_rows(const model::Model& model) {
    std::vector<ConstraintRow> rows;
    if (model.constraints.empty()) return rows;
    for (const auto& given : model.constraints) {
        ConstraintRow row = constraint_row(model, given.name, given.holonomic, given.expression, given.pos);
        row.stabilization = stabilization_of(given.stabilization);
        row.alpha = given.alpha;
        row.beta = given.beta;
        rows.push_back(std::move(row));
    }
    check_independent(model, rows);
    return rows;
}

bool reactions_do_no_work(const model::Model& model, const std::vector<ConstraintRow>& rows) {
    // Ideal constraints do no virtual work (Lur'e, ch. 2; Chetaev 1932 for the kinematic rows), but
    // their reactions do work along the actual motion when the rows depend on t: the power
    // Σ_α λ_α (W_α · u) equals −Σ_α λ_α ∂_t f_α for a holonomic row (ḟ = W·q̇ + ∂_t f = 0) and
    // −Σ_α λ_α b_α for a kinematic one (φ = W u + b = 0). The energy (Jacobi) integral therefore
    // survives only if every row is scleronomic and homogeneous (Mei, §6.6).
    for (const ConstraintRow& row : rows) {
        if (row.holonomic) {
            if (!GiNaC::normal(derivative(row.position, model.t)).is_zero()) return false;
        } else {
            GiNaC::exmap at_rest;
            for (const auto& c : model.coordinates) at_rest[c.q_dot] = 0;
            for (const auto& q : model.quasi_velocities) at_rest[q.symbol] = 0;
            if (!GiNaC::normal(row.velocity.subs(at_rest)).is_zero()) return false;
            for (const ex& w : row.W)
                if (!GiNaC::normal(derivative(w, model.t)).is_zero()) return false;
        }
    }
    return true;
}

std::optional<std::vector<ex>> closed_form_multipliers(const Equations& eqs, std::string* why) {
    const auto refuse = [&](const std::string& reason) -> std::optional<std::vector<ex>> {
        if (why) *why = reason;
        return std::nullopt;
    };
    const std::size_t m = eqs.constraints.size(), n = eqs.mass_matrix.rows();
    if (m == 0) return refuse("no constraint rows");
    if (m > 2) return refuse(fmt::format("{} rows (the closed form is printed for at most two)", m));
    if (n > 3) return refuse(fmt::format("M is {}×{} (the closed form is printed up to 3×3)", n, n));
    // Past this many nodes an expression is no longer something to read.
    constexpr std::size_t max_nodes = 4000;
    try {
        const unsigned rows = static_cast<unsigned>(m), cols = static_cast<unsigned>(n);
        GiNaC::matrix W(rows, cols), f(cols, 1), bias(rows, 1);
        for (std::size_t a = 0; a < m; ++a) {
            for (std::size_t k = 0; k < n; ++k) W(unsigned(a), unsigned(k)) = eqs.constraints[a].W[k];
            bias(unsigned(a), 0) = eqs.constraints[a].bias;
        }
        for (std::size_t k = 0; k < n; ++k) f(unsigned(k), 0) = eqs.forcing[k];
        const GiNaC::matrix M_inv = eqs.mass_matrix.inverse();
        const GiNaC::matrix WMi = W.mul(M_inv);
        const GiNaC::matrix G = WMi.mul(W.transpose());
        GiNaC::matrix G_normal(rows, rows);
        for (unsigned i = 0; i < m; ++i)
            for (unsigned j = 0; j < m; ++j) G_normal(i, j) = symbolic::normalized(G(i, j));
        const GiNaC::matrix rhs = WMi.mul(f).add(bias);
        const GiNaC::matrix lambda = G_normal.inverse().mul(rhs).mul_scalar(-1);
        std::vector<ex> out;
        for (unsigned a = 0; a < m; ++a) {
            if (symbolic::node_count(lambda(a, 0)) > 20 * max_nodes)
                return refuse("the expression is too large to print");
            const ex value = symbolic::normalized(lambda(a, 0));
            if (symbolic::node_count(value) > max_nodes) return refuse("the expression is too large to print");
            out.push_back(value);
        }
        return out;
    } catch (const std::exception& e) {
        return refuse(std::string("GiNaC could not form it: ") + e.what());
    }
}

}  // namespace eomc::mechanics
