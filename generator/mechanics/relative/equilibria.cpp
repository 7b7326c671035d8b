#include "mechanics/relative/equilibria.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/closed_form.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using namespace eomc::symbolic;

using GiNaC::ex;

namespace {

// The equations at rest and their first derivatives, ready to evaluate.
struct RestSystem {
    std::size_t n = 0;
    std::vector<ex> f;       // f(q, 0)
    std::vector<ex> M;       // M(q), row-major
    std::vector<ex> f_q;     // ∂f/∂q at q̇ = 0, row-major
    std::vector<ex> f_qdot;  // ∂f/∂q̇ at q̇ = 0, row-major
    // Coordinates that f(q, 0) does not contain (cyclic at rest: every value of theirs is as
    // much an equilibrium as any other) and equations that vanish at rest identically. When
    // they are equally many, the search runs over the rest, the free ones held at 0.
    std::vector<bool> free;
    std::vector<std::size_t> rows, columns;  // the equations and coordinates the search solves
    double scale = 0;  // the largest |f|, |∂f/∂q| seen at random points: the size of f where it is regular
};

RestSystem rest_system(const model::Model& model, const Equations& eqs) {
    RestSystem r;
    // An orbit scene has no carrier, and a point mass about a central body is at rest nowhere:
    // the central attraction −μq/|q|³ dominates every perturbation it takes, and only vanishes
    // in the limit at its singularity q = 0 (which the numeric search used to report).
    if (model.orbit)
        throw InputError(SourcePos{model.source, 0, 0},
                         fmt::format("'{}' is an orbit scene ([orbit]): `eomc equilibria` finds the relative equilibria "
                                     "of bodies carried by a steadily moving carrier (states at rest, f(q, 0) = 0), and "
                                     "a point mass about a central body has none (its only candidate is the "
                                     "singularity r = 0); use `eomc derive` or `eomc simulate` for an orbit",
                                     model.name));
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
    // Decided at random points (sin² + cos² need not cancel symbolically): zero to round-off
    // of the largest entry seen.
    const auto points = probe_points(model, 12);
    double scale = 0;
    for (const auto& at : points)
        for (const auto* group : {&r.f, &r.f_q})
            for (const ex& e : *group) scale = std::max(scale, std::abs(evaluate(e, at)));
    r.scale = scale;
    const double zero = 1e-10 * (1 + scale);
    auto vanishes = [&](const ex& e) {
        return std::all_of(points.begin(), points.end(), [&](const ProbePoint& at) { return std::abs(evaluate(e, at)) <= zero; });
    };
    r.free.assign(r.n, false);
    std::vector<std::size_t> rows, columns;
    for (std::size_t k = 0; k < r.n; ++k) {
        bool absent = true;
        for (std::size_t i = 0; i < r.n && absent; ++i) absent = vanishes(r.f_q[i * r.n + k]);
        r.free[k] = absent;
        if (!absent) columns.push_back(k);
    }
    for (std::size_t i = 0; i < r.n; ++i)
        if (!vanishes(r.f[i])) rows.push_back(i);
    if (rows.size() == columns.size()) {
        r.rows = rows;
        r.columns = columns;
    } else {
        r.free.assign(r.n, false);  // not square: search everything (a singular Jacobian finds nothing)
        for (std::size_t k = 0; k < r.n; ++k) r.rows.push_back(k), r.columns.push_back(k);
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
    const Eigen::Index m = Eigen::Index(r.rows.size());
    for (int iteration = 0; iteration < 60; ++iteration) {
        at.set(q);
        const Eigen::VectorXd F_all = at.vector(r.f);
        const Eigen::MatrixXd J_all = at.matrix(r.f_q, r.n);
        Eigen::VectorXd F(m);
        Eigen::MatrixXd J(m, m);
        for (Eigen::Index i = 0; i < m; ++i) {
            F(i) = F_all(Eigen::Index(r.rows[std::size_t(i)]));
            for (Eigen::Index j = 0; j < m; ++j)
                J(i, j) = J_all(Eigen::Index(r.rows[std::size_t(i)]), Eigen::Index(r.columns[std::size_t(j)]));
        }
        if (!F.allFinite() || !J.allFinite()) return false;
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
        if (!lu.isInvertible()) return false;
        const Eigen::VectorXd reduced = lu.solve(F);
        Eigen::VectorXd step = Eigen::VectorXd::Zero(q.size());
        for (Eigen::Index j = 0; j < m; ++j) step(Eigen::Index(r.columns[std::size_t(j)])) = reduced(j);
        q -= step;
        // Converged when the step is at round-off of q (quadratic convergence gets there in
        // a few iterations from a good start).
        if (step.norm() <= 1e-13 * (1.0 + q.norm())) return q.allFinite();
    }
    return false;
}

// The equations are regular at q: f, M and their derivatives finite, M invertible. A root of
// a numerator where a denominator vanishes too (a centre of attraction, 0/0) is a singular
// point of the equations, not an equilibrium.
bool regular_at(const RestSystem& r, Evaluation& at, const Eigen::VectorXd& q) {
    at.set(q);
    const Eigen::VectorXd F = at.vector(r.f);
    // Newton's steps also shrink to round-off next to a pole (−μq/|q|³: q → 1.5 q away from it,
    // or onto it from the side of a perturbation), with f there enormous, not zero: a root has
    // f at round-off of the size f has where the equations are regular.
    if (!(F.norm() <= 1e-8 * (1 + r.scale))) return false;
    const Eigen::MatrixXd M = at.matrix(r.M, r.n), Fq = at.matrix(r.f_q, r.n), Fv = at.matrix(r.f_qdot, r.n);
    if (!F.allFinite() || !M.allFinite() || !Fq.allFinite() || !Fv.allFinite()) return false;
    if (r.n == 0) return true;
    // Singular to round-off: the smallest singular value of M below ε·n times the largest.
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M);
    const Eigen::VectorXd sigma = svd.singularValues();
    return sigma(0) > 0 && sigma(sigma.size() - 1) > 1e-14 * double(r.n) * sigma(0);
}

// q enters e only through sin and cos of n q + (terms free of q), n an integer: e has period
// 2π in q.
bool only_through_sin_cos(const ex& e, const GiNaC::symbol& q) {
    if (!e.has(q)) return true;
    if (e.is_equal(q)) return false;
    if (GiNaC::is_a<GiNaC::function>(e)) {
        const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
        if (name == "sin" || name == "cos") {
            const ex argument = e.op(0), n = argument.diff(q);
            return GiNaC::is_a<GiNaC::numeric>(n) && GiNaC::ex_to<GiNaC::numeric>(n).is_integer() &&
                   !(argument - n * q).expand().has(q);
        }
    }
    for (std::size_t i = 0; i < e.nops(); ++i)
        if (!only_through_sin_cos(e.op(i), q)) return false;
    return true;
}

// Per coordinate: an angle, periodic in everything the equilibria and their stability are
// computed from (f, M, ∂f/∂q, ∂f/∂q̇ at rest).
std::vector<bool> angles(const model::Model& model, const RestSystem& r) {
    std::vector<bool> out;
    for (const auto& c : model.coordinates) {
        bool periodic = true;
        for (const auto* group : {&r.f, &r.M, &r.f_q, &r.f_qdot})
            for (const ex& e : *group) periodic = periodic && only_through_sin_cos(e, c.q);
        out.push_back(periodic);
    }
    return out;
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
    e.free = r.free;
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
        // Stiffness (symmetric part) over the coordinates that have one: a free coordinate only
        // drifts (a zero eigenvalue pair), which does not make the rest gyroscopic.
        const Eigen::Index m = Eigen::Index(r.columns.size());
        Eigen::MatrixXd K(m, m);
        for (Eigen::Index i = 0; i < m; ++i)
            for (Eigen::Index j = 0; j < m; ++j) {
                const auto a = Eigen::Index(r.columns[std::size_t(i)]), b = Eigen::Index(r.columns[std::size_t(j)]);
                K(i, j) = -(Fq(a, b) + Fq(b, a)) / 2;
            }
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> k(K);
        e.verdict = m == 0 || k.eigenvalues().minCoeff() > 0 ? "stable" : "gyroscopically stabilised";
    }
    return e;
}

