#include "mechanics/control/control.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "mechanics/constraints/constraints.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"
#include "symbolic/vector3.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

namespace {

std::size_t column_count(const std::vector<ProgramRow>& rows) {
    std::size_t k = 0;
    for (const auto& p : rows) k += p.columns.size();
    return k;
}

// The probe points of the rank checks; a rigid body's ω and γ drawn too (γ on the unit sphere).
std::vector<symbolic::ProbePoint> control_points(const model::Model& model) {
    auto points = symbolic::probe_points(model, 4, 0xc047201);
    if (!model.rigid) return points;
    double x = 0.3;
    for (auto& point : points)
        for (std::size_t i = 0; i < 3; ++i) {
            x = std::fmod(x * 7.31 + 0.417, 1.0);  // a fixed sequence in [0, 1)
            point.values[model.rigid->omega[i]] = 2 * x - 1;
            point.values[model.rigid->gamma[i]] = std::sqrt(1.0 / 3.0) * (i == 1 ? -1 : 1);
        }
    if (model.rigid->attitude) {
        // A unit quaternion per point, away from the error quaternion's singular set δ0 = 0 of any
        // particular program (the points differ).
        for (auto& point : points) {
            std::array<double, 4> e{};
            double n = 0;
            for (auto& c : e) {
                x = std::fmod(x * 7.31 + 0.417, 1.0);
                c = 2 * x - 1;
                n += c * c;
            }
            for (std::size_t k = 0; k < 4; ++k) point.values[(*model.rigid->attitude)[k]] = e[k] / std::sqrt(n);
        }
    }
    return points;
}

// A program on a rigid body (Mei §3.2) as a row over the velocity block ω of Euler's equations
// I ω̇ = f. Its attitude (γ, and e in the quaternion formulation) moves by rates linear in ω
// (RigidBody::attitude_rates), so with v the program's first-order form — φ(ω, attitude, t) itself
// (phase space), or ω̇ = Σ ∂ω/∂s ṡ + ∂ω/∂t for an attitude program ω(attitude, t) (configuration
// space, v linear in ω) — the next derivative is v̇ = W ω̇ + bias with W = ∂v/∂ω (Ā's row) and
// bias = Σ ∂v/∂s ṡ + ∂v/∂t over the attitude's symbols s.
ConstraintRow rigid_row(const model::Model& model, const model::Program& given) {
    const model::RigidBody& body = *model.rigid;
    const auto kinematics = body.attitude_rates();
    const auto along = [&](const ex& h) {  // ∂h/∂t + Σ ∂h/∂s ṡ
        ex rate = symbolic::derivative(h, model.t);
        for (const auto& [s, s_dot] : kinematics) rate += symbolic::derivative(h, s) * s_dot;
        return rate.expand();
    };
    ConstraintRow row;
    row.name = given.name;
    row.holonomic = given.configuration;
    row.position = given.configuration ? given.expression : ex(0);
    row.velocity = given.configuration ? along(given.expression) : given.expression;
    row.pos = given.pos;
    row.bias = along(row.velocity);
    for (std::size_t i = 0; i < 3; ++i) row.W.push_back(symbolic::derivative(row.velocity, body.omega[i]).expand());
    return row;
}

// Ā M⁻¹ D and Ā at a probe point (NaN entries read as 0: a pole is not a rank).
struct AtPoint {
    Eigen::MatrixXd A, AMD;
    Eigen::VectorXd c;  // the targets, Ā q̈ = c
};

AtPoint at_point(const Equations& eqs, const std::vector<ProgramRow>& rows, const symbolic::ProbePoint& point) {
    const auto value = [&](const ex& e) {
        const double v = symbolic::evaluate(e, point);
        return std::isfinite(v) ? v : 0.0;
    };
    const Eigen::Index n = Eigen::Index(eqs.mass_matrix.rows()), m = Eigen::Index(rows.size()),
                       k = Eigen::Index(column_count(rows));
    Eigen::MatrixXd M(n, n), A(m, n), D(n, k);
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j) M(i, j) = value(eqs.mass_matrix(unsigned(i), unsigned(j)));
    Eigen::VectorXd c(m);
    Eigen::Index column = 0;
    for (Eigen::Index a = 0; a < m; ++a) {
        c(a) = value(rows[std::size_t(a)].target);
        for (Eigen::Index j = 0; j < n; ++j) A(a, j) = value(rows[std::size_t(a)].row.W[std::size_t(j)]);
        for (const auto& d : rows[std::size_t(a)].columns) {
            for (Eigen::Index j = 0; j < n; ++j) D(j, column) = value(d[std::size_t(j)]);
            ++column;
        }
    }
    return {A, A * M.ldlt().solve(D), c};
}

