// The record every chapter's derivation returns: the equations of motion of a model as
// M(q, t) u̇ = f(q, u, t), with each coordinate's equation kept as the book writes it (inertial
// side, applied side, named effects), a free carrier's balance equations, and the invariants
// proven along the motion. Lowering, printing and the kernel read this record only.
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/constraints/rows.hpp"
#include "mechanics/control/rows.hpp"
#include "mechanics/unilateral/rows.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

struct EffectTerm {
    model::Effect effect;
    GiNaC::ex value;  // generalized inertial term, on the left side of the equation
};

struct Equation {
    std::string coordinate;
    GiNaC::ex lhs;       // inertial side: Σ kept effects, or ε_s(T) for a given Lagrangian
    GiNaC::ex rhs;       // applied side: Q_s + ε_s(V) (= Q_s − ∂V/∂q_s when V depends on q only)
    std::vector<EffectTerm> effects;  // the kept effects, in the canonical order (particles only)
    GiNaC::ex dT_dqdot;  // ∂T/∂q̇_s
};

// A set of states where the mass matrix is singular (mechanics/rigid/last_multiplier.hpp):
// indicator^order divides det M, so M⁻¹ blows up where indicator(t, q) = 0 (gimbal lock of
// Euler angles at sin θ = 0, the pole r = 0 of polar coordinates). The kernel carries the
// indicators so that a simulation stops before it reaches the set.
struct SingularSet {
    std::string condition;  // "sin(theta) = 0"
    GiNaC::ex indicator;    // sin(theta)
    int order = 1;          // its power in det M
};

struct Invariant {
    std::string name;         // "energy"
    GiNaC::ex value;
    std::string description;  // how it was formed, for the printer
};

// One of a free carrier's six balance equations (1.1.14)–(1.1.15), in carrier axes:
// force_i   (dP/dt + ω × P)_i           = V_i  (+ R_i when held)
// moment_i  (dK/dt + ω × K + v_o × P)_i = m⁰_i (+ N_i when held)
// with P = ∂T/∂v_o and K = ∂T/∂ω, T the kinetic energy of the whole system.
struct CarrierEquation {
    std::string name;        // force_1 … moment_3
    GiNaC::ex lhs;           // inertial side (contains q̈ and the quasi-velocities' rates)
    GiNaC::ex applied;       // V_i or m⁰_i
    bool held = false;       // the component is held at zero: the equation gives its reaction
    GiNaC::symbol reaction;  // R_i or N_i, the constraint's reaction (held components only)
    std::string quasi_velocity;  // otherwise: the quasi-velocity it determines
};

struct Equations {
    bool from_particles = false;  // T built from carried particles (T_e, T_m, T_r meaningful)
    bool has_carrier = false;
    GiNaC::ex T, T_e, T_m, T_r, V;
    std::vector<Equation> equations;   // one per coordinate, in declaration order
    std::vector<CarrierEquation> carrier_equations;  // a free carrier's six, force_1 … moment_3
    GiNaC::ex momentum[3], angular_momentum[3];      // a free carrier's P and K (about o)
    // Over the velocities u = (q̇, the quasi-velocities in model order): rows of the
    // coordinate equations, then of the carrier equations of the unknown quasi-velocities.
    GiNaC::matrix mass_matrix;         // M_sk = ∂(lhs_s − rhs_s)/∂u̇_k, symmetric
    std::vector<GiNaC::ex> forcing;    // f_s = −(lhs_s − rhs_s)|u̇=0
    std::vector<Invariant> invariants; // only those proven conserved along the equations
    std::vector<SingularSet> singular_sets;  // where det M = 0 (models given by their energies)
    // Bilateral constraint rows ([[constraint]]): the system is M u̇ − Wᵀλ = f, W u̇ = −bias;
    // mass_matrix and forcing above hold M and f without the reactions.
    std::vector<ConstraintRow> constraints;
    // Unilateral rows ([[unilateral]], Mei ch. 6): gaps f ≥ 0 or φ ≥ 0 with their restitutions. Off
    // the boundary they do nothing; M and f above are those of the free system.
    std::vector<UnilateralRow> unilateral;
    // Programs realised by control forces ([[program]], Mei ch. 3): M u̇ = f + D λ, Ā u̇ = c; M and f
    // above are those of the uncontrolled system. Ideal programs that are dependent are realised by
    // Udwadia and Kalaba's acceleration (redundant_programs).
    std::vector<ProgramRow> programs;
    bool redundant_programs = false;
};

}  // namespace eomc::mechanics
