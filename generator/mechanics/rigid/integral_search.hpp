// Polynomial first integrals of a polynomial vector field ẋ = f(x), found by undetermined
// coefficients (Mei, Special Topics in Analytical Mechanics, ch. 5; the heavy rigid body's
// integrable cases of Euler, Lagrange, Kovalevskaya and Goryachev–Chaplygin are its examples).
//
// F = Σ c_m m(x) over the monomials of degree ≤ d; dF/dt = Σ ∂F/∂x_i f_i has coefficients linear
// in c, and all of them vanishing is an exact rational linear system whose null space holds
// every polynomial integral of degree ≤ d. Integrals already known (the energy, the area
// integral, |γ|²) and every polynomial in them are quotiented out, so only what is new is
// reported. Conditional integrals (dF/dt = Λ(x)·(C(x) − c0), constant only on a level set of a
// known integral C: Goryachev–Chaplygin's on K_z = 0) are searched the same way with Λ's
// coefficients as further unknowns.
//
// Everything is exact (rationals) and independent of the scene and the model: the caller
// substitutes parameter values (rational_from_decimal turns the scenes' decimals into exact
// numbers). The output depends only on the input's order of the state, never on GiNaC's symbol
// serials: monomials are ordered by their exponent vectors.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::mechanics::rigid {

struct NamedPolynomial {
    std::string name;
    GiNaC::ex value;
};

// The level set C(x) = level of a first integral C, on which conditional integrals are sought.
struct LevelCondition {
    std::string name;  // "area" → reported as "holds on area = 0"
    GiNaC::ex value;
    GiNaC::numeric level = 0;
};

struct IntegralSearchInput {
    std::vector<GiNaC::symbol> state;  // x_1..x_n
    std::vector<GiNaC::ex> field;      // ẋ_i = f_i(x): polynomials in the state, rational coefficients
    unsigned degree = 0;               // search F of total degree ≤ degree
    // Integrals already known: only integrals outside the algebra they generate (the
    // polynomials in them of degree ≤ degree) are reported. Each is checked to be one.
    std::vector<NamedPolynomial> known;
    // Level sets of first integrals (each checked to be one) on which conditional integrals
    // are sought; none: unconditional integrals only.
    std::vector<LevelCondition> conditions;
    // The elimination's budget in entry operations (0: none). The exact elimination's cost grows
    // steeply with the degree (the heavy gyrostat: 1 s at degree 5, 35 s at 6, past 900 s at 7).
    std::size_t work_budget = 0;
};

// The budget ran out before the search could decide: no integral is reported for this degree.
struct SearchBudgetExhausted : std::runtime_error {
    explicit SearchBudgetExhausted(std::size_t spent)
        : std::runtime_error("the integral search ran out of its work budget"), spent(spent) {}
    std::size_t spent;
};

struct FoundIntegral {
    GiNaC::ex value;  // canonical form: integer coefficients, gcd 1, leading coefficient > 0
    unsigned degree = 0;
    bool conditional = false;
    std::string condition_name;  // "holds on area = 0" when conditional
    GiNaC::ex cofactor;          // Λ with dF/dt = Λ·(C − c0) when conditional; 0 otherwise
};

// A basis, in canonical form, of the integrals of degree ≤ input.degree modulo the known
// algebra (unconditional ones first), then for each condition a basis of the conditional
// integrals modulo the unconditional ones, the known algebra and the multiples of C − c0 (which
// vanish on the level set, so are constant there trivially). Each one reported has been
// re-verified symbolically: expand(dF/dt) is exactly 0, or exactly Λ·(C − c0).
//
// Canonical form: monomials are ordered by total degree, then by exponent vector (x_1 first),
// highest first; a reported F is the row of the reduced row echelon basis of the solution
// space whose leading monomial is not the leading monomial of any trivial solution, scaled to
// primitive integers. The same input gives the same output.
//
// Throws std::invalid_argument when the field, a known integral or a condition is not a
// polynomial in the state with rational coefficients (a parameter left as a symbol), when the
// sizes disagree, or when a known integral or condition is not a first integral.
// work_spent, when given, receives the entry operations the elimination took.
std::vector<FoundIntegral> search_polynomial_integrals(const IntegralSearchInput& input,
                                                       std::size_t* work_spent = nullptr);

// The exact rational a scene meant by a decimal parameter: the shortest decimal that reads back
// as v (0.5 → 1/2, 0.1 → 1/10, 2.5e-3 → 1/400), when it has at most max_significant_digits
// digits; nullopt otherwise (a computed value such as 1/3 written out to 17 digits) and for
// infinities and NaN.
std::optional<GiNaC::numeric> rational_from_decimal(double v, unsigned max_significant_digits = 12);

}  // namespace eomc::mechanics::rigid