// The largest numeric rank over the points, each matrix scaled to unit size so that the
// threshold is relative.
Eigen::Index generic_rank(const std::vector<Eigen::MatrixXd>& at_points) {
    Eigen::Index best = 0;
    for (Eigen::MatrixXd X : at_points) {
        if (const double s = X.norm(); s > 0) X /= s;
        Eigen::FullPivLU<Eigen::MatrixXd> lu(X);
        lu.setThreshold(1e-9);
        best = std::max(best, lu.rank());
    }
    return best;
}

std::string program_names(const std::vector<ProgramRow>& rows) {
    std::string out;
    for (std::size_t i = 0; i < rows.size(); ++i)
        out += (i == 0 ? "'" : i + 1 == rows.size() ? " and '" : ", '") + rows[i].name() + "'";
    return out;
}

// What the controls act on, in words, for the underactuation refusal: the velocities that some
// column of D holds (coordinates, or a rigid body's axes) and the rank of D.
std::string controls_reach(const model::Model& model, const std::vector<ProgramRow>& rows,
                           const std::vector<symbolic::ProbePoint>& points) {
    const std::size_t nu = rows.front().row.W.size();
    std::vector<std::string> names;
    for (std::size_t j = 0; j < nu; ++j) {
        bool held = false;
        for (const auto& p : rows)
            for (const auto& d : p.columns) held = held || !d[j].is_zero();
        if (held)
            names.push_back(model.rigid ? fmt::format("axis {} ({})", j + 1, std::array{"p", "q", "r"}[j])
                                        : model.velocity_names()[j]);
    }
    std::vector<Eigen::MatrixXd> D;
    for (const auto& point : points) {
        Eigen::MatrixXd X(Eigen::Index(nu), Eigen::Index(column_count(rows)));
        Eigen::Index column = 0;
        for (const auto& p : rows)
            for (const auto& d : p.columns) {
                for (std::size_t j = 0; j < nu; ++j) {
                    const double v = symbolic::evaluate(d[j], point);
                    X(Eigen::Index(j), column) = std::isfinite(v) ? v : 0.0;
                }
                ++column;
            }
        D.push_back(X);
    }
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i) list += (i ? ", " : "") + names[i];
    const Eigen::Index rank = generic_rank(D);
    if (model.rigid)
        return fmt::format("the torques span {} body ax{} ({})", rank, rank == 1 ? "is" : "es", list);
    return fmt::format("the controls act in {} direction{} (on {})", rank, rank == 1 ? "" : "s", list);
}

bool all_ideal(const std::vector<ProgramRow>& rows) {
    return std::all_of(rows.begin(), rows.end(),
                       [](const ProgramRow& p) { return p.control == model::ProgramControl::ideal; });
}

// The rows without the rank checks.
std::vector<ProgramRow> build_rows(const model::Model& model) {
    std::vector<ProgramRow> rows;
    const std::size_t nu = model.rigid ? 3 : model.coordinates.size() + model.quasi_velocities.size();
    for (const auto& given : model.programs) {
        ProgramRow p;
        p.row = model.rigid ? rigid_row(model, given)
                            : constraint_row(model, given.name, given.configuration, given.expression, given.pos);
        p.configuration = given.configuration;
        p.closed_loop = given.closed_loop;
        p.alpha = given.alpha;
        p.beta = given.beta;
        p.kappa = given.kappa;
        p.control = given.control;
        p.pos = given.pos;
        p.control_pos = given.control_pos;
        // Galiullin's choice of Erugin's function: ω̈ = −2α ω̇ − β² ω, φ̇ = −κ φ.
        ex law = 0;
        if (given.closed_loop)
            law = given.configuration ? 2 * ex(given.alpha) * p.row.velocity + ex(given.beta * given.beta) * p.row.position
                                      : ex(given.kappa) * p.row.velocity;
        p.target = -p.row.bias - law;
        switch (given.control) {
            case model::ProgramControl::ideal:
                // Ā's row: the gradient ∂ω/∂q, or Chetaev's ∂φ/∂q̇.
                p.columns.push_back(p.row.W);
                p.column_names.push_back("lambda_" + given.name);
                break;
            case model::ProgramControl::directions:
            case model::ProgramControl::moment: {
                std::vector<ex> d(nu, 0);
                std::copy(given.direction.begin(), given.direction.end(), d.begin());
                p.columns.push_back(d);
                p.column_names.push_back("lambda_" + given.name);
                break;
            }
            case model::ProgramControl::actuated:
                for (std::size_t k : given.actuated) {
                    std::vector<ex> d(nu, 0);
                    d[k] = 1;
                    p.columns.push_back(d);
                    p.column_names.push_back(given.actuated.size() == 1
                                                 ? "lambda_" + given.name
                                                 : "lambda_" + given.name + "_" + model.coordinates[k].name);
                }
                break;
        }
        rows.push_back(std::move(p));
    }
    return rows;
}

}  // namespace

