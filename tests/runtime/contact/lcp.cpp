// contact/lcp.hpp: Lemke's method against the enumeration of all complementary bases (unique
// solutions: SPD and P-matrices; the common w of a symmetric PSD problem), degenerate ratio tests
// on integer data (the lexicographic rule must terminate), ray termination on infeasible
// copositive-plus data, the pivot limit, and the complementarity conditions for n up to 50, in
// double and long double.
#define BOOST_TEST_MODULE runtime_lcp
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "eomc/runtime/contact/lcp.hpp"

namespace rt = eomc::runtime;

namespace eomc::runtime {
std::ostream& operator<<(std::ostream& os, LcpStatus s) { return os << to_string(s); }
}  // namespace eomc::runtime

namespace {

template <class S>
using Mat = rt::LcpMatrix<S>;
template <class S>
using Vec = rt::LcpVector<S>;

template <class S>
Mat<S> random_matrix(std::mt19937_64& rng, Eigen::Index rows, Eigen::Index cols) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat<S> A(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) A(i, j) = S(u(rng));
  return A;
}

template <class S>
Vec<S> random_vector(std::mt19937_64& rng, Eigen::Index n) {
  return random_matrix<S>(rng, n, 1);
}

// Symmetric positive definite, condition number about 10² to 10³.
template <class S>
Mat<S> random_spd(std::mt19937_64& rng, Eigen::Index n) {
  const Mat<S> B = random_matrix<S>(rng, n, n);
  return B * B.transpose() + S(0.05) * Mat<S>::Identity(n, n);
}

template <class S>
S spd_condition(const Mat<S>& M) {
  const Eigen::SelfAdjointEigenSolver<Mat<S>> es(M);
  return es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
}

// Every principal minor positive (2ⁿ determinants; n ≤ 10).
template <class S>
bool is_p_matrix(const Mat<S>& M) {
  const Eigen::Index n = M.rows();
  for (std::uint32_t mask = 1; mask < (std::uint32_t(1) << n); ++mask) {
    std::vector<Eigen::Index> a;
    for (Eigen::Index i = 0; i < n; ++i)
      if (mask & (std::uint32_t(1) << i)) a.push_back(i);
    Mat<S> sub(Eigen::Index(a.size()), Eigen::Index(a.size()));
    for (std::size_t r = 0; r < a.size(); ++r)
      for (std::size_t c = 0; c < a.size(); ++c) sub(Eigen::Index(r), Eigen::Index(c)) = M(a[r], a[c]);
    if (!(sub.determinant() > S(0))) return false;
  }
  return true;
}

// The largest violation of z ≥ 0, w ≥ 0 and of |z_i w_i| (the products, in units of z·w).
template <class S>
struct Violation {
  S negative_z, negative_w, product;
};
template <class S>
Violation<S> violation(const rt::LcpResult<S>& r) {
  Violation<S> v{S(0), S(0), S(0)};
  for (Eigen::Index i = 0; i < r.z.size(); ++i) {
    v.negative_z = std::max(v.negative_z, -r.z[i]);
    v.negative_w = std::max(v.negative_w, -r.w[i]);
    v.product = std::max(v.product, std::abs(r.z[i] * r.w[i]));
  }
  return v;
}

// The complementarity conditions to the rounding of a backward-stable solve of the final basis:
// w_α = (M z + q)_α is a residual of size n ε (‖M‖ ‖z‖ + ‖q‖); z_α carries a relative error
// κ n ε (κ the condition number of M_αα, bounded by `kappa`).
template <class S>
void check_complementarity(const Mat<S>& M, const Vec<S>& q, const rt::LcpResult<S>& r, S kappa) {
  const S eps = std::numeric_limits<S>::epsilon();
  const S n = S(q.size());
  const S zmax = r.z.cwiseAbs().maxCoeff();
  const S residual = S(10) * n * eps * (M.cwiseAbs().maxCoeff() * n * zmax + q.cwiseAbs().maxCoeff());
  const Violation<S> v = violation(r);
  BOOST_TEST(r.status == rt::LcpStatus::solved);
  BOOST_TEST(v.negative_z <= S(10) * n * eps * kappa * zmax);
  BOOST_TEST(v.negative_w <= residual);
  BOOST_TEST(v.product <= residual * zmax);
  BOOST_TEST((r.w - (M * r.z + q)).cwiseAbs().maxCoeff() == S(0));
}

