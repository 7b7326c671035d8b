// The inverse problem of Lagrangian mechanics (Mei ch. 4; FORMULAS §3): given equations of
// motion, are they the Euler–Lagrange equations of some L, possibly after multiplying them by
// a matrix g(t, q, q̇)? If so, build L and prove it.
//
//   fundamental form  E_i = A_ij(t,q,q̇) q̈_j + B_i(t,q,q̇) = 0
//   kinematic form    q̈ = f(t,q,q̇)            (E = A (q̈ − f), f = −A⁻¹B)
//
// 1. Santilli's conditions S1–S5 of variational self-adjointness of the fundamental form,
//    each as simplified residuals; a verdict (self-adjoint, not self-adjoint with a point
//    where a residual is non-zero, or undecided: residuals GiNaC cannot simplify that vanish
//    at every random point tried).
// 2. When not self-adjoint: the Douglas / Sarlet conditions H1–H3 on a multiplier g for the
//    kinematic form. One degree of freedom: H2 is a linear first-order PDE, solved for the
//    separable cases g(t)h(q), g(q̇), g(t)k(q̇), h(q)k(q̇). n degrees of freedom: the algebraic
//    consequences of H1 and H2 (g ∇ᵏΦ symmetric) first — when they force det g = 0 no regular
//    Lagrangian exists — then constant and diagonal (in t, q) multipliers, whose conditions
//    are linear in unknown constant coefficients.
// 3. Santilli's construction L = K + D_k q̇_k + C for a self-adjoint (possibly multiplied)
//    fundamental form, then ε_i(L) = E_i checked symbolically.
//
// Every candidate (antiderivative, multiplier, Lagrangian) is checked by substitution before
// it is reported: a case the solver does not recognise is reported as not found, never as a
// wrong answer.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse {

// ---------------------------------------------------------------------------------------
// Algebra used throughout (exposed for the tests).

// An equal expression, as small as expansion, normal form, exp(a)exp(b) = exp(a+b) and
// sin² = 1 − cos² make it. Zero when any of those shows it is zero.
GiNaC::ex simplified(const GiNaC::ex& e);
// exp(φ) with the c·log(w) terms of φ turned into powers w^c (exp(2 log r) = r²).
GiNaC::ex exp_of(const GiNaC::ex& phi);
// An antiderivative in v for sums of: polynomials, powers of one linear form in v (a Laurent
// polynomial after substitution), exp/sin/cos/sinh/cosh/tan of linear arguments, and those
// times polynomials (by parts). Checked by differentiation; nullopt when not found.
std::optional<GiNaC::ex> antiderivative(const GiNaC::ex& e, const GiNaC::symbol& v);
// φ with ∂φ/∂vars[k] = gradient[k] for all k (integrating one variable after another);
// nullopt when the gradient is not exact or an integral is out of reach.
std::optional<GiNaC::ex> potential(const std::vector<GiNaC::ex>& gradient, const std::vector<GiNaC::symbol>& vars);

// ---------------------------------------------------------------------------------------
// The two forms.

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

// ---------------------------------------------------------------------------------------
// Santilli's conditions (FORMULAS §3), D = ∂_t + q̇_k ∂/∂q_k:
//   S1 (i<j)      A_ij − A_ji
//   S2 (i; j<k)   ∂A_ij/∂q̇_k − ∂A_ik/∂q̇_j
//   S3 (i≤j)      ∂B_i/∂q̇_j + ∂B_j/∂q̇_i − 2 D A_ij
//   S4 (i<j; k)   ∂A_ik/∂q_j − ∂A_jk/∂q_i − ½ ∂/∂q̇_k (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)
//   S5 (i<j)      ∂B_i/∂q_j − ∂B_j/∂q_i − ½ D (∂B_i/∂q̇_j − ∂B_j/∂q̇_i)

struct Residual {
    std::string condition;            // "S1" … "S5"
    std::size_t i = 0, j = 0;
    std::optional<std::size_t> k;     // S2 and S4 only
    GiNaC::ex value;                  // simplified
    bool zero = false;                // simplified to 0
};

// "S3(x,y)", "S2(x;y,z)", "S4(x,y;z)" with the coordinate names.
std::string label(const model::Model& model, const Residual& r);

std::vector<Residual> santilli_conditions(const model::Model& model, const FundamentalForm& form);

enum class Verdict { self_adjoint, not_self_adjoint, undecided };

struct Decision {
    Verdict verdict = Verdict::undecided;
    // not_self_adjoint: a residual and a point where it is non-zero.
    std::size_t witness = 0;
    std::vector<std::pair<std::string, double>> point;  // t, q, q̇, parameters
    double witness_value = 0;
    // undecided: the residuals left, and how many random points each vanished at.
    std::vector<std::size_t> unresolved;
    std::size_t points_tried = 0;
};

Decision decide(const model::Model& model, const std::vector<Residual>& residuals);

// ---------------------------------------------------------------------------------------
// Multipliers for the kinematic form (Douglas 1941; Sarlet 1982), d/dt = ∂_t + q̇·∂_q + f·∂_q̇,
// N = ∂f/∂q̇, Φ = ½ d/dt N − ∂f/∂q − ¼ N²:
//   H1  g Φ symmetric;  H2  ġ + ½ Nᵀ g + ½ g N = 0;  H3  ∂g_ij/∂q̇_k symmetric in (j, k).

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

// ---------------------------------------------------------------------------------------
// Santilli's construction (FORMULAS §3), for a self-adjoint fundamental form:
//   K   = (q̇−v₀)_i (q̇−v₀)_j ∫₀¹ (1−τ) A_ij(t, q, v₀ + τ(q̇−v₀)) dτ     (∂²K/∂q̇∂q̇ = A)
//   E_i − ε_i(K) = α_i(t,q) + β_ik(t,q) q̇_k,   β antisymmetric
//   D_i = ∫₀¹ τ (q−q₀)_k β_ik(t, q₀ + τ(q−q₀)) dτ                          (∂_k D_i − ∂_i D_k = β_ik)
//   C   = ∫₀¹ (q−q₀)_i (∂_t D_i − α_i)(t, q₀ + τ(q−q₀)) dτ                 (∂_i C = ∂_t D_i − α_i)
// The homotopy centres v₀, q₀ are 0 unless an integrand is singular there (then 1, then 2);
// when C is singular at all three, it is found by integrating ∂_i C one coordinate at a time.

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

// ---------------------------------------------------------------------------------------
// The whole analysis behind `eomc inverse`.

struct Alternative {           // a second Lagrangian from another member of the multiplier family
    GiNaC::matrix g;
    Construction construction;
};

struct Analysis {
    Forms forms;
    std::vector<Residual> conditions;
    Decision decision;
    std::optional<Multiplier> multiplier;          // searched when not self-adjoint (and allowed)
    std::optional<FundamentalForm> multiplied_form;
    std::vector<Residual> multiplied_conditions;   // Santilli's conditions of g (q̈ − f)
    std::optional<Construction> construction;      // when construct = true and a self-adjoint form is at hand
    std::optional<Alternative> alternative;        // non-uniqueness, when the constant multipliers allow it
    std::string reason;                            // one sentence: the outcome and why
};

Analysis analyse(const model::Model& model, const Equations& equations, const SearchBudget& budget = {});

// [lagrangian] T and V for L (T: the terms of positive degree in q̇, V: minus the rest).
std::pair<GiNaC::ex, GiNaC::ex> split_lagrangian(const model::Model& model, const GiNaC::ex& L);

}  // namespace eomc::mechanics::inverse
