// The Pleiades of the bundled scene (seven stars in a plane, m_i = i, G = 1; Hairer, Nørsett &
// Wanner, Solving Ordinary Differential Equations I, 2nd ed., 1993, §II.10), against
//   * Newton's law written out: ẍ_i = Σ_{j≠i} G m_j (r_j − r_i)/|r_j − r_i|³ at random states;
//   * the published reference state at t = 3 (problem PLEI of F. Mazzia and C. Magherini, Test
//     Set for IVP Solvers, release 2.4, University of Bari, 2008; 16 significant digits), within
//     the global-error bound propagated from every accepted step's tolerance through the
//     variational equation (physics_support.hpp) plus the reference's own rounding;
//   * the conserved energy, total momentum (zero here) and angular momentum, within the drift
//     bound of the same steps.
// The run passes several close encounters, which is what makes the problem a standard test of
// step-size control.
#define BOOST_TEST_MODULE physics_pleiades
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pleiades.hpp"
#include "physics_support.hpp"

using Model = eomc::models::Pleiades;
namespace rt = eomc::runtime;

namespace {

constexpr int stars = 7;
constexpr double eps = std::numeric_limits<double>::epsilon();

// PLEI's y(3): x_1..x_7, y_1..y_7, ẋ_1..ẋ_7, ẏ_1..ẏ_7 (the test set's order, which is the scene's).
constexpr std::array<double, 28> reference = {
    0.3706139143970502,  0.3237284092057233e1,  -0.3222559032418324e1, 0.6597091455775310,
    0.3425581707156584,  0.1562172101400631e1,  -0.7003092922212495,   -0.3943437585517392e1,
    -0.3271380973972550e1, 0.5225081843456543e1, -0.2590612434977470e1, 0.1198213693392275e1,
    -0.2429682344935824, 0.1091449240428980e1,  0.3417003806314313e1,  0.1354584501625501e1,
    -0.2590065597810775e1, 0.2025053734714242e1, -0.1155815100160448e1, -0.8072988170223021,
    0.5952396354208710,  -0.3741244961234010e1, 0.3773459685750630,    0.9386858869551073,
    0.3667922227200571,  -0.3474046353808490,   0.2344915448180937e1,  -0.1947020434263292e1};

double mass(int i) { return i + 1.0; }
double x_of(const std::vector<double>& s, int i) { return s[std::size_t(i)]; }
double y_of(const std::vector<double>& s, int i) { return s[std::size_t(stars + i)]; }
double vx_of(const std::vector<double>& s, int i) { return s[std::size_t(2 * stars + i)]; }
double vy_of(const std::vector<double>& s, int i) { return s[std::size_t(3 * stars + i)]; }

double momentum_x(const std::vector<double>& s) {
    double p = 0;
    for (int i = 0; i < stars; ++i) p += mass(i) * vx_of(s, i);
    return p;
}
double momentum_y(const std::vector<double>& s) {
    double p = 0;
    for (int i = 0; i < stars; ++i) p += mass(i) * vy_of(s, i);
    return p;
}
double angular_momentum(const std::vector<double>& s) {
    double l = 0;
    for (int i = 0; i < stars; ++i) l += mass(i) * (x_of(s, i) * vy_of(s, i) - y_of(s, i) * vx_of(s, i));
    return l;
}
// Σ of the magnitudes of each invariant's terms: the scale of its rounding.
double momentum_terms(const std::vector<double>& s) {
    double sum = 0;
    for (int i = 0; i < stars; ++i) sum += mass(i) * (std::abs(vx_of(s, i)) + std::abs(vy_of(s, i)));
    return sum;
}
double angular_momentum_terms(const std::vector<double>& s) {
    double sum = 0;
    for (int i = 0; i < stars; ++i)
        sum += mass(i) * (std::abs(x_of(s, i) * vy_of(s, i)) + std::abs(y_of(s, i) * vx_of(s, i)));
    return sum;
}
double energy_terms(const std::vector<double>& s) {
    double sum = 0;
    for (int i = 0; i < stars; ++i) {
        sum += mass(i) * (vx_of(s, i) * vx_of(s, i) + vy_of(s, i) * vy_of(s, i)) / 2;
        for (int j = i + 1; j < stars; ++j)
            sum += mass(i) * mass(j) / std::hypot(x_of(s, j) - x_of(s, i), y_of(s, j) - y_of(s, i));
    }
    return sum;
}
double energy(const std::vector<double>& s) {
    double e = 0;
    Model::invariants(0.0, s.data(), &e, Model::Parameters{});
    return e;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_scene_is_the_test_sets_problem) {
    const Model::Parameters p{};
    BOOST_TEST(p.G == 1.0);
    const std::array<double, stars> masses{p.m1, p.m2, p.m3, p.m4, p.m5, p.m6, p.m7};
    for (int i = 0; i < stars; ++i) BOOST_TEST(masses[std::size_t(i)] == mass(i));
    BOOST_TEST(std::string(Model::invariant_names[0]) == "energy");
    // y(0) of PLEI.
    const std::array<double, 28> initial = {3, 3, -1, -3, 2, -2, 2, 3, -3, 2, 0, 0, -4, 4,
                                            0, 0, 0, 0, 0, 1.75, -1.5, 0, 0, 0, -1.25, 1, 0, 0};
    for (int i = 0; i < Model::n_state; ++i) BOOST_TEST(Model::initial_state[std::size_t(i)] == initial[std::size_t(i)], i);
}

BOOST_AUTO_TEST_CASE(the_rates_are_newtons_law) {
    // Both sides form each pair's term with at most a dozen roundings and sum six of them, so
    // they differ by at most 2 (12 + 6) ε Σ_j |term_j| per component.
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> position(-5, 5), velocity(-2, 2);
    const Model::Parameters p{};
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<double> s(Model::n_state), rates(Model::n_state);
        for (int k = 0; k < 2 * stars; ++k) s[std::size_t(k)] = position(gen);
        for (int k = 2 * stars; k < 4 * stars; ++k) s[std::size_t(k)] = velocity(gen);
        Model::rhs(0.0, s.data(), rates.data(), p);
        for (int i = 0; i < stars; ++i) {
            double ax = 0, ay = 0, scale_x = 0, scale_y = 0;
            for (int j = 0; j < stars; ++j) {
                if (j == i) continue;
                const double dx = x_of(s, j) - x_of(s, i), dy = y_of(s, j) - y_of(s, i);
                const double r = std::sqrt(dx * dx + dy * dy);
                const double k = p.G * mass(j) / (r * r * r);
                ax += k * dx;
                ay += k * dy;
                scale_x += std::abs(k * dx);
                scale_y += std::abs(k * dy);
            }
            BOOST_TEST(rates[std::size_t(i)] == vx_of(s, i));
            BOOST_TEST(std::abs(rates[std::size_t(2 * stars + i)] - ax) <= 36 * eps * scale_x, "star " << i + 1);
            BOOST_TEST(std::abs(rates[std::size_t(3 * stars + i)] - ay) <= 36 * eps * scale_y, "star " << i + 1);
        }
    }
}

