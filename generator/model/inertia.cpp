// A body's inertia, checked wherever its values come from (the scene's defaults, --set, an
// ensemble member): positive principal moments that satisfy the triangle inequalities.
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "model/build_steps.hpp"
#include "support/diagnostic.hpp"

namespace eomc::model {

namespace {

// The principal moments A <= B <= C of `inertia` at `values` (refused at `pos` when it does not
// evaluate to real numbers), and whether they belong to a body: A > 0 and A + B >= C. With C = ∫(x² +
// y²) dm and so on, A + B − C = 2∫z² dm >= 0 about any point (Landau and Lifshitz, Mechanics, §32),
// the equality a lamina's. The eigenvalues of the symmetric 3×3 matrix are each within a small
// multiple of ε‖I‖ of the exact ones (a backward-stable solver, Weyl's bound: Golub and Van Loan,
// Matrix Computations, 4th ed., §8.1.2), the entries rounded to double once: a slack of 16 ε C keeps
// a lamina's equality and refuses any real violation.
void check_inertia(const GiNaC::matrix& inertia, const GiNaC::exmap& values, const SourcePos& pos,
                   const std::string& what, const std::string& at) {
    bool given = false;
    Eigen::Matrix3d I;
    for (unsigned i = 0; i < 3; ++i)
        for (unsigned j = 0; j < 3; ++j) {
            given |= !inertia(i, j).is_zero();
            const auto v = real_value(inertia(i, j), values);
            if (!v) throw InputError(pos, fmt::format("{} does not evaluate to real numbers {}", what, at));
            I(i, j) = v->to_double();
        }
    if (!given) return;  // none given (a prescribed carrier's)
    const Eigen::Vector3d m = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
    const double slack = 16 * std::numeric_limits<double>::epsilon() * std::abs(m(2));
    if (!(m(0) > 0))
        throw InputError(pos, fmt::format("the principal moments of {} are {:.6g}, {:.6g}, {:.6g} {}: a body's "
                                          "moments of inertia must be positive",
                                          what, m(0), m(1), m(2), at));
    if (!(m(0) + m(1) >= m(2) - slack))
        throw InputError(pos, fmt::format("the principal moments of {} are {:.6g}, {:.6g}, {:.6g} {}: they violate the "
                                          "triangle inequality A + B >= C ({:.6g} + {:.6g} < {:.6g}), which every body's "
                                          "moments satisfy (A + B - C = 2 ∫z² dm)",
                                          what, m(0), m(1), m(2), at, m(0), m(1), m(2)));
}

}  // namespace

void check_inertias(const Model& model, const GiNaC::exmap& values, const std::string& at) {
    if (model.rigid)
        check_inertia(model.rigid->inertia, values, model.rigid->inertia_pos, "the rigid body's inertia", at);
    for (const auto& body : model.particles)
        if (body.rigid)
            check_inertia(body.inertia, values, body.inertia_pos, fmt::format("the inertia of body '{}'", body.name), at);
    if (model.carrier) check_inertia(model.carrier->inertia, values, model.carrier->inertia_pos, "the carrier's inertia", at);
}

}  // namespace eomc::model
