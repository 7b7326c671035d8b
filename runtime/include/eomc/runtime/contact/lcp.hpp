#pragma once

// The linear complementarity problem LCP(M, q): find z with
//
//   z ≥ 0,   w = M z + q ≥ 0,   zᵀ w = 0,
//
// the form every unilateral contact law takes once the dynamics is linear in the unknown impulses
// or forces (impact.hpp: Newton's law in Moreau's form; moreau_jean.hpp: the time stepping).
//
// solve_lcp is Lemke's complementary pivoting algorithm (C. E. Lemke, "Bimatrix equilibrium
// points and mathematical programming", Management Sci. 11 (1965) 681–689; R. W. Cottle,
// J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic Press 1992, §4.4). An
// artificial variable z₀ with covering vector d = (1, …, 1) makes w = q + d z₀ + M z feasible at
// z = 0; then one pivot after another keeps one complementary pair (w_i, z_i) both non-basic and
// brings in the complement of the variable that just left, until z₀ leaves (a solution) or the
// entering column has no positive entry (a secondary ray).
// Degenerate ratio tests are resolved by the lexicographic rule (Cottle–Pang–Stone §4.9): the row
// minimising (b̄_i, β_i) / ā_i lexicographically, β_i the row of the basis inverse, is unique and
// no basis repeats, so the method terminates on any data.
//
// What termination means (Cottle–Pang–Stone §4.4): for a P-matrix M (all principal minors
// positive; symmetric positive definite M among them) Lemke's method always ends in the unique
// solution; for a copositive-plus M (positive semidefinite among them) a ray
// termination proves that LCP(M, q) has no solution.
//
// The tableau is worked on M and q scaled to unit max-norm (z is invariant up to one factor, see
// below), so that the tolerances are absolute numbers of order ε. At the end the solution is
// recomputed from the final complementary basis α = {i : z_i basic} by one fresh LU solve of
// M_αα z_α = −q_α on the unscaled data, which removes the rounding accumulated over the pivots;
// the recomputed z is kept when it satisfies the complementarity conditions at least as well.
//
// lcp_solutions_by_enumeration visits all 2ⁿ complementary bases (the solutions of LCP(M, q) with
// M_αα nonsingular are exactly the feasible complementary basic solutions); it is the oracle of the tests and a solver for n up to about 10.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