std::vector<ProgramRow> program_rows(const model::Model& model, const Equations& eqs) {
    std::vector<ProgramRow> rows = build_rows(model);
    if (rows.empty()) return rows;
    const std::size_t m = rows.size(), k = column_count(rows), n = eqs.mass_matrix.rows();
    if (m > n)
        throw InputError(rows[n].pos, fmt::format("{} programs for {} coordinates: the programs {} cannot all be "
                                                  "independent relations of the motion",
                                                  m, n, program_names(rows)));
    if (k > m) {
        const auto wide = std::find_if(rows.begin(), rows.end(), [](const ProgramRow& p) { return p.columns.size() > 1; });
        throw InputError(wide->control_pos,
                         fmt::format("the programs {} bring {} controls for {} programs: λ is not determined by "
                                     "Ā M⁻¹ D λ = c − Ā M⁻¹ f; actuate one coordinate per program",
                                     program_names(rows), k, m));
    }
    const auto points = control_points(model);
    std::vector<Eigen::MatrixXd> AMD;
    for (const auto& point : points) AMD.push_back(at_point(eqs, rows, point).AMD);
    for (const auto& p : rows)
        if (std::all_of(p.row.W.begin(), p.row.W.end(), [](const ex& w) { return w.is_zero(); }))
            throw InputError(p.pos, fmt::format("the program '{}' does not reach the accelerations (its row of Ā "
                                                "vanishes): no force can steer it",
                                                p.name()));
    if (all_ideal(rows)) {
        // Dependent ideal programs are realised by Udwadia and Kalaba's pseudo-inverse (Analytical
        // Dynamics: A New Approach, 1996, ch. 2), which needs Ā q̈ = c to be consistent: c in the
        // range of Ā wherever the programs are dependent. Two laws imposed on one relation (the same
        // ω with other gains, or ω and 2ω with different α, β) are not, off the programs, and the
        // pseudo-inverse would silently realise a least-squares compromise that follows neither law.
        for (const auto& point : points) {
            const AtPoint at = at_point(eqs, rows, point);
            Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(at.A);
            cod.setThreshold(1e-9);
            if (cod.rank() == Eigen::Index(m)) continue;  // independent here: any c is reached
            const Eigen::VectorXd x = cod.solve(at.c);
            const double scale = at.c.norm() + at.A.norm() * x.norm();
            if (const double miss = (at.A * x - at.c).norm(); scale > 0 && miss > 1e-8 * scale)
                throw InputError(rows.back().pos,
                                 fmt::format("the ideal programs {} are dependent (Ā has rank {} < {}) but their "
                                             "laws contradict each other: Ā q̈ = c has no solution off the programs "
                                             "(|Ā q̈ − c| ≥ {:.3g} of its scale at a probe state), so no control "
                                             "realises both; give a relation written twice the same erugin gains, "
                                             "or drop the repeated program",
                                             program_names(rows), cod.rank(), m, miss / scale));
        }
        return rows;
    }
    if (const Eigen::Index rank = generic_rank(AMD); rank < Eigen::Index(m)) {
        // The first program whose row of Ā M⁻¹ D depends on the rows before it is where the scene
        // asks for more than the controls can give.
        std::size_t first = m - 1;
        for (std::size_t j = 1; j <= m; ++j) {
            std::vector<Eigen::MatrixXd> head;
            for (const auto& X : AMD) head.push_back(X.topRows(Eigen::Index(j)));
            if (generic_rank(head) < Eigen::Index(j)) {
                first = j - 1;
                break;
            }
        }
        throw InputError(rows[first].control_pos,
                         fmt::format("the program{} {} ask{} for {} independent acceleration{} but {}: Ā M⁻¹ D has "
                                     "rank {} < {} at every probe point (underactuated: the program '{}' is not "
                                     "reached independently); actuate another {} or drop a program",
                                     m == 1 ? "" : "s", program_names(rows), m == 1 ? "s" : "", m, m == 1 ? "" : "s",
                                     controls_reach(model, rows, points), rank, m, rows[first].name(),
                                     model.rigid ? "body axis" : "coordinate"));
    }
    return rows;
}

