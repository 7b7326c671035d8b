// Gradients of GiNaC expressions with respect to many symbols at once: forward mode over the
// expression DAG, one memo shared by every symbol and every expression differentiated.
//
// symbolic::derivative(e, x_j) walks e once per symbol, so the n × n Jacobian of n residuals costs
// n² walks of O(n²)-node expressions: O(n⁴). Here each node's gradient is computed once, as a
// sparse list of (symbol, ∂node/∂symbol) holding only the nonzero entries, from its operands'
// gradients by the same rules symbolic::derivative applies (sum, product, numeric power, the
// scene language's functions, Kepler's E; GiNaC's diff for anything else). Entry j of a gradient
// is therefore the very expression derivative(e, x_j) returns, built once, and a node is visited
// once whatever the number of symbols: O(nodes × nonzero entries).
#pragma once

#include <unordered_map>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::symbolic {

class Gradient {
public:
    // The symbols to differentiate by, in the order of the gradient's entries.
    explicit Gradient(const std::vector<GiNaC::symbol>& variables);

    // (∂e/∂x_0, …, ∂e/∂x_{n−1}); the memo persists across calls, so subexpressions shared by
    // several expressions are differentiated once.
    std::vector<GiNaC::ex> operator()(const GiNaC::ex& e);

private:
    // (variable index, nonzero derivative), sorted by index.
    using Sparse = std::vector<std::pair<unsigned, GiNaC::ex>>;

    const Sparse& of(const GiNaC::ex& e);
    Sparse compute(const GiNaC::ex& e);
    Sparse by_diff(const GiNaC::ex& e) const;

    std::vector<GiNaC::symbol> variables_;
    std::unordered_map<GiNaC::ex, unsigned> index_;
    std::unordered_map<GiNaC::ex, Sparse> memo_;
    const Sparse none_;
};

// The row-major Jacobian ∂rows_i/∂variables_j, through one Gradient.
std::vector<GiNaC::ex> jacobian(const std::vector<GiNaC::ex>& rows, const std::vector<GiNaC::symbol>& variables);

}  // namespace eomc::symbolic
