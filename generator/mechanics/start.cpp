#include "mechanics/start.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

// The model's symbols by the names the kernel's parameters and state carry.
std::map<std::string, GiNaC::symbol> symbols_by_name(const model::Model& model) {
    std::map<std::string, GiNaC::symbol> out;
    for (const auto& p : model.parameters) out.emplace(p.name, p.symbol);
    for (const auto& c : model.coordinates) {
        out.emplace(c.name, c.q);
        out.emplace(c.name + "_dot", c.q_dot);
    }
    for (const auto& v : model.quasi_velocities) out.emplace(v.name, v.symbol);
    if (model.rigid) {
        for (std::size_t i = 0; i < 3; ++i) {
            out.emplace(model.rigid->omega[i].get_name(), model.rigid->omega[i]);
            out.emplace(model.rigid->gamma[i].get_name(), model.rigid->gamma[i]);
        }
        if (model.rigid->attitude)
            for (const auto& e : *model.rigid->attitude) out.emplace(e.get_name(), e);
    }
    return out;
}

double number(const ex& e, const GiNaC::exmap& values) {
    return model::value_and_magnitude(e, values).first;
}

// The rows' Jacobian W (m × n) at the start, each row checked not to vanish and then scaled to unit
// length, so that the rank threshold is relative to each row's own scale.
Eigen::MatrixXd scaled_jacobian(const Equations& eqs, const GiNaC::exmap& values, const std::string& at) {
    const std::size_t m = eqs.constraints.size(), n = eqs.constraints.front().W.size();
    Eigen::MatrixXd W(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n));
    for (std::size_t a = 0; a < m; ++a) {
        const ConstraintRow& row = eqs.constraints[a];
        // A row's W vanishes when every entry is zero to the tolerance the residual check holds the
        // start to (1e-9 of the magnitudes that cancel): ∂(f²)/∂q = 2 f ∂f/∂q is as small as f.
        bool vanishes = true;
        for (std::size_t k = 0; k < n; ++k) {
            const auto [value, size] = model::value_and_magnitude(row.W[k], values);
            if (!std::isfinite(value))
                throw InputError(row.pos, fmt::format("the Jacobian of the constraint '{}' does not evaluate to a real "
                                                      "number at the initial state {}",
                                                      row.name, at));
            W(Eigen::Index(a), Eigen::Index(k)) = value;
            vanishes = vanishes && std::abs(value) <= 1e-9 * size;
        }
        if (vanishes)
            throw InputError(row.pos, fmt::format("the Jacobian of the constraint '{}' vanishes at the initial state {} "
                                                  "(every dphi/du_k is 0 to 1e-9 of its terms): the row fixes no "
                                                  "direction of the reaction, so its multiplier is not determined; write "
                                                  "the constraint so that its gradient does not vanish where it holds "
                                                  "(f = 0, not f^2 = 0)",
                                                  row.name, at));
        W.row(Eigen::Index(a)) /= W.row(Eigen::Index(a)).norm();
    }
    return W;
}

// The numerical rank of the scaled rows (Golub and Van Loan, Matrix Computations, 4th ed., §5.4.1):
// σ_k > max(m, n) ε σ_1. Each scaled entry holds a rounding of order ε, so singular values below
// that bound cannot be told from zero (the threshold LAPACK's and NumPy's rank use).
Eigen::Index numerical_rank(const Eigen::MatrixXd& rows) {
    if (rows.rows() == 0) return 0;
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(rows).singularValues();
    const double threshold = double(std::max(rows.rows(), rows.cols())) * eps * s(0);
    Eigen::Index rank = 0;
    while (rank < s.size() && s(rank) > threshold) ++rank;
    return rank;
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& W, const std::vector<Eigen::Index>& which) {
    Eigen::MatrixXd out(Eigen::Index(which.size()), W.cols());
    for (std::size_t i = 0; i < which.size(); ++i) out.row(Eigen::Index(i)) = W.row(which[i]);
    return out;
}

