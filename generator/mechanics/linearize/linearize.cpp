#include "mechanics/linearize/linearize.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using symbolic::derivative;
using symbolic::evaluate;
using symbolic::ProbePoint;

namespace {

void refuse_unsupported(const model::Model& model, const Equations& eqs) {
    const SourcePos scene{model.source, 0, 0};
    if (model.orbit)
        throw InputError(scene, "`eomc linearize` linearises Lagrange's equations in the scene's coordinates; an orbit "
                                "scene ([orbit]) has no operating point at rest (use `eomc derive --variational`)");
    if (model.free_carrier())
        throw InputError(scene, "`eomc linearize` does not linearise a free carrier (its quasi-velocities have no "
                                "coordinates); use a prescribed carrier");
    if (model.rigid && !model.lagrangian_in_coordinates())
        throw InputError(scene, "`eomc linearize` linearises a rigid body in Euler angles only "
                                "(--rigid-formulation euler_angles); `eomc equilibria` linearises its permanent rotations");
    if (!model.unilateral.empty())
        throw InputError(model.unilateral.front().pos,
                         "`eomc linearize` does not linearise through [[unilateral]] gaps: contact switches the equations");
    if (!model.programs.empty())
        throw InputError(scene, "`eomc linearize` does not linearise [[program]] rows (their controls are solved at run "
                                "time); `eomc control` realises them");
    if (eqs.mass_matrix.rows() != model.coordinates.size())
        throw InputError(scene, "`eomc linearize` needs one velocity per coordinate (no quasi-velocities)");
}

// e is zero at every probe point, to round-off of its own size there (sin² + cos² need not cancel
// symbolically).
bool vanishes(const ex& e, const ex& of, const std::vector<ProbePoint>& points) {
    for (const ProbePoint& at : points) {
        const double v = evaluate(e, at), size = std::abs(evaluate(of, at));
        if (!(std::abs(v) <= 1e-10 * (1.0 + size))) return false;
    }
    return true;
}

Eigen::MatrixXd selection(const std::vector<std::size_t>& picked, std::size_t n) {
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(picked.size()));
    for (std::size_t j = 0; j < picked.size(); ++j) P(Eigen::Index(picked[j]), Eigen::Index(j)) = 1.0;
    return P;
}

// The rows' dependent columns: column-pivoted QR of J (rows × n) picks the best conditioned block to
// invert. Throws at `where` when the rows are dependent there.
void split_columns(const Eigen::MatrixXd& J, std::vector<std::size_t>& dependent, std::vector<std::size_t>& independent,
                   const char* what, const SourcePos& where) {
    const std::size_t n = std::size_t(J.cols()), rows = std::size_t(J.rows());
    dependent.clear();
    independent.clear();
    if (rows > 0) {
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
        if (std::size_t(qr.rank()) < rows)
            throw InputError(where, fmt::format("the {} rows are dependent at the operating point (rank {} of {}): "
                                                "no set of independent {} to eliminate them by",
                                                what, qr.rank(), rows, what == std::string("holonomic") ? "coordinates"
                                                                                                      : "speeds"));
        for (std::size_t j = 0; j < rows; ++j) dependent.push_back(std::size_t(qr.colsPermutation().indices()(Eigen::Index(j))));
        std::sort(dependent.begin(), dependent.end());
    }
    for (std::size_t k = 0; k < n; ++k)
        if (!std::binary_search(dependent.begin(), dependent.end(), k)) independent.push_back(k);
}

std::string listing(const model::Model& model, const std::vector<double>& v, const char* suffix) {
    std::string out;
    for (std::size_t k = 0; k < v.size(); ++k)
        out += fmt::format("{}{}{} = {:.6g}", k ? ", " : "", model.coordinates[k].name, suffix, v[k]);
    return out;
}

}  // namespace

const char* stability_name(LinearStability s) {
    switch (s) {
    case LinearStability::asymptotically_stable: return "asymptotically stable";
    case LinearStability::stable_linear: return "stable in the linear approximation";
    case LinearStability::unstable: return "unstable";
    }
    return "unstable";
}

// The numbers at one point: the equations' parts and Jacobians, row-major.
struct Linearizer::Point {
    Eigen::MatrixXd M, W, dynamic_q, dynamic_u, holonomic_q, velocity_q;
    Eigen::VectorXd f, bias, holonomic, velocity;
};

