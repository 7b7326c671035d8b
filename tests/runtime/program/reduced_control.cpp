// runtime/program/reduced_control.hpp: LU with partial pivoting of the programs' G λ = h, and the
// u̇, λ, Q_c it gives.
//
// Bounds (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed.): the computed factors
// satisfy L̂Û = PG + ΔG and the computed x̂ solves (PG + ΔG') x̂ = P h with |ΔG|, |ΔG'| ≤ γ_{3m} |L̂||Û|
// (Thm. 9.3 and 9.4), γ_k = k u/(1 − k u). So the residual P(h − G x̂), evaluated in long double, is
// within γ_{3m} (|L̂||Û||x̂|)_i row by row; and det Ĝ = ±Π Û_jj rounded m − 1 times is det(PG + ΔG)
// up to γ_m, which differs from det(PG) by at most |tr((PG)⁻¹ΔG)| ≤ Σ_ij |(PG)⁻¹|_ji |ΔG|_ij to first
// order (Jacobi's formula); twice that bounds it while the sum stays below 0.1.
#define BOOST_TEST_MODULE runtime_reduced_control
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Dense>

#include "eomc/runtime/program/reduced_control.hpp"

namespace {

namespace program = eomc::runtime::program;

template <class S>
S gamma(int k) {
    const S u = std::numeric_limits<S>::epsilon() / 2;
    return k * u / (1 - k * u);
}

// One random G (uniform entries in [−1, 1], so that partial pivoting has rows to exchange) and h,
// solved and checked against the bounds above. Returns whether a row was exchanged.
template <class S, int m>
bool check_random_system(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::array<S, std::size_t(m * m)> G, factors;
    std::array<S, std::size_t(m)> h, x;
    for (auto& g : G) g = S(u(rng));
    for (auto& v : h) v = S(u(rng));
    factors = G;
    x = h;
    const S det = program::lu_solve_in_place<m>(factors, x);
    std::array<int, std::size_t(m)> swaps{};
    std::array<S, std::size_t(m * m)> lu = G;
    BOOST_TEST(program::lu_factor<m>(lu, swaps) == det);

    // P as the row order the exchanges leave.
    std::array<int, std::size_t(m)> order;
    for (int i = 0; i < m; ++i) order[std::size_t(i)] = i;
    bool exchanged = false;
    for (int j = 0; j < m; ++j) {
        exchanged = exchanged || swaps[std::size_t(j)] != j;
        std::swap(order[std::size_t(j)], order[std::size_t(swaps[std::size_t(j)])]);
    }
    using Wide = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    Wide PG(m, m), absL = Wide::Identity(m, m), absU = Wide::Zero(m, m);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            PG(i, j) = G[std::size_t(order[std::size_t(i)] * m + j)];
            const long double v = std::abs(static_cast<long double>(lu[std::size_t(i * m + j)]));
            if (j < i) absL(i, j) = v;
            else absU(i, j) = v;
        }
    const Wide LU = absL * absU;  // |L̂||Û|
    const S g3m = gamma<S>(3 * m);
    for (int i = 0; i < m; ++i) {
        long double residual = h[std::size_t(order[std::size_t(i)])], bound = 0;
        for (int j = 0; j < m; ++j) {
            residual -= PG(i, j) * static_cast<long double>(x[std::size_t(j)]);
            bound += LU(i, j) * std::abs(static_cast<long double>(x[std::size_t(j)]));
        }
        // The long double evaluation's own rounding, m + 1 operations on terms of that size.
        bound = static_cast<long double>(g3m) * bound + gamma<long double>(m + 1) * bound;
        BOOST_TEST(std::abs(residual) <= bound, "row " << i << ": residual " << double(residual) << " > " << double(bound));
    }

    const Wide inverse = PG.inverse();
    long double first_order = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) first_order += std::abs(inverse(j, i)) * static_cast<long double>(g3m) * LU(i, j);
    BOOST_TEST_REQUIRE(first_order < 0.1L, "G is too ill-conditioned for the first-order bound");
    Wide G_wide(m, m);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) G_wide(i, j) = G[std::size_t(i * m + j)];
    const long double exact = G_wide.fullPivLu().determinant();
    const long double error = std::abs(static_cast<long double>(det) - exact), bound = std::abs(exact) * (2 * first_order + gamma<S>(m));
    BOOST_TEST(error <= bound, "det " << double(det) << " against " << double(exact));
    return exchanged;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_zero_leading_entry_is_pivoted_past_and_small_integer_systems_solve_exactly) {
    // [[0, 2], [3, 0]] λ = (4, 9): λ = (3, 2), det = −6; no step rounds.
    std::array<double, 4> G{0, 2, 3, 0};
    std::array<double, 2> h{4, 9};
    BOOST_TEST(program::lu_solve_in_place<2>(G, h) == -6.0);
    BOOST_TEST(h[0] == 3.0);
    BOOST_TEST(h[1] == 2.0);
    // A cyclic permutation scaled: [[0, 0, 4], [2, 0, 0], [0, 8, 0]], det = +64 (an even permutation).
    std::array<double, 9> P{0, 0, 4, 2, 0, 0, 0, 8, 0};
    std::array<double, 3> b{12, 2, 16};
    BOOST_TEST(program::lu_solve_in_place<3>(P, b) == 64.0);
    BOOST_TEST(b[0] == 1.0);
    BOOST_TEST(b[1] == 2.0);
    BOOST_TEST(b[2] == 3.0);
}

