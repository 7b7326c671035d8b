// Equilibria with unilateral gaps f_α(q) ≥ 0 (Mei, ch. 6, §6.4): by the principle of virtual work
// with unilateral constraints (Fourier's inequality, δ'W = Σ Q_s δq_s ≤ 0 for every admissible δq,
// Σ ∂f_α/∂q_s δq_s ≥ 0 on the active rows), a state at rest is an equilibrium when
//     ∂V/∂q_s = Σ_α λ_α ∂f_α/∂q_s,   λ_α ≥ 0,   f_α ≥ 0,   λ_α f_α = 0,
// the Karush–Kuhn–Tucker conditions of min V on {f ≥ 0} (Kuhn & Tucker 1951; Nocedal & Wright,
// *Numerical Optimization*, 2nd ed. 2006, Thm 12.1). Here ∂V/∂q is −f(q, 0), the forces of the
// equations at rest (M q̈ = f), so a carrier's steady effects enter as the amended potential does.
//
// Every active set A is tried: ∂V/∂q − Σ_A λ_α ∂f_α/∂q = 0 with f_A = 0, solved in closed form
// where symbolic/closed_form can (λ first, then q), else by Newton's method from a grid of starts;
// a solution is kept when λ_A ≥ 0 and the inactive gaps are ≥ 0, and reported as rejected
// otherwise.
//
// Stability (Lagrange–Dirichlet: a strict local minimum of V on the admissible set is stable, the
// impacts losing energy by Carnot's theorem for e ≤ 1 and the reactions doing no work on
// scleronomic gaps; Brogliato, *Nonsmooth Mechanics*, 3rd ed. 2016,
// its Lagrange–Dirichlet theorem for unilaterally constrained systems), decided by the
// second-order conditions of the minimum (Nocedal & Wright, Thm 12.5 and 12.6):
//  - interior (no active row): the Hessian ∂²V/∂q² positive definite → stable; an eigenvalue < 0
//    → unstable (gyroscopic forces at rest leave this undecided);
//  - boundary (λ_α > 0 on every active row): the Hessian of V − Σ λ_α f_α on the tangent space
//    {d: ∂f_A/∂q d = 0} of the active manifold. When the active normals span the configuration
//    space that space is {0}, and the point is a strict minimum on first order alone: V grows
//    along every admissible direction (d ≠ 0 has ∂f_α/∂q d > 0 for some α, so ∂V/∂q d > 0). A
//    one-degree-of-freedom system leaning on a wall with λ > 0 is stable whatever V'' is.
//  - degenerate (λ_α = 0 on some active row): stable when that Hessian is positive definite on
//    the tangent space of the rows with λ > 0 (a superset of the critical cone), else undecided.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::unilateral {

enum class KktKind { interior, boundary, degenerate };
const char* name(KktKind kind);

struct KktPoint {
    std::vector<double> q;                 // in coordinate order
    std::vector<bool> free;                // per coordinate: absent from V and the gaps (held at 0)
    std::vector<bool> active;              // per row: in the active set A (f_α = 0)
    std::vector<double> lambda;            // per row: λ_α (0 off A)
    std::vector<double> gap;               // per row: f_α(q)
    // Closed forms (parameters symbolic), when solved symbolically: q per coordinate, λ per row.
    std::vector<GiNaC::ex> exact_q, exact_lambda;
};

struct KktEquilibrium {
    KktPoint point;
    KktKind kind = KktKind::interior;
    std::string verdict;                   // "stable" | "unstable" | "undecided"
    std::string reason;                    // the rule that gave the verdict
    std::vector<double> curvature;         // eigenvalues of the (reduced) Hessian, ascending; empty on a vertex
};

struct KktRejected {
    KktPoint point;
    std::string reason;                    // which of λ ≥ 0, f ≥ 0 fails, with the values
};

struct UnilateralEquilibria {
    std::vector<std::string> rows;         // the gaps' names, in scene order
    std::vector<GiNaC::ex> gaps;           // f_α(q)
    std::optional<GiNaC::ex> potential;    // V(q) up to a constant, when found in closed form
    std::vector<GiNaC::ex> gradient;       // ∂V/∂q = −f(q, 0)
    std::vector<KktEquilibrium> equilibria;
    std::vector<KktRejected> rejected;     // solutions of an active set's equations that fail λ ≥ 0 or f ≥ 0
    bool closed_form_complete = true;      // every active set's equations solved in closed form
};

struct KktSearch {
    double range = 3.141592653589793;  // Newton starts on [−range, range] per coordinate
    int starts_per_coordinate = 25;    // capped so that a set's starts stay below about 1000
};

// Throws InputError at the row for a time-dependent gap or a velocity row (§6.7), and at the
// scene for what has no potential at rest (bilateral rows, a free carrier, given equations, an
// orbit or a rigid body in Euler–Poisson form, forces at rest that are not a gradient or depend
// on t). Parameters at their defaults.
UnilateralEquilibria kkt_equilibria(const model::Model& model, const Equations& equations, const KktSearch& search = {});

}  // namespace eomc::mechanics::unilateral
