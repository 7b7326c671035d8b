// Santilli's conditions of variational self-adjointness of the fundamental form
// A(t,q,q̇) q̈ + B(t,q,q̇) = 0 (Santilli, Foundations of Theoretical Mechanics I, 1978, ch. 2:
// the conditions for systems linear in the accelerations; Mei, ch. 4): the equations are the
// Euler–Lagrange equations of some L, as they stand, exactly when, with D = ∂_t + q̇_k ∂/∂q_k,
//
//   S1 (i<j)      A_ij − A_ji
//   S2 (i; j<k)   ∂A_ij/∂q̇_k − ∂A_ik/∂q̇_j
//   S3 (i≤j)      ∂B_i/∂q̇_j + ∂B_j/∂q̇_i − 2 D A_ij
//   S4 (i<j; k)   ∂A_ik/∂q_j − ∂A_jk/∂q_i − ½ ∂/∂q̇_k (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)
//   S5 (i<j)      ∂B_i/∂q_j − ∂B_j/∂q_i − ½ D (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)
//
// all vanish. Each is computed as a simplified residual; the verdict comes from the residuals
// that do not simplify to 0, evaluated at random points.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/inverse/forms.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse {

struct Residual {
    std::string condition;            // "S1" … "S5"
    std::size_t i = 0, j = 0;
    std::optional<std::size_t> k;     // S2 and S4 only
    GiNaC::ex value;                  // simplified
    bool zero = false;                // simplified to 0
};

// "S3(x,y)", "S2(x;y,z)", "S4(x,y;z)" with the coordinate names.
std::string label(const model::Model& model, const Residual& r);

std::vector<Residual> santilli_conditions(const model::Model& model, const FundamentalForm& form);

enum class Verdict { self_adjoint, not_self_adjoint, undecided };

struct Decision {
    Verdict verdict = Verdict::undecided;
    // not_self_adjoint: a residual and a point where it is non-zero.
    std::size_t witness = 0;
    std::vector<std::pair<std::string, double>> point;  // t, q, q̇, parameters
    double witness_value = 0;
    // undecided: the residuals left, and how many random points each vanished at.
    std::vector<std::size_t> unresolved;
    std::size_t points_tried = 0;
};

// Self-adjoint when every residual simplified to 0; not self-adjoint with the first residual
// and random point where it is clearly non-zero; otherwise undecided.
Decision decide(const model::Model& model, const std::vector<Residual>& residuals);

}  // namespace eomc::mechanics::inverse
