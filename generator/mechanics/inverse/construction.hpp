// Santilli's construction of a Lagrangian for a self-adjoint fundamental form
// A(t,q,q̇) q̈ + B(t,q,q̇) = 0 (Santilli, Foundations of Theoretical Mechanics I, 1978, ch. 3:
// the fundamental analytic theorem and the construction of L by homotopy integrals; Mei,
// ch. 4):
//
//   K   = (q̇−v₀)_i (q̇−v₀)_j ∫₀¹ (1−τ) A_ij(t, q, v₀ + τ(q̇−v₀)) dτ     (∂²K/∂q̇∂q̇ = A)
//   E_i − ε_i(K) = α_i(t,q) + β_ik(t,q) q̇_k,   β antisymmetric
//   D_i = ∫₀¹ τ (q−q₀)_k β_ik(t, q₀ + τ(q−q₀)) dτ                          (∂_k D_i − ∂_i D_k = β_ik)
//   C   = ∫₀¹ (q−q₀)_i (∂_t D_i − α_i)(t, q₀ + τ(q−q₀)) dτ                 (∂_i C = ∂_t D_i − α_i)
//   L   = K + D_k q̇_k + C
//
// The homotopy centres v₀, q₀ are 0 unless an integrand is singular there (then 1, then 2);
// when C is singular at all three, it is found by integrating ∂_i C one coordinate at a time.
// The result is checked: ε_i(L) = E_i symbolically, else at random points.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/inverse/forms.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse {

struct Construction {
    bool built = false;
    std::string reason;                   // why not, when !built
    GiNaC::ex K, C, L;
    std::vector<GiNaC::ex> D;
    std::vector<GiNaC::ex> alpha;
    GiNaC::matrix beta;
    double q_centre = 0, v_centre = 0;    // homotopy centres used (every component)
    bool C_by_coordinates = false;        // C by integrating one coordinate after another (no centre worked)
    bool verified = false;                // ε_i(L) − E_i simplified to 0 for every i
    std::size_t points_agreeing = 0;      // when not proven: random points where they agree to round-off
    std::vector<GiNaC::ex> check;         // ε_i(L) − E_i, simplified
};

Construction construct_lagrangian(const model::Model& model, const FundamentalForm& form);

// ε_i(L) − E_i for each i, simplified (all zero: L generates exactly these equations).
std::vector<GiNaC::ex> euler_lagrange_mismatch(const model::Model& model, const GiNaC::ex& L, const FundamentalForm& form);

// [lagrangian] T and V for L (T: the terms of positive degree in q̇, V: minus the rest).
std::pair<GiNaC::ex, GiNaC::ex> split_lagrangian(const model::Model& model, const GiNaC::ex& L);

}  // namespace eomc::mechanics::inverse
