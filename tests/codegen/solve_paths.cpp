// Every path of the solve of M u̇ = f (codegen/solve_plan.hpp) in emitted kernels: the banner
// names the path, only the Eigen path includes Eigen, and at random states the velocity block of
// rhs agrees with Eigen's LDLT solve of the kernel's own mass_matrix and forcing.
//
//   identity        leo_j2 (Cowell, M = I)
//   diagonal        damped_particle (M = m I, constant), free_disk_tube_ball (M(q))
//   block-diagonal  static_imbalance_gyroscope (Euler angles: blocks {φ, ψ} and {θ})
//   unrolled LDLᵀ   relative_masses (numbers only: factored at generation time),
//                   relative_masses_parametric (parameters only), n-link pendulums n = 3, 4, 8, 16
//   Eigen LLT       pendulum_17 (fixed sizes), chain46 (dynamic sizes)
//
// Bound. Both sides run in float128 (unit round-off u = 2⁻¹¹³). Each solve is backward stable:
// the computed x̂ solves (M + ΔM) x̂ = f with ‖ΔM‖₂ ≤ n γ_{3n+1} ‖M‖₂, γ_k = k u/(1 − k u) (Higham,
// Accuracy and Stability of Numerical Algorithms, 2nd ed., Thm. 10.4; LDLᵀ is Cholesky's
// arithmetic with the square roots moved into D), so each is within 2 κ₂(M) n γ_{3n+1} of the exact
// solution and the two within 4 κ₂ n γ_{3n+1}. rhs evaluates M and f in its own order (CSE'd
// together) where mass_matrix and forcing evaluate them apart; for these smooth, uncancelled
// expressions that differs by a few u per entry, inside the n γ_{3n+1} ≥ 12 u of the bound. A
// wrong solve (a misplaced entry, a dropped term, the wrong block) is off by O(1), and one done in
// double by 10⁻¹⁶, both far outside. The double round-off of the straight-line solve is checked
// against Eigen's in solve_plan.cpp, where both sides see the same double M and f.
#define BOOST_TEST_MODULE codegen_solve_paths
#include <boost/mpl/list.hpp>
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include <eomc/runtime/float128.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "chain46.hpp"
#include "damped_particle.hpp"
#include "four_link_pendulum.hpp"
#include "free_disk_tube_ball.hpp"
#include "leo_j2.hpp"
#include "pendulum_16.hpp"
#include "pendulum_17.hpp"
#include "pendulum_8.hpp"
#include "relative_masses.hpp"
#include "relative_masses_parametric.hpp"
#include "static_imbalance_gyroscope.hpp"
#include "three_link_pendulum.hpp"

namespace models = eomc::models;
using Q = eomc::runtime::float128;

namespace {

// The header's banner comment as one line: the emitter wraps it at word boundaries.
std::string banner(const std::string& path) {
    std::ifstream in(path);
    BOOST_TEST_REQUIRE(in.good(), "cannot read " << path);
    std::string text, line;
    while (std::getline(in, line) && line.rfind("//", 0) == 0) text.append(" ").append(line, std::min<std::size_t>(3, line.size()));
    return text;
}

bool includes_eigen(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str().find("#include <Eigen/") != std::string::npos;
}

// γ_k of float128: u = 2⁻¹¹³.
double gamma(int k) {
    const double u = std::ldexp(1.0, -113);
    return k * u / (1 - k * u);
}

// At `samples` states x_i = x0_i (1 + u_i/5) + u_i/5 around the scene's initial state (u uniform in
// [−1, 1]): rhs's velocity block against Eigen's LDLT on mass_matrix and forcing, all in float128.
template <class K>
void check_rates(int samples) {
    constexpr int N = K::n_state, n = K::n_velocities;
    using Matrix = Eigen::Matrix<Q, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    using Vector = Eigen::Matrix<Q, Eigen::Dynamic, 1>;
    const typename K::Parameters p{};
    std::mt19937 gen(1126);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worst = 0;
    for (int s = 0; s < samples; ++s) {
        std::array<Q, N> x, dx;
        for (int i = 0; i < N; ++i) {
            const double v = u(gen);
            x[std::size_t(i)] = Q(K::initial_state[std::size_t(i)] * (1 + v / 5) + v / 5);
        }
        const Q t = Q(0.3 * s);
        Matrix M(n, n);
        Vector f(n);
        K::mass_matrix(t, x.data(), M.data(), p);
        K::forcing(t, x.data(), f.data(), p);
        K::rhs(t, x.data(), dx.data(), p);
        const Vector reference = M.ldlt().solve(f);

        Eigen::MatrixXd Md(n, n);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) Md(i, j) = double(M(i, j));
        const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Md).eigenvalues();
        BOOST_TEST_REQUIRE(lambda.minCoeff() > 0, K::scene_name << ": M is not positive definite at sample " << s);
        const double bound = 4 * lambda.maxCoeff() / lambda.minCoeff() * n * gamma(3 * n + 1);
        double diff = 0, norm = 0;
        for (int i = 0; i < n; ++i) {
            const double d = double(dx[std::size_t(K::velocity_offset + i)] - reference(i));
            diff += d * d;
            norm += double(reference(i)) * double(reference(i));
        }
        const double relative = std::sqrt(diff) / std::max(std::sqrt(norm), std::numeric_limits<double>::min());
        BOOST_TEST(relative <= bound, K::scene_name << " sample " << s << ": |u̇ − u̇_Eigen|/|u̇_Eigen| = " << relative
                                                    << " > " << bound);
        worst = std::max(worst, relative / bound);
    }
    BOOST_TEST_MESSAGE(K::scene_name << ": largest difference / bound " << worst);
}

