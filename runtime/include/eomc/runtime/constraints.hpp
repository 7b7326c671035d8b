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
  std::vector<int> position_rows, velocity_rows;
  for (int a = 0; a < m; ++a) {
    if (!projected[a]) continue;
    velocity_rows.push_back(a);
    if (holonomic[a]) position_rows.push_back(a);
  }
  if (velocity_rows.empty()) return 0;
  RowMajor M(n, n), W(m, n);
  ConstraintVector<S> f(m), phi(m);

  // M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ v over the selected rows, with M and W at the current x.
  struct Correction {
    Eigen::LDLT<ConstraintMatrix<S>> G;
    ConstraintMatrix<S> Y;
  };
  const auto factor = [&](const std::vector<int>& rows) {
    mass(t, static_cast<const S*>(x), M.data());
    jacobian(t, static_cast<const S*>(x), W.data());
    ConstraintMatrix<S> Wr(static_cast<Eigen::Index>(rows.size()), n);
    for (std::size_t i = 0; i < rows.size(); ++i) Wr.row(Eigen::Index(i)) = W.row(rows[i]);
    const ConstraintMatrix<S> Md = M;
    Correction c;
    c.Y = Md.ldlt().solve(Wr.transpose());
    c.G.compute(Wr * c.Y);
    return c;
  };
  const auto selected = [](const ConstraintVector<S>& v, const std::vector<int>& rows) {
    ConstraintVector<S> out(static_cast<Eigen::Index>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) out[Eigen::Index(i)] = v[rows[i]];
    return out;
  };

  int iterations = 0;
  if (!position_rows.empty()) {
    // Simplified Newton (HLW IV.4): W and M frozen at the step's end point.
    const Correction c = factor(position_rows);
    using std::abs;
    for (; iterations < max_iterations;) {
      residuals(t, static_cast<const S*>(x), f.data(), phi.data());
      const ConstraintVector<S> dq = c.Y * c.G.solve(selected(f, position_rows));
      S dq_norm(0), q_norm(0);
      for (int k = 0; k < n; ++k) {
        x[k] -= dq[k];
        dq_norm = abs(dq[k]) > dq_norm ? abs(dq[k]) : dq_norm;
        q_norm = abs(x[k]) > q_norm ? abs(x[k]) : q_norm;
      }
      ++iterations;
      if (dq_norm <= S(5) * Eigen::NumTraits<S>::epsilon() * (S(1) + q_norm)) break;
    }
  }
  // φ is linear in u: one step puts it on φ = 0 (to round-off).
  const Correction c = factor(velocity_rows);
  residuals(t, static_cast<const S*>(x), f.data(), phi.data());
  const ConstraintVector<S> du = c.Y * c.G.solve(selected(phi, velocity_rows));
  for (int k = 0; k < n; ++k) x[layout.velocity_offset + k] -= du[k];
  return iterations;
}

}  // namespace eomc::runtime
