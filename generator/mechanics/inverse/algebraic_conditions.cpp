// The algebraic consequences of the Helmholtz conditions H1 and H2 for n degrees of freedom
// (Sarlet, J. Phys. A 15 (1982) 1503, §4): differentiating H1 (g Φ symmetric) along the motion
// and using H2 for dg/dt gives g ∇ᵏΦ symmetric for every k, with ∇X = dX/dt + ΓX − XΓ and
// Γ = −½ ∂f/∂q̇. These are pointwise linear conditions on the entries of g; when they leave
// only g = 0, or only singular g, no regular multiplier and so no regular Lagrangian exists
// (Douglas, Trans. Amer. Math. Soc. 50 (1941) 71, whose case IV is the first such system).
#include <algorithm>
#include <exception>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "mechanics/inverse/helmholtz.hpp"
#include "symbolic/expression_text.hpp"
#include "symbolic/numeric_probe.hpp"
#include "symbolic/simplify.hpp"

namespace eomc::mechanics::inverse::detail {

using namespace eomc::symbolic;

using GiNaC::ex;
using GiNaC::ex_to;
using GiNaC::matrix;
using GiNaC::symbol;

namespace {

// Expression nodes up to which the conditions are also solved exactly, for the reasoning steps.
constexpr std::size_t symbolic_limit = 600;

// A symmetric g of unknown entries g_ij (i ≤ j).
struct Unknowns {
    matrix G;
    std::vector<symbol> entries;
};

Unknowns symmetric_unknowns(const model::Model& model) {
    const unsigned n = unsigned(model.coordinates.size());
    Unknowns u{matrix(n, n), {}};
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i; j < n; ++j) {
            const std::string name = fmt::format("g_{}_{}", coordinate(model, i), coordinate(model, j));
            const std::string tex = fmt::format("g_{{{}{}}}", coordinate(model, i), coordinate(model, j));
            u.entries.emplace_back(name, tex);
            u.G(i, j) = u.G(j, i) = u.entries.back();
        }
    return u;
}

// The conditions gathered so far: each a row of coefficients on the unknown entries.
struct Conditions {
    std::vector<std::vector<ex>> rows;
    std::size_t size = 0;  // expression nodes in all rows
};

// The rank of the rows at random points: the generic rank (a non-zero minor at a point proves
// it is not lower).
std::size_t numeric_rank(const Conditions& c, std::size_t unknowns, const std::vector<ProbePoint>& points) {
    Eigen::Index best = 0;
    for (const auto& point : points) {
        Eigen::MatrixXd C(Eigen::Index(c.rows.size()), Eigen::Index(unknowns));
        for (std::size_t r = 0; r < c.rows.size(); ++r)
            for (std::size_t k = 0; k < unknowns; ++k) C(Eigen::Index(r), Eigen::Index(k)) = evaluate(c.rows[r][k], point);
        if (!C.allFinite()) continue;
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(C);
        const Eigen::VectorXd sigma = svd.singularValues();
        Eigen::Index rank = 0;
        for (Eigen::Index k = 0; k < sigma.size(); ++k)
            if (sigma(k) > 1e-9 * sigma(0)) ++rank;
        best = std::max(best, rank);
    }
    return std::size_t(best);
}

// The rows solved exactly, when small; trusted only when its rank agrees with the numeric one
// (a pivot that is zero but not recognised as zero would not).
std::optional<GiNaC::exmap> exact_solution(const Conditions& c, const std::vector<symbol>& unknowns, std::size_t rank) {
    if (c.rows.empty() || c.size > symbolic_limit) return std::nullopt;
    GiNaC::lst equations, vars;
    for (const auto& row : c.rows) {
        ex e = 0;
        for (std::size_t k = 0; k < unknowns.size(); ++k) e += row[k] * unknowns[k];
        equations.append(e == 0);
    }
    for (const auto& unknown : unknowns) vars.append(unknown);
    try {
        const ex s = GiNaC::lsolve(equations, vars);
        GiNaC::exmap sol;
        std::size_t determined = 0;
        for (std::size_t i = 0; i < s.nops(); ++i) {
            sol[s.op(i).op(0)] = simplified(s.op(i).op(1));
            if (!sol[s.op(i).op(0)].is_equal(s.op(i).op(0))) ++determined;
        }
        if (s.nops() == unknowns.size() && determined == rank) return sol;
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

// Level k: g X symmetric (X = ∇ᵏΦ), its non-trivial conditions appended to `c` and shown in the step.
Step level_conditions(const model::Model& model, std::size_t k, const Unknowns& u, const matrix& X, Conditions& c) {
    const unsigned n = unsigned(model.coordinates.size());
    const matrix GX = u.G.mul(X);
    Step step{k == 0 ? "H1: g Φ must be symmetric (pointwise conditions on the entries of g)"
                     : fmt::format("H1 differentiated along the motion {} time{}, with H2 for dg/dt: g ∇{}Φ must be "
                                   "symmetric, ∇X = dX/dt + ΓX − XΓ, Γ = −½ ∂f/∂q̇",
                                   k, k == 1 ? "" : "s", k == 1 ? "" : fmt::format("^{}", k)),
              {}};
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = i + 1; j < n; ++j) {
            const ex difference = (GX(i, j) - GX(j, i)).expand();
            std::vector<ex> row;
            ex condition = 0;
            for (const auto& unknown : u.entries) {
                row.push_back(simplified(difference.coeff(unknown, 1)));
                condition += row.back() * unknown;
                c.size += node_count(row.back());
            }
            if (std::all_of(row.begin(), row.end(), [](const ex& e) { return e.is_zero(); })) continue;
            step.equations.emplace_back(fmt::format("({0})_{1}{2} − ({0})_{2}{1}", k == 0 ? "gΦ" : "g∇Φ",
                                                    coordinate(model, i), coordinate(model, j)),
                                        condition);
            c.rows.push_back(std::move(row));
        }
    return step;
}

// ∇X = dX/dt + ΓX − XΓ, simplified.
matrix next_level(const model::Model& model, const std::vector<ex>& f, const matrix& X, const matrix& Gamma) {
    const unsigned n = X.rows();
    matrix next(n, n);
    const matrix commutator = Gamma.mul(X).sub(X.mul(Gamma));
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) next(i, j) = simplified(along_motion(model, f, X(i, j)) + commutator(i, j));
    return next;
}

std::size_t matrix_size(const matrix& X) {
    std::size_t size = 0;
    for (unsigned i = 0; i < X.rows(); ++i)
        for (unsigned j = 0; j < X.cols(); ++j) size += node_count(X(i, j));
    return size;
}

}  // namespace

