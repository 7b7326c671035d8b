// Multipliers for the kinematic form q̈ = f(t,q,q̇) (Mei, ch. 4): a regular g(t,q,q̇) such that
// g (q̈ − f) = 0 are Euler–Lagrange equations. With d/dt = ∂_t + q̇·∂_q + f·∂_q̇, N = ∂f/∂q̇ and
// Φ = ½ d/dt N − ∂f/∂q − ¼ N², g must satisfy the Helmholtz conditions
//
//   H1  g Φ symmetric;   H2  ġ + ½ Nᵀ g + ½ g N = 0;   H3  ∂g_ij/∂q̇_k symmetric in (j, k)
//
// (Douglas, Trans. Amer. Math. Soc. 50 (1941) 71, for two degrees of freedom; Sarlet,
// J. Phys. A 15 (1982) 1503, in this form for any number).
//
// One degree of freedom: H1 and H3 are empty and H2 is a linear first-order PDE, which always
// has solutions locally (Darboux); the separable ones g(t)h(q), g(q̇), g(t)k(q̇), h(q)k(q̇)
// are found. n degrees of freedom: the algebraic consequences of H1 and H2 (g ∇ᵏΦ symmetric,
// Sarlet 1982 §4) first — when they force det g = 0 no regular Lagrangian exists (Douglas) —
// then constant and diagonal (in t, q) multipliers, whose conditions are linear in unknown
// constant coefficients. Every multiplier reported is verified by substitution into H1–H3.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/inverse/forms.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse {

// One step of the reasoning: a sentence and the equations it produced ("lhs" = ex).
struct Step {
    std::string text;
    std::vector<std::pair<std::string, GiNaC::ex>> equations;
};

struct Multiplier {
    GiNaC::matrix N, Phi;                  // ∂f/∂q̇ and Φ
    std::vector<Step> steps;               // what was tried and concluded, in order
    std::optional<GiNaC::matrix> g;        // the multiplier found (regular, H1–H3 verified)
    std::string kind;                      // "g(t)", "g(t)h(q)", "constant", "diagonal in q", …
    // The family of multipliers of that kind: g_family over the free constants (the solution
    // of the linear conditions; several free constants = several Lagrangians).
    std::optional<GiNaC::matrix> family;
    std::vector<GiNaC::symbol> free_constants;
    bool singular_forced = false;          // H1–H2 force det g = 0: no regular Lagrangian
    // Non-empty when a work bound (SearchBudget) stopped the search before it could decide:
    // which step and which bound. The search is then undecided, not negative.
    std::string undecided;
};

// The H1, H2, H3 residuals of a candidate g (each simplified), named "H1(x,y)" etc.
std::vector<std::pair<std::string, GiNaC::ex>> helmholtz_residuals(const model::Model& model,
                                                                   const std::vector<GiNaC::ex>& f,
                                                                   const GiNaC::matrix& g);

// Work bounds of the search, in expression nodes (a count, not a clock: the verdict and the
// report are the same on every machine). The algebraic conditions of H1–H2 are formed one
// derivative along the motion at a time, each 10–20 times the size of the one before when f
// is not polynomial; the next one is formed only while the current one is within `nodes`.
// The default takes every bundled scene and test case to its answer in seconds and stops
// leo_drag's 3-dof drag system, whose conditions close at ∇Φ, long before memory is at risk.
struct SearchBudget {
    std::size_t nodes = 1'000'000;
};

Multiplier search_multiplier(const model::Model& model, const std::vector<GiNaC::ex>& f, const SearchBudget& budget = {});

// g (q̈ − f) as a fundamental form.
FundamentalForm multiplied(const GiNaC::matrix& g, const std::vector<GiNaC::ex>& f);

}  // namespace eomc::mechanics::inverse