namespace eomc::runtime {

template <class S>
using LcpMatrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using LcpVector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

// solved: z, w satisfy the conditions (to rounding). ray_termination: Lemke's method reached a
// secondary ray (for copositive-plus M: no solution exists). pivot_limit: the pivot budget ran
// out. infeasible: the enumeration found no feasible complementary basis (enumeration only).
enum class LcpStatus : int { solved = 0, ray_termination = 1, pivot_limit = 2, infeasible = 3 };

inline const char* to_string(LcpStatus s) {
  switch (s) {
    case LcpStatus::solved: return "solved";
    case LcpStatus::ray_termination: return "ray termination";
    case LcpStatus::pivot_limit: return "pivot limit";
    case LcpStatus::infeasible: return "infeasible";
  }
  return "unknown";
}

template <class S>
struct LcpResult {
  LcpVector<S> z, w;  // w = M z + q; on failure, the last almost-complementary point (z₀ dropped)
  LcpStatus status = LcpStatus::solved;
  int pivots = 0;  // Lemke pivots, the initial one included (0 when q ≥ 0)
};

namespace detail {

// LCP(M, q) and LCP(M/μ, q/ν) have the same solutions up to z = (ν/μ) z', w = ν w'
// (w = M z + q ⇔ w/ν = (M/μ)(μ z/ν) + q/ν): the scaled problem has entries of unit size.
template <class S>
struct LcpScaling {
  S mu = S(1), nu = S(1);
  LcpScaling(const LcpMatrix<S>& M, const LcpVector<S>& q) {
    const S m = M.size() ? M.cwiseAbs().maxCoeff() : S(0);
    const S r = q.size() ? q.cwiseAbs().maxCoeff() : S(0);
    if (m > S(0)) mu = m;
    if (r > S(0)) nu = r;
  }
};

template <class S>
void check_lcp_shapes(const LcpMatrix<S>& M, const LcpVector<S>& q) {
  if (M.rows() != M.cols() || M.rows() != q.size())
    throw std::invalid_argument("LCP: M must be n x n and q of size n");
}

// Largest violation of z ≥ 0, w ≥ 0, z_i w_i = 0 (the complementarity measured as min(z_i, w_i),
// which is in the units of z and w alike once scaled).
template <class S>
S lcp_violation(const LcpVector<S>& z, const LcpVector<S>& w) {
  using std::abs;
  using std::max;
  using std::min;
  S v(0);
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    v = max(v, max(-z[i], -w[i]));
    v = max(v, min(abs(z[i]), abs(w[i])));
  }
  return v;
}

// Refinement of a solved tableau on its final basis: M_αα z_α = −q_α, z_ᾱ = 0, from the original
// data, kept when it violates the complementarity conditions no more than the tableau's point.
template <class S>
void refine_on_basis(const LcpMatrix<S>& M, const LcpVector<S>& q, const std::vector<Eigen::Index>& basis,
                     const LcpScaling<S>& scale, LcpResult<S>& result) {
  const Eigen::Index n = q.size(), cz = n, c0 = 2 * n;
  std::vector<Eigen::Index> alpha;
  for (Eigen::Index v : basis)
    if (v >= cz && v < c0) alpha.push_back(v - n);
  if (alpha.empty()) return;
  const Eigen::Index k = Eigen::Index(alpha.size());
  LcpMatrix<S> Ma(k, k);
  LcpVector<S> qa(k);
  for (Eigen::Index a = 0; a < k; ++a) {
    qa[a] = -q[alpha[std::size_t(a)]];
    for (Eigen::Index b = 0; b < k; ++b) Ma(a, b) = M(alpha[std::size_t(a)], alpha[std::size_t(b)]);
  }
  const LcpVector<S> za = Ma.partialPivLu().solve(qa);
  LcpVector<S> refined = LcpVector<S>::Zero(n);
  for (Eigen::Index a = 0; a < k; ++a) refined[alpha[std::size_t(a)]] = za[a];
  const LcpVector<S> refined_w = M * refined + q;
  if (refined.allFinite() && lcp_violation<S>(refined / scale.nu * scale.mu, refined_w / scale.nu) <=
                                 lcp_violation<S>(result.z / scale.nu * scale.mu, result.w / scale.nu)) {
    result.z = refined;
    result.w = refined_w;
  }
}

}  // namespace detail

