// The inverse problem of Lagrangian mechanics (Mei, ch. 4): given equations of motion, are
// they the Euler–Lagrange equations of some L, possibly after multiplying them by a matrix
// g(t, q, q̇)? If so, build L and prove it. The public entry of mechanics/inverse/:
//
// 1. forms.hpp: the fundamental form A q̈ + B = 0 and the kinematic form q̈ = f.
// 2. santilli_conditions.hpp: Santilli's conditions S1–S5 of variational self-adjointness of
//    the fundamental form (Santilli, Foundations of Theoretical Mechanics I, 1978, ch. 2), each
//    as simplified residuals; a verdict (self-adjoint, not self-adjoint with a point where a
//    residual is non-zero, or undecided: residuals GiNaC cannot simplify that vanish at every
//    random point tried).
// 3. multiplier.hpp: when not self-adjoint, the Helmholtz conditions H1–H3 on a multiplier g
//    for the kinematic form (Douglas 1941; Sarlet, J. Phys. A 15 (1982) 1503): separable
//    solutions in one degree of freedom; in n, the algebraic consequences of H1–H2 (do they
//    force det g = 0?), then constant and diagonal multipliers.
// 4. construction.hpp: Santilli's construction L = K + D_k q̇_k + C for a self-adjoint
//    (possibly multiplied) fundamental form (Santilli 1978, ch. 3), then ε_i(L) = E_i checked.
//
// Every candidate (antiderivative, multiplier, Lagrangian) is checked by substitution before
// it is reported: a case the solver does not recognise is reported as not found, never as a
// wrong answer. The GiNaC tools this uses (simplified, antiderivative, potential, exp_of) are
// in symbolic/simplify.hpp and symbolic/integrate.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "mechanics/inverse/construction.hpp"
#include "mechanics/inverse/forms.hpp"
#include "mechanics/inverse/multiplier.hpp"
#include "mechanics/inverse/santilli_conditions.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse {

struct Alternative {           // a second Lagrangian from another member of the multiplier family
    GiNaC::matrix g;
    Construction construction;
};

struct Analysis {
    Forms forms;
    std::vector<Residual> conditions;
    Decision decision;
    std::optional<Multiplier> multiplier;          // searched when not self-adjoint (and allowed)
    std::optional<FundamentalForm> multiplied_form;
    std::vector<Residual> multiplied_conditions;   // Santilli's conditions of g (q̈ − f)
    std::optional<Construction> construction;      // when construct = true and a self-adjoint form is at hand
    std::optional<Alternative> alternative;        // non-uniqueness, when the constant multipliers allow it
    std::string reason;                            // one sentence: the outcome and why
};

// The whole analysis behind `eomc inverse`: the forms, Santilli's conditions and their verdict,
// the multiplier search when they fail (and [inverse] multiplier_search allows it), and the
// construction of L (when [inverse] construct allows it) with, for self-adjoint equations of
// several degrees of freedom, a second, inequivalent Lagrangian when a constant multiplier
// gives one.
Analysis analyse(const model::Model& model, const Equations& equations, const SearchBudget& budget = {});

}  // namespace eomc::mechanics::inverse
