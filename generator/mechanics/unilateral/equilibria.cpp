#include "mechanics/unilateral/equilibria.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/closed_form.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/integrate.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics::unilateral {

using namespace eomc::symbolic;
using GiNaC::ex;

const char* name(KktKind kind) {
    switch (kind) {
    case KktKind::interior: return "interior";
    case KktKind::boundary: return "boundary";
    case KktKind::degenerate: return "degenerate";
    }
    return "?";
}

namespace {

// The rest forces, the gaps and their first and second derivatives, ready to evaluate.
struct System {
    std::size_t n = 0, m = 0;
    std::vector<GiNaC::symbol> q, lambda;
    std::vector<ex> force;      // f(q, 0) = −∂V/∂q
    std::vector<ex> force_q;    // ∂f/∂q at rest, row-major n × n
    std::vector<ex> force_qdot; // ∂f/∂q̇ at rest (gyroscopic coupling), row-major
    std::vector<ex> gap;        // f_α(q)
    std::vector<ex> normal;     // ∂f_α/∂q_s, row-major m × n
    std::vector<ex> curvature;  // ∂²f_α/∂q_s∂q_k, m blocks of n × n
    std::vector<bool> free;     // coordinates absent from f(q, 0) and every gap
    std::vector<bool> force_row;  // force equations that do not vanish identically with their normals
    double scale = 0;           // the largest |f|, |∂f/∂q|, |∂f_α/∂q| at random points
};

class Evaluation {
public:
    Evaluation(const model::Model& model, const System& s) : s_(s) {
        point_.values[model.t] = 0.0;
        for (const auto& p : model.parameters) point_.values[p.symbol] = p.value;
        for (const auto& c : model.coordinates) point_.values[c.q_dot] = 0.0, point_.values[c.q_ddot] = 0.0;
    }
    void set(const Eigen::VectorXd& q) {
        for (std::size_t k = 0; k < s_.n; ++k) point_.values[s_.q[k]] = q(Eigen::Index(k));
    }
    Eigen::MatrixXd matrix(const std::vector<ex>& v, std::size_t rows, std::size_t columns, std::size_t offset = 0) const {
        Eigen::MatrixXd out(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(columns));
        for (std::size_t i = 0; i < rows; ++i)
            for (std::size_t j = 0; j < columns; ++j)
                out(Eigen::Index(i), Eigen::Index(j)) = evaluate(v[offset + i * columns + j], point_);
        return out;
    }

private:
    const System& s_;
    ProbePoint point_;
};

SourcePos scene_pos(const model::Model& model) { return SourcePos{model.source, 0, 0}; }

System system_of(const model::Model& model, const Equations& eqs) {
    if (model.kind() != model::ModelKind::energies || model.free_carrier())
        throw InputError(scene_pos(model),
                         fmt::format("`eomc equilibria` finds the KKT equilibria of [[unilateral]] rows (Mei §6.4) in a "
                                     "scene given by T and V in its coordinates (a [lagrangian] or carried bodies on "
                                     "a prescribed carrier); '{}' is {}",
                                     model.name,
                                     model.free_carrier() ? "on a free carrier" : "not given by its energies"));
    if (!model.constraints.empty())
        throw InputError(model.constraints.front().pos,
                         fmt::format("`eomc equilibria` does not support bilateral rows beside unilateral ones "
                                     "([[constraint]] '{}'): the rest conditions would need their reactions too",
                                     model.constraints.front().name));
    System s;
    s.n = model.coordinates.size();
    s.m = eqs.unilateral.size();
    for (const auto& c : model.coordinates) s.q.push_back(c.q);
    GiNaC::exmap at_rest;
    for (const auto& c : model.coordinates) at_rest[c.q_dot] = 0;
    for (const auto& row : eqs.unilateral) {
        // §6.4 is about fixed, holonomic gaps: a moving wall has no equilibrium, and a velocity row
        // (§6.7) says nothing at rest.
        if (!row.row.holonomic)
            throw InputError(row.row.pos,
                             fmt::format("the unilateral constraint '{}' is a velocity row (§6.7): the KKT equilibria "
                                         "of §6.4 are defined for gaps f(q) >= 0",
                                         row.row.name));
        if (row.row.position.has(model.t))
            throw InputError(row.row.pos,
                             fmt::format("the gap '{}' depends on t: a moving boundary has no equilibria (the KKT "
                                         "conditions of §6.4 need f(q) >= 0 fixed in time)",
                                         row.row.name));
        s.lambda.push_back(row.row.lambda);
        s.gap.push_back(row.row.position);
    }
    for (std::size_t i = 0; i < s.n; ++i) {
        s.force.push_back(eqs.forcing[i].subs(at_rest));
        for (std::size_t k = 0; k < s.n; ++k) {
            s.force_q.push_back(derivative(eqs.forcing[i], s.q[k]).subs(at_rest));
            s.force_qdot.push_back(derivative(eqs.forcing[i], model.coordinates[k].q_dot).subs(at_rest));
        }
    }
    for (const ex& f : s.gap)
        for (std::size_t k = 0; k < s.n; ++k) s.normal.push_back(derivative(f, s.q[k]));
    for (std::size_t a = 0; a < s.m; ++a)
        for (std::size_t i = 0; i < s.n; ++i)
            for (std::size_t k = 0; k < s.n; ++k) s.curvature.push_back(derivative(s.normal[a * s.n + i], s.q[k]));
    for (const auto* group : {&s.force, &s.force_q, &s.force_qdot})
        for (const ex& e : *group)
            if (e.has(model.t))
                throw InputError(scene_pos(model), "the forces at rest depend on t: the scene has no equilibria (the "
                                                   "KKT conditions of §6.4 need a potential V(q))");

    // Decided at random points (sin² + cos² need not cancel symbolically): zero to round-off of
    // the largest entry seen.
    const auto points = probe_points(model, 12);
    for (const auto& at : points)
        for (const auto* group : {&s.force, &s.force_q, &s.normal})
            for (const ex& e : *group) s.scale = std::max(s.scale, std::abs(evaluate(e, at)));
    const double zero = 1e-10 * (1 + s.scale);
    auto vanishes = [&](const ex& e) {
        return std::all_of(points.begin(), points.end(), [&](const ProbePoint& at) { return std::abs(evaluate(e, at)) <= zero; });
    };
    // The KKT conditions need ∂V/∂q: the rest forces must be a gradient (∂f_i/∂q_j symmetric).
    for (std::size_t i = 0; i < s.n; ++i)
        for (std::size_t k = i + 1; k < s.n; ++k)
            if (!vanishes(s.force_q[i * s.n + k] - s.force_q[k * s.n + i]))
                throw InputError(scene_pos(model),
                                 fmt::format("the forces at rest are not the gradient of a potential (∂f_{0}/∂{1} ≠ "
                                             "∂f_{1}/∂{0}): the KKT conditions of §6.4 need V(q)",
                                             model.coordinates[i].name, model.coordinates[k].name));
    s.free.assign(s.n, true);
    s.force_row.assign(s.n, false);
    for (std::size_t k = 0; k < s.n; ++k) {
        for (std::size_t i = 0; i < s.n; ++i) s.free[k] = s.free[k] && vanishes(s.force_q[i * s.n + k]);
        for (std::size_t a = 0; a < s.m; ++a) s.free[k] = s.free[k] && vanishes(s.normal[a * s.n + k]);
        s.force_row[k] = !vanishes(s.force[k]);
        for (std::size_t a = 0; a < s.m; ++a) s.force_row[k] = s.force_row[k] || !vanishes(s.normal[a * s.n + k]);
    }
    return s;
}

// V with ∂V/∂q = −f(q, 0): the scene's own V when it is that, else integrated (nullopt when out of reach).
std::optional<ex> potential_of(const model::Model& model, const System& s) {
    std::vector<ex> gradient;
    for (const ex& f : s.force) gradient.push_back(-f);
    bool own = !model.potential.has(model.t);
    for (const auto& c : model.coordinates) own = own && !model.potential.has(c.q_dot);
    for (std::size_t k = 0; k < s.n && own; ++k)
        own = GiNaC::normal((derivative(model.potential, s.q[k]) - gradient[k]).expand()).is_zero();
    if (own) return model.potential;
    return potential(gradient, s.q);
}

// One solution of an active set's equations: q, λ over the set, and the closed forms when known.
struct Candidate {
    Eigen::VectorXd q, lambda;  // λ over A, in row order
    std::optional<GiNaC::exmap> exact;  // q_k and λ_α → closed forms
};

class ActiveSet {
public:
    ActiveSet(const System& s, Evaluation& at, std::vector<std::size_t> rows) : s_(s), at_(at), rows_(std::move(rows)) {
        for (std::size_t k = 0; k < s.n; ++k)
            if (!s.free[k]) columns_.push_back(k);
        for (std::size_t k = 0; k < s.n; ++k)
            if (s.force_row[k]) force_rows_.push_back(k);
    }

