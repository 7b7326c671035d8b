// The spectrum of a linearisation and its verdict (Lyapunov's first method: the linear system
// decides unless eigenvalues lie on the imaginary axis; Chetaev, The Stability of Motion, ch. 2),
// judged on the system reduced by its ignorable coordinates (Routh's cyclic coordinates: their
// drift is a neighbouring steady motion, not an instability of this one).
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "mechanics/linearize/linearize.hpp"

namespace eomc::mechanics {

namespace {

using complex = std::complex<double>;

// The order the eigenvalues are listed in: decreasing real part, then decreasing imaginary part,
// real parts within `tolerance` of zero taken as zero (so ±iω pairs keep their order under
// round-off).
std::vector<std::size_t> listed_order(const Eigen::VectorXcd& values, double tolerance) {
    std::vector<std::size_t> order(std::size_t(values.size()));
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto key = [&](std::size_t i) {
        const complex v = values(Eigen::Index(i));
        return std::pair<double, double>(std::abs(v.real()) <= tolerance ? 0.0 : v.real(),
                                         std::abs(v.imag()) <= tolerance ? 0.0 : v.imag());
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) > key(b); });
    return order;
}

// Coordinates whose column is zero in every row still kept; each found sets its own row aside,
// which may free another (a sleigh's y carries its heading: y first, then the heading).
std::vector<std::size_t> ignorable_rows(const Eigen::MatrixXd& A, std::size_t coordinates, double zero) {
    std::vector<bool> removed(std::size_t(A.rows()), false);
    std::vector<std::size_t> found;
    for (bool again = true; again;) {
        again = false;
        for (std::size_t j = 0; j < coordinates; ++j) {
            if (removed[j]) continue;
            bool absent = true;
            for (Eigen::Index i = 0; i < A.rows() && absent; ++i)
                absent = removed[std::size_t(i)] || std::abs(A(i, Eigen::Index(j))) <= zero;
            if (absent) removed[j] = true, found.push_back(j), again = true;
        }
    }
    std::sort(found.begin(), found.end());
    return found;
}

// An eigenvalue on the axis whose geometric multiplicity is below its algebraic one (a Jordan
// block: δx grows like t^k); nullopt when all are semisimple.
std::optional<complex> defective_on_axis(const Eigen::MatrixXd& A, const Eigen::VectorXcd& values, double tolerance) {
    for (Eigen::Index i = 0; i < values.size(); ++i) {
        if (std::abs(values(i).real()) > tolerance) continue;
        Eigen::Index algebraic = 0;
        for (Eigen::Index j = 0; j < values.size(); ++j) algebraic += std::abs(values(j) - values(i)) <= tolerance;
        if (algebraic < 2) continue;
        const Eigen::MatrixXcd shifted = A.cast<complex>() - values(i) * Eigen::MatrixXcd::Identity(A.rows(), A.cols());
        const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(shifted);
        const Eigen::Index geometric = (svd.singularValues().array() <= tolerance).count();
        if (geometric < algebraic) return values(i);
    }
    return std::nullopt;
}

}  // namespace

void classify_linearization(Linearization& out) {
    const Eigen::MatrixXd& A = out.A;
    const std::size_t N = std::size_t(A.rows()), coordinates = out.independent_coordinates.size();
    // A perturbation of A of size ε‖A‖ (the eigensolver's backward error, and the round-off of the
    // entries) moves a simple eigenvalue by about ε‖A‖ and a double defective one by √ε‖A‖: real
    // parts within 8√ε‖A‖ of zero are on the axis, and entries within √ε of the largest are zero.
    const double norm = A.norm(), eps = std::numeric_limits<double>::epsilon();
    out.tolerance = 8 * std::sqrt(eps) * norm;
    out.eigenvalues.clear();
    out.modes.resize(Eigen::Index(N), Eigen::Index(N));
    out.ignorable.clear();
    if (N == 0) {
        out.verdict = LinearStability::stable_linear;
        out.reason = "no independent state: the rows fix the motion";
        return;
    }
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(A, true);
    const auto order = listed_order(eig.eigenvalues(), out.tolerance);
    for (std::size_t j = 0; j < N; ++j) {
        out.eigenvalues.push_back(eig.eigenvalues()(Eigen::Index(order[j])));
        Eigen::VectorXcd v = eig.eigenvectors().col(Eigen::Index(order[j]));
        Eigen::Index largest = 0;
        v.cwiseAbs().maxCoeff(&largest);
        if (std::abs(v(largest)) > 0) v /= v(largest);  // the largest component 1: a deterministic phase
        out.modes.col(Eigen::Index(j)) = v;
    }
    const std::vector<std::size_t> cyclic = ignorable_rows(A, coordinates, std::sqrt(eps) * A.cwiseAbs().maxCoeff());
    for (std::size_t j : cyclic) out.ignorable.push_back(out.independent_coordinates[j]);
    std::vector<Eigen::Index> kept;
    for (std::size_t i = 0; i < N; ++i)
        if (!std::binary_search(cyclic.begin(), cyclic.end(), i)) kept.push_back(Eigen::Index(i));
    const Eigen::MatrixXd reduced = A(kept, kept);
    const std::string scope = cyclic.empty() ? "" : " of the system without its ignorable coordinates";
    const Eigen::VectorXcd values = reduced.size() ? Eigen::VectorXcd(reduced.eigenvalues()) : Eigen::VectorXcd();
    double largest = -std::numeric_limits<double>::infinity();
    for (Eigen::Index i = 0; i < values.size(); ++i) largest = std::max(largest, values(i).real());
    if (values.size() && largest > out.tolerance) {
        out.verdict = LinearStability::unstable;
        out.reason = fmt::format("an eigenvalue{} has Re λ = {:.6g} > 0", scope, largest);
    } else if (values.size() && largest < -out.tolerance) {
        out.verdict = LinearStability::asymptotically_stable;
        out.reason = fmt::format("every eigenvalue{} has Re λ < 0 (the largest {:.6g})", scope, largest);
    } else if (const auto defective = defective_on_axis(reduced, values, out.tolerance)) {
        out.verdict = LinearStability::unstable;
        out.reason = fmt::format("the eigenvalue{} {:.6g}{:+.6g}i on the imaginary axis is defective (a Jordan block: "
                                 "the perturbation grows like a power of t)",
                                 scope, defective->real(), defective->imag());
    } else {
        out.verdict = LinearStability::stable_linear;
        out.reason = fmt::format("the eigenvalues{} on the imaginary axis are semisimple and none lies right of it; "
                                 "the nonlinear terms decide (a critical case of Lyapunov's first method)",
                                 scope);
    }
}

}  // namespace eomc::mechanics
