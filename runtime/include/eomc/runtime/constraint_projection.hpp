#pragma once

// What a kernel with bilateral constraint rows needs from the runtime when its solves are
// straight-line code (generator/codegen/solve_plan.hpp, plan_saddle_point): no Eigen. The kernel
// computes u̇ and λ itself; here are the projection driven by the kernel's correction matrices and
// the differenced Jacobian. runtime/constraints.hpp holds the Eigen versions for the other kernels
// and the contact drivers.
//
// The projection is the coordinate projection of E. Hairer, C. Lubich, G. Wanner, Geometric
// Numerical Integration, 2nd ed., Springer 2006, §IV.4 (Algorithm 4.2, eq. (4.4)), in the metric
// of M: a simplified Newton iteration q ← q − C f(q) with C = M⁻¹Wᵀ(W M⁻¹ Wᵀ)⁻¹ frozen at the
// step's end point, then u ← u − C φ(q, u), exact in one step because φ is linear in u.

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace eomc::runtime {

// Where the rows act in a kernel's state: the generalized coordinates are x[0 .. n_coordinates),
// the velocity block x[velocity_offset .. velocity_offset + n_velocities). The position step
// needs q̇ = u (n_coordinates == n_velocities): then W's holonomic rows are ∂f/∂q.
struct ConstraintLayout {
  int n_coordinates = 0, velocity_offset = 0, n_velocities = 0, n_constraints = 0;
};

// Puts x back on the rows with projected[α], positions on the holonomic ones then velocities on all
// of them, with the kernel's corrections:
//   residuals(t, x, f, phi):  f_α (holonomic rows; kinematic rows ignored here) and φ_α, m each;
//   position(t, x, C):        C over the projected holonomic rows (n_velocities × p, row-major);
//   velocity(t, x, C):        C over every projected row (n_velocities × v, row-major);
// rows in their order in the kernel. Returns the number of Newton iterations of the position step.
template <class S, class Residuals, class PositionCorrection, class VelocityCorrection>
int project_by_corrections(S t, S* x, const ConstraintLayout& layout, const bool* projected, const bool* holonomic,
                           Residuals&& residuals, PositionCorrection&& position, VelocityCorrection&& velocity,
                           int max_iterations = 4) {
  using std::abs;
  const int m = layout.n_constraints, n = layout.n_velocities;
  std::vector<int> position_rows, velocity_rows;
  for (int a = 0; a < m; ++a) {
    if (!projected[a]) continue;
    velocity_rows.push_back(a);
    if (holonomic[a]) position_rows.push_back(a);
  }
  if (velocity_rows.empty()) return 0;
  std::vector<S> f(static_cast<std::size_t>(m)), phi(static_cast<std::size_t>(m)), C;
  // x_block −= C v over the selected rows.
  const auto apply = [&](S* block, const std::vector<int>& rows, const std::vector<S>& v, S* largest) {
    const std::size_t p = rows.size();
    for (int k = 0; k < n; ++k) {
      S d(0);
      for (std::size_t j = 0; j < p; ++j) d += C[std::size_t(k) * p + j] * v[std::size_t(rows[j])];
      block[k] -= d;
      if (largest && abs(d) > *largest) *largest = abs(d);
    }
  };

  int iterations = 0;
  if (!position_rows.empty()) {
    C.assign(std::size_t(n) * position_rows.size(), S(0));
    position(t, static_cast<const S*>(x), C.data());  // frozen at the step's end point
    for (; iterations < max_iterations;) {
      residuals(t, static_cast<const S*>(x), f.data(), phi.data());
      S dq_norm(0), q_norm(0);
      apply(x, position_rows, f, &dq_norm);
      for (int k = 0; k < n; ++k) q_norm = abs(x[k]) > q_norm ? abs(x[k]) : q_norm;
      ++iterations;
      if (dq_norm <= S(5) * std::numeric_limits<S>::epsilon() * (S(1) + q_norm)) break;
    }
  }
  C.assign(std::size_t(n) * velocity_rows.size(), S(0));
  velocity(t, static_cast<const S*>(x), C.data());
  residuals(t, static_cast<const S*>(x), f.data(), phi.data());
  apply(x + layout.velocity_offset, velocity_rows, phi, nullptr);
  return iterations;
}

// ∂ẋ/∂x by central differences of rhs(t, x, dxdt), row-major n × n: the Jacobian of a
// constrained kernel, whose rates go through the saddle-point solve (the implicit methods only
// need it for their Newton iterations). Step (ε^(1/3)) max(1, |x_j|): error O(ε^(2/3)).
template <class S, class Rates>
void central_difference_jacobian(S t, const S* x, S* out, int n, Rates&& rhs) {
  using std::abs;
  using std::cbrt;
  std::vector<S> y(x, x + n), plus(static_cast<std::size_t>(n)), minus(static_cast<std::size_t>(n));
  const S scale = cbrt(std::numeric_limits<S>::epsilon());
  for (int j = 0; j < n; ++j) {
    const S h = scale * (abs(x[j]) > S(1) ? abs(x[j]) : S(1));
    y[std::size_t(j)] = x[j] + h;
    rhs(t, static_cast<const S*>(y.data()), plus.data());
    y[std::size_t(j)] = x[j] - h;
    rhs(t, static_cast<const S*>(y.data()), minus.data());
    y[std::size_t(j)] = x[j];
    for (int i = 0; i < n; ++i) out[i * n + j] = (plus[std::size_t(i)] - minus[std::size_t(i)]) / (S(2) * h);
  }
}

}  // namespace eomc::runtime