    // F(q, λ) = (f + Σ_A λ_α ∂f_α/∂q over the force rows; f_A) and its Jacobian in (q over the
    // non-free coordinates, λ_A).
    void residual(const Eigen::VectorXd& q, const Eigen::VectorXd& lambda, Eigen::VectorXd& F, Eigen::MatrixXd* J) const {
        at_.set(q);
        const std::size_t n = s_.n, r = rows_.size();
        Eigen::VectorXd force = at_.matrix(s_.force, n, 1);
        Eigen::MatrixXd K = at_.matrix(s_.force_q, n, n);
        Eigen::MatrixXd N(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(n));
        Eigen::VectorXd g(static_cast<Eigen::Index>(r));
        for (std::size_t i = 0; i < r; ++i) {
            const std::size_t a = rows_[i];
            N.row(Eigen::Index(i)) = at_.matrix(s_.normal, 1, n, a * n);
            g(Eigen::Index(i)) = at_.matrix(s_.gap, 1, 1, a)(0, 0);
            force += lambda(Eigen::Index(i)) * N.row(Eigen::Index(i)).transpose();
            if (J) K += lambda(Eigen::Index(i)) * at_.matrix(s_.curvature, n, n, a * n * n);
        }
        const Eigen::Index fr = Eigen::Index(force_rows_.size()), c = Eigen::Index(columns_.size());
        F.resize(fr + Eigen::Index(r));
        for (Eigen::Index i = 0; i < fr; ++i) F(i) = force(Eigen::Index(force_rows_[std::size_t(i)]));
        F.tail(Eigen::Index(r)) = g;
        if (!J) return;
        J->setZero(fr + Eigen::Index(r), c + Eigen::Index(r));
        for (Eigen::Index i = 0; i < fr; ++i) {
            const auto row = Eigen::Index(force_rows_[std::size_t(i)]);
            for (Eigen::Index j = 0; j < c; ++j) (*J)(i, j) = K(row, Eigen::Index(columns_[std::size_t(j)]));
            for (Eigen::Index j = 0; j < Eigen::Index(r); ++j) (*J)(i, c + j) = N(j, row);
        }
        for (Eigen::Index i = 0; i < Eigen::Index(r); ++i)
            for (Eigen::Index j = 0; j < c; ++j) (*J)(fr + i, j) = N(i, Eigen::Index(columns_[std::size_t(j)]));
    }