// The first row that depends on the rows before it is refused, with the rows it depends on (those
// without which it would not).
void check_rank(const Equations& eqs, const GiNaC::exmap& values, const std::string& at) {
    const Eigen::MatrixXd W = scaled_jacobian(eqs, values, at);
    std::vector<Eigen::Index> independent;
    for (Eigen::Index k = 0; k < W.rows(); ++k) {
        std::vector<Eigen::Index> with = independent;
        with.push_back(k);
        if (numerical_rank(rows_of(W, with)) > Eigen::Index(independent.size())) {
            independent.push_back(k);
            continue;
        }
        std::string names;
        for (Eigen::Index j : independent) {
            std::vector<Eigen::Index> rest;
            for (Eigen::Index i : independent)
                if (i != j) rest.push_back(i);
            const Eigen::Index without = numerical_rank(rows_of(W, rest));
            rest.push_back(k);
            if (numerical_rank(rows_of(W, rest)) > without) names += fmt::format("'{}', ", eqs.constraints[std::size_t(j)].name);
        }
        const ConstraintRow& row = eqs.constraints[std::size_t(k)];
        throw InputError(row.pos, fmt::format("the constraint '{}' is linearly dependent on {} at the initial state {}: "
                                              "the rows' Jacobian dphi/du has rank {} < {} there (the constraint "
                                              "qualification fails), so the reactions are not determined; drop the "
                                              "row or start where the rows are independent",
                                              row.name, names.substr(0, names.size() - 2), at, independent.size(),
                                              independent.size() + 1));
    }
}

// M positive definite: its smallest eigenvalue above n ε λ_max, below which M is singular to
// working precision (its entries rounded to double, the symmetric eigensolver backward stable;
// Golub and Van Loan §8.1.2).
void check_mass_matrix(const model::Model& model, const Equations& eqs, const GiNaC::exmap& values,
                       const std::string& at) {
    const unsigned n = eqs.mass_matrix.rows();
    if (n == 0) return;
    Eigen::MatrixXd M(n, n);
    for (unsigned i = 0; i < n; ++i)
        for (unsigned j = 0; j < n; ++j) {
            M(i, j) = number(eqs.mass_matrix(i, j), values);
            if (!std::isfinite(M(i, j)))
                throw InputError(model.kinetic_pos,
                                 fmt::format("the mass matrix does not evaluate to real numbers at the initial state {} "
                                             "(entry ({},{}))",
                                             at, i + 1, j + 1));
        }
    const Eigen::VectorXd lambda =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues();
    const double largest = lambda.cwiseAbs().maxCoeff();
    if (!(lambda(0) > double(n) * eps * largest))
        throw InputError(model.kinetic_pos,
                         fmt::format("the mass matrix is not positive definite at the initial state {} (its smallest "
                                     "eigenvalue is {:.6g}, its largest in magnitude {:.6g}): the kinetic energy must be "
                                     "a positive definite form in the velocities; is a mass or a moment of inertia "
                                     "negative or zero, or is the start on a singular set of the coordinates?",
                                     at, lambda(0), largest));
}

}  // namespace

StartValues start_values(const model::Model& model, const std::vector<std::pair<std::string, double>>& overrides) {
    StartValues start{model::initial_values(model), true};
    const auto symbols = symbols_by_name(model);
    std::vector<std::pair<std::string, double>> all = overrides;
    const auto derived = model::initial_overrides(model, overrides);  // initial values as expressions
    all.insert(all.end(), derived.begin(), derived.end());
    for (const auto& [name, value] : all) {
        const auto found = symbols.find(name);
        if (found == symbols.end()) start.state_known = false;
        else start.values[found->second] = GiNaC::numeric(value);
    }
    return start;
}

void check_start(const model::Model& model, const Equations& eqs, const StartValues& start, const std::string& at) {
    model::check_inertias(model, start.values, at);
    if (!start.state_known) return;
    for (const auto& row : model.constraints) model::check_constraint_start(model, row, start.values, at);
    if (!eqs.constraints.empty()) check_rank(eqs, start.values, at);
    if (model.kind() == model::ModelKind::energies || model.kind() == model::ModelKind::rigid)
        check_mass_matrix(model, eqs, start.values, at);
}

}  // namespace eomc::mechanics
