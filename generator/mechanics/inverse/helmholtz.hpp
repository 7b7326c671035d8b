// The Helmholtz conditions H1–H3 on a multiplier g of the kinematic form (Sarlet, J. Phys. A
// 15 (1982) 1503; see multiplier.hpp) as the multiplier search uses them: residuals of a
// candidate, and g as an ansatz Σ (unknown constant) × (known function) solved through its
// linear conditions. Internal to mechanics/inverse/.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/inverse/multiplier.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::inverse::detail {

// N = ∂f/∂q̇ and Φ = ½ d/dt N − ∂f/∂q − ¼ N², simplified.
struct FlowMatrices {
    GiNaC::matrix N, Phi;
};
FlowMatrices flow_matrices(const model::Model& model, const std::vector<GiNaC::ex>& f);

// H1(i<j), H2(i≤j), H3(i; j<k) of g, named with the coordinates; simplified when `simplify`.
std::vector<std::pair<std::string, GiNaC::ex>> helmholtz(const model::Model& model, const std::vector<GiNaC::ex>& f,
                                                         const FlowMatrices& m, const GiNaC::matrix& g, bool simplify);
bool all_zero(const std::vector<std::pair<std::string, GiNaC::ex>>& residuals);
// det g does not simplify to 0.
bool regular(const GiNaC::matrix& g);

struct AnsatzResult {
    bool any = false;  // a non-zero family exists
    GiNaC::matrix family;
    std::vector<GiNaC::symbol> free;
    std::optional<GiNaC::matrix> g;  // a regular member, when one of those tried is
    std::size_t over_budget = 0;     // the size of the conditions when over the budget (then not solved)
};

// The ansatz's H1–H3 solved identically in (t, q, q̇) for its unknown constants; the regular
// member tried first sets the free diagonal constants to 1 and the others to 0.
AnsatzResult solve_ansatz(const model::Model& model, const std::vector<GiNaC::ex>& f, const FlowMatrices& m,
                          const GiNaC::matrix& ansatz, const std::vector<GiNaC::symbol>& unknowns,
                          const std::vector<bool>& unknown_on_diagonal, const SearchBudget& budget);

// The constant symmetric ansatz g_ij = g_ji = c_ij, one unknown per entry on or above the diagonal.
struct Ansatz {
    GiNaC::matrix g;
    std::vector<GiNaC::symbol> unknowns;
    std::vector<bool> on_diagonal;
};
Ansatz constant_ansatz(const model::Model& model);

// n degrees of freedom: whether the algebraic consequences of H1 and H2 force det g = 0
// (algebraic_conditions.cpp). Records its steps in m; sets m.undecided when the budget cut it.
bool singular_forced(const model::Model& model, const std::vector<GiNaC::ex>& f, const SearchBudget& budget,
                     Multiplier& m);

}  // namespace eomc::mechanics::inverse::detail
