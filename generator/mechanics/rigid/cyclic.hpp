// Cyclic (ignorable) coordinates and Routh's reduction (Mei, Special Topics in Analytical
// Mechanics, ch. 5; Whittaker, Analytical Dynamics, §38).
//
// A coordinate q_c absent from L = T − V and from every generalized force, with Q_c = 0, has the
// momentum p_c = ∂L/∂q̇_c constant along the motion (Noether's theorem for the translation of q_c).
// The absence is only the reason to propose p_c: each momentum is kept as an invariant only when
// mechanics/invariants proves it constant along the equations, never assumed.
//
// With the momenta fixed at constants β_c, Routh's function
//     R(q_r, q̇_r; β) = L − Σ_c β_c q̇_c,   q̇_c eliminated through p_c(q, q̇) = β_c
// (the sign of Whittaker §38; some books use −R) is a Lagrangian of the remaining coordinates:
//     d/dt ∂R/∂q̇_r − ∂R/∂q_r = Q_r,
// and each cyclic coordinate follows by a quadrature, q̇_c = −∂R/∂β_c.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::rigid {

struct CyclicCoordinate {
    std::string coordinate;
    std::size_t index = 0;  // in model.coordinates
    GiNaC::ex momentum;     // p_c = ∂L/∂q̇_c
    bool proven = false;    // constant along the equations (mechanics/invariants' prover)
};

// The coordinates of a model given by its energies (no free carrier) that appear in neither T,
// V nor any Q_s, with Q_c = 0 and no constraint row acting on them (W_αc = 0, so no reaction
// enters their equation); each with its momentum and whether the prover confirmed it.
std::vector<CyclicCoordinate> cyclic_coordinates(const model::Model& model, const Equations& eqs);

// The invariant's name for a cyclic coordinate's momentum: "momentum_<coordinate>".
std::string momentum_name(const std::string& coordinate);

// Appends the proven momenta to eqs.invariants (after the energy), unless a kernel column of that
// name already exists (a coordinate called momentum_x).
void add_cyclic_momenta(const model::Model& model, Equations& eqs);

struct ReducedEquation {
    std::string coordinate;
    GiNaC::ex lhs;  // ε_r(R) = d/dt ∂R/∂q̇_r − ∂R/∂q_r (with q̈_r)
    GiNaC::ex rhs;  // Q_r
};

struct RouthReduction {
    std::vector<CyclicCoordinate> cyclic;  // the proven ones only
    std::vector<GiNaC::symbol> beta;        // β_c, the momenta's constant values
    std::vector<GiNaC::ex> velocities;      // q̇_c as functions of (q_r, q̇_r, β)
    GiNaC::ex routhian;                     // R(q_r, q̇_r; β)
    std::vector<ReducedEquation> equations; // one per remaining coordinate
    bool done = false;
    std::string reason;                     // why not, when !done
};

// Routh's reduction over the proven cyclic coordinates (done = false with a reason when there are
// none, or when p_c = β_c cannot be solved for q̇_c). Creates symbols (β_c) and uses GiNaC's linear
// solver: call it for a report, after the kernel has been lowered, never on the way to a kernel.
RouthReduction routh_reduction(const model::Model& model, const Equations& eqs,
                               const std::vector<CyclicCoordinate>& cyclic);

}  // namespace eomc::mechanics::rigid
