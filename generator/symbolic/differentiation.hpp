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
#include <unordered_map>
#include <utility>

#include <ginac/ginac.h>

namespace eomc::symbolic {

GiNaC::ex derivative(const GiNaC::ex& e, const GiNaC::symbol& s);

// The derivative along a direction v (symbol → coefficient), Σ_x v_x ∂e/∂x, in one walk of e's
// DAG (forward mode) instead of one walk per symbol; and the memo is kept from one expression to
// the next, so a subexpression shared by many expressions (a bob's velocity in every momentum of
// a chain) is differentiated once. The total time derivative of Lagrange's equations is one such
// direction: ∂_t + Σ q̇_k ∂_{q_k}.
class DirectionalDerivative {
public:
    explicit DirectionalDerivative(GiNaC::exmap direction) : direction_(std::move(direction)) {}
    explicit DirectionalDerivative(const GiNaC::symbol& s) : direction_{{s, 1}} {}

    GiNaC::ex operator()(const GiNaC::ex& e);

private:
    GiNaC::ex compute(const GiNaC::ex& e);

    GiNaC::exmap direction_;
    std::unordered_map<GiNaC::ex, GiNaC::ex> memo_;
};

// Whether e contains any of `symbols`, each shared node looked at once (GiNaC's has() walks the
// tree, a subexpression shared k times k times).
bool depends_on_any(const GiNaC::ex& e, const GiNaC::exset& symbols);

// d f(u)/du for the scene language's functions (model/functions.hpp) into `out`; false for any
// other function (also symbolic/gradient.cpp's rules).
bool outer_derivative(const std::string& f, const GiNaC::ex& u, GiNaC::ex& out);

}  // namespace eomc::symbolic