    // Newton's method (least squares where the set's system is not square) from q0, λ = 0.
    // Converged: the step at round-off, the residual at round-off of the forces' size, the
    // Jacobian of full column rank (an isolated solution); `continuum` set when it converged to a
    // point of a family instead.
    std::optional<Candidate> newton(Eigen::VectorXd q, bool& continuum) const {
        const std::size_t r = rows_.size();
        Eigen::VectorXd lambda = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r)), F;
        Eigen::MatrixXd J;
        const Eigen::Index c = Eigen::Index(columns_.size());
        for (int iteration = 0; iteration < 60; ++iteration) {
            residual(q, lambda, F, &J);
            if (!F.allFinite() || !J.allFinite()) return std::nullopt;
            if (J.cols() == 0) return F.norm() <= tolerance(q) ? std::optional<Candidate>(Candidate{q, lambda, {}}) : std::nullopt;
            const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(J);
            const Eigen::VectorXd step = cod.solve(F);
            for (Eigen::Index j = 0; j < c; ++j) q(Eigen::Index(columns_[std::size_t(j)])) -= step(j);
            lambda -= step.tail(Eigen::Index(r));
            if (step.norm() <= 1e-13 * (1.0 + q.norm() + lambda.norm())) {
                residual(q, lambda, F, &J);
                if (!(F.norm() <= tolerance(q)) || !q.allFinite()) return std::nullopt;
                if (Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(J).rank() < J.cols()) {
                    continuum = true;
                    return std::nullopt;
                }
                return Candidate{q, lambda, {}};
            }
        }
        return std::nullopt;
    }

    // Round-off of F on the forces' scale: ∂F/∂q times q, as for the relative equilibria.
    double tolerance(const Eigen::VectorXd& q) const { return 1e-9 * (1.0 + s_.scale * (1.0 + q.norm())); }

    const std::vector<std::size_t>& rows() const { return rows_; }
    const std::vector<std::size_t>& columns() const { return columns_; }
    const std::vector<std::size_t>& force_rows() const { return force_rows_; }