Linearizer::Linearizer(const model::Model& model, const Equations& eqs) : model_(model) {
    refuse_unsupported(model, eqs);
    n_ = model.coordinates.size();
    m_ = eqs.constraints.size();
    for (std::size_t s = 0; s < n_; ++s)
        for (std::size_t k = 0; k < n_; ++k) mass_.push_back(eqs.mass_matrix(unsigned(s), unsigned(k)));
    forcing_ = eqs.forcing;
    for (const ConstraintRow& row : eqs.constraints) {
        for (std::size_t k = 0; k < n_; ++k) W_.push_back(row.W[k]);
        bias_.push_back(row.bias);
        velocity_.push_back(row.velocity);
        lambda_.push_back(row.lambda);
        if (row.holonomic) holonomic_.push_back(row.position), ++l_;
    }
    // The residuals (M u̇ − f − Wᵀλ; W u̇ + b̂) whose linearisation gives δu̇ and δλ together.
    std::vector<ex> residual;
    for (std::size_t s = 0; s < n_; ++s) {
        ex r = -forcing_[s];
        for (std::size_t k = 0; k < n_; ++k) r += mass_[s * n_ + k] * model.coordinates[k].q_ddot;
        for (std::size_t a = 0; a < m_; ++a) r -= W_[a * n_ + s] * lambda_[a];
        residual.push_back(r);
    }
    for (std::size_t a = 0; a < m_; ++a) {
        ex r = bias_[a];
        for (std::size_t k = 0; k < n_; ++k) r += W_[a * n_ + k] * model.coordinates[k].q_ddot;
        residual.push_back(r);
    }
    for (const ex& r : residual)
        for (const auto& c : model.coordinates)
            dynamic_q_.push_back(derivative(r, c.q)), dynamic_u_.push_back(derivative(r, c.q_dot));
    for (const ex& h : holonomic_)
        for (const auto& c : model.coordinates) holonomic_q_.push_back(derivative(h, c.q));
    for (const ex& v : velocity_)
        for (const auto& c : model.coordinates) velocity_q_.push_back(derivative(v, c.q));

    // A point of a motion is steady only if time and the moving coordinates are absent.
    const auto points = symbolic::probe_points(model, 6);
    enters_.assign(n_, false);
    for (const auto* group : {&mass_, &forcing_, &W_, &bias_, &holonomic_, &velocity_})
        for (const ex& e : *group) {
            if (e.has(model.t) && !vanishes(derivative(e, model.t), e, points))
                throw InputError(SourcePos{model.source, 0, 0},
                                 "the equations depend on t explicitly: there is no steady operating point to linearise "
                                 "about (a carrier or a row whose motion is not steady)");
            for (std::size_t k = 0; k < n_; ++k)
                if (!enters_[k] && e.has(model.coordinates[k].q) && !vanishes(derivative(e, model.coordinates[k].q), e, points))
                    enters_[k] = true;
        }
}

Linearizer::Point Linearizer::evaluate_at(const std::vector<double>& parameters, const std::vector<double>& q,
                                          const std::vector<double>& u, const std::vector<double>& udot,
                                          const std::vector<double>& lambda) const {
    ProbePoint at;
    at.values[model_.t] = 0.0;
    for (std::size_t i = 0; i < model_.parameters.size(); ++i) at.values[model_.parameters[i].symbol] = parameters[i];
    for (std::size_t k = 0; k < n_; ++k) {
        at.values[model_.coordinates[k].q] = q[k];
        at.values[model_.coordinates[k].q_dot] = u[k];
        at.values[model_.coordinates[k].q_ddot] = udot[k];
    }
    for (std::size_t a = 0; a < m_; ++a) at.values[lambda_[a]] = lambda[a];
    const auto vec = [&](const std::vector<ex>& v) {
        Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
        for (std::size_t i = 0; i < v.size(); ++i) out(Eigen::Index(i)) = evaluate(v[i], at);
        return out;
    };
    const auto mat = [&](const std::vector<ex>& v, std::size_t rows) {
        Eigen::MatrixXd out(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(n_));
        for (std::size_t i = 0; i < rows; ++i)
            for (std::size_t k = 0; k < n_; ++k) out(Eigen::Index(i), Eigen::Index(k)) = evaluate(v[i * n_ + k], at);
        return out;
    };
    Point p;
    p.M = mat(mass_, n_);
    p.W = mat(W_, m_);
    p.dynamic_q = mat(dynamic_q_, n_ + m_);
    p.dynamic_u = mat(dynamic_u_, n_ + m_);
    p.holonomic_q = mat(holonomic_q_, l_);
    p.velocity_q = mat(velocity_q_, m_);
    p.f = vec(forcing_);
    p.bias = vec(bias_);
    p.holonomic = vec(holonomic_);
    p.velocity = vec(velocity_);
    return p;
}

