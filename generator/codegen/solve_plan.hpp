// The solve of M u̇ = f, chosen at generation time from M's symbolic structure.
//
// M is symmetric positive definite (a kinetic energy's Hessian), often sparse and often
// constant: Cowell's orbit has M = I, a system of particles a constant diagonal M. Instead of
// factoring M with Eigen at every call, the plan splits M into the blocks it couples and
// solves each where it can in straight-line code over the kernel's scalar:
//   identity         u̇ = f, no solve;
//   one velocity     u̇_k = f_k / M_kk;
//   a dense block    LDLᵀ without pivoting, unrolled (exact arithmetic folds numbers, so a
//                    numeric M is factored at generation time);
//   past unrolled_limit velocities in one block: Eigen's LLT at run time.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "codegen/kernel_ir.hpp"

namespace eomc::codegen {

// The largest block solved in straight-line code (bench/RESULTS.md, "The solve of M u̇ = f").
inline constexpr std::size_t unrolled_limit = 16;

// The plan for the symmetric matrix M; `varying` are the symbols that make M non-constant (t
// and the state). Throws EmitError when M is not symmetric or when a block of a numeric M has a
// zero pivot (M singular, or indefinite so that LDLᵀ needs pivoting).
SolvePlan plan_solve(const GiNaC::matrix& M, const std::vector<GiNaC::ex>& varying);

// `system` computes M (n × n, row-major) then the right-hand sides B (n × columns, row-major) as
// its outputs; the result computes X = M⁻¹B (n × columns, row-major) in straight-line code: the
// system's temporaries (those the solve reads), then the factors' and the substitutions'. For
// every method but eigen_llt. Temporaries continue system's numbering with `prefix`.
Block solve_block(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t columns,
                  const std::string& prefix);

// Programs beside M u̇ = f (Mei ch. 3): M u̇ = f + D λ, Ā u̇ = c, Ā m × n, D n × k. With z = M⁻¹f and
// Y = M⁻¹D, Ā u̇ = c becomes G λ = h with G = Ā Y (m × k) and h = c − Ā z, and u̇ = z + Y λ. `system`
// computes M (n²), f (n), Ā (m × n), c (m) and D (n × k, row-major), the layout of
// mass_forcing_and_programs; `plan` is plan_solve's for M. The result computes z (n), Y (n × k),
// G (m × k), h (m) and D (n × k), all row-major, in straight-line code. G is in general neither
// symmetric nor definite (D ≠ Āᵀ for a non-ideal control), so G λ = h is left to the run time's
// pivoted solve (runtime/program/reduced_control.hpp), which also gives det G, the realisability
// indicator.
Block reduce_programs(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m, std::size_t k,
                      const std::string& prefix);

// Constraint rows beside M u̇ = f: M u̇ − Wᵀλ = f, W u̇ = r is the saddle-point system
//     [M  Wᵀ] [ u̇ ]   [f]
//     [W  0 ] [−λ ] = [r]
// (Golub & Van Loan, Matrix Computations, 4th ed., §4.4 and §12.1). With the velocities ordered
// before the multipliers it is quasi-definite (M positive definite, −W M⁻¹ Wᵀ negative definite
// when W has full row rank), so LDLᵀ without pivoting exists in that order (R. J. Vanderbei, SIAM
// J. Optim. 5 (1995) 100–113) and is the Schur-complement solve: the first pivots factor M, the
// last ones −W M⁻¹ Wᵀ. The plan splits K into the blocks it couples like plan_solve; past
// unrolled_limit unknowns in one block it says eigen_llt: the runtime's Schur complement solves it.
// `W` is m × n row-major. Throws EmitError when a row constrains no velocity, or when a numeric K
// has a zero pivot (dependent rows).
SolvePlan plan_saddle_point(const GiNaC::matrix& M, const std::vector<GiNaC::ex>& W, std::size_t m,
                            const std::vector<GiNaC::ex>& varying);

// `system` computes M (n²), f (n), W (m × n) and r (m), the layout of mass_forcing_and_constraints;
// the result computes u̇ (n), λ (m) and the generalized reactions Wᵀλ (n) in straight-line code.
Block solve_saddle_point(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m,
                         const std::string& prefix);

// `system` computes M (n²) and W (m × n); the result computes C = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ (n × m,
// row-major), the M-metric correction that moves a state by C v to change W's rows by v (the
// saddle-point system with f = 0 and r the unit vectors). `plan` is plan_saddle_point's for M, W.
Block saddle_point_correction(const Block& system, const SolvePlan& plan, std::size_t n, std::size_t m,
                              const std::string& prefix);

// The plan in words, for the kernel's banner ("M u̇ = f is solved …").
std::string describe(const SolvePlan& plan, std::size_t n_velocities);

}  // namespace eomc::codegen