BOOST_AUTO_TEST_CASE(random_systems_meet_the_backward_error_and_determinant_bounds) {
    std::mt19937 rng(20261127);
    int exchanged = 0, total = 0;
    for (int trial = 0; trial < 40; ++trial) {
        exchanged += check_random_system<double, 1>(rng);
        exchanged += check_random_system<double, 2>(rng);
        exchanged += check_random_system<double, 3>(rng);
        exchanged += check_random_system<double, 4>(rng);
        exchanged += check_random_system<double, 6>(rng);
        exchanged += check_random_system<long double, 3>(rng);
        total += 6;
    }
    // The pivoting was exercised (m = 1 never exchanges; most of the others do).
    BOOST_TEST(exchanged > total / 2);
}

BOOST_AUTO_TEST_CASE(a_singular_g_has_determinant_zero_and_non_finite_multipliers_a_tiny_one_does_not) {
    // Rows (1, 2) and (2, 4): after one exchange the second pivot is 2 − ½·4 = 0 exactly.
    std::array<double, 4> G{1, 2, 2, 4};
    std::array<double, 2> h{1, 1};
    BOOST_TEST(program::lu_solve_in_place<2>(G, h) == 0.0);
    BOOST_TEST(!std::isfinite(h[0]));
    BOOST_TEST(!std::isfinite(h[1]));
    // Regular but tiny: det underflows to 0, the solve does not.
    std::array<double, 4> T{1e-200, 0, 0, 1e-200};
    std::array<double, 2> t{1e-200, 2e-200};
    BOOST_TEST(program::lu_solve_in_place<2>(T, t) == 0.0);
    BOOST_TEST(t[0] == 1.0);
    BOOST_TEST(t[1] == 2.0);
    // A zero column: no pivot at the first step.
    std::array<double, 4> Z{0, 1, 0, 1};
    std::array<int, 2> swaps{};
    BOOST_TEST(program::lu_factor<2>(Z, swaps) == 0.0);
}

BOOST_AUTO_TEST_CASE(the_reduced_system_gives_the_programmed_acceleration) {
    // M = diag(2, 1), f = (2, 0), one ideal program Ā = (1, 1), c = 3, D = Āᵀ:
    // z = (1, 0), Y = (½, 1), G = 3/2, h = 2, so λ = 4/3, u̇ = (5/3, 4/3) and Q_c = (4/3, 4/3):
    // Ā u̇ = 3 and M u̇ = f + D λ.
    using L = program::ReducedLayout<2, 1>;
    std::array<double, L::size> reduced{};
    reduced[L::z + 0] = 1.0;
    reduced[L::z + 1] = 0.0;
    reduced[L::Y + 0] = 0.5;
    reduced[L::Y + 1] = 1.0;
    reduced[L::G] = 1.5;
    reduced[L::h] = 2.0;
    reduced[L::D + 0] = 1.0;
    reduced[L::D + 1] = 1.0;
    std::array<double, 2> udot, Qc;
    std::array<double, 1> lambda;
    const double det = program::reduced_control_solve<2, 1>(reduced.data(), udot.data(), lambda.data(), Qc.data());
    BOOST_TEST(det == 1.5);
    // Each value is at most three roundings from its exact fraction.
    const double tol = 3 * std::numeric_limits<double>::epsilon();
    BOOST_TEST(std::abs(lambda[0] - 4.0 / 3.0) <= tol * 4.0 / 3.0);
    BOOST_TEST(std::abs(udot[0] - 5.0 / 3.0) <= tol * 5.0 / 3.0);
    BOOST_TEST(std::abs(udot[1] - 4.0 / 3.0) <= tol * 4.0 / 3.0);
    BOOST_TEST(std::abs(Qc[0] - 4.0 / 3.0) <= tol * 4.0 / 3.0);
    BOOST_TEST(std::abs(Qc[1] - 4.0 / 3.0) <= tol * 4.0 / 3.0);
    const double alone = program::reduced_control_determinant<2, 1>(reduced.data());
    BOOST_TEST(alone == 1.5);
}