// Lemke against the enumeration on a problem whose solution is unique; tolerance from the
// condition number (both solves carry κ n ε relative error).
template <class S>
S check_unique(const Mat<S>& M, const Vec<S>& q, S kappa) {
  const S eps = std::numeric_limits<S>::epsilon();
  const rt::LcpResult<S> lemke = rt::solve_lcp<S>(M, q);
  const std::vector<Vec<S>> all = rt::lcp_solutions_by_enumeration<S>(M, q);
  BOOST_TEST_REQUIRE(all.size() == 1u);
  check_complementarity(M, q, lemke, kappa);
  const S scale = std::max(S(1), all.front().cwiseAbs().maxCoeff());
  const S err = (lemke.z - all.front()).cwiseAbs().maxCoeff() / scale;
  BOOST_TEST(err <= S(20) * S(q.size()) * kappa * eps);
  return err / (kappa * eps);
}

}  // namespace

BOOST_AUTO_TEST_CASE(nonnegative_q_is_solved_by_zero) {
  const Mat<double> M = Mat<double>::Identity(3, 3) * -1.0;  // any M
  const Vec<double> q = Vec<double>::LinSpaced(3, 0.0, 2.0);
  const rt::LcpResult<double> r = rt::solve_lcp<double>(M, q);
  BOOST_TEST(r.status == rt::LcpStatus::solved);
  BOOST_TEST(r.pivots == 0);
  BOOST_TEST(r.z.isZero(0.0));
  BOOST_TEST(r.w == q);
}

BOOST_AUTO_TEST_CASE(two_by_two_by_hand) {
  // 2 z1 + z2 = 5, z1 + 2 z2 = 6: z = (4/3, 7/3), w = 0.
  Mat<double> M(2, 2);
  M << 2, 1, 1, 2;
  Vec<double> q(2);
  q << -5, -6;
  const rt::LcpResult<double> r = rt::solve_lcp<double>(M, q);
  BOOST_TEST(r.status == rt::LcpStatus::solved);
  BOOST_TEST(std::abs(r.z[0] - 4.0 / 3.0) <= 4 * std::numeric_limits<double>::epsilon());
  BOOST_TEST(std::abs(r.z[1] - 7.0 / 3.0) <= 4 * std::numeric_limits<double>::epsilon());
  // One contact lifts off: q = (−1, 3) gives z = (1/2, 0), w = (0, 3.5).
  q << -1, 3;
  const rt::LcpResult<double> s = rt::solve_lcp<double>(M, q);
  BOOST_TEST(s.z[0] == 0.5);
  BOOST_TEST(s.z[1] == 0.0);
  BOOST_TEST(s.w[1] == 3.5);
}

BOOST_AUTO_TEST_CASE(spd_matches_enumeration) {
  std::mt19937_64 rng(20240601);
  double worst = 0;
  int pivots = 0, problems = 0;
  for (Eigen::Index n = 1; n <= 10; ++n)
    for (int trial = 0; trial < 20; ++trial) {
      const Mat<double> M = random_spd<double>(rng, n);
      const Vec<double> q = random_vector<double>(rng, n);
      worst = std::max(worst, check_unique<double>(M, q, spd_condition<double>(M)));
      pivots += rt::solve_lcp<double>(M, q).pivots;
      ++problems;
    }
  BOOST_TEST_MESSAGE("SPD n <= 10: worst |z_lemke - z_enum| / (kappa eps) = " << worst << ", mean pivots "
                                                                              << double(pivots) / problems);
}

BOOST_AUTO_TEST_CASE(spd_long_double) {
  std::mt19937_64 rng(7);
  long double worst = 0;
  for (Eigen::Index n = 2; n <= 8; ++n)
    for (int trial = 0; trial < 5; ++trial) {
      const Mat<long double> M = random_spd<long double>(rng, n);
      const Vec<long double> q = random_vector<long double>(rng, n);
      worst = std::max(worst, check_unique<long double>(M, q, spd_condition<long double>(M)));
    }
  BOOST_TEST_MESSAGE("SPD long double: worst error / (kappa eps) = " << double(worst));
}

