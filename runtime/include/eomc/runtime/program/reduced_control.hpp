#pragma once

// The last step of a programmed motion's solve when the generator has done the rest in straight-line
// code (generator/codegen/solve_plan.hpp, reduce_programs; Mei ch. 3): M u̇ = f + D λ, Ā u̇ = c with
// z = M⁻¹f, Y = M⁻¹D becomes
//   G λ = h,   G = Ā Y (m × m),   h = c − Ā z,   u̇ = z + Y λ,   Q_c = D λ.
// G is small, neither symmetric nor definite (D ≠ Āᵀ for a non-ideal control), and singular exactly
// where no control in these directions realises the programs, so it is solved by LU with partial
// pivoting (Golub & Van Loan, Matrix Computations, 4th ed., Alg. 3.4.1), whose pivots also give
// det G. No Eigen: a kernel of a few coordinates compiles in a fraction of a second.
//
// A zero pivot (G singular) divides by zero: the rates become inf or NaN, which the runtime's
// checker stops on, never a finite guess. The kernel's events watch det G before that.

#include <array>
#include <cstddef>
#include <cmath>
#include <utility>

namespace eomc::runtime::program {

// G = P⁻¹ L U in place (G m × m row-major becomes L's multipliers below the diagonal and U on and
// above it; `swaps[j]` is the row exchanged with row j at step j). Returns det G, and 0 as soon
// as a pivot column is zero (G singular; the factors are then incomplete).
template <int m, class S>
S lu_factor(std::array<S, std::size_t(m * m)>& G, std::array<int, std::size_t(m)>& swaps) {
  using std::abs;
  const auto at = [&G](int i, int j) -> S& { return G[std::size_t(i * m + j)]; };
  S det = S(1);
  for (int j = 0; j < m; ++j) {
    int p = j;
    for (int i = j + 1; i < m; ++i)
      if (abs(at(i, j)) > abs(at(p, j))) p = i;
    swaps[std::size_t(j)] = p;
    if (at(p, j) == S(0)) return S(0);
    if (p != j) {
      for (int c = 0; c < m; ++c) std::swap(at(j, c), at(p, c));
      det = -det;
    }
    det *= at(j, j);
    const S inverse = S(1) / at(j, j);
    for (int i = j + 1; i < m; ++i) {
      const S l = at(i, j) * inverse;
      at(i, j) = l;
      for (int c = j + 1; c < m; ++c) at(i, c) -= l * at(j, c);
    }
  }
  return det;
}

// Solves G x = h in place (G is overwritten by its factors, h by x) and returns det G. Where G is
// singular x is h / 0: inf or NaN, for the checker to stop on.
template <int m, class S>
S lu_solve_in_place(std::array<S, std::size_t(m * m)>& G, std::array<S, std::size_t(m)>& h) {
  std::array<int, std::size_t(m)> swaps{};
  const S det = lu_factor<m>(G, swaps);
  // Singular where a pivot is zero (lu_factor stopped there), not where det underflowed.
  for (int j = 0; j < m; ++j)
    if (G[std::size_t(j * m + j)] == S(0)) {
      for (auto& v : h) v = v / S(0);
      return S(0);
    }
  const auto at = [&G](int i, int j) { return G[std::size_t(i * m + j)]; };
  // The exchanges moved whole rows, multipliers included: L is in the final row order, so P h comes
  // first, then L y = P h.
  for (int j = 0; j < m; ++j) std::swap(h[std::size_t(j)], h[std::size_t(swaps[std::size_t(j)])]);
  for (int j = 0; j < m; ++j)
    for (int i = j + 1; i < m; ++i) h[std::size_t(i)] -= at(i, j) * h[std::size_t(j)];
  for (int i = m; i-- > 0;) {
    S v = h[std::size_t(i)];
    for (int c = i + 1; c < m; ++c) v -= at(i, c) * h[std::size_t(c)];
    h[std::size_t(i)] = v / at(i, i);
  }
  return det;
}

// The layout of the reduced system a kernel computes: z (n), Y (n × m), G (m × m), h (m), D (n × m).
template <int n, int m>
struct ReducedLayout {
  static constexpr std::size_t z = 0, Y = z + n, G = Y + n * m, h = G + m * m, D = h + m, size = D + n * m;
};

// u̇, λ and Q_c = D λ from the reduced system; returns det G.
template <int n, int m, class S>
S reduced_control_solve(const S* reduced, S* udot, S* lambda, S* Qc) {
  using L = ReducedLayout<n, m>;
  std::array<S, std::size_t(m * m)> G;
  std::array<S, std::size_t(m)> x;
  for (std::size_t e = 0; e < G.size(); ++e) G[e] = reduced[L::G + e];
  for (std::size_t a = 0; a < x.size(); ++a) x[a] = reduced[L::h + a];
  const S det = lu_solve_in_place<m>(G, x);
  for (std::size_t i = 0; i < std::size_t(n); ++i) {
    S u = reduced[L::z + i], q = S(0);
    for (std::size_t a = 0; a < std::size_t(m); ++a) {
      u += reduced[L::Y + i * m + a] * x[a];
      q += reduced[L::D + i * m + a] * x[a];
    }
    udot[i] = u;
    Qc[i] = q;
  }
  for (std::size_t a = 0; a < std::size_t(m); ++a) lambda[a] = x[a];
  return det;
}

// det G = det(Ā M⁻¹ D) alone, for the event that watches realisability.
template <int n, int m, class S>
S reduced_control_determinant(const S* reduced) {
  using L = ReducedLayout<n, m>;
  std::array<S, std::size_t(m * m)> G;
  std::array<int, std::size_t(m)> swaps{};
  for (std::size_t e = 0; e < G.size(); ++e) G[e] = reduced[L::G + e];
  return lu_factor<m>(G, swaps);
}

}  // namespace eomc::runtime::program
