#include "symbolic/regularity.hpp"

#include <cmath>

#include <Eigen/SVD>

#include "symbolic/numeric_probe.hpp"

namespace eomc::symbolic {

using namespace eomc::symbolic;

std::optional<std::vector<std::size_t>> singular_as_function(const model::Model& model, const GiNaC::matrix& A,
                                                             std::uint64_t seed) {
    const std::size_t n = A.rows();
    Eigen::VectorXd null_direction;
    for (const auto& point : probe_points_at_defaults(model, 3, seed)) {
        Eigen::MatrixXd a(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                a(Eigen::Index(i), Eigen::Index(j)) = evaluate(A(unsigned(i), unsigned(j)), point);
        if (!a.allFinite()) continue;
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
        const Eigen::VectorXd sigma = svd.singularValues();
        // Relative to the largest singular value: far above round-off, far below any real conditioning.
        if (sigma(0) > 0 && sigma(Eigen::Index(n) - 1) > 1e-12 * sigma(0)) return std::nullopt;
        null_direction = svd.matrixV().col(Eigen::Index(n) - 1);
    }
    std::vector<std::size_t> involved;
    for (std::size_t i = 0; i < n; ++i)
        if (null_direction.size() == 0 || std::abs(null_direction(Eigen::Index(i))) > 1e-6) involved.push_back(i);
    return involved;
}

}  // namespace eomc::symbolic
