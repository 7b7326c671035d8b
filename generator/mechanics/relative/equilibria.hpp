// Relative equilibria of a steadily moving carrier (Mei §1.3): the states with q̇ = 0 that
// the equations keep at rest, f(q, 0) = 0 (the amended potential V − T_e is stationary
// when all effects are kept), and their linear stability.
//
// Linearising M q̈ = f about (q*, 0) gives M δq̈ = (∂f/∂q) δq + (∂f/∂q̇) δq̇; the
// velocity part holds the gyroscopic (Coriolis) coupling. The eigenvalues λ of the
// first-order system decide: any Re λ > 0 is unstable (growth rate Re λ); all on the
// imaginary axis is stable (frequencies |Im λ|), and "gyroscopically stabilised" when the
// stiffness −∂f/∂q alone is not positive definite.
//
// The equilibria are solved in closed form where the equations at rest allow it: each
// equation is factored (sin q and cos q taken as variables), and factors in one coordinate
// of the forms a q + b, a q² + b q + c, a sin q + b, a cos q + b, a cos² q + b cos q + c and
// a sin q + b cos q are solved and substituted into the remaining equations. Newton's
// method from a grid of starts finds the rest and confirms the closed forms numerically.
#pragma once

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"

namespace eomc::mechanics {

struct Equilibrium {
    std::vector<double> q;                          // in coordinate order
    std::vector<bool> free;                         // per coordinate: absent from f(q, 0), any value (q holds 0)
    std::vector<std::complex<double>> eigenvalues;  // of the linearised first-order system, 2n of them
    std::string verdict;                            // "stable" | "unstable" | "gyroscopically stabilised"
    std::vector<GiNaC::ex> exact;                   // q in closed form (parameters symbolic); empty if numeric only
    // One degree of freedom without velocity coupling: λ² = (∂f/∂q)/M at the closed-form q,
    // simplified (the squared growth rate; −λ² the squared frequency).
    std::optional<GiNaC::ex> lambda_squared;
};

struct EquilibriumSearch {
    double range = 3.141592653589793;  // starts for Newton's method on [−range, range] per coordinate
    int starts_per_coordinate = 25;    // grid of starts (capped so that the total stays moderate)
};

// Throws InputError when the equations depend on t at rest (the carrier motion is not
// steady, so there are no relative equilibria to speak of). Parameters at their defaults.
std::vector<Equilibrium> relative_equilibria(const model::Model& model, const Equations& equations,
                                             const EquilibriumSearch& search = {});

}  // namespace eomc::mechanics
