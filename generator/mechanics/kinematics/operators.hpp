// The operators of analytical mechanics on functions of (t, q, q̇): the total time derivative
// along a motion and the Euler–Lagrange operator ε_s (Mei, §1.1).
#pragma once

#include <cstddef>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics {

// Total time derivative along a motion: ∂_t + Σ q̇_k ∂_{q_k} + Σ q̈_k ∂_{q̇_k} (+ Σ ν̇ ∂_ν over a
// free carrier's quasi-velocities).
GiNaC::ex total_derivative(const model::Model& model, const GiNaC::ex& F);

// The Euler operator ε_s(F) = d/dt ∂F/∂q̇_s − ∂F/∂q_s, d/dt acting on explicit t too.
GiNaC::ex euler_operator(const model::Model& model, const GiNaC::ex& F, std::size_t s);

// ε_s(F) for every coordinate s with its terms in the rates u̇ = (q̈, quasi-velocities' rates)
// apart, as Lagrange's equations need them:
//   ε_s(F) = Σ_k rates[s][k] u̇_k + rest[s],   rates[s][k] = ∂²F/∂q̇_s∂u_k (symmetric in the q̇ block),
//   rest[s] = (∂_t + Σ_j q̇_j ∂_{q_j}) ∂F/∂q̇_s − ∂F/∂q_s.
// With product_rule, rest[s] is formed on F's own, unexpanded expression by the product rule of ε_s,
//   ε_s(fg) = ε_s(f) g + f ε_s(g) + ḟ ∂g/∂q̇_s + ∂f/∂q̇_s ġ,
// so that the terms which cancel in Lagrange's expression meet inside the factor they come from,
// where GiNaC collects them: for a velocity v = d/dt r(q, t), d/dt ∂v/∂q̇_s = ∂v/∂q_s (Lagrange's
// cancellation lemma), and ε_s(v²/2) = v̇ ∂v/∂q̇_s comes out as a body's projection would give it,
// not as both sides of that identity. Each family of derivatives keeps one memo across all s, so
// a chain's T costs O(n |T|), not the O(n² |T|) of applying euler_operator to each s.
// For up to per_coordinate_limit coordinates rest[s] is also formed one partial at a time,
// ∂_t p_s + Σ_j q̇_j ∂p_s/∂q_j − ∂F/∂q_s (O(n² |F|)), and that form is kept when it has fewer
// distinct subexpressions: its flat sums of monomials let GiNaC cancel across the whole
// expression, which wins for a rigid body's ½ ωᵀ I ω in Euler angles, where no velocity is a time
// derivative and every term mixes the same angles.
struct EulerOperatorSplit {
    std::vector<GiNaC::ex> momenta;            // ∂F/∂q̇_s
    std::vector<std::vector<GiNaC::ex>> rates;  // [s][k]: the coefficient of u̇_k in ε_s(F)
    std::vector<GiNaC::ex> rest;               // ε_s(F) without its u̇ terms

    // Σ_k rates[s][k] u̇_k + rest[s]: ε_s(F).
    GiNaC::ex value(const model::Model& model, std::size_t s) const;
};
inline constexpr std::size_t per_coordinate_limit = 8;
EulerOperatorSplit euler_operator_split(const model::Model& model, const GiNaC::ex& F);

}  // namespace eomc::mechanics