// The value of a closed form at the parameters' defaults; nullopt when it is not real there.
std::optional<double> at_defaults(const model::Model& model, const ex& value) {
    return real_value(model.parameter_defaults(), value);
}

std::vector<GiNaC::symbol> coordinate_symbols(const model::Model& model) {
    std::vector<GiNaC::symbol> out;
    for (const auto& c : model.coordinates) out.push_back(c.q);
    return out;
}

// The rest conditions here are those of the free system: a constrained one rests where the
// applied forces balance the reactions, and with unilateral rows the equilibria are KKT points
// (λ ≥ 0 on the boundary); this search finds neither.
void refuse_rows(const model::Model& model) {
    if (!model.constraints.empty())
        throw InputError(model.constraints.front().pos,
                         fmt::format("`eomc equilibria` does not support constrained scenes ([[constraint]] '{}'): "
                                     "the rest conditions would need the reactions λ",
                                     model.constraints.front().name));
    if (!model.unilateral.empty())
        throw InputError(model.unilateral.front().pos,
                         fmt::format("`eomc equilibria` does not support unilateral constraints ([[unilateral]] '{}'): "
                                     "the rest conditions on the boundary would need the reactions lambda >= 0",
                                     model.unilateral.front().name));
}

// Newton's roots from a grid of starts, at most about 4000 of them whatever n is: each regular, in
// the range, and once.
std::vector<Eigen::VectorXd> newton_roots(const RestSystem& r, Evaluation& at, const EquilibriumSearch& search) {
    const std::size_t n = r.n;
    int per = search.starts_per_coordinate;
    while (per > 2 && std::pow(double(per), double(r.columns.size())) > 4000) --per;

    std::vector<Eigen::VectorXd> roots;
    std::vector<int> index(n, 0);
    for (;;) {
        Eigen::VectorXd q(static_cast<Eigen::Index>(n));
        for (std::size_t k = 0; k < n; ++k)
            q(Eigen::Index(k)) = r.free[k] ? 0.0 : -search.range + 2 * search.range * (index[k] + 0.5) / per;
        if (newton(r, at, q) && q.cwiseAbs().maxCoeff() <= search.range * (1 + 1e-9) && regular_at(r, at, q)) {
            const bool known = std::any_of(roots.begin(), roots.end(), [&](const Eigen::VectorXd& other) {
                return (other - q).norm() <= 1e-7 * (1.0 + q.norm());
            });
            if (!known) roots.push_back(q);
        }
        std::size_t k = 0;
        while (k < n && (r.free[k] || ++index[k] == per)) index[k++] = 0;
        if (k == n) break;
    }
    return roots;
}

