#include "mechanics/inverse/given_equations.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/regularity.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using symbolic::derivative;

namespace {

// A must be regular for the accelerations to be determined; the symbolic determinant is quoted
// when it is small enough to print.
void require_regular(const model::Model& model, const GiNaC::matrix& A) {
    const std::size_t n = model.coordinates.size();
    const auto involved = symbolic::singular_as_function(model, A, 0xa11ce);
    if (!involved) return;
    std::string names;
    for (const std::size_t i : *involved) names += (names.empty() ? "'" : ", '") + model.coordinates[i].name + "_ddot'";
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

Equations derive_given_equations(const model::Model& model) {
    if (!model.newtonian) throw std::logic_error("derive_given_equations: the model has no [newtonian] equations");
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
