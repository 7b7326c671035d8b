// The two forms of given equations of motion in the inverse problem (Mei, ch. 4; Santilli,
// Foundations of Theoretical Mechanics I, 1978, whose conditions are stated on the first):
//
//   fundamental form  E_i = A_ij(t,q,q̇) q̈_j + B_i(t,q,q̇) = 0
//   kinematic form    q̈ = f(t,q,q̇)            (E = A (q̈ − f), f = −A⁻¹B)
//
// and the derivatives along the motion that Santilli's and the Helmholtz conditions are
// written with (detail::).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics::inverse {

struct FundamentalForm {
    GiNaC::matrix A;               // n×n
    std::vector<GiNaC::ex> B;      // n
    GiNaC::ex expression(const model::Model& model, std::size_t i) const;  // A_ij q̈_j + B_i
};

struct Forms {
    bool given_fundamental = false;  // which form the scene wrote (Lagrangian and body scenes: fundamental)
    FundamentalForm fundamental;
    std::vector<GiNaC::ex> kinematic;  // f, q̈ = f
};

// From a [newtonian] scene as written; from any other scene as E = M q̈ − f of its equations.
// Throws std::runtime_error when the kinematic form needs A⁻¹ of more than 4 coordinates.
Forms forms(const model::Model& model, const Equations& equations);

// Shared by the parts of the analysis; not for other callers.
namespace detail {

// D = ∂_t + q̇_k ∂/∂q_k (no q̈: A and B are functions of t, q, q̇).
GiNaC::ex total_derivative(const model::Model& model, const GiNaC::ex& F);
// d/dt along q̈ = f: ∂_t + q̇_k ∂/∂q_k + f_k ∂/∂q̇_k.
GiNaC::ex along_motion(const model::Model& model, const std::vector<GiNaC::ex>& f, const GiNaC::ex& F);

// t, then q_k and q̇_k of each coordinate.
std::vector<GiNaC::symbol> state_symbols(const model::Model& model);
bool depends_on_state(const GiNaC::ex& e, const std::vector<GiNaC::symbol>& state);
bool has_velocity(const model::Model& model, const GiNaC::ex& e);
std::string coordinate(const model::Model& model, std::size_t i);

// "[[a, b], [c, d]]" in GiNaC's syntax.
std::string matrix_text(const GiNaC::matrix& g);

// The random points at which an identity that does not simplify to 0 is tested, and Σ |term|
// at a point: the size against which "zero to round-off" is judged.
constexpr std::size_t probe_count = 32;
double magnitude(const GiNaC::ex& e, const symbolic::ProbePoint& point);

}  // namespace detail

}  // namespace eomc::mechanics::inverse