BOOST_AUTO_TEST_CASE(p_matrices_match_enumeration) {
  std::mt19937_64 rng(99);
  double worst = 0;
  for (Eigen::Index n = 2; n <= 8; ++n)
    for (int trial = 0; trial < 20; ++trial) {
      // Non-symmetric P-matrices: positive definite (SPD plus skew) and strictly diagonally
      // dominant with positive diagonal (Cottle–Pang–Stone §3.3).
      Mat<double> M;
      if (trial % 2 == 0) {
        const Mat<double> K = random_matrix<double>(rng, n, n);
        M = random_spd<double>(rng, n) + 2.0 * (K - K.transpose());
      } else {
        M = random_matrix<double>(rng, n, n);
        for (Eigen::Index i = 0; i < n; ++i) M(i, i) = M.row(i).cwiseAbs().sum() + 0.1;
      }
      BOOST_TEST_REQUIRE(is_p_matrix(M));
      const Vec<double> q = random_vector<double>(rng, n);
      // κ of M itself bounds no principal submatrix here; take the worst over the principal
      // submatrices through the singular values of M (σ_max / σ_min of M_αα ≤ ‖M‖ / σ_min(M_αα)),
      // which the enumeration's solves see: use the largest 1-norm condition estimate over all.
      double kappa = 1;
      for (std::uint32_t mask = 1; mask < (std::uint32_t(1) << n); ++mask) {
        std::vector<Eigen::Index> a;
        for (Eigen::Index i = 0; i < n; ++i)
          if (mask & (std::uint32_t(1) << i)) a.push_back(i);
        Mat<double> sub(Eigen::Index(a.size()), Eigen::Index(a.size()));
        for (std::size_t r = 0; r < a.size(); ++r)
          for (std::size_t c = 0; c < a.size(); ++c) sub(Eigen::Index(r), Eigen::Index(c)) = M(a[r], a[c]);
        kappa = std::max(kappa, 1.0 / sub.partialPivLu().rcond());
      }
      worst = std::max(worst, check_unique<double>(M, q, kappa));
    }
  BOOST_TEST_MESSAGE("P-matrices: worst error / (kappa eps) = " << worst);
}

// Degenerate data: integer PSD matrices of low rank and q with entries in {−1, 0, 1}, so the ratio
// tests tie (the first pivot ties across all rows with q_i = −1; basic variables sit at zero).
// Lemke must terminate (lexicographic rule) and agree with the enumeration: solved exactly when a
// solution exists (PSD is copositive-plus: a ray proves infeasibility), with the same w (for
// symmetric PSD M, w is common to all solutions: (z₁ − z₂)ᵀ M (z₁ − z₂) ≤ 0 forces M z₁ = M z₂).
BOOST_AUTO_TEST_CASE(degenerate_psd_terminates) {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> digit(-1, 1);
  int solved = 0, rays = 0, max_pivots = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Index n = 2 + trial % 7, rank = 1 + trial % std::max<Eigen::Index>(1, n - 1);
    Mat<double> B(n, rank);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < rank; ++j) B(i, j) = digit(rng);
    const Mat<double> M = B * B.transpose();
    Vec<double> q(n);
    for (Eigen::Index i = 0; i < n; ++i) q[i] = digit(rng);
    if (trial % 3 == 0) q.setConstant(-1);  // every row tied in the first ratio test
    const rt::LcpResult<double> r = rt::solve_lcp<double>(M, q);
    const std::vector<Vec<double>> all = rt::lcp_solutions_by_enumeration<double>(M, q);
    BOOST_TEST(r.status != rt::LcpStatus::pivot_limit);
    max_pivots = std::max(max_pivots, r.pivots);
    if (all.empty()) {
      BOOST_TEST(r.status == rt::LcpStatus::ray_termination);
      ++rays;
    } else {
      BOOST_TEST(r.status == rt::LcpStatus::solved);
      check_complementarity<double>(M, q, r, 1e3);
      const Vec<double> w_enum = M * all.front() + q;
      BOOST_TEST((r.w - w_enum).cwiseAbs().maxCoeff() <= 1e-12);
      ++solved;
    }
  }
  BOOST_TEST(solved > 50);
  BOOST_TEST(rays > 20);
  BOOST_TEST_MESSAGE("degenerate PSD: " << solved << " solved, " << rays << " rays, max pivots " << max_pivots);
}

