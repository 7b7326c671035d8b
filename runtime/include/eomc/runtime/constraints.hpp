#pragma once

// Bilateral constraint rows in a generated kernel (generator/mechanics/constraints/rows.hpp):
// the index-1 solve of the equations of motion with multipliers, and the projection back onto
// the constraint manifold after an accepted step. A kernel only calls these; the algorithms
// live here, over Eigen types and callables that evaluate the kernel's blocks.
//
//   M u̇ − Wᵀ λ = f,   W u̇ = r        (r = −bias − stabilisation)
//
// solved by the Schur complement of M in the bordered matrix [[M, −Wᵀ], [W, 0]] (G. H. Golub,
// C. F. Van Loan, Matrix Computations, 4th ed., Johns Hopkins 2013, §4.4 and §12.1 on
// saddle-point systems): with M = L D Lᵀ, Y = M⁻¹Wᵀ and the Schur complement G = W M⁻¹ Wᵀ
// (symmetric positive definite when M is and W has full row rank),
//   λ = G⁻¹ (r − W M⁻¹ f),   u̇ = M⁻¹ f + Y λ.
//
// The projection is the coordinate projection of E. Hairer, C. Lubich, G. Wanner, Geometric
// Numerical Integration, 2nd ed., Springer 2006, §IV.4 (Algorithm 4.2, eq. (4.4)), in the metric
// of M: a simplified Newton iteration q ← q − M⁻¹Wᵀ (W M⁻¹ Wᵀ)⁻¹ f(q) with W frozen at the
// step's end point, then u ← u − M⁻¹Wᵀ (W M⁻¹ Wᵀ)⁻¹ φ(q, u), which is exact in one step because
// φ is linear in u.

#include <cstddef>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "eomc/runtime/constraint_projection.hpp"  // ConstraintLayout, central_difference_jacobian

namespace eomc::runtime {

template <class S>
using ConstraintMatrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using ConstraintVector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

// u̇ and λ of M u̇ − Wᵀλ = f, W u̇ = r: M n × n symmetric positive definite, W m × n of full row
// rank, f of n, r of m (Golub & Van Loan, the Schur complement on the LDLT of M).
template <class S>
void schur_solve(const ConstraintMatrix<S>& M, const ConstraintVector<S>& f, const ConstraintMatrix<S>& W,
                 const ConstraintVector<S>& r, ConstraintVector<S>& udot, ConstraintVector<S>& lambda) {
  const Eigen::LDLT<ConstraintMatrix<S>> ldlt(M);
  const ConstraintMatrix<S> Y = ldlt.solve(W.transpose());  // M⁻¹ Wᵀ
  const ConstraintVector<S> free_acceleration = ldlt.solve(f);  // M⁻¹ f
  const ConstraintMatrix<S> G = W * Y;                          // W M⁻¹ Wᵀ
  lambda = G.ldlt().solve(r - W * free_acceleration);
  udot = free_acceleration + Y * lambda;
}

// Puts x back on the rows with projected[α]: first the positions on the holonomic ones, then the
// velocities on all of them (HLW IV.4, M-metric). The callables evaluate the kernel's blocks:
//   residuals(t, x, f, phi): f_α (holonomic rows; kinematic rows ignored here) and φ_α, m each;
//   jacobian(t, x, W):       W, m × n_velocities row-major;
//   mass(t, x, M):           M, n_velocities × n_velocities row-major.
// Returns the number of Newton iterations of the position step (0 when it had nothing to do).
template <class S, class Residuals, class Jacobian, class Mass>
int project_onto_constraints(S t, S* x, const ConstraintLayout& layout, const bool* projected, const bool* holonomic,
                             Residuals&& residuals, Jacobian&& jacobian, Mass&& mass, int max_iterations = 4) {
  using RowMajor = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int m = layout.n_constraints, n = layout.n_velocities;
  // The steps of project_by_corrections, C = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ over the selected rows (n × p,
  // row-major), with M and W at the state it is asked at.
  const auto correction = [&](bool positions) {
    return [&, positions](S tau, const S* y, S* C) {
      RowMajor M(n, n), W(m, n);
      mass(tau, y, M.data());
      jacobian(tau, y, W.data());
      std::vector<int> rows;
      for (int a = 0; a < m; ++a)
        if (projected[a] && (!positions || holonomic[a])) rows.push_back(a);
      ConstraintMatrix<S> Wr(static_cast<Eigen::Index>(rows.size()), n);
      for (std::size_t i = 0; i < rows.size(); ++i) Wr.row(Eigen::Index(i)) = W.row(rows[i]);
      const ConstraintMatrix<S> Y = ConstraintMatrix<S>(M).ldlt().solve(Wr.transpose());
      const ConstraintMatrix<S> G = Wr * Y;
      Eigen::Map<RowMajor>(C, n, Eigen::Index(rows.size())) = Y * G.ldlt().solve(ConstraintMatrix<S>::Identity(G.rows(), G.cols()));
    };
  };
  return project_by_corrections(t, x, layout, projected, holonomic, residuals, correction(true), correction(false),
                                max_iterations);
}

}  // namespace eomc::runtime