const std::string checked_in = EOMC_SOURCE_DIR "/generated/";
const std::string built = EOMC_MODELS_DIR "/";

}  // namespace

BOOST_AUTO_TEST_CASE(the_banner_names_the_path_and_only_the_eigen_path_includes_eigen) {
    const auto expect = [](const std::string& path, const std::string& words, bool eigen) {
        const std::string text = banner(path);
        BOOST_TEST(text.find(words) != std::string::npos, path << ": the banner lacks \"" << words << "\":" << text);
        BOOST_TEST(includes_eigen(path) == eigen, path);
    };
    expect(checked_in + "leo_j2.hpp", "Solve of M u̇ = f: identity (M = I, u̇ = f; no solve at run time).", false);
    expect(checked_in + "damped_particle.hpp", "Solve of M u̇ = f: diagonal (u̇_k = f_k / M_kk). M is constant (parameters only).",
           false);
    expect(checked_in + "free_disk_tube_ball.hpp", "Solve of M u̇ = f: diagonal (u̇_k = f_k / M_kk).", false);
    BOOST_TEST(banner(checked_in + "free_disk_tube_ball.hpp").find("constant") == std::string::npos);
    expect(checked_in + "static_imbalance_gyroscope.hpp",
           "Solve of M u̇ = f: block-diagonal (blocks {0, 2} by unrolled LDLᵀ in straight-line code, the other velocities "
           "by division).",
           false);
    expect(built + "relative_masses.hpp",
           "Solve of M u̇ = f: unrolled LDLᵀ in straight-line code (n_velocities = 3 ≤ 16). M is constant (numbers only): its "
           "factors were computed at generation time.",
           false);
    expect(built + "relative_masses_parametric.hpp",
           "Solve of M u̇ = f: unrolled LDLᵀ in straight-line code (n_velocities = 3 ≤ 16). M is constant (parameters only).",
           false);
    expect(built + "three_link_pendulum.hpp", "Solve of M u̇ = f: unrolled LDLᵀ in straight-line code (n_velocities = 3 ≤ 16).",
           false);
    expect(built + "pendulum_16.hpp", "Solve of M u̇ = f: unrolled LDLᵀ in straight-line code (n_velocities = 16 ≤ 16).",
           false);
    expect(built + "pendulum_17.hpp", "Solve of M u̇ = f: Eigen LLT at run time (a block of 17 velocities > 16).", true);
    expect(built + "chain46.hpp",
           "Solve of M u̇ = f: Eigen LLT at run time (a block of 46 velocities > 16). M is constant, factored at run time all "
           "the same.",
           true);
}

using Kernels = boost::mpl::list<models::LeoJ2, models::DampedParticle, models::FreeDiskTubeBall,
                                 models::StaticImbalanceGyroscope, models::RelativeMasses, models::RelativeMassesParametric,
                                 models::ThreeLinkPendulum, models::FourLinkPendulum, models::Pendulum8, models::Pendulum16,
                                 models::Pendulum17, models::Chain46>;

BOOST_AUTO_TEST_CASE_TEMPLATE(rhs_agrees_with_eigens_solve_of_mass_matrix_and_forcing, K, Kernels) {
    check_rates<K>(40);
}