private:
    const System& s_;
    Evaluation& at_;
    std::vector<std::size_t> rows_, columns_, force_rows_;
};

bool same_point(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() <= 1e-7 * (1.0 + a.norm()); }

void add(std::vector<Candidate>& found, Candidate c) {
    auto it = std::find_if(found.begin(), found.end(), [&](const Candidate& other) { return same_point(other.q, c.q); });
    if (it == found.end()) found.push_back(std::move(c));
    else if (c.exact && !it->exact) *it = std::move(c);  // the closed form evaluated: exact zeros stay zero
}

// The closed forms of one active set, each real one (at the defaults) with its images q + 2πk in
// the range for coordinates it reaches through sin/cos, checked against the equations numerically.
void closed_forms(const model::Model& model, const System& s, const ActiveSet& set, const KktSearch& search,
                  std::vector<Candidate>& found, bool& complete) {
    // λ first: each force equation is linear in the multipliers, and solving it for one keeps q
    // inside sin and cos, where the forms of symbolic/closed_form reach it.
    std::vector<GiNaC::symbol> unknowns;
    for (std::size_t a : set.rows()) unknowns.push_back(s.lambda[a]);
    unknowns.insert(unknowns.end(), s.q.begin(), s.q.end());
    std::vector<bool> free(set.rows().size(), false);
    free.insert(free.end(), s.free.begin(), s.free.end());
    const TrigVariables trig(unknowns);
    std::vector<ex> equations;
    for (std::size_t k : set.force_rows()) {
        ex e = s.force[k];
        for (std::size_t a : set.rows()) e += s.lambda[a] * s.normal[a * s.n + k];
        equations.push_back(e.subs(trig.to_variables).expand());
    }
    for (std::size_t a : set.rows()) equations.push_back(s.gap[a].subs(trig.to_variables).expand());
    const GiNaC::exmap defaults = model.parameter_defaults();
    bool solved_all = true;
    const auto forms = ClosedFormSolver(unknowns, trig, defaults).solve(equations, free, solved_all);
    complete = complete && solved_all;
    const std::size_t r = set.rows().size(), n = s.n;
    for (const ClosedForm& form : forms) {
        Eigen::VectorXd q(static_cast<Eigen::Index>(n)), lambda(static_cast<Eigen::Index>(r));
        bool real = true;
        for (std::size_t i = 0; i < r + n && real; ++i) {
            const auto v = real_value(defaults, form.q[i].q.subs(trig.to_functions));
            real = v.has_value();
            if (real && i < r) lambda(Eigen::Index(i)) = *v;
            if (real && i >= r) q(Eigen::Index(i - r)) = *v;
        }
        if (!real) continue;
        std::vector<std::vector<long>> turns(n);
        for (std::size_t k = 0; k < n; ++k) {
            const double base = q(Eigen::Index(k)), turn = 2 * std::numbers::pi;
            if (!form.periodic[r + k]) {  // exact: kept wherever it lies
                turns[k].push_back(0);
                continue;
            }
            for (long j = long(std::ceil((-search.range - base) / turn - 1e-9)); base + double(j) * turn <= search.range * (1 + 1e-9); ++j)
                turns[k].push_back(j);
        }
        if (std::any_of(turns.begin(), turns.end(), [](const auto& v) { return v.empty(); })) continue;
        std::vector<std::size_t> pick(n, 0);
        for (;;) {
            Candidate c{q, lambda, GiNaC::exmap{}};
            for (std::size_t k = 0; k < n; ++k) {
                const long j = turns[k][pick[k]];
                c.q(Eigen::Index(k)) += double(j) * 2 * std::numbers::pi;
                (*c.exact)[s.q[k]] = (form.q[r + k].q + 2 * j * GiNaC::Pi).subs(trig.to_functions).eval();
            }
            for (std::size_t i = 0; i < r; ++i) (*c.exact)[s.lambda[set.rows()[i]]] = form.q[i].q.subs(trig.to_functions);
            // A root of a numerator only (a denominator vanishing too) is not a solution.
            Eigen::VectorXd F;
            set.residual(c.q, c.lambda, F, nullptr);
            if (F.norm() <= set.tolerance(c.q)) add(found, std::move(c));
            std::size_t k = 0;
            while (k < n && ++pick[k] == turns[k].size()) pick[k++] = 0;
            if (k == n) break;
        }
    }
}

