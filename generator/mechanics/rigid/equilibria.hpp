// Permanent rotations of the heavy rigid body (and gyrostat) about a fixed point, and their
// linear stability (Staude, J. reine angew. Math. 113 (1894) 318–334; Leimanis 1965, §4;
// Mei, ch. 5). In the Euler–Poisson form (mechanics/rigid/euler_poisson.hpp)
//   I ω̇ = (Iω + k) × ω + P γ × r_c,      γ̇ = γ × ω,
// a uniform rotation about the vertical, ω = Ω γ with γ fixed, keeps γ̇ = γ × Ωγ = 0, and I ω̇ = 0
// asks for
//   Ω² γ × Iγ + Ω γ × k = P γ × r_c.                                              (S)
// Every term is orthogonal to γ, so (S) is two scalar equations for Ω. Without a rotor (k = 0),
// γ × Iγ ∥ γ × r_c is (γ × Iγ) × (γ × r_c) = det[γ, Iγ, r_c] γ = 0: the admissible verticals lie on
// Staude's cone det[γ, Iγ, r_c] = 0, and then Ω² = P (γ × r_c)·(γ × Iγ)/|γ × Iγ|² (a rotation when
// it is positive; Ω = 0 where γ ∥ r_c, the body at rest). With a rotor, writing [u, v] = γ·(u × v)
// and D(x, y) = det[γ, x, y]: crossing (S) with γ × Iγ and with γ × k gives
//   Ω = P D(Iγ, r_c) / D(Iγ, k),      P D(Iγ, r_c)² = D(r_c, k) D(Iγ, k),
// the gyrostat's (quartic) cone. On a principal axis, γ × Iγ = 0: with k = 0 the axis holds r_c
// (the "sleeping top": any Ω), with a rotor Ω = (γ × k)·(P γ × r_c)/|γ × k|² when that solves (S).
//
// Stability: the 6×6 Jacobian J of the field at (Ωγ, γ). The Casimirs |γ|² and K·γ (K = Iω + k)
// have gradients c with cᵀ J = 0 at an equilibrium (differentiate ∇C·f = 0), so J maps onto the
// tangent space T of their common level set (the symplectic leaf) and has two zero eigenvalues
// from the directions across it; J restricted to T (a 4×4 Hamiltonian matrix) holds the rest.
// All four on the imaginary axis (up to round-off) is "spectrally stable", else "unstable".
//
// The Lagrange case (A = B, r_c = (0, 0, z0), k = (0, 0, k3)) sleeping on its axis, γ = ±e3,
// ω = (0, 0, r0): the characteristic polynomial of the linearisation, λ² times a quartic in λ
// with only even powers, is derived by GiNaC; its roots λ² are real and ≤ 0 iff the discriminant
// of the quadratic in λ² is ≥ 0, and the discriminant's factor of odd multiplicity (squares and
// the positive moments dropped) is the criterion: for k = 0, γ = e3, C² r0² − 4 A P z0 > 0
// (Maievskii), eigenvalues ±i[(2A − C) r0 ± √(C² r0² − 4 A P z0)]/(2A), critical spin 2√(A P z0)/C.
#pragma once

#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics::rigid {

struct PermanentRotation {
    std::string label;                // "+e3", "−e1", "initial state", "axis 2 (+)", …
    std::array<double, 3> gamma{};    // the vertical, body axes (unit)
    double spin = 0;                  // Ω: ω = Ω γ
    bool any_spin = false;            // a family in Ω (a principal axis holding r_c, no rotor across it)
    std::vector<std::complex<double>> eigenvalues;  // of the 6×6 Jacobian (two zeros among them)
    std::vector<std::complex<double>> reduced;      // of J on the leaf's tangent space (4)
    std::string verdict;              // "spectrally stable" | "unstable"
};

// The Lagrange case's sleeping top, γ = sign e3, ω = (0, 0, spin): derived symbolically.
struct SleepingCriterion {
    int sign = 1;                    // γ = sign · e3
    GiNaC::symbol spin;              // r0
    GiNaC::symbol lambda;            // λ
    GiNaC::ex quartic;               // det(λ − J)/λ², even in λ, leading coefficient 1
    GiNaC::ex discriminant;          // of the quartic as a quadratic in λ²
    GiNaC::ex criterion;             // stable iff criterion > 0 (the discriminant's odd factors)
    std::optional<GiNaC::ex> critical_spin;  // the positive root r0 of the criterion, when it is r0² a + b
};

struct RigidEquilibria {
    bool gyrostat = false;           // k ≠ 0 (symbolically)
    GiNaC::ex cone;                  // det[γ, Iγ, r_c]; with a rotor P det[γ, Iγ, r_c]² − D(r_c, k) D(Iγ, k)
    GiNaC::ex spin_on_cone;          // Ω² (k = 0) or Ω (k ≠ 0) at a vertical on the cone
    double spin = 0;                 // the spin the principal-axis families were linearised at
    std::vector<PermanentRotation> rotations;  // about the principal axes, at the defaults
    std::optional<PermanentRotation> initial;  // the scene's initial state, when it is one
    std::string initial_note;                  // why it is not, otherwise
    std::vector<SleepingCriterion> lagrange;   // γ = ±e3, in the Lagrange case
};

// spin: Ω for the families (default: ω0·γ0 of the scene). Parameters at their defaults for the
// numbers; the cone and the criteria are symbolic. Throws std::logic_error without model.rigid.
RigidEquilibria rigid_equilibria(const model::Model& model, std::optional<double> spin = std::nullopt);

// The rotation ω = spin·γ about the vertical gamma (unit), linearised at the defaults. Does not
// check that it is one (see residual).
PermanentRotation linearise_rotation(const model::Model& model, const std::array<double, 3>& gamma, double spin);

// |I ω̇| at ω = spin·γ, γ (the defaults): zero at a permanent rotation.
double rotation_residual(const model::Model& model, const std::array<double, 3>& gamma, double spin);

// Ω² = P (γ × r_c)·(γ × Iγ)/|γ × Iγ|² at the defaults (k = 0), for a γ on Staude's cone.
double staude_spin_squared(const model::Model& model, const std::array<double, 3>& gamma);

// The Lagrange case's criterion, or nothing when the body is not in it.
std::optional<SleepingCriterion> sleeping_criterion(const model::Model& model, int sign);

}  // namespace eomc::mechanics::rigid