// Lemke's method with the lexicographic rule. max_pivots = 0 selects 10 n² + 100 (the number of
// bases visited is finite but can grow exponentially in n, Murty's examples; in practice a few n).
// pivot_tolerance (≤ 0: ε^(2/3)) is the smallest entry of the scaled entering column, relative to
// the column's size, that the ratio test accepts as positive.
template <class S>
LcpResult<S> solve_lcp(const LcpMatrix<S>& M, const LcpVector<S>& q, int max_pivots = 0,
                       S pivot_tolerance = S(0)) {
  using std::abs;
  using std::cbrt;
  using std::max;
  detail::check_lcp_shapes(M, q);
  const Eigen::Index n = q.size();
  LcpResult<S> result;
  result.z = LcpVector<S>::Zero(n);
  result.w = q;
  if (n == 0 || q.minCoeff() >= S(0)) return result;  // z = 0 solves it
  if (max_pivots <= 0) max_pivots = int(10 * n * n + 100);
  const S eps = Eigen::NumTraits<S>::epsilon();
  if (!(pivot_tolerance > S(0))) pivot_tolerance = cbrt(eps) * cbrt(eps);
  // Ratios within tie_tolerance (relative) are a tie, passed on to the lexicographic comparison:
  // rounding of order ε on the tableau must not decide a degenerate ratio test.
  const S tie_tolerance = S(1024) * eps;

  const detail::LcpScaling<S> scale(M, q);
  // Columns: w_0..w_{n−1}, z_0..z_{n−1}, z₀ (the artificial variable), then the right-hand side.
  // Row i reads Σ_j T_ij x_j = T_i,rhs; initially w − M z − d z₀ = q, the basis the w's (B = I).
  const Eigen::Index cz = n, c0 = 2 * n, crhs = 2 * n + 1;
  LcpMatrix<S> T = LcpMatrix<S>::Zero(n, 2 * n + 2);
  T.leftCols(n).setIdentity();
  T.block(0, cz, n, n) = -M / scale.mu;
  T.col(c0).setConstant(S(-1));
  T.col(crhs) = q / scale.nu;
  std::vector<Eigen::Index> basis(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) basis[std::size_t(i)] = i;

  // The columns of the initial basis (the w's) hold B⁻¹ throughout: the lexicographic vectors.
  // lex_less(i, ai, j, aj): (b̄_i, β_i)/a_i < (b̄_j, β_j)/a_j lexicographically, ties to tolerance.
  const auto component = [&](Eigen::Index i, Eigen::Index k) { return k == 0 ? T(i, crhs) : T(i, k - 1); };
  const auto lex_less = [&](Eigen::Index i, S ai, Eigen::Index j, S aj) {
    for (Eigen::Index k = 0; k <= n; ++k) {
      const S x = component(i, k) / ai, y = component(j, k) / aj;
      const S tol = tie_tolerance * (S(1) + max(abs(x), abs(y)));
      if (x < y - tol) return true;
      if (y < x - tol) return false;
    }
    return i < j;  // unreachable for a nonsingular basis: the rows of B⁻¹ are independent
  };
  const auto pivot = [&](Eigen::Index r, Eigen::Index c) {
    T.row(r) /= T(r, c);
    for (Eigen::Index i = 0; i < n; ++i) {
      if (i == r) continue;
      const S f = T(i, c);
      if (f != S(0)) T.row(i) -= f * T.row(r);
      T(i, c) = S(0);
    }
    T(r, c) = S(1);
  };
  const auto complement = [&](Eigen::Index v) { return v < n ? v + n : v - n; };

  // The initial pivot: z₀ enters at the level max_i(−q_i/d_i), which leaves every w ≥ 0; the row
  // that leaves is the lexicographic minimum of (q_i, e_iᵀ)/d_i (d = 1).
  Eigen::Index r = 0;
  for (Eigen::Index i = 1; i < n; ++i)
    if (lex_less(i, S(1), r, S(1))) r = i;
  pivot(r, c0);
  Eigen::Index leaving = basis[std::size_t(r)];
  basis[std::size_t(r)] = c0;
  result.pivots = 1;
  result.status = LcpStatus::pivot_limit;
  for (;;) {
    if (result.pivots >= max_pivots) break;
    const Eigen::Index entering = complement(leaving);
    // The ratio test on the rows whose basic variable decreases as `entering` grows (ā_i > 0).
    const S column_size = max(S(1), T.col(entering).cwiseAbs().maxCoeff());
    Eigen::Index best = -1, z0_row = -1;
    for (Eigen::Index i = 0; i < n; ++i) {
      const S a = T(i, entering);
      if (!(a > pivot_tolerance * column_size)) continue;
      if (basis[std::size_t(i)] == c0) z0_row = i;
      if (best < 0 || lex_less(i, a, best, T(best, entering))) best = i;
    }
    if (best < 0) {
      result.status = LcpStatus::ray_termination;
      break;
    }
    // z₀ tied for the minimum ratio: let it leave, a solution now rather than after degenerate
    // pivots (the basic variables stay ≥ 0 all the same).
    if (z0_row >= 0 && best != z0_row) {
      const S x = T(z0_row, crhs) / T(z0_row, entering), y = T(best, crhs) / T(best, entering);
      if (x <= y + tie_tolerance * (S(1) + max(abs(x), abs(y)))) best = z0_row;
    }
    pivot(best, entering);
    leaving = basis[std::size_t(best)];
    basis[std::size_t(best)] = entering;
    ++result.pivots;
    if (leaving == c0) {
      result.status = LcpStatus::solved;
      break;
    }
  }

  // The point the tableau holds (z₀ dropped on failure), back in the unscaled units.
  LcpVector<S> z = LcpVector<S>::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index v = basis[std::size_t(i)];
    if (v >= cz && v < c0) z[v - n] = T(i, crhs) * scale.nu / scale.mu;
  }
  result.z = z;
  result.w = M * z + q;
  if (result.status != LcpStatus::solved) return result;

  detail::refine_on_basis(M, q, basis, scale, result);
  return result;
}

