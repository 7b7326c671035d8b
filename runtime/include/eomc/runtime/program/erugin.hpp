#pragma once

// Erugin's law in closed form (N. P. Erugin, PMM 16 (1952); Galiullin, Inverse Problems of
// Dynamics, 1981, ch. 3): the residual of a program realised with Galiullin's choice,
//   ω̈ + 2α ω̇ + β² ω = 0   (configuration-space programs),   φ̇ + κ φ = 0   (phase space),
// from ω(0) = ω0, ω̇(0) = ω̇0 (φ(0) = φ0): what a controlled run is compared with.

#include <cmath>

namespace eomc::runtime::program {

// ω(t): underdamped (α < β, ν = √(β² − α²)) e^{−αt}[ω0 cos νt + (ω̇0 + α ω0)/ν sin νt]; critical
// (α = β) (ω0 + (ω̇0 + β ω0) t) e^{−βt}; overdamped (α > β) A e^{r₁t} + B e^{r₂t} with
// r₁,₂ = −α ± √(α² − β²). α = β = 0 is the open loop ω̈ = 0: ω0 + ω̇0 t.
template <class S>
S erugin_configuration(S alpha, S beta, S omega0, S omega_dot0, S t) {
  using std::cos, std::exp, std::sin, std::sqrt;
  if (alpha < beta) {
    const S nu = sqrt(beta * beta - alpha * alpha);
    return exp(-alpha * t) * (omega0 * cos(nu * t) + (omega_dot0 + alpha * omega0) / nu * sin(nu * t));
  }
  if (alpha == beta) return (omega0 + (omega_dot0 + beta * omega0) * t) * exp(-beta * t);
  const S s = sqrt(alpha * alpha - beta * beta), r1 = -alpha + s, r2 = -alpha - s;
  const S a = (omega_dot0 - r2 * omega0) / (r1 - r2);
  return a * exp(r1 * t) + (omega0 - a) * exp(r2 * t);
}

// φ(t) = φ0 e^{−κt}; κ = 0 is the open loop φ̇ = 0.
template <class S>
S erugin_phase(S kappa, S phi0, S t) {
  using std::exp;
  return phi0 * exp(-kappa * t);
}

}  // namespace eomc::runtime::program
