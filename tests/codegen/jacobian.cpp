// The generated `jacobian` of every bundled kernel (n ≤ 2: q̈ solved in closed form) and of
// pendulums generated at build time (n > 2: M q̈ = f solved by the unrolled LDLᵀ of
// codegen/solve_plan.hpp up to 16 links, by Eigen's LLT past them, J from G = ∂f/∂x − (∂M/∂x)·q̈)
// against central finite differences of the generated `rhs`, at random states.
//
// Bound. Everything is evaluated in long double (the kernels are templated on the scalar), so
// round-off is ~1e-19 relative and the truncation error of the central difference dominates:
//   D(h) = J + c h² + O(h⁴),  hence  J − D(h/2) = −(D(h) − D(h/2))/3 + O(h⁴).
// The Richardson difference |D(h) − D(h/2)|/3 is therefore a measured estimate of the error of
// D(h/2); it is allowed twice that (the O(h⁴) remainder is h² smaller), plus the round-off of a
// difference quotient, 2 · 64 ε_ld · max|f| / h (64 ulps per rhs evaluation: a few dozen
// operations, each adding half an ulp relative to the largest intermediate, which is bounded
// here by max|f| times the condition number of the closed-form solve, O(10) for these states).
// A wrong Jacobian entry is off by O(1) times the entry, orders above this bound.
#define BOOST_TEST_MODULE mechanics_jacobian
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

#include "bead_on_hoop.hpp"
#include "disk_tube_ball.hpp"
#include "double_pendulum.hpp"
#include "foucault_pendulum.hpp"
#include "four_link_pendulum.hpp"  // generated at build time (eomc_add_model), as the next two
#include "seventeen_link_pendulum.hpp"
#include "ten_link_pendulum.hpp"
#include "kepler_orbit.hpp"

namespace models = eomc::models;
using LD = long double;

namespace {

template <class Model>
std::array<LD, Model::n_state> random_state(std::mt19937& gen) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::array<LD, Model::n_state> x{};
    for (auto& v : x) v = u(gen);
    return x;
}

// Keeps each state inside the domain of its kernel (Foucault: x² + y² < L²; Kepler: r > 0).
template <class Model>
void adjust(std::array<LD, Model::n_state>&) {}
template <>
void adjust<models::KeplerOrbit>(std::array<LD, 4>& x) { x[0] = 0.5L + std::abs(x[0]); }
template <>
void adjust<models::FoucaultPendulum>(std::array<LD, 4>& x) {
    x[0] *= 3;  // |x|, |y| ≤ 3 < L/√2 with L = 10: the bob well below the suspension point
    x[1] *= 3;
}

template <class Model>
void check_model(int samples) {
    constexpr int n = Model::n_state;
    const typename Model::Parameters p{};
    std::mt19937 gen(20240611);
    const LD eps = std::numeric_limits<LD>::epsilon();
    double worst_ratio = 0.0;  // max |J − D| / bound, reported
    for (int k = 0; k < samples; ++k) {
        auto x = random_state<Model>(gen);
        adjust<Model>(x);
        const LD t = LD(0.37) * k;
        std::array<LD, n * n> J{};
        Model::jacobian(t, x.data(), J.data(), p);
        for (int j = 0; j < n; ++j) {
            const LD h = LD(1e-3) * (1 + std::abs(x[j]));
            auto diff_quotient = [&](LD step, std::array<LD, n>& d, LD& fmax) {
                auto xp = x, xm = x;
                xp[j] += step;
                xm[j] -= step;
                std::array<LD, n> fp{}, fm{};
                Model::rhs(t, xp.data(), fp.data(), p);
                Model::rhs(t, xm.data(), fm.data(), p);
                for (int i = 0; i < n; ++i) {
                    d[i] = (fp[i] - fm[i]) / ((xp[j] - xm[j]));
                    fmax = std::max({fmax, std::abs(fp[i]), std::abs(fm[i])});
                }
            };
            std::array<LD, n> d1{}, d2{};
            LD fmax = 0;
            diff_quotient(h, d1, fmax);
            diff_quotient(h / 2, d2, fmax);
            for (int i = 0; i < n; ++i) {
                const LD truncation = std::abs(d1[i] - d2[i]) / 3;
                const LD roundoff = 2 * 64 * eps * (fmax + 1) / (h / 2);
                const LD bound = 2 * truncation + roundoff;
                const LD error = std::abs(J[i * n + j] - d2[i]);
                worst_ratio = std::max(worst_ratio, double(error / bound));
                BOOST_TEST_INFO(Model::scene_name << ": dxdt[" << i << "]/dx[" << j << "] at sample " << k
                                                  << ": jacobian " << double(J[i * n + j]) << ", FD "
                                                  << double(d2[i]) << ", bound " << double(bound));
                BOOST_TEST(error <= bound);
            }
        }
    }
    BOOST_TEST_MESSAGE(Model::scene_name << ": max |J - FD| / bound = " << worst_ratio);
}

}  // namespace

BOOST_AUTO_TEST_CASE(disk_tube_ball) { check_model<models::DiskTubeBall>(10); }
BOOST_AUTO_TEST_CASE(bead_on_hoop) { check_model<models::BeadOnHoop>(20); }
BOOST_AUTO_TEST_CASE(double_pendulum) { check_model<models::DoublePendulum>(50); }
BOOST_AUTO_TEST_CASE(foucault_pendulum) { check_model<models::FoucaultPendulum>(50); }
BOOST_AUTO_TEST_CASE(kepler_orbit) { check_model<models::KeplerOrbit>(50); }
BOOST_AUTO_TEST_CASE(four_link_pendulum) { check_model<models::FourLinkPendulum>(50); }

// Jacobians past operations_per_part (codegen/cpp_emitter.cpp) come in parts, each with the
// temporaries its outputs need: the unrolled LDLᵀ path (10 links) and Eigen's LLT path (17).
std::string generated_header(const std::string& scene) {
    std::ifstream in(std::string(EOMC_MODELS_DIR) + "/" + scene + ".hpp");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

BOOST_AUTO_TEST_CASE(ten_link_pendulum_in_parts) {
    BOOST_TEST(generated_header("ten_link_pendulum").find("static void velocity_jacobian_part1_(") != std::string::npos);
    check_model<models::TenLinkPendulum>(5);
}

BOOST_AUTO_TEST_CASE(seventeen_link_pendulum_in_parts) {
    BOOST_TEST(generated_header("seventeen_link_pendulum").find("static void mass_matrix_and_jacobian_terms_part2_(") !=
               std::string::npos);
    check_model<models::SeventeenLinkPendulum>(3);
}