// Every solution of LCP(M, q) at a complementary basis with M_αα nonsingular (2ⁿ LU solves; n is
// limited to 20). A basic solution is feasible when its z and w are ≥ −tolerance in the scaled
// units (tolerance ≤ 0: ε^(2/3)); solutions equal within the tolerance are reported once (a
// degenerate q makes several bases give one point). A singular M_αα is skipped: where it carries
// a continuum of solutions (PSD M), only the continuum's basic points at other bases are found.
template <class S>
std::vector<LcpVector<S>> lcp_solutions_by_enumeration(const LcpMatrix<S>& M, const LcpVector<S>& q,
                                                       S tolerance = S(0)) {
  using std::cbrt;
  detail::check_lcp_shapes(M, q);
  const Eigen::Index n = q.size();
  if (n > 20) throw std::invalid_argument("LCP enumeration: n > 20 (2^n bases)");
  if (!(tolerance > S(0))) tolerance = cbrt(Eigen::NumTraits<S>::epsilon()) * cbrt(Eigen::NumTraits<S>::epsilon());
  const detail::LcpScaling<S> scale(M, q);
  const LcpMatrix<S> Ms = M / scale.mu;
  const LcpVector<S> qs = q / scale.nu;
  std::vector<LcpVector<S>> found;  // in scaled units until the end
  for (std::uint32_t mask = 0; mask < (std::uint32_t(1) << n); ++mask) {
    std::vector<Eigen::Index> alpha;
    for (Eigen::Index i = 0; i < n; ++i)
      if (mask & (std::uint32_t(1) << i)) alpha.push_back(i);
    const Eigen::Index k = Eigen::Index(alpha.size());
    LcpVector<S> z = LcpVector<S>::Zero(n);
    if (k > 0) {
      LcpMatrix<S> Ma(k, k);
      LcpVector<S> qa(k);
      for (Eigen::Index a = 0; a < k; ++a) {
        qa[a] = -qs[alpha[std::size_t(a)]];
        for (Eigen::Index b = 0; b < k; ++b) Ma(a, b) = Ms(alpha[std::size_t(a)], alpha[std::size_t(b)]);
      }
      const Eigen::FullPivLU<LcpMatrix<S>> lu(Ma);
      if (!lu.isInvertible()) continue;
      const LcpVector<S> za = lu.solve(qa);
      for (Eigen::Index a = 0; a < k; ++a) z[alpha[std::size_t(a)]] = za[a];
    }
    const LcpVector<S> w = Ms * z + qs;
    if (z.minCoeff() < -tolerance || w.minCoeff() < -tolerance) continue;
    bool seen = false;
    for (const LcpVector<S>& other : found)
      if ((other - z).cwiseAbs().maxCoeff() <= tolerance * (S(1) + z.cwiseAbs().maxCoeff())) seen = true;
    if (!seen) found.push_back(z);
  }
  for (LcpVector<S>& z : found) z *= scale.nu / scale.mu;
  return found;
}

// The first solution the enumeration finds, as an LcpResult (status infeasible when there is none).
template <class S>
LcpResult<S> solve_lcp_by_enumeration(const LcpMatrix<S>& M, const LcpVector<S>& q, S tolerance = S(0)) {
  const std::vector<LcpVector<S>> all = lcp_solutions_by_enumeration<S>(M, q, tolerance);
  LcpResult<S> result;
  if (all.empty()) {
    result.z = LcpVector<S>::Zero(q.size());
    result.status = LcpStatus::infeasible;
  } else {
    result.z = all.front();
  }
  result.w = M * result.z + q;
  return result;
}

}  // namespace eomc::runtime
