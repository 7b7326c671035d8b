// Conservation proofs: whether a candidate h(t, q, u) is constant along every motion of the
// equations. Invariants are never assumed; a chapter proposes a candidate (the Jacobi
// integral, an angular momentum) and keeps it only when one of these proves it.
#pragma once

#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// The velocities u (q̇, then a free carrier's quasi-velocities) with the residual E = lhs − rhs
// of the equation each one's rate comes from.
std::vector<std::pair<GiNaC::ex, GiNaC::ex>> velocity_residuals(const model::Model& model, const Equations& eqs);

// dh/dt = Σ u_s E_s identically: h is conserved along every motion (the equations are linear
// in u̇, so this is an identity in u̇ too). The power balance of a Jacobi-type integral.
bool proven_conserved(const model::Model& model, const Equations& eqs, const GiNaC::ex& h);

// dh/dt = 0 at states where u̇ solves M u̇ = f: h(t, q, q̇) is a first integral. For coordinates
// without quasi-velocities only (false otherwise).
bool proven_constant(const model::Model& model, const Equations& eqs, const GiNaC::ex& h);

}  // namespace eomc::mechanics
