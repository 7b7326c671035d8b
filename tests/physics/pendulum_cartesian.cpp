// The pendulum in Cartesian coordinates with the rod as a holonomic constraint
// (scenes/pendulum_cartesian.toml): Lagrange's equations of the first kind, m ẍ = 2xλ,
// m ÿ = −mg + 2yλ, x² + y² = l². Known answers: the period of a swing of amplitude θ0,
// T = 4 √(l/g) K(sin(θ0/2)) (the complete elliptic integral of the first kind), and the
// multiplier λ = −N/(2l) with N = m(l θ̇² + g cos θ) the tension of the rod.
#define BOOST_TEST_MODULE physics_pendulum_cartesian
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "pendulum_cartesian.hpp"
#include "physics_support.hpp"

using Model = eomc::models::PendulumCartesian;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
enum { x, y, x_dot, y_dot };
constexpr S eps = std::numeric_limits<S>::epsilon();

struct ProjectedPendulum {
    void operator()(S t, const rt::State<S>& s, rt::State<S>& ds) const { Model::rhs(t, s.data(), ds.data(), P); }
    void project(S t, rt::State<S>& s) const { Model::project(t, s.data(), P); }
};

S energy(const std::vector<S>& s) { return Model::energy(S(0), s.data(), P); }

}  // namespace

BOOST_AUTO_TEST_CASE(period_tension_energy_and_rod) {
    static_assert(Model::n_constraints == 1 && Model::n_outputs == 3);
    const S theta0 = std::atan2(Model::initial_state[x], -Model::initial_state[y]);
    const S T_exact = 4 * std::sqrt(P.l / P.g) * std::comp_ellint_1(std::sin(theta0 / 2));

    ProjectedPendulum sys;
    rt::State<S> s(Model::initial_state.begin(), Model::initial_state.end());
    const std::vector<S> s0(s.begin(), s.end());
    const rt::Tolerances tol{1e-12, 1e-14};
    rt::Dopri5<S> stepper;
    // Turning points of θ: l² θ̇ = x ẏ − y ẋ crosses zero downwards (at θ = θ0; t = 0 is one).
    auto turning = phys::down_crossings<S>([](const std::vector<S>& q) { return q[x] * q[y_dot] - q[y] * q[x_dot]; });
    S worst_tension = 0;
    const int periods = 10;
    const auto steps = phys::run(stepper, sys, s, S(0), S((periods + 0.5) * T_exact), tol,
                                 [&](const phys::Step<S>& st, const rt::Dopri5<S>& stepper_now) {
                                     turning(st, stepper_now);
                                     // λ against the tension at the state the integration goes on from.
                                     std::vector<S> q = st.x_new, out(Model::n_outputs);
                                     Model::project(st.t_new, q.data(), P);
                                     Model::outputs(st.t_new, q.data(), out.data(), P);
                                     const S theta_dot = (q[x] * q[y_dot] - q[y] * q[x_dot]) / (P.l * P.l);
                                     const S cos_theta = -q[y] / P.l;
                                     const S tension = P.m * (P.l * theta_dot * theta_dot + P.g * cos_theta);
                                     const S scale = P.m * (P.l * theta_dot * theta_dot + P.g) / (2 * P.l);
                                     worst_tension = std::max(worst_tension, std::abs(out[0] + tension / (2 * P.l)) / scale);
                                 });
    // Two evaluations of the same quantity on the rod: round-off of a dozen operations.
    BOOST_TEST(worst_tension <= 64 * eps);

    // The period. A state error δ displaces a turning point in time by δ/(l |θ̈|), |θ̈| = (g/l) sin θ0
    // there; the error grows at most linearly in time for this conservative oscillation (phase
    // drift), so δ ≤ (Σ local bounds)(1 + 2π·periods).
    BOOST_REQUIRE_EQUAL(turning.times.size(), std::size_t(periods));
    S local = 0;
    for (const auto& st : steps) local += *std::max_element(st.local_bound.begin(), st.local_bound.end());
    const S delta = local * (1 + 2 * std::numbers::pi * periods);
    const S timing = delta / (P.l * P.g / P.l * std::sin(theta0));
    const S T_measured = turning.times.back() / periods;
    BOOST_TEST_MESSAGE("period " << T_measured << " vs " << T_exact << " (|Δ| " << std::abs(T_measured - T_exact)
                                 << ", bound " << timing / periods << ")");
    BOOST_TEST(std::abs(T_measured - T_exact) <= timing / periods);

    // The rod after the last projection, and the energy (twice the propagated local bound: the
    // projection moves the state by no more than the local error it removes).
    BOOST_TEST(std::abs(s[x] * s[x] + s[y] * s[y] - P.l * P.l) <= 8 * eps * P.l * P.l);
    BOOST_TEST(std::abs(s[x] * s[x_dot] + s[y] * s[y_dot]) <= 8 * eps * P.l * (std::abs(s[x_dot]) + std::abs(s[y_dot])));
    const S E0 = energy(s0), E1 = energy(std::vector<S>(s.begin(), s.end()));
    const S E_bound = 2 * phys::invariant_drift_bound<S>(steps, energy, std::abs(E0));
    BOOST_TEST_MESSAGE("energy drift " << std::abs(E1 - E0) << " (bound " << E_bound << ")");
    BOOST_TEST(std::abs(E1 - E0) <= E_bound);
}
