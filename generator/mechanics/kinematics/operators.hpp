// The operators of analytical mechanics on functions of (t, q, q̇): the total time derivative
// along a motion and the Euler–Lagrange operator ε_s (Mei, §1.1).
#pragma once

#include <cstddef>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics {

// Total time derivative along a motion: ∂_t + Σ q̇_k ∂_{q_k} + Σ q̈_k ∂_{q̇_k} (+ Σ ν̇ ∂_ν over a
// free carrier's quasi-velocities).
GiNaC::ex total_derivative(const model::Model& model, const GiNaC::ex& F);

// The Euler operator ε_s(F) = d/dt ∂F/∂q̇_s − ∂F/∂q_s, d/dt acting on explicit t too.
GiNaC::ex euler_operator(const model::Model& model, const GiNaC::ex& F, std::size_t s);

}  // namespace eomc::mechanics