// Gauss–Newton (minimum-norm steps: a kinematic row's reaction at rest need not be unique) on
// f(q, 0) + Wᵀλ = 0, f_h(q) = 0, φ(q, 0) = 0 from the initial configuration.
void Linearizer::find_equilibrium(const std::vector<double>& parameters, std::vector<double>& q,
                                  const SourcePos& where) const {
    const Eigen::Index n = Eigen::Index(n_), m = Eigen::Index(m_), l = Eigen::Index(l_);
    const std::vector<double> zero(n_, 0.0);
    std::vector<double> lambda(m_, 0.0);
    double residual = 0, scale = 0;
    for (int iteration = 0; iteration < 100; ++iteration) {
        const Point p = evaluate_at(parameters, q, zero, zero, lambda);
        const Eigen::Map<const Eigen::VectorXd> lam(lambda.data(), m);
        Eigen::VectorXd R(n + l + m);
        R << -p.f - p.W.transpose() * lam, p.holonomic, p.velocity;
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n + l + m, n + m);
        J.topLeftCorner(n, n) = p.dynamic_q.topRows(n);
        J.topRightCorner(n, m) = -p.W.transpose();
        J.block(n, 0, l, n) = p.holonomic_q;
        J.block(n + l, 0, m, n) = p.velocity_q;
        if (!R.allFinite() || !J.allFinite()) break;
        residual = R.norm();
        // The size of the terms that cancel at a root: ∂R/∂x times (1 + |x|), and R itself.
        Eigen::VectorXd x(n + m);
        for (Eigen::Index k = 0; k < n; ++k) x(k) = q[std::size_t(k)];
        x.tail(m) = lam;
        scale = R.norm() + (J.cwiseAbs() * (x.cwiseAbs().array() + 1.0).matrix()).norm();
        Eigen::VectorXd step = J.completeOrthogonalDecomposition().solve(R);
        // Steps at most half the size of the point (and 1): Newton's full step from a slope can land
        // several turns of an angle away, past nearer equilibria.
        const double longest = 0.5 * (1.0 + x.norm());
        if (step.norm() > longest) step *= longest / step.norm();
        x -= step;
        for (Eigen::Index k = 0; k < n; ++k) q[std::size_t(k)] = x(k);
        for (Eigen::Index a = 0; a < m; ++a) lambda[std::size_t(a)] = x(n + a);
        if (step.norm() <= 1e-13 * (1.0 + x.norm())) {
            if (residual <= 1e-9 * scale) return;
            break;
        }
    }
    throw InputError(where, fmt::format("no equilibrium found near the initial configuration ({}): Newton's method "
                                        "stopped with the residual {:.3g}; give a configuration nearer one",
                                        listing(model_, q, ""), residual));
}

// The operating point is steady: the rows hold, the accelerations vanish and every moving coordinate
// is absent from the equations — to round-off of the terms that cancel, f and Wᵀλ and ∂f/∂q (1 + |q|)
// as in mechanics/relative/equilibria.cpp (1e-9 of them: a point given to ten digits passes).
void Linearizer::check_steady(const Point& p, const std::vector<double>& q, const std::vector<double>& u,
                              Linearization& out, const SourcePos& where) const {
    const Eigen::Map<const Eigen::VectorXd> Q(q.data(), Eigen::Index(n_)), U(u.data(), Eigen::Index(n_));
    const Eigen::Map<const Eigen::VectorXd> A(out.accelerations.data(), Eigen::Index(n_));
    const Eigen::Map<const Eigen::VectorXd> L(out.multipliers.data(), Eigen::Index(m_));
    for (std::size_t i = 0; i < l_; ++i) {
        const double scale = 1.0 + (p.holonomic_q.row(Eigen::Index(i)).cwiseAbs() * Q.cwiseAbs());
        if (!(std::abs(p.holonomic(Eigen::Index(i))) <= 1e-9 * scale))
            throw InputError(where, fmt::format("the operating point breaks a holonomic row: f = {:.3g} ({})",
                                                p.holonomic(Eigen::Index(i)), listing(model_, q, "")));
    }
    for (std::size_t a = 0; a < m_; ++a) {
        const double scale = 1.0 + (p.W.row(Eigen::Index(a)).cwiseAbs() * U.cwiseAbs());
        if (!(std::abs(p.velocity(Eigen::Index(a))) <= 1e-9 * scale))
            throw InputError(where, fmt::format("the operating point breaks a velocity row: φ = {:.3g} ({})",
                                                p.velocity(Eigen::Index(a)), listing(model_, u, "_dot")));
    }
    const Eigen::VectorXd force = p.M * A;
    const Eigen::VectorXd terms = p.f.cwiseAbs() + (p.W.transpose() * L).cwiseAbs() +
                                  p.dynamic_q.topRows(Eigen::Index(n_)).cwiseAbs() * (Q.cwiseAbs().array() + 1.0).matrix() +
                                  p.dynamic_u.topRows(Eigen::Index(n_)).cwiseAbs() * U.cwiseAbs();
    for (std::size_t s = 0; s < n_; ++s)
        if (!(std::abs(force(Eigen::Index(s))) <= 1e-9 * terms(Eigen::Index(s))) && force(Eigen::Index(s)) != 0.0)
            throw InputError(where, fmt::format("the operating point is not an equilibrium or a steady motion: the "
                                                "accelerations there are {} (residual M q̈ = {:.3g} in the {} equation, "
                                                "against terms of size {:.3g}); `--about equilibrium` finds the rest "
                                                "state nearest the initial configuration",
                                                listing(model_, out.accelerations, "_ddot"), force(Eigen::Index(s)),
                                                model_.coordinates[s].name, terms(Eigen::Index(s))));
    for (std::size_t k = 0; k < n_; ++k)
        if (u[k] != 0.0 && enters_[k])
            throw InputError(where, fmt::format("{} moves at the operating point ({}_dot = {:.6g}) and enters the "
                                                "equations: the motion through the point is not steady (only cyclic "
                                                "coordinates may move)",
                                                model_.coordinates[k].name, model_.coordinates[k].name, u[k]));
}