std::vector<Candidate> solve_set(const model::Model& model, const System& s, const ActiveSet& set,
                                 const KktSearch& search, bool& complete, bool& continuum) {
    std::vector<Candidate> found;
    closed_forms(model, s, set, search, found, complete);
    const std::size_t dims = set.columns().size();
    int per = search.starts_per_coordinate;
    while (per > 2 && std::pow(double(per), double(dims)) > 1000) --per;
    std::vector<int> index(s.n, 0);
    for (;;) {
        Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(s.n));
        for (std::size_t k = 0; k < s.n; ++k)
            if (!s.free[k]) q(Eigen::Index(k)) = -search.range + 2 * search.range * (index[k] + 0.5) / per;
        if (auto c = set.newton(q, continuum); c && c->q.cwiseAbs().maxCoeff() <= search.range * (1 + 1e-9))
            add(found, std::move(*c));
        std::size_t k = 0;
        while (k < s.n && (s.free[k] || ++index[k] == per)) index[k++] = 0;
        if (k == s.n) break;
    }
    return found;
}

// Eigenvalues of the symmetric matrix Zᵀ H Z, ascending.
std::vector<double> reduced_eigenvalues(const Eigen::MatrixXd& H, const Eigen::MatrixXd& Z) {
    if (Z.cols() == 0) return {};
    const Eigen::MatrixXd R = Z.transpose() * H * Z;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig((R + R.transpose()) / 2, Eigen::EigenvaluesOnly);
    return {eig.eigenvalues().data(), eig.eigenvalues().data() + eig.eigenvalues().size()};
}

