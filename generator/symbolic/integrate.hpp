// Integration of GiNaC expressions, knowing no mechanics: antiderivatives of the elementary
// integrands that Santilli's homotopy formulas produce, potentials of exact gradients, and
// definite integrals over [0, 1]. Every result is checked before it is returned (by
// differentiation, or by evaluating at both ends): an integrand out of reach gives nullopt,
// never a wrong answer.
#pragma once

#include <optional>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::symbolic {

// An antiderivative in v for sums of: polynomials, powers of one linear form in v (a Laurent
// polynomial after substitution), exp/sin/cos/sinh/cosh/tan of linear arguments, products of
// sines and cosines (to sums), v h(v²) (by w = v²), and those times polynomials (by parts).
// Checked by differentiation; nullopt when not found.
std::optional<GiNaC::ex> antiderivative(const GiNaC::ex& e, const GiNaC::symbol& v);

// φ with ∂φ/∂vars[k] = gradient[k] for all k (integrating one variable after another);
// nullopt when the gradient is not exact or an integral is out of reach.
std::optional<GiNaC::ex> potential(const std::vector<GiNaC::ex>& gradient, const std::vector<GiNaC::symbol>& vars);

// ∫₀¹ integrand dτ by an antiderivative in τ, simplified; nullopt when none is found or it is
// singular at an end (the homotopy integrals of the inverse problem).
std::optional<GiNaC::ex> unit_integral(const GiNaC::ex& integrand, const GiNaC::symbol& tau);

}  // namespace eomc::symbolic