// M = [[1, −1], [−1, 1]] (PSD) and q = (−1, −1): w₁ + w₂ = −2 < 0 for every z, no solution; the
// zero matrix with a negative q likewise.
BOOST_AUTO_TEST_CASE(ray_termination_on_infeasible_copositive_plus) {
  Mat<double> M(2, 2);
  M << 1, -1, -1, 1;
  Vec<double> q(2);
  q << -1, -1;
  const rt::LcpResult<double> r = rt::solve_lcp<double>(M, q);
  BOOST_TEST(r.status == rt::LcpStatus::ray_termination);
  BOOST_TEST(rt::lcp_solutions_by_enumeration<double>(M, q).empty());
  BOOST_TEST(rt::solve_lcp_by_enumeration<double>(M, q).status == rt::LcpStatus::infeasible);
  const Mat<double> Z = Mat<double>::Zero(3, 3);
  Vec<double> p(3);
  p << 1, -2, 0;
  BOOST_TEST(rt::solve_lcp<double>(Z, p).status == rt::LcpStatus::ray_termination);
}

BOOST_AUTO_TEST_CASE(pivot_limit) {
  std::mt19937_64 rng(11);
  const Mat<double> M = random_spd<double>(rng, 6);
  const Vec<double> q = -Vec<double>::Ones(6) - random_vector<double>(rng, 6).cwiseAbs();
  const rt::LcpResult<double> full = rt::solve_lcp<double>(M, q);
  BOOST_TEST_REQUIRE(full.status == rt::LcpStatus::solved);
  BOOST_TEST_REQUIRE(full.pivots > 2);
  const rt::LcpResult<double> cut = rt::solve_lcp<double>(M, q, full.pivots - 1);
  BOOST_TEST(cut.status == rt::LcpStatus::pivot_limit);
  BOOST_TEST(cut.pivots == full.pivots - 1);
}

// Large n, beyond the enumeration: SPD, diagonally dominant P-matrices and feasible-by-construction
// PSD problems (q = w* − M z* with z*, w* ≥ 0 complementary), the conditions checked directly.
BOOST_AUTO_TEST_CASE(large_problems_satisfy_complementarity) {
  std::mt19937_64 rng(5);
  std::bernoulli_distribution coin(0.5);
  for (Eigen::Index n : {20, 35, 50}) {
    int pivots[3] = {0, 0, 0};
    for (int trial = 0; trial < 4; ++trial) {
      const Mat<double> A = random_spd<double>(rng, n);
      const Vec<double> qa = random_vector<double>(rng, n);
      const rt::LcpResult<double> ra = rt::solve_lcp<double>(A, qa);
      check_complementarity<double>(A, qa, ra, spd_condition<double>(A));
      pivots[0] = std::max(pivots[0], ra.pivots);

      Mat<double> P = random_matrix<double>(rng, n, n);
      for (Eigen::Index i = 0; i < n; ++i) P(i, i) = P.row(i).cwiseAbs().sum() + 0.1;
      const Vec<double> qp = random_vector<double>(rng, n);
      const rt::LcpResult<double> rp = rt::solve_lcp<double>(P, qp);
      // Diagonally dominant: κ of any principal submatrix ≤ (2 max row sum) / 0.1-margin; bound by
      // the full matrix's 1-norm estimate times n.
      check_complementarity<double>(P, qp, rp, double(n) / P.partialPivLu().rcond());
      pivots[1] = std::max(pivots[1], rp.pivots);

      const Mat<double> B = random_matrix<double>(rng, n, n / 3);
      const Mat<double> S = B * B.transpose();
      Vec<double> zs = Vec<double>::Zero(n), ws = Vec<double>::Zero(n);
      for (Eigen::Index i = 0; i < n; ++i) (coin(rng) ? zs[i] : ws[i]) = 0.5 + 0.5 * random_vector<double>(rng, 1)[0];
      const Vec<double> qs = ws - S * zs;
      const rt::LcpResult<double> rs = rt::solve_lcp<double>(S, qs);
      check_complementarity<double>(S, qs, rs, 1e6);
      BOOST_TEST((rs.w - ws).cwiseAbs().maxCoeff() <= 1e-10);  // w common to all solutions
      pivots[2] = std::max(pivots[2], rs.pivots);
    }
    BOOST_TEST_MESSAGE("n = " << n << ": max pivots SPD " << pivots[0] << ", P " << pivots[1] << ", PSD "
                              << pivots[2]);
  }
}
