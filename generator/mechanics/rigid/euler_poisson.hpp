// The heavy rigid body (and gyrostat) about a fixed point in Euler–Poisson form (Mei, ch. 5;
// Leimanis, The General Problem of the Motion of Coupled Rigid Bodies about a Fixed Point, 1965,
// §1): in body axes, with K = Iω + k the angular momentum (k a gyrostat's rotor),
//   I ω̇ = K × ω + P γ × r_c,      γ̇ = γ × ω,
// γ the upward vertical (fixed in space), P the weight, r_c the mass centre. Every formulation
// of the body (mechanics/rigid/formulation.hpp) is this system in other variables.
#pragma once

#include <array>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::rigid {

using Vec3 = model::Vec3;

struct EulerPoisson {
    Vec3 momentum;    // K = Iω + k
    Vec3 torque;      // P γ × r_c, gravity's moment about O
    Vec3 forcing;     // K × ω + P γ × r_c = I ω̇
    Vec3 omega_rate;  // ω̇ = I⁻¹(K × ω + P γ × r_c)
    Vec3 gamma_rate;  // γ̇ = γ × ω
    GiNaC::ex kinetic, potential;  // ½ ω·Iω, P r_c·γ
    // The classical integrals (Mei, ch. 5): energy ½ ω·Iω + P r_c·γ, area K·γ, geometric |γ|².
    std::vector<Invariant> integrals;
    // div of the field, expanded: 0 proves Jacobi's last multiplier is 1 (Whittaker, Analytical
    // Dynamics, §§118–119).
    GiNaC::ex divergence;
};

// The system of `body`, with the integrals kept only when proven along it.
EulerPoisson euler_poisson(const model::RigidBody& body);

// dh/dt along the Euler–Poisson field, expanded: zero exactly when h(ω, γ) is a first integral.
GiNaC::ex rate_along(const EulerPoisson& system, const model::RigidBody& body, const GiNaC::ex& h);

// The equations of a rigid-body model: Euler's three (I ω̇ = f) as the Equations record holds
// them, with the proven integrals (not for the euler_angles formulation: Lagrange's in φ, θ, ψ).
Equations derive_rigid(const model::Model& model);

// A body in Euler angles: the area integral and the searched ones, proven along the Euler–Poisson
// field, written in the angles and added to Lagrange's equations' invariants; one that is already
// there (K·γ is the cyclic φ's momentum) is named there instead.
void add_body_integrals_in_angles(const model::Model& model, Equations& eqs);

}  // namespace eomc::mechanics::rigid