bool redundant_ideal(const model::Model& model, const Equations& eqs) {
    if (eqs.programs.empty() || !all_ideal(eqs.programs)) return false;
    const auto points = control_points(model);
    std::vector<Eigen::MatrixXd> A;
    for (const auto& point : points) A.push_back(at_point(eqs, eqs.programs, point).A);
    return generic_rank(A) < Eigen::Index(eqs.programs.size());
}

namespace {

// Ā (the rows' W), c (their targets) and D (each row's control columns, in row order).
void control_matrices(const std::vector<ProgramRow>& rows, unsigned n, Realisation& r) {
    const unsigned m = unsigned(rows.size());
    unsigned column = 0;
    for (unsigned a = 0; a < m; ++a) {
        for (unsigned j = 0; j < n; ++j) r.A(a, j) = rows[a].row.W[j];
        r.c(a, 0) = rows[a].target;
        for (const auto& d : rows[a].columns) {
            for (unsigned j = 0; j < n; ++j) r.D(j, column) = d[j];
            ++column;
        }
    }
}

// The state the singular set is a set of: the coordinates and their rates, a rigid body's ω, γ and
// attitude.
GiNaC::lst state_variables(const model::Model& model) {
    GiNaC::lst state;
    for (const auto& c : model.coordinates) {
        state.append(c.q);
        state.append(c.q_dot);
    }
    if (model.rigid) {
        for (std::size_t i = 0; i < 3; ++i) state.append(model.rigid->omega[i]).append(model.rigid->gamma[i]);
        if (model.rigid->attitude)
            for (const auto& e : *model.rigid->attitude) state.append(e);
    }
    return state;
}

// The singular set: the factors of det Ā M⁻¹ D's numerator (factored, `back` undoing its stand-ins)
// that hold the state.
std::vector<ex> singular_factors(const model::Model& model, const Equations& eqs, const ex& numerator,
                                 const GiNaC::exmap& back) {
    const GiNaC::lst state = state_variables(model);
    const unsigned n = eqs.mass_matrix.rows();
    std::vector<ex> singular;
    // |e|² and |γ|² are 1 on every state: not a singular set.
    std::vector<ex> unit_norms{model.rigid ? symbolic::dot(model.rigid->gamma_vector(), model.rigid->gamma_vector())
                                           : ex(0)};
    if (model.rigid && model.rigid->attitude) {
        ex n = 0;
        for (const auto& e : *model.rigid->attitude) n += e * e;
        unit_norms.push_back(n);
    }
    // M's principal minors are positive wherever M is (the kinetic energy is positive definite):
    // a factor that is one of them, up to a number, is no singular set (an actuated coordinate's
    // Ā M⁻¹ D = minor / det M).
    std::vector<ex> minors;
    for (unsigned i = 0; i < n; ++i) {
        minors.push_back(eqs.mass_matrix(i, i));
        for (unsigned j = i + 1; j < n; ++j)
            minors.push_back(eqs.mass_matrix(i, i) * eqs.mass_matrix(j, j) -
                             eqs.mass_matrix(i, j) * eqs.mass_matrix(j, i));
    }
    const auto is_minor = [&](const ex& base) {
        return std::any_of(minors.begin(), minors.end(), [&](const ex& minor) {
            const ex ratio = symbolic::normalized(base / minor);
            return GiNaC::is_a<GiNaC::numeric>(ratio) && !ratio.is_zero();
        });
    };
    for (const ex& factor : symbolic::factors_of(numerator)) {
        const ex base = (GiNaC::is_a<GiNaC::power>(factor) ? factor.op(0) : factor).subs(back);
        bool holds_state = false;
        for (const ex& s : state) holds_state = holds_state || base.has(s);
        if (model.rigid && std::any_of(unit_norms.begin(), unit_norms.end(),
                                       [&](const ex& n) { return (n - base).expand().is_zero(); }))
            holds_state = false;
        if (holds_state && is_minor(base)) holds_state = false;
        if (holds_state &&
            std::none_of(singular.begin(), singular.end(), [&](const ex& e) { return (e - base).is_zero(); }))
            singular.push_back(base);
    }
    return singular;
}

}  // namespace

