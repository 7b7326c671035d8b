// Bilateral constraints as rows of the equations of motion (Mei, §6.6 and ch. 3; Lur'e,
// Analytical Mechanics, ch. 2): each row α is either holonomic, f_α(q, t) = 0, or kinematic,
// φ_α = Σ_s B_αs(q, t) q̇_s + b_α(q, t) = 0, linear in the rates. Both reach the acceleration level
// as
//     φ̇_α = Σ_s W_αs q̈_s + bias_α(t, q, q̇),  W_αs = ∂f_α/∂q_s (holonomic) or B_αs (kinematic),
// and, with ideal reactions (Chetaev's for the kinematic rows), Lagrange's equations gain
// Σ_α λ_α W_αs on their applied side:
//     M q̈ − Wᵀ λ = f,   W q̈ = −bias − (stabilisation).
// This record is what the unilateral (ch. 6) and control (ch. 3) chapters reuse: a chapter that
// adds rows fills these fields and everything after mechanics follows.
#pragma once

#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "support/diagnostic.hpp"

namespace eomc::mechanics {

// How the integration keeps a row satisfied.
enum class Stabilization {
    project,    // the M-metric projection onto f = 0, then φ = 0, after every accepted step (default)
    baumgarte,  // φ̇ + 2α φ + β² f = 0 (holonomic) or φ̇ + α φ = 0 (kinematic) instead of φ̇ = 0
    none,       // φ̇ = 0 alone: the drift grows
};

struct ConstraintRow {
    std::string name;              // the scene's [[constraint]] name: λ is output as lambda_<name>
    bool holonomic = true;
    GiNaC::ex position;            // f(q, t) (holonomic rows; 0 for kinematic rows)
    GiNaC::ex velocity;            // φ(q, q̇, t): ḟ for a holonomic row, the row itself otherwise
    std::vector<GiNaC::ex> W;      // ∂φ/∂u_k over the velocities of M (q̇, then quasi-velocities)
    GiNaC::ex bias;                // φ̇ − W u̇: a function of (t, q, u)
    GiNaC::symbol lambda;          // λ_α, printed λ_<name>
    Stabilization stabilization = Stabilization::project;
    double alpha = 0.0, beta = 0.0;  // Baumgarte's constants
    SourcePos pos;                 // the row's expression in the scene
};

}  // namespace eomc::mechanics
