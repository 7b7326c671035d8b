// Partial derivatives of GiNaC expressions, without exceptions.
//
// GiNaC's function::derivative first tries an explicit derivative and falls back to the
// chain rule from a catch block, so every derivative of sin(θ₁) with respect to θ₅ —
// identically zero — throws and unwinds. In Lagrange's equations almost every derivative
// is of that kind, and the unwinding dominated the derivation time. This differentiates
// the node kinds the scene language can produce directly, memoized over the expression
// DAG, and defers to GiNaC only for anything else.
#pragma once

#include <string>

#include <ginac/ginac.h>

namespace eomc::symbolic {

GiNaC::ex derivative(const GiNaC::ex& e, const GiNaC::symbol& s);

// d f(u)/du for the scene language's functions into `out`; false for any other function
// (shared with symbolic/gradient.cpp, which applies the same rules).
bool outer_derivative(const std::string& f, const GiNaC::ex& u, GiNaC::ex& out);

}  // namespace eomc::symbolic