// A closed form's values in the range: for a periodic coordinate every q + 2πk in [−range, range].
std::vector<std::vector<double>> images_in_range(const ClosedForm& form, const Eigen::VectorXd& q, double range) {
    std::vector<std::vector<double>> images(std::size_t(q.size()));
    for (std::size_t k = 0; k < images.size(); ++k) {
        const double base = q(Eigen::Index(k));
        if (!form.periodic[k]) {
            if (std::abs(base) <= range * (1 + 1e-9)) images[k].push_back(base);
            continue;
        }
        const double turn = 2 * std::numbers::pi;
        for (double v = base - turn * std::ceil((base + range) / turn); v <= range * (1 + 1e-9); v += turn)
            if (v >= -range * (1 + 1e-9)) images[k].push_back(v);
    }
    return images;
}

// The closed forms: each real one (at the defaults), with its images q + 2πk in the range
// for coordinates it reaches through sin/cos, names a numeric root or adds one Newton missed.
// `exact` holds per root its q, sin q, cos q in closed form, where known.
void add_closed_forms(const model::Model& model, const RestSystem& r, Evaluation& at, const EquilibriumSearch& search,
                      const TrigVariables& trig, std::vector<Eigen::VectorXd>& roots,
                      std::vector<std::optional<GiNaC::exmap>>& exact) {
    const std::size_t n = r.n;
    std::vector<ex> f_trig;
    for (const ex& e : r.f) f_trig.push_back(e.subs(trig.to_variables).expand());
    bool complete = true;
    for (const ClosedForm& form : ClosedFormSolver(coordinate_symbols(model), trig, model.parameter_defaults()).solve(f_trig, r.free, complete)) {
        Eigen::VectorXd q(static_cast<Eigen::Index>(n));
        bool real = true;
        for (std::size_t k = 0; k < n && real; ++k) {
            const auto v = at_defaults(model, form.q[k].q);
            real = v.has_value();
            if (real) q(Eigen::Index(k)) = *v;
        }
        if (!real) continue;
        const std::vector<std::vector<double>> images = images_in_range(form, q, search.range);
        std::vector<std::size_t> pick(n, 0);
        const bool any = std::all_of(images.begin(), images.end(), [](const auto& v) { return !v.empty(); });
        while (any) {
            Eigen::VectorXd point(static_cast<Eigen::Index>(n));
            GiNaC::exmap shifted = form.substitution;
            for (std::size_t k = 0; k < n; ++k) {
                point(Eigen::Index(k)) = images[k][pick[k]];
                const long turns = std::lround((images[k][pick[k]] - q(Eigen::Index(k))) / (2 * std::numbers::pi));
                shifted[model.coordinates[k].q] = (form.q[k].q + 2 * turns * GiNaC::Pi).eval();
            }
            // A root of a numerator only (a denominator vanishing too) is not an equilibrium: f
            // must vanish there to round-off of its terms, on the scale of ∂f/∂q times q.
            at.set(point);
            const double residual = at.vector(r.f).norm();
            const double scale = 1.0 + at.matrix(r.f_q, n).norm() * (1.0 + point.norm());
            auto it = std::find_if(roots.begin(), roots.end(), [&](const Eigen::VectorXd& other) {
                return (other - point).norm() <= 1e-7 * (1.0 + point.norm());
            });
            if (!(residual <= 1e-9 * scale) || !regular_at(r, at, point)) {
                // not an equilibrium at these parameters, or a singular point of the equations
            } else if (it == roots.end()) {
                roots.push_back(point);
                exact.push_back(shifted);
            } else if (!exact[std::size_t(it - roots.begin())]) {
                *it = point;  // the closed form evaluated: as accurate as Newton's root, and exact zeros stay zero
                exact[std::size_t(it - roots.begin())] = shifted;
            }
            std::size_t k = 0;
            while (k < n && ++pick[k] == images[k].size()) pick[k++] = 0;
            if (k == n) break;
        }
    }
}

