// Stage 4: the kernel as straight-line code, ready to print.
//
// A Block is what one emitted function computes: temporaries w_k = expr in dependency
// order (after common-subexpression elimination), then the outputs written in terms of
// them. Expressions are still GiNaC objects, but only over the symbols listed in
// KernelIR (time, state, parameters, accelerations, temporaries); the emitter prints
// them and knows nothing of mechanics.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/lagrange.hpp"
#include "model/model.hpp"

namespace eomc::codegen {

struct Temporary {
    GiNaC::symbol symbol;
    GiNaC::ex value;
};

struct Block {
    std::vector<Temporary> temporaries;
    std::vector<GiNaC::ex> outputs;
    std::size_t ops_before = 0;  // operations in the outputs as derived (shared subtrees counted every time)
    std::size_t ops_after = 0;   // operations left after CSE
};

struct NamedSymbol {
    std::string name;
    GiNaC::ex symbol;
};

struct KernelIR {
    std::string scene_name, struct_name, summary, source;
    std::size_t n_coordinates = 0;
    GiNaC::ex t;
    std::vector<NamedSymbol> state;          // q_1..q_n, q_1_dot..q_n_dot
    std::vector<NamedSymbol> accelerations;  // inputs of jacobian_terms (the solved q̈)
    std::vector<NamedSymbol> parameters;
    std::vector<double> parameter_defaults;
    std::vector<double> initial_state;
    std::vector<std::string> invariant_names;

    Block mass_matrix;   // n*n outputs, row-major
    Block forcing;       // n outputs
    Block mass_and_forcing;  // both, CSE'd together: what rhs evaluates
    bool explicit_solution = false;  // n ≤ 2: q̈ = M⁻¹f solved symbolically
    Block accelerations_explicit;    // n outputs, when explicit_solution
    Block jacobian_explicit;         // 2n*2n outputs, when explicit_solution
    Block mass_and_jacobian_terms;   // otherwise: n*n outputs of M, then n*2n of G = ∂f/∂x − (∂M/∂x)·q̈
    Block invariants;                // one output per invariant

    // Newtonian scenes only (empty otherwise, and then nothing is emitted): Santilli's
    // conditions S1–S5 of the fundamental form as residuals, one output per name.
    std::vector<std::string> santilli_residual_names;
    Block santilli_residuals;
};

// Common-subexpression elimination over all outputs of one function.
Block eliminate_common_subexpressions(const std::vector<GiNaC::ex>& outputs, const std::string& temp_prefix);

// Operations of an expression tree, shared subtrees counted each time they occur:
// + − × ÷ one each, an integer power |k| as |k|−1 multiplications (and a division when k < 0),
// any other power, sqrt and every function call one each.
std::size_t count_operations(const GiNaC::ex& e);

// Seconds spent per lowering step, for `eomc generate --timings` and the benchmarks.
struct LoweringTimes {
    double mass_and_forcing = 0;  // CSE of M, f and M+f
    double jacobian = 0;          // the Jacobian's derivatives and their CSE
    double invariants = 0;
};

// Model + equations → kernel IR. Deterministic: the same scene gives the same IR.
KernelIR lower(const model::Model& model, const mechanics::Equations& equations, LoweringTimes* times = nullptr);

}  // namespace eomc::codegen
