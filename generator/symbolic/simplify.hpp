// Simplification of GiNaC expressions, knowing no mechanics: the structural helpers (terms,
// factors, size), and two simplifiers for two different jobs.
//
//   simplified(e)  decides: the smallest of several equal forms, and 0 whenever any of them
//                  shows e is zero. For residuals and candidates that must be recognised as
//                  zero (Santilli's conditions, the Helmholtz conditions, antiderivatives).
//                  Its result's shape depends on which form was smallest, and it gives up
//                  (returns the expanded form) on expressions too large for normal().
//   normalized(e)  presents: always GiNaC's rational normal form, with sin² = 1 − cos² used
//                  where that is shorter. For expressions the kernel and the printers see
//                  (the Legendre transform's W⁻¹): one predictable shape, whatever the size.
//
// They are kept apart because each one's output is what its callers print and compile: the
// Hamiltonian's kernels and reports are written from normalized() forms, the inverse
// problem's reports from simplified() ones, and either swapped for the other would change
// the generated files.
#pragma once

#include <cstddef>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::symbolic {

// Nodes in the expression tree (shared subexpressions counted each time they occur).
std::size_t node_count(const GiNaC::ex& e);
// Whether e is a call of the named function (exp, log, sin, …).
bool is_function(const GiNaC::ex& e, const char* name);
// The terms of a sum (one term otherwise; none for 0), the factors of a product.
std::vector<GiNaC::ex> terms_of(const GiNaC::ex& e);
std::vector<GiNaC::ex> factors_of(const GiNaC::ex& e);

// exp(a)·exp(b)^k → exp(a + k b) in every product: GiNaC keeps exponentials apart, so
// e^{γt}·e^{−γt} would otherwise never cancel.
GiNaC::ex combine_exponentials(const GiNaC::ex& e);

// The rewriting sin² = 1 − cos² (and, with `hyperbolic`, cosh² = 1 + sinh²) of every even
// power, as an algebraic substitution; not expanded.
GiNaC::ex without_sin_squared(const GiNaC::ex& e, bool hyperbolic);

// An equal expression, as small as expansion, normal form, exp(a)exp(b) = exp(a+b) and
// sin² = 1 − cos² make it. Zero when any of those shows it is zero (trigonometric
// polynomials are also tested through complex exponentials).
GiNaC::ex simplified(const GiNaC::ex& e);

// The rational normal form of e, or of e with sin² = 1 − cos² when that has fewer nodes.
// Throws what GiNaC::normal throws.
GiNaC::ex normalized(const GiNaC::ex& e);

// exp(φ) with the c·log(w) terms of φ turned into powers w^c (exp(2 log r) = r²).
GiNaC::ex exp_of(const GiNaC::ex& phi);

}  // namespace eomc::symbolic
