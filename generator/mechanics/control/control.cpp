#include "mechanics/control/control.hpp"

#include <algorithm>
#include <cmath>
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
    return points;
}

// A program on a rigid body's angular velocity (Mei §3.2), φ(ω, γ, t) = 0, as a row over the
// velocity block ω of Euler's equations I ω̇ = f: W = ∂φ/∂ω (Ā's row) and the bias
// ∂φ/∂t + ∂φ/∂γ · γ̇ with Poisson's γ̇ = γ × ω, so that φ̇ = W ω̇ + bias.
ConstraintRow rigid_row(const model::Model& model, const model::Program& given) {
    const model::RigidBody& body = *model.rigid;
    ConstraintRow row;
    row.name = given.name;
    row.holonomic = false;
    row.position = 0;
    row.velocity = given.expression;
    row.pos = given.pos;
    const model::Vec3 gamma_rate = symbolic::cross(body.gamma_vector(), body.omega_vector());
    row.bias = symbolic::derivative(given.expression, model.t);
    for (std::size_t i = 0; i < 3; ++i) {
        row.W.push_back(symbolic::derivative(given.expression, body.omega[i]));
        row.bias += symbolic::derivative(given.expression, body.gamma[i]) * gamma_rate[i];
    }
    row.bias = row.bias.expand();
    return row;
}

// Ā M⁻¹ D and Ā at a probe point (NaN entries read as 0: a pole is not a rank).
struct AtPoint {
    Eigen::MatrixXd A, AMD;
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
    Eigen::Index column = 0;
    for (Eigen::Index a = 0; a < m; ++a) {
        for (Eigen::Index j = 0; j < n; ++j) A(a, j) = value(rows[std::size_t(a)].row.W[std::size_t(j)]);
        for (const auto& d : rows[std::size_t(a)].columns) {
            for (Eigen::Index j = 0; j < n; ++j) D(j, column) = value(d[std::size_t(j)]);
            ++column;
        }
    }
    return {A, A * M.ldlt().solve(D)};
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
    if (all_ideal(rows)) return rows;  // dependent ideal programs: Udwadia–Kalaba (redundant_ideal)
    if (generic_rank(AMD) < Eigen::Index(m))
        throw InputError(rows.front().control_pos,
                         fmt::format("the programs {} are not realisable by these controls: Ā M⁻¹ D is singular at "
                                     "every probe point (underactuated: the controls' directions do not reach the "
                                     "programs' accelerations); choose other directions or actuated coordinates",
                                     program_names(rows)));
    return rows;
}

bool redundant_ideal(const model::Model& model, const Equations& eqs) {
    if (eqs.programs.empty() || !all_ideal(eqs.programs)) return false;
    const auto points = control_points(model);
    std::vector<Eigen::MatrixXd> A;
    for (const auto& point : points) A.push_back(at_point(eqs, eqs.programs, point).A);
    return generic_rank(A) < Eigen::Index(eqs.programs.size());
}

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
    unsigned column = 0;
    for (unsigned a = 0; a < m; ++a) {
        for (unsigned j = 0; j < n; ++j) r.A(a, j) = rows[a].row.W[j];
        r.c(a, 0) = rows[a].target;
        for (const auto& d : rows[a].columns) {
            for (unsigned j = 0; j < n; ++j) r.D(j, column) = d[j];
            ++column;
        }
    }
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
        // The singular set: the factors of the numerator that hold the state.
        GiNaC::lst state;
        for (const auto& c : model.coordinates) {
            state.append(c.q);
            state.append(c.q_dot);
        }
        if (model.rigid)
            for (std::size_t i = 0; i < 3; ++i) state.append(model.rigid->omega[i]).append(model.rigid->gamma[i]);
        const ex numerator = GiNaC::factor(GiNaC::numer(det));
        for (const ex& factor : symbolic::factors_of(numerator)) {
            const ex base = GiNaC::is_a<GiNaC::power>(factor) ? factor.op(0) : factor;
            bool holds_state = false;
            for (const ex& s : state) holds_state = holds_state || base.has(s);
            if (holds_state &&
                std::none_of(r.singular.begin(), r.singular.end(), [&](const ex& e) { return (e - base).is_zero(); }))
                r.singular.push_back(base);
        }
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

}  // namespace eomc::mechanics
