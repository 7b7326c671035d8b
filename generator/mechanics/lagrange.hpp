// Stage 3: Lagrange's equations of the model, M(q,t) q̈ = f(q,q̇,t).
//
// For carried particles the kinetic energy is split T = T_e + T_m + T_r (Mei, §1.1) and the
// inertial side of each equation is written as the sum of named effects (FORMULAS §1):
//   relative      ε_s(T_r)                       = Σ m_i a_r,i · e_is
//   translation   Σ m_i (v̇_o + ω × v_o) · e_is
//   euler         Σ m_i (ω̇ × r'_i) · e_is
//   centrifugal   Σ m_i (ω × (ω × r'_i)) · e_is
//   coriolis      Σ m_i 2 (ω × ṙ'_i) · e_is
// with e_is = ∂r'_i/∂q_s. The relative term is formed by projection (d'Alembert–Lagrange);
// it equals ε_s(T_r) identically (tested), and the projection keeps the expressions
// factored, which is what makes the generated code small. Effects the scene does not keep
// are never added, so nothing downstream can emit them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

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
};

// Throws InputError when M is singular (naming the coordinates involved).
Equations derive(const model::Model& model);

// The Euler operator ε_s(F) = d/dt ∂F/∂q̇_s − ∂F/∂q_s, d/dt acting on explicit t too.
GiNaC::ex euler_operator(const model::Model& model, const GiNaC::ex& F, std::size_t s);
// Total time derivative along a motion: ∂_t + Σ q̇_k ∂_{q_k} + Σ q̈_k ∂_{q̇_k} (+ Σ ν̇ ∂_ν over a
// free carrier's quasi-velocities).
GiNaC::ex total_derivative(const model::Model& model, const GiNaC::ex& F);

// A rigid body's orientation relative to the carrier, R = R_1 R_2 … R_m (carrier components =
// R · body components), and its angular velocity relative to the carrier in body axes.
struct BodyRotation {
    GiNaC::matrix R;
    model::Vec3 relative_angular_velocity;
};
BodyRotation body_rotation(const model::Model& model, const model::Particle& body);

// Kinetic energy parts of carried particles (FORMULAS §1); zero carrier motion when the
// model has no carrier.
struct EnergySplit {
    GiNaC::ex T_e, T_m, T_r;
};
EnergySplit split_kinetic_energy(const model::Model& model);

}  // namespace eomc::mechanics