// An angle's q and q + 2π are one configuration (θ = −π and θ = π are the top of the hoop):
// each root is taken to (−π, π] in its angles and reported once.
void fold_angles(const model::Model& model, const RestSystem& r, std::vector<Eigen::VectorXd>& roots,
                 std::vector<std::optional<GiNaC::exmap>>& exact) {
    const std::size_t n = r.n;
    const std::vector<bool> angle = angles(model, r);
    const double turn = 2 * std::numbers::pi;
    std::vector<Eigen::VectorXd> kept;
    std::vector<std::optional<GiNaC::exmap>> kept_exact;
    for (std::size_t i = 0; i < roots.size(); ++i) {
        Eigen::VectorXd q = roots[i];
        std::optional<GiNaC::exmap> form = exact[i];
        for (std::size_t k = 0; k < n; ++k) {
            if (!angle[k] || r.free[k]) continue;
            const double v = q(Eigen::Index(k));
            double w = std::remainder(v, turn);  // in [−π, π]
            if (w <= -std::numbers::pi * (1 - 1e-12)) w += turn;
            const long turns = std::lround((w - v) / turn);
            if (turns == 0) continue;
            q(Eigen::Index(k)) = v + double(turns) * turn;
            if (form) (*form)[model.coordinates[k].q] = ((*form)[model.coordinates[k].q] + 2 * turns * GiNaC::Pi).eval();
        }
        auto it = std::find_if(kept.begin(), kept.end(), [&](const Eigen::VectorXd& other) {
            return (other - q).norm() <= 1e-7 * (1.0 + q.norm());
        });
        if (it == kept.end()) {
            kept.push_back(q);
            kept_exact.push_back(form);
        } else if (form && !kept_exact[std::size_t(it - kept.begin())]) {
            kept_exact[std::size_t(it - kept.begin())] = form;
        }
    }
    roots = std::move(kept);
    exact = std::move(kept_exact);
}

}  // namespace

std::vector<Equilibrium> relative_equilibria(const model::Model& model, const Equations& eqs,
                                             const EquilibriumSearch& search) {
    refuse_rows(model);
    const RestSystem r = rest_system(model, eqs);
    Evaluation at(model);
    const std::size_t n = r.n;
    std::vector<Eigen::VectorXd> roots = newton_roots(r, at, search);
    const TrigVariables trig(coordinate_symbols(model));
    std::vector<std::optional<GiNaC::exmap>> exact(roots.size());  // per root: q, sin q, cos q in closed form
    add_closed_forms(model, r, at, search, trig, roots, exact);
    fold_angles(model, r, roots, exact);

    std::vector<std::size_t> order(roots.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return std::lexicographical_compare(roots[a].data(), roots[a].data() + roots[a].size(), roots[b].data(),
                                            roots[b].data() + roots[b].size());
    });
    std::vector<Equilibrium> out;
    for (std::size_t i : order) {
        Equilibrium e = classify(r, at, roots[i]);
        if (exact[i]) {
            for (const auto& c : model.coordinates) e.exact.push_back(exact[i]->at(c.q));
            // One coordinate: λ² = (∂f/∂q)/M at q*, when the velocities do not enter the linearisation.
            auto at_q = [&](const ex& v) { return v.subs(trig.to_variables).subs(*exact[i]); };
            if (n == 1 && at_q(r.f_qdot[0]).normal().is_zero())
                e.lambda_squared = (at_q(r.f_q[0]) / at_q(r.M[0])).normal();
        }
        out.push_back(std::move(e));
    }
    return out;
}

}  // namespace eomc::mechanics
