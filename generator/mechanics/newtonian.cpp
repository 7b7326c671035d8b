#include "mechanics/newtonian.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "mechanics/differentiation.hpp"
#include "mechanics/numeric_probe.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

namespace {

// A must be regular for the accelerations to be determined. Singular at every one of a few
// random states (parameters at their defaults) means singular as a function, not an unlucky
// point; the symbolic determinant is quoted when it is small enough to print.
void require_regular(const model::Model& model, const GiNaC::matrix& A) {
    const std::size_t n = model.coordinates.size();
    Eigen::VectorXd null_direction;
    for (const auto& point : probe_points_at_defaults(model, 3, 0xa11ce)) {
        Eigen::MatrixXd a(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) a(Eigen::Index(i), Eigen::Index(j)) = evaluate(A(unsigned(i), unsigned(j)), point);
        if (!a.allFinite()) continue;
        // A need not be symmetric here (that is one of the questions `eomc inverse` asks):
        // singular values, not eigenvalues.
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
        const Eigen::VectorXd sigma = svd.singularValues();
        if (sigma(0) > 0 && sigma(Eigen::Index(n) - 1) > 1e-12 * sigma(0)) return;
        null_direction = svd.matrixV().col(Eigen::Index(n) - 1);
    }
    std::string names;
    for (std::size_t i = 0; i < n; ++i)
        if (null_direction.size() == 0 || std::abs(null_direction(Eigen::Index(i))) > 1e-6)
            names += (names.empty() ? "'" : ", '") + model.coordinates[i].name + "_ddot'";
    std::string det;
    if (n <= 3) det = fmt::format(" (det A = {})", [&] {
                          std::ostringstream os;
                          os << A.determinant().normal();
                          return os.str();
                      }());
    throw InputError(model.newtonian->pos,
                     fmt::format("the fundamental form A(t,q,q̇) q̈ + B = 0 has a singular A = ∂Φ/∂q̈{}: the equations "
                                 "do not determine {}",
                                 det, names));
}

}  // namespace

Equations derive_newtonian(const model::Model& model) {
    if (!model.newtonian) throw std::logic_error("derive_newtonian: the model has no [newtonian] equations");
    const model::Newtonian& given = *model.newtonian;
    const std::size_t n = model.coordinates.size();
    Equations eqs;
    eqs.T = eqs.T_e = eqs.T_m = eqs.T_r = eqs.V = 0;
    eqs.mass_matrix = GiNaC::matrix(unsigned(n), unsigned(n));
    GiNaC::exmap no_acceleration;
    for (const auto& c : model.coordinates) no_acceleration[c.q_ddot] = 0;
    for (std::size_t s = 0; s < n; ++s) {
        const auto& c = model.coordinates[s];
        Equation eq;
        eq.coordinate = c.name;
        eq.dT_dqdot = 0;
        if (given.fundamental) {
            eq.lhs = given.expressions[s];
            eq.rhs = 0;
            for (std::size_t k = 0; k < n; ++k)
                eqs.mass_matrix(unsigned(s), unsigned(k)) = derivative(given.expressions[s], model.coordinates[k].q_ddot);
            eqs.forcing.push_back(-given.expressions[s].subs(no_acceleration));
        } else {
            eq.lhs = c.q_ddot;
            eq.rhs = given.expressions[s];
            for (std::size_t k = 0; k < n; ++k) eqs.mass_matrix(unsigned(s), unsigned(k)) = s == k ? 1 : 0;
            eqs.forcing.push_back(given.expressions[s]);
        }
        eqs.equations.push_back(std::move(eq));
    }
    if (given.fundamental) require_regular(model, eqs.mass_matrix);
    return eqs;
}

}  // namespace eomc::mechanics