KktEquilibrium classify(const System& s, Evaluation& at, const KktPoint& p, double lambda_zero) {
    KktEquilibrium e{p, KktKind::interior, "", "", {}};
    Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(p.q.data(), Eigen::Index(p.q.size()));
    at.set(q);
    // Over the non-free coordinates (a free one only moves the equilibrium along its family).
    std::vector<std::size_t> cols;
    for (std::size_t k = 0; k < s.n; ++k)
        if (!s.free[k]) cols.push_back(k);
    const Eigen::Index c = Eigen::Index(cols.size());
    const Eigen::MatrixXd K = at.matrix(s.force_q, s.n, s.n), G = at.matrix(s.force_qdot, s.n, s.n);
    // The Hessian of V − Σ λ_α f_α: −∂f/∂q − Σ λ_α ∂²f_α/∂q².
    Eigen::MatrixXd H_full = -K;
    std::vector<Eigen::RowVectorXd> pressing, slack;  // active normals with λ > 0, with λ = 0
    bool any_active = false;
    for (std::size_t a = 0; a < s.m; ++a) {
        if (!p.active[a]) continue;
        any_active = true;
        H_full -= p.lambda[a] * at.matrix(s.curvature, s.n, s.n, a * s.n * s.n);
        Eigen::RowVectorXd row(c);
        const Eigen::MatrixXd N = at.matrix(s.normal, 1, s.n, a * s.n);
        for (Eigen::Index j = 0; j < c; ++j) row(j) = N(0, Eigen::Index(cols[std::size_t(j)]));
        (p.lambda[a] > lambda_zero ? pressing : slack).push_back(row);
    }
    Eigen::MatrixXd H(c, c);
    for (Eigen::Index i = 0; i < c; ++i)
        for (Eigen::Index j = 0; j < c; ++j) H(i, j) = H_full(Eigen::Index(cols[std::size_t(i)]), Eigen::Index(cols[std::size_t(j)]));
    e.kind = !any_active ? KktKind::interior : slack.empty() ? KktKind::boundary : KktKind::degenerate;
    // The tangent space of the rows pressing (λ > 0): the kernel of their normals.
    Eigen::MatrixXd N(Eigen::Index(pressing.size()), c);
    for (std::size_t i = 0; i < pressing.size(); ++i) N.row(Eigen::Index(i)) = pressing[i];
    Eigen::MatrixXd Z = Eigen::MatrixXd::Identity(c, c);
    if (N.rows() > 0) {
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(N);
        Z = lu.rank() < c ? Eigen::MatrixXd(lu.kernel()) : Eigen::MatrixXd(c, 0);
        if (Z.cols() > 0) Z = Eigen::HouseholderQR<Eigen::MatrixXd>(Z).householderQ() * Eigen::MatrixXd::Identity(c, Z.cols());
    }
    e.curvature = reduced_eigenvalues(H, Z);
    const double tol = 1e-9 * (1.0 + H.cwiseAbs().maxCoeff());
    const bool gyroscopic = G.cwiseAbs().maxCoeff() > 1e-10 * (1.0 + s.scale);
    if (Z.cols() == 0) {
        e.verdict = "stable";
        e.reason = "the normals of the rows pressing (λ > 0) span the configuration space: V increases along "
                   "every admissible displacement, a strict minimum on first order alone";
    } else if (e.curvature.front() > tol) {
        e.verdict = "stable";
        e.reason = e.kind == KktKind::interior ? "∂²V/∂q² positive definite: a strict minimum of V (Lagrange–Dirichlet)"
                                               : "∂²(V − λ·f)/∂q² positive definite on the tangent space of the rows "
                                                 "pressing: a strict minimum of V on the admissible set";
    } else if (e.kind == KktKind::degenerate) {
        e.verdict = "undecided";
        e.reason = "a row is active with λ = 0 and ∂²(V − λ·f)/∂q² is not positive definite on the tangent space of "
                   "the rows pressing: the second-order test on the critical cone is not done here";
    } else if (e.curvature.front() < -tol && !gyroscopic) {
        e.verdict = "unstable";
        e.reason = e.kind == KktKind::interior ? "∂²V/∂q² has a negative eigenvalue: not a minimum of V, and without "
                                                 "gyroscopic forces the linearisation grows"
                                               : "∂²(V − λ·f)/∂q² has a negative eigenvalue on the tangent space of the "
                                                 "rows pressing: the motion along the boundary grows";
    } else {
        e.verdict = "undecided";
        e.reason = gyroscopic ? "not a minimum of V, and the gyroscopic forces at rest may stabilise it"
                              : "a zero eigenvalue of the Hessian: the second-order test does not decide";
    }
    return e;
}

std::string number_list(const std::vector<std::string>& names, const std::vector<double>& values) {
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i) out += fmt::format("{}{} = {:.6g}", i ? ", " : "", names[i], values[i]);
    return out;
}

}  // namespace

