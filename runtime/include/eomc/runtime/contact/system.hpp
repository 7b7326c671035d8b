#pragma once

// A mechanical system with unilateral rows, as both contact drivers take it (event_driven.hpp and
// moreau_jean.hpp), and the events they report (Mei, Special Topics in Analytical Mechanics, ch. 6;
// F. Pfeiffer, C. Glocker, Multibody Dynamics with Unilateral Contacts, Wiley 1996):
//
//   M(t, q) u̇ = f(t, q, u) + Wᵀ λ,   q̇ = u,   g_α(t, q) ≥ 0,  W_α = ∂g_α/∂q,  w_α = ∂g_α/∂t,
//   ġ_α = W_α u + w_α,   g̈_α = W_α u̇ + b_α,
//
// with kinematic rows φ_α(t, q, u) ≥ 0 linear in u (Mei §6.7) and bilateral rows beside them
// (Mei §6.6). from_kernel.hpp builds one from a generated kernel's blocks.

#include <cstddef>
#include <functional>
#include <string_view>
#include <vector>

#include "eomc/runtime/constraints.hpp"
#include "eomc/runtime/contact/method.hpp"

namespace eomc::runtime::contact {

template <class S>
using Matrix = ConstraintMatrix<S>;
template <class S>
using Vector = ConstraintVector<S>;

// Where a unilateral constraint acts: a gap g(t, q) ≥ 0 (impacts), or a kinematic constraint
// φ(t, q, u) ≥ 0 (velocity level, no impacts).
enum class GapLevel { position, velocity };

template <class S>
struct Contact {
  S restitution = S(0);  // Newton's coefficient e in [0, 1]
  GapLevel level = GapLevel::position;
};

// The system as callables (a generated kernel provides the same blocks). Outputs are presized:
//   mass(t, q, M)              M, n × n symmetric positive definite;
//   force(t, q, u, f)          f, n: every force but the contact reactions (gyroscopic terms too);
//   gaps(t, q, u, g)           g, m: g_α(t, q) for position contacts, φ_α(t, q, u) for kinematic;
//   rows(t, q, u, W, b)        W, m × n and b, m: g̈_α = W_α u̇ + b_α (φ̇_α = W_α u̇ + b_α);
//   time_rates(t, q, w)        w, m: w_α = ∂g_α/∂t of a moving gap, ġ_α = W_α u + w_α (0 for a
//                              kinematic row). Optional: without it every w_α is 0 (fixed walls).
template <class S>
struct ContactSystem {
  int dof = 0;
  std::vector<Contact<S>> contacts;
  std::function<void(S, const Vector<S>&, Matrix<S>&)> mass;
  std::function<void(S, const Vector<S>&, const Vector<S>&, Vector<S>&)> force;
  std::function<void(S, const Vector<S>&, const Vector<S>&, Vector<S>&)> gaps;
  std::function<void(S, const Vector<S>&, const Vector<S>&, Matrix<S>&, Vector<S>&)> rows;
  std::function<void(S, const Vector<S>&, Vector<S>&)> time_rates;
  // Bilateral rows, always active (none by default): which are holonomic, and
  //   bilateral(t, q, u, f, phi, C, r)  f, k: f(t, q) (holonomic) or φ(t, q, u); phi, k: φ (ḟ for a
  //                                     holonomic row); C, k × n: ∂φ/∂u; r, k: C u̇ = r.
  std::vector<bool> bilateral_holonomic;
  std::function<void(S, const Vector<S>&, const Vector<S>&, Vector<S>&, Vector<S>&, Matrix<S>&, Vector<S>&)> bilateral;
};

// What a contact driver reports, in time order (the state after the transition follows).
enum class ContactEventKind { impact, contact, separation, zeno };

template <class S>
struct ContactEvent {
  ContactEventKind kind = ContactEventKind::impact;
  std::size_t contact = 0;
  S t = S(0);
  // impact: ġ⁻, ġ⁺ of this contact, its impulse P (a generalized impulse, the units of W's dual),
  // the kinetic energy change of the whole impact T⁺ − T⁻ and Carnot's −((1 − e)/(1 + e)) ½ ΔuᵀMΔu
  // (with the e of the contact that fired; exact when every contact of the impact shares it).
  S rate_before = S(0), rate_after = S(0), impulse = S(0), energy_change = S(0), carnot = S(0);
  // contact: λ_α where the contact phase starts (a generalized force, M u̇ = f + Wᵀλ).
  S lambda = S(0);
  // zeno: the ratio r of the series and the extrapolation's sensitivity bound Δt_k δr / (1 − r)²,
  // δr the spread of the agreeing ratios.
  S ratio = S(0), extrapolation_error = S(0);
};

// The kind's name, as summaries and CSV labels print it ("impact:floor").
constexpr std::string_view name(ContactEventKind kind) {
  switch (kind) {
    case ContactEventKind::impact: return "impact";
    case ContactEventKind::contact: return "contact";
    case ContactEventKind::separation: return "separation";
    case ContactEventKind::zeno: return "zeno";
  }
  return "?";
}

}  // namespace eomc::runtime::contact
