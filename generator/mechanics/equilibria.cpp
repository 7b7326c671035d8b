#include "mechanics/equilibria.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mechanics/differentiation.hpp"
#include "mechanics/numeric_probe.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

namespace {

// The equations at rest and their first derivatives, ready to evaluate.
struct RestSystem {
    std::size_t n = 0;
    std::vector<ex> f;       // f(q, 0)
    std::vector<ex> M;       // M(q), row-major
    std::vector<ex> f_q;     // ∂f/∂q at q̇ = 0, row-major
    std::vector<ex> f_qdot;  // ∂f/∂q̇ at q̇ = 0, row-major
};

RestSystem rest_system(const model::Model& model, const Equations& eqs) {
    RestSystem r;
    if (model.free_carrier())
        throw InputError(SourcePos{model.source, 0, 0},
                         "relative equilibria are defined for a carrier whose motion is prescribed and steady; this "
                         "scene's carrier is free (its motion is part of the solution)");
    r.n = model.coordinates.size();
    GiNaC::exmap at_rest;
    for (const auto& c : model.coordinates) at_rest[c.q_dot] = 0;
    for (std::size_t s = 0; s < r.n; ++s) {
        r.f.push_back(eqs.forcing[s].subs(at_rest));
        for (std::size_t k = 0; k < r.n; ++k) {
            r.M.push_back(eqs.mass_matrix(unsigned(s), unsigned(k)).subs(at_rest));
            r.f_q.push_back(derivative(eqs.forcing[s], model.coordinates[k].q).subs(at_rest));
            r.f_qdot.push_back(derivative(eqs.forcing[s], model.coordinates[k].q_dot).subs(at_rest));
        }
    }
    for (const auto* group : {&r.f, &r.M, &r.f_q, &r.f_qdot})
        for (const ex& e : *group)
            if (e.has(model.t))
                throw InputError(SourcePos{model.source, 0, 0},
                                 "the equations at rest depend on t: the carrier's motion is not steady, so the scene "
                                 "has no relative equilibria");
    return r;
}

class Evaluation {
public:
    Evaluation(const model::Model& model) : model_(model) {
        point_.values[model.t] = 0.0;
        for (const auto& p : model.parameters) point_.values[p.symbol] = p.value;
        for (const auto& c : model.coordinates) point_.values[c.q_dot] = 0.0, point_.values[c.q_ddot] = 0.0;
    }
    void set(const Eigen::VectorXd& q) {
        for (std::size_t k = 0; k < model_.coordinates.size(); ++k) point_.values[model_.coordinates[k].q] = q(Eigen::Index(k));
    }
    Eigen::VectorXd vector(const std::vector<ex>& v) const {
        Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
        for (std::size_t i = 0; i < v.size(); ++i) out(Eigen::Index(i)) = evaluate(v[i], point_);
        return out;
    }
    Eigen::MatrixXd matrix(const std::vector<ex>& m, std::size_t n) const {
        Eigen::MatrixXd out(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) out(Eigen::Index(i), Eigen::Index(j)) = evaluate(m[i * n + j], point_);
        return out;
    }

private:
    const model::Model& model_;
    ProbePoint point_;
};

// Newton's method on f(q, 0) = 0 from q0; true and the root in q when it converges.
bool newton(const RestSystem& r, Evaluation& at, Eigen::VectorXd& q) {
    for (int iteration = 0; iteration < 60; ++iteration) {
        at.set(q);
        const Eigen::VectorXd F = at.vector(r.f);
        const Eigen::MatrixXd J = at.matrix(r.f_q, r.n);
        if (!F.allFinite() || !J.allFinite()) return false;
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
        if (!lu.isInvertible()) return false;
        const Eigen::VectorXd step = lu.solve(F);
        q -= step;
        // Converged when the step is at round-off of q (quadratic convergence gets there in
        // a few iterations from a good start).
        if (step.norm() <= 1e-13 * (1.0 + q.norm())) return q.allFinite();
    }
    return false;
}

Equilibrium classify(const RestSystem& r, Evaluation& at, const Eigen::VectorXd& q) {
    const Eigen::Index n = Eigen::Index(r.n);
    at.set(q);
    const Eigen::MatrixXd M = at.matrix(r.M, r.n), Fq = at.matrix(r.f_q, r.n), Fv = at.matrix(r.f_qdot, r.n);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    A.topRightCorner(n, n).setIdentity();
    A.bottomLeftCorner(n, n) = M.ldlt().solve(Fq);
    A.bottomRightCorner(n, n) = M.ldlt().solve(Fv);
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(A, false);

    Equilibrium e;
    e.q.assign(q.data(), q.data() + n);
    double largest = 0;
    for (Eigen::Index i = 0; i < 2 * n; ++i) {
        e.eigenvalues.push_back(eig.eigenvalues()(i));
        largest = std::max(largest, std::abs(eig.eigenvalues()(i)));
    }
    std::sort(e.eigenvalues.begin(), e.eigenvalues.end(), [](auto a, auto b) {
        return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
    });
    // Eigenvalues of a conservative system come in ±λ pairs; "on the axis" up to the
    // eigensolver's backward error, a few ulp of the largest one.
    const double tolerance = 1e-9 * (1.0 + largest);
    const bool unstable = e.eigenvalues.front().real() > tolerance;
    if (unstable) {
        e.verdict = "unstable";
    } else {
        const Eigen::MatrixXd K = -(Fq + Fq.transpose()) / 2;  // stiffness, symmetric part
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> k(K);
        e.verdict = k.eigenvalues().minCoeff() > 0 ? "stable" : "gyroscopically stabilised";
    }
    return e;
}

}  // namespace

std::vector<Equilibrium> relative_equilibria(const model::Model& model, const Equations& eqs,
                                             const EquilibriumSearch& search) {
    const RestSystem r = rest_system(model, eqs);
    Evaluation at(model);
    const std::size_t n = r.n;
    // A grid of starts, at most about 4000 of them whatever n is.
    int per = search.starts_per_coordinate;
    while (per > 2 && std::pow(double(per), double(n)) > 4000) --per;

    std::vector<Eigen::VectorXd> roots;
    std::vector<int> index(n, 0);
    for (;;) {
        Eigen::VectorXd q(static_cast<Eigen::Index>(n));
        for (std::size_t k = 0; k < n; ++k)
            q(Eigen::Index(k)) = -search.range + 2 * search.range * (index[k] + 0.5) / per;
        if (newton(r, at, q) && q.cwiseAbs().maxCoeff() <= search.range * (1 + 1e-9)) {
            const bool known = std::any_of(roots.begin(), roots.end(), [&](const Eigen::VectorXd& other) {
                return (other - q).norm() <= 1e-7 * (1.0 + q.norm());
            });
            if (!known) roots.push_back(q);
        }
        std::size_t k = 0;
        while (k < n && ++index[k] == per) index[k++] = 0;
        if (k == n) break;
    }
    std::sort(roots.begin(), roots.end(), [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
        return std::lexicographical_compare(a.data(), a.data() + a.size(), b.data(), b.data() + b.size());
    });
    std::vector<Equilibrium> out;
    for (const auto& q : roots) out.push_back(classify(r, at, q));
    return out;
}

}  // namespace eomc::mechanics
