// runtime/constraints.hpp: the Schur-complement solve of M u̇ − Wᵀλ = f, W u̇ = r against a
// direct solve of the bordered system, and the M-metric projection (Hairer, Lubich, Wanner,
// Geometric Numerical Integration, 2nd ed., IV.4) onto a circle against its closed form.
#define BOOST_TEST_MODULE runtime_constraints
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Dense>

#include "eomc/runtime/constraints.hpp"

namespace {

namespace rt = eomc::runtime;
using Matrix = rt::ConstraintMatrix<double>;
using Vector = rt::ConstraintVector<double>;
const double eps = std::numeric_limits<double>::epsilon();

}  // namespace

BOOST_AUTO_TEST_CASE(schur_solve_agrees_with_the_bordered_system) {
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
        const int n = 2 + trial % 7, m = 1 + trial % n;
        Matrix A(n, n), W(m, n);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) A(i, j) = u(rng);
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < n; ++j) W(i, j) = u(rng);
        const Matrix M = A * A.transpose() + Matrix::Identity(n, n);  // SPD
        Vector f(n), r(m);
        for (int i = 0; i < n; ++i) f[i] = u(rng);
        for (int i = 0; i < m; ++i) r[i] = u(rng);

        Vector udot, lambda;
        rt::schur_solve(M, f, W, r, udot, lambda);

        // [[M, −Wᵀ], [W, 0]] [u̇; λ] = [f; r], by Householder QR with column pivoting.
        Matrix K = Matrix::Zero(n + m, n + m);
        K.topLeftCorner(n, n) = M;
        K.topRightCorner(n, m) = -W.transpose();
        K.bottomLeftCorner(m, n) = W;
        Vector rhs(n + m);
        rhs << f, r;
        const Vector direct = K.colPivHouseholderQr().solve(rhs);
        const Eigen::JacobiSVD<Matrix> svd(K);
        const double cond = svd.singularValues()(0) / svd.singularValues()(n + m - 1);
        const double scale = direct.cwiseAbs().maxCoeff() + 1.0;
        const double bound = 1e3 * eps * cond * scale;
        BOOST_TEST((udot - direct.head(n)).cwiseAbs().maxCoeff() <= bound, "trial " << trial);
        BOOST_TEST((lambda - direct.tail(m)).cwiseAbs().maxCoeff() <= bound, "trial " << trial);
        // And the constraint holds: W u̇ = r.
        BOOST_TEST((W * udot - r).cwiseAbs().maxCoeff() <= bound);
    }
}

namespace {

// A particle in the plane on the circle x² + y² = l², M = diag(m, m); state (x, y, ẋ, ẏ).
constexpr double mass = 2.5, l = 1.3;
const rt::ConstraintLayout layout{2, 2, 2, 1};
const std::array<bool, 1> projected{true}, holonomic{true};

void residuals(double, const double* x, double* f, double* phi) {
    f[0] = x[0] * x[0] + x[1] * x[1] - l * l;
    phi[0] = 2 * x[0] * x[2] + 2 * x[1] * x[3];
}
void jacobian(double, const double* x, double* W) {
    W[0] = 2 * x[0];
    W[1] = 2 * x[1];
}
void mass_matrix(double, const double*, double* M) {
    M[0] = mass, M[1] = 0, M[2] = 0, M[3] = mass;
}

}  // namespace

BOOST_AUTO_TEST_CASE(projection_lands_on_the_circle_along_the_m_normal) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> angle(-3.14, 3.14), off(-1e-6, 1e-6), speed(-2.0, 2.0);
    for (int trial = 0; trial < 100; ++trial) {
        const double a = angle(rng), rho = l * (1 + off(rng));
        std::array<double, 4> x{rho * std::sin(a), -rho * std::cos(a), speed(rng), speed(rng)};
        const std::array<double, 4> before = x;
        const int iterations = rt::project_onto_constraints(0.0, x.data(), layout, projected.data(), holonomic.data(),
                                                            residuals, jacobian, mass_matrix);
        BOOST_TEST(iterations >= 1);
        BOOST_TEST(iterations <= 4);
        // On the circle to round-off …
        BOOST_TEST(std::abs(x[0] * x[0] + x[1] * x[1] - l * l) <= 8 * eps * l * l);
        // … at the M-orthogonal (here Euclidean: M = m I) projection l (x, y)/|(x, y)|.
        const double norm = std::hypot(before[0], before[1]);
        BOOST_TEST(std::abs(x[0] - l * before[0] / norm) <= 4 * eps * l);
        BOOST_TEST(std::abs(x[1] - l * before[1] / norm) <= 4 * eps * l);
        // The velocity loses exactly its normal component: v − (v·n) n with n = (x, y)/l.
        const double nx = x[0] / l, ny = x[1] / l, vn = before[2] * nx + before[3] * ny;
        BOOST_TEST(std::abs(x[2] - (before[2] - vn * nx)) <= 8 * eps * 2.0);
        BOOST_TEST(std::abs(x[3] - (before[3] - vn * ny)) <= 8 * eps * 2.0);
        BOOST_TEST(std::abs(x[0] * x[2] + x[1] * x[3]) <= 8 * eps * l * 2.0);
    }
}

BOOST_AUTO_TEST_CASE(rows_not_projected_are_left_alone) {
    std::array<double, 4> x{1.0, 0.5, 0.3, -0.2};
    const std::array<double, 4> before = x;
    const std::array<bool, 1> none{false};
    BOOST_TEST(rt::project_onto_constraints(0.0, x.data(), layout, none.data(), holonomic.data(), residuals, jacobian,
                                            mass_matrix) == 0);
    BOOST_TEST(x == before);
}

BOOST_AUTO_TEST_CASE(central_differences_recover_a_jacobian) {
    // ẋ = (y², sin x): ∂ẋ/∂x = [[0, 2y], [cos x, 0]].
    const auto rhs = [](double, const double* x, double* d) {
        d[0] = x[1] * x[1];
        d[1] = std::sin(x[0]);
    };
    const std::array<double, 2> x{0.7, -1.1};
    std::array<double, 4> J{};
    rt::central_difference_jacobian(0.0, x.data(), J.data(), 2, rhs);
    const double tol = 1e-9;
    BOOST_TEST(std::abs(J[0]) <= tol);
    BOOST_TEST(std::abs(J[1] - 2 * x[1]) <= tol);
    BOOST_TEST(std::abs(J[2] - std::cos(x[0])) <= tol);
    BOOST_TEST(std::abs(J[3]) <= tol);
}