Realisation realise(const model::Model& model, const Equations& eqs) {
    Realisation r;
    const auto& rows = eqs.programs;
    const unsigned m = unsigned(rows.size()), k = unsigned(column_count(rows)), n = eqs.mass_matrix.rows();
    r.programs = m;
    r.controls = k;
    r.velocities = n;
    r.A = GiNaC::matrix(m, n);
    r.D = GiNaC::matrix(n, k);
    r.c = GiNaC::matrix(m, 1);
    control_matrices(rows, n, r);
    r.redundant = redundant_ideal(model, eqs);
    if (r.redundant) {
        r.why_not = "the ideal programs are dependent (Ā has deficient rank): the control is Udwadia and Kalaba's "
                    "Q_c = M^(1/2) (Ā M^(-1/2))⁺ (c − Ā M⁻¹ f), formed at run time";
        return r;
    }
    if (n > 3 || m > 3) {
        r.why_not = fmt::format("M is {}×{} with {} programs (the closed form is printed up to 3×3)", n, n, m);
        return r;
    }
    constexpr std::size_t max_nodes = 4000;
    try {
        GiNaC::matrix f(n, 1);
        for (unsigned j = 0; j < n; ++j) f(j, 0) = eqs.forcing[j];
        const GiNaC::matrix M_inv = eqs.mass_matrix.inverse();
        const GiNaC::matrix AMi = r.A.mul(M_inv);
        const GiNaC::matrix G = AMi.mul(r.D);
        GiNaC::matrix G_normal(m, m);
        for (unsigned i = 0; i < m; ++i)
            for (unsigned j = 0; j < m; ++j) G_normal(i, j) = symbolic::normalized(G(i, j));
        r.AMD = G_normal;
        const ex det = symbolic::normalized(G_normal.determinant());
        r.determinant = det;
        if (det.is_zero()) {
            r.realisable = false;
            r.why_not = "det Ā M⁻¹ D vanishes identically";
            return r;
        }
        // Functions of the parameters (cos(slew/2)) stand in for symbols while factoring, which
        // GiNaC does over polynomials only.
        GiNaC::exmap stand_ins;
        const ex polynomial = GiNaC::numer(det).to_polynomial(stand_ins);
        GiNaC::exmap back;
        for (const auto& [s, e] : stand_ins) back[s] = e;
        const ex numerator = GiNaC::factor(polynomial);
        r.determinant = numerator.subs(back) / GiNaC::denom(det);  // printed factored
        r.singular = singular_factors(model, eqs, numerator, back);
        const GiNaC::matrix rhs = r.c.sub(AMi.mul(f));
        const GiNaC::matrix lambda = G_normal.inverse().mul(rhs);
        std::vector<ex> l, q;
        for (unsigned a = 0; a < m; ++a) {
            const ex value = symbolic::normalized(lambda(a, 0));
            if (symbolic::node_count(value) > max_nodes) {
                r.why_not = "λ is too large to print";
                return r;
            }
            l.push_back(value);
        }
        for (unsigned j = 0; j < n; ++j) {
            ex value = 0;
            for (unsigned a = 0; a < k; ++a) value += r.D(j, a) * l[a];
            q.push_back(symbolic::normalized(value));
        }
        r.lambda = l;
        r.Qc = q;
    } catch (const std::exception& e) {
        r.why_not = std::string("GiNaC could not form it: ") + e.what();
    }
    return r;
}

std::vector<std::complex<double>> residual_eigenvalues(const model::Program& p) {
    if (!p.closed_loop) return {};
    if (!p.configuration) return {-p.kappa};
    const double d = p.alpha * p.alpha - p.beta * p.beta;
    if (d < 0) return {{-p.alpha, std::sqrt(-d)}};
    return {-p.alpha - std::sqrt(d), -p.alpha + std::sqrt(d)};
}

}  // namespace eomc::mechanics