Linearization Linearizer::linearize(const std::vector<double>& parameters, OperatingPointKind about,
                                    std::vector<double> q, std::vector<double> u, const SourcePos& where) const {
    const Eigen::Index n = Eigen::Index(n_), m = Eigen::Index(m_);
    if (about == OperatingPointKind::equilibrium) {
        std::fill(u.begin(), u.end(), 0.0);
        find_equilibrium(parameters, q, where);
    }
    Linearization out;
    const std::vector<double> zero(n_, 0.0), no_lambda(m_, 0.0);
    // u̇₀ and λ₀ from M u̇ − Wᵀλ = f, W u̇ = −b̂ at the point.
    Point p = evaluate_at(parameters, q, u, zero, no_lambda);
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + m, n + m);
    K.topLeftCorner(n, n) = p.M;
    K.topRightCorner(n, m) = -p.W.transpose();
    K.bottomLeftCorner(m, n) = p.W;
    Eigen::VectorXd rhs(n + m);
    rhs << p.f, -p.bias;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
    if (!K.allFinite() || !rhs.allFinite() || !lu.isInvertible())
        throw InputError(where, fmt::format("the equations are singular at the operating point ({}): M, with the rows' "
                                            "W, cannot be solved for the accelerations",
                                            listing(model_, q, "")));
    const Eigen::VectorXd solved = lu.solve(rhs);
    out.q = q;
    out.u = u;
    out.accelerations.assign(solved.data(), solved.data() + n);
    out.multipliers.assign(solved.data() + n, solved.data() + n + m);
    p = evaluate_at(parameters, q, u, out.accelerations, out.multipliers);
    check_steady(p, q, u, out, where);

    // (δu̇, δλ) = −K⁻¹ (∂r/∂q δq + ∂r/∂u δu): the implicit-function derivative of the residuals r.
    Eigen::MatrixXd R(n + m, 2 * n);
    R << p.dynamic_q, p.dynamic_u;
    const Eigen::MatrixXd D = -lu.solve(R);
    const Eigen::MatrixXd Gq = D.topLeftCorner(n, n), Gu = D.topRightCorner(n, n);

    split_columns(p.holonomic_q, out.dependent_coordinates, out.independent_coordinates, "holonomic", where);
    split_columns(p.W, out.dependent_speeds, out.independent_speeds, "velocity", where);
    const Eigen::MatrixXd Pqi = selection(out.independent_coordinates, n_), Pqd = selection(out.dependent_coordinates, n_);
    const Eigen::MatrixXd Pui = selection(out.independent_speeds, n_), Pud = selection(out.dependent_speeds, n_);
    // PGH eqs. (20)–(27): the dependent perturbations from the independent ones.
    const Eigen::MatrixXd C0 =
        l_ ? Eigen::MatrixXd(Pqi - Pqd * (p.holonomic_q * Pqd).fullPivLu().solve(p.holonomic_q * Pqi)) : Pqi;
    const Eigen::FullPivLU<Eigen::MatrixXd> Wd(p.W * Pud);
    const Eigen::MatrixXd C1 = m ? Eigen::MatrixXd(-Pud * Wd.solve(p.velocity_q * C0)) : Eigen::MatrixXd::Zero(n, C0.cols());
    const Eigen::MatrixXd C2 = m ? Eigen::MatrixXd(Pui - Pud * Wd.solve(p.W * Pui)) : Pui;
    const Eigen::Index ni = C0.cols(), nu = C2.cols();
    out.A.resize(ni + nu, ni + nu);
    out.A << Pqi.transpose() * C1, Pqi.transpose() * C2, Pui.transpose() * (Gq * C0 + Gu * C1), Pui.transpose() * Gu * C2;
    for (std::size_t k : out.independent_coordinates) out.state.push_back(model_.coordinates[k].name);
    for (std::size_t k : out.independent_speeds) out.state.push_back(model_.coordinates[k].name + "_dot");
    classify_linearization(out);
    return out;
}

}  // namespace eomc::mechanics