// The rank of the conditions is taken at random points; when it reaches the number of entries
// only g = 0 is left. When the conditions are small enough they are also solved symbolically,
// for the reasoning steps, and a general solution with det g ≡ 0 proves singularity as well.
bool singular_forced(const model::Model& model, const std::vector<ex>& f, const SearchBudget& budget, Multiplier& m) {
    const Unknowns unknowns = symmetric_unknowns(model);
    const std::size_t u = unknowns.entries.size();
    const matrix Gamma = m.N.mul_scalar(ex(-1) / 2);
    const auto points = probe_points(model, 8, 0xd06145);
    Conditions conditions;

    matrix X = m.Phi;
    std::size_t previous_rank = 0;
    for (std::size_t k = 0; k < u; ++k) {
        Step step = level_conditions(model, k, unknowns, X, conditions);
        const std::size_t rank = conditions.rows.empty() ? 0 : numeric_rank(conditions, u, points);
        const auto solution = exact_solution(conditions, unknowns.entries, rank);
        if (step.equations.empty() || rank == previous_rank) {
            step.text += step.equations.empty() ? ": nothing new" : ": nothing new (implied by the conditions above)";
            step.equations.clear();
        } else if (solution) {
            std::string forced;
            for (const auto& unknown : unknowns.entries)
                if (!solution->at(unknown).is_equal(unknown))
                    forced += (forced.empty() ? "" : ", ") + text(unknown) + " = " + text(solution->at(unknown));
            step.text += "; so " + forced;
        } else {
            step.text += fmt::format("; the conditions so far have rank {} on the {} entries of g (at random points)", rank, u);
        }
        m.steps.push_back(std::move(step));
        if (rank == u) {
            m.steps.push_back({fmt::format("H1 and H2 leave only g = 0 ({0} independent conditions on the {0} entries), "
                                           "det g = 0. No regular multiplier exists, so no regular Lagrangian (Douglas).",
                                           u),
                               {}});
            return true;
        }
        if (rank == previous_rank) {
            // The conditions close: each level is the derivative of the one before (with H2
            // for dg/dt), so once a level adds nothing every later one adds nothing either
            // (Sarlet 1982, §4; Crampin et al., Inverse Problems 10 (1994) 245). H1–H2 then
            // leave a space of g of dimension u − rank at each point.
            m.steps.push_back({fmt::format("The algebraic conditions close at rank {} of {} (at random points): every "
                                           "further derivative along the motion is implied by them, so they leave "
                                           "g free in {} dimension{} at each point.",
                                           rank, u, u - rank, u - rank == 1 ? "" : "s"),
                               {}});
            return false;
        }
        previous_rank = rank;
        if (solution) {
            const matrix general = ex_to<matrix>(unknowns.G.subs(*solution));
            if (matrix_size(general) <= symbolic_limit && simplified(general.determinant()).is_zero()) {
                m.steps.push_back({fmt::format("Every g allowed by H1 and H2 is singular: g = {}, det g = 0. No regular "
                                               "multiplier exists, so no regular Lagrangian (Douglas).",
                                               matrix_text(general)),
                                   {}});
                return true;
            }
        }
        // Each derivative along the motion multiplies the size of ∇ᵏΦ by 10–20 for a
        // non-polynomial force (drag: exp and square roots of the state), so the next level is
        // only formed while the current one is within the budget.
        if (const std::size_t size = matrix_size(X); size > budget.nodes) {
            m.undecided = fmt::format("the algebraic consequences of H1–H2 were cut after {}Φ (rank {} of {}): it has "
                                      "{} expression nodes, over the budget of {} for forming the next derivative",
                                      k == 0 ? "" : k == 1 ? "∇" : fmt::format("∇^{}", k), rank, u, size, budget.nodes);
            m.steps.push_back({"Stopped: " + m.undecided, {}});
            return false;
        }
        X = next_level(model, f, X, Gamma);
    }
    return false;
}

}  // namespace eomc::mechanics::inverse::detail