BOOST_AUTO_TEST_CASE(the_state_at_t3_is_the_published_reference) {
    phys::KernelSystem<Model, double> sys;
    const std::vector<double> x0(Model::initial_state.begin(), Model::initial_state.end());
    std::vector<double> x = x0;
    rt::Dopri5<double> stepper;
    const rt::Tolerances tol{1e-12, 1e-12};
    const auto steps = phys::run(stepper, sys, x, 0.0, 3.0, tol);
    const auto bound = phys::propagated_error_bound<Model, double>(steps, x0, 0.0, sys.p, tol);
    double worst = 0, worst_ratio = 0;
    for (int i = 0; i < Model::n_state; ++i) {
        // The reference is rounded to 16 significant digits: half a unit of the 16th.
        const double ref = reference[std::size_t(i)];
        const double rounding = 0.5e-15 * std::pow(10.0, std::floor(std::log10(std::abs(ref))) + 1);
        const double err = std::abs(x[std::size_t(i)] - ref);
        worst = std::max(worst, err);
        worst_ratio = std::max(worst_ratio, err / (bound[std::size_t(i)] + rounding));
        BOOST_TEST(err <= bound[std::size_t(i)] + rounding,
                   Model::state_names[i] << ": |x − reference| = " << err << ", bound " << bound[std::size_t(i)]);
    }
    BOOST_TEST_MESSAGE("t = 3: largest error " << worst << ", largest error / bound " << worst_ratio << " ("
                                                << steps.size() << " steps)");
    // The bound is loose (the close encounters amplify every step's local bound through Φ, and
    // the sum takes no cancellation), but not vacuous: one star's mass off by 1e-4 of itself
    // moves the state at t = 3 outside it.
    {
        phys::KernelSystem<Model, double> perturbed;
        perturbed.p.m7 *= 1 + 1e-4;
        std::vector<double> y = x0;
        rt::Dopri5<double> other;
        phys::run(other, perturbed, y, 0.0, 3.0, tol);
        bool outside = false;
        for (int i = 0; i < Model::n_state; ++i)
            outside = outside || std::abs(y[std::size_t(i)] - reference[std::size_t(i)]) > bound[std::size_t(i)];
        BOOST_TEST(outside, "m7 (1 + 1e-4) stays within the bound: the check could not see a wrong mass");
    }

    // Conserved along the run: energy, momentum (zero at the start) and angular momentum.
    const auto check = [&](const char* name, auto&& invariant, auto&& terms) {
        const double drift = std::abs(invariant(x) - invariant(x0));
        const double allowed = phys::invariant_drift_bound(steps, invariant, std::max(terms(x0), terms(x)));
        BOOST_TEST(drift <= allowed, name << ": drift " << drift << ", bound " << allowed);
    };
    check("energy", energy, energy_terms);
    check("momentum x", momentum_x, momentum_terms);
    check("momentum y", momentum_y, momentum_terms);
    check("angular momentum", angular_momentum, angular_momentum_terms);
    BOOST_TEST(std::abs(momentum_x(x0)) == 0.0);
    BOOST_TEST(std::abs(momentum_y(x0)) == 0.0);
}