UnilateralEquilibria kkt_equilibria(const model::Model& model, const Equations& eqs, const KktSearch& search) {
    const System s = system_of(model, eqs);
    UnilateralEquilibria out;
    for (const auto& row : eqs.unilateral) out.rows.push_back(row.row.name);
    out.gaps = s.gap;
    for (const ex& f : s.force) out.gradient.push_back(-f);
    out.potential = potential_of(model, s);
    Evaluation at(model, s);

    // Every active set of at most n rows (more normals than coordinates are dependent: such a
    // vertex is found as a degenerate point of a smaller set, λ = 0 on the rows left out).
    struct Found {
        KktPoint point;
        std::size_t active_rows;
    };
    std::vector<Found> all;
    const std::size_t sets = std::size_t(1) << s.m;
    for (std::size_t mask = 0; mask < sets; ++mask) {
        std::vector<std::size_t> rows;
        for (std::size_t a = 0; a < s.m; ++a)
            if (mask >> a & 1) rows.push_back(a);
        if (rows.size() > s.n) continue;
        const ActiveSet set(s, at, rows);
        bool continuum = false;
        for (const Candidate& c : solve_set(model, s, set, search, out.closed_form_complete, continuum)) {
            KktPoint p;
            p.q.assign(c.q.data(), c.q.data() + c.q.size());
            p.free = s.free;
            p.active.assign(s.m, false);
            p.lambda.assign(s.m, 0.0);
            at.set(c.q);
            for (std::size_t a = 0; a < s.m; ++a) p.gap.push_back(at.matrix(s.gap, 1, 1, a)(0, 0));
            for (std::size_t i = 0; i < rows.size(); ++i) {
                p.active[rows[i]] = true;
                p.lambda[rows[i]] = c.lambda(Eigen::Index(i));
                p.gap[rows[i]] = 0.0;  // solved for: round-off
            }
            if (c.exact) {
                for (const auto& sym : s.q) p.exact_q.push_back(c.exact->at(sym));
                for (std::size_t a = 0; a < s.m; ++a) p.exact_lambda.push_back(p.active[a] ? c.exact->at(s.lambda[a]) : ex(0));
            }
            all.push_back({std::move(p), rows.size()});
        }
        if (continuum) out.closed_form_complete = false;
    }

    // A point on a boundary with λ = 0 is found by both sets: the larger one names it.
    std::stable_sort(all.begin(), all.end(), [](const Found& a, const Found& b) { return a.active_rows > b.active_rows; });
    std::vector<Eigen::VectorXd> seen;
    for (const Found& f : all) {
        const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(f.point.q.data(), Eigen::Index(f.point.q.size()));
        if (std::any_of(seen.begin(), seen.end(), [&](const Eigen::VectorXd& o) { return same_point(o, q); })) continue;
        seen.push_back(q);
        // λ and f to round-off of the forces: their residual tolerance, scaled by |∂f_α/∂q| for f.
        double lambda_scale = 1.0 + s.scale;
        for (double l : f.point.lambda) lambda_scale = std::max(lambda_scale, std::abs(l));
        const double lambda_zero = 1e-8 * lambda_scale, gap_zero = 1e-8 * (1.0 + q.norm());
        std::vector<std::string> negative, violated;
        std::vector<double> negative_values, violated_values;
        for (std::size_t a = 0; a < s.m; ++a) {
            if (f.point.active[a] && f.point.lambda[a] < -lambda_zero)
                negative.push_back("λ_" + out.rows[a]), negative_values.push_back(f.point.lambda[a]);
            if (!f.point.active[a] && f.point.gap[a] < -gap_zero)
                violated.push_back(out.rows[a]), violated_values.push_back(f.point.gap[a]);
        }
        if (!negative.empty() || !violated.empty()) {
            std::string reason;
            if (!negative.empty())
                reason = fmt::format("λ < 0 ({}): the wall would have to pull", number_list(negative, negative_values));
            if (!violated.empty())
                reason += fmt::format("{}outside the admissible set ({} < 0)", reason.empty() ? "" : "; ",
                                      number_list(violated, violated_values));
            out.rejected.push_back({f.point, reason});
            continue;
        }
        out.equilibria.push_back(classify(s, at, f.point, lambda_zero));
    }
    auto by_q = [](const auto& a, const auto& b) { return a.point.q < b.point.q; };
    std::sort(out.equilibria.begin(), out.equilibria.end(), by_q);
    std::sort(out.rejected.begin(), out.rejected.end(), by_q);
    return out;
}

}  // namespace eomc::mechanics::unilateral
