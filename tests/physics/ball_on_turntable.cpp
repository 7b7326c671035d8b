// A ball rolling on a turntable (scenes/ball_on_turntable.toml): two kinematic rows on a
// carrier spinning at Ω. Known answer: the centre's velocity seen from the ground turns at the
// constant rate Ω·I/(I + m r²) = 2Ω/7 with constant magnitude (Ehrlich and Tuszynski, Am. J.
// Phys. 63 (1995) 351), V(t) = R(2Ωt/7) V(0), where V = R(Ωt)(ẋ − Ω y, ẏ + Ω x) from the
// table's coordinates.
#define BOOST_TEST_MODULE physics_ball_on_turntable
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "ball_on_turntable.hpp"
#include "physics_support.hpp"

using Model = eomc::models::BallOnTurntable;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
enum { x, y, phi, theta, psi, x_dot, y_dot, phi_dot, theta_dot, psi_dot };
constexpr S eps = std::numeric_limits<S>::epsilon();

struct ProjectedBall {
    void operator()(S t, const rt::State<S>& s, rt::State<S>& ds) const { Model::rhs(t, s.data(), ds.data(), P); }
    void project(S t, rt::State<S>& s) const { Model::project(t, s.data(), P); }
};

// The centre's velocity in ground axes.
std::array<S, 2> ground_velocity(S t, const std::vector<S>& s) {
    const S vx = s[x_dot] - P.Omega * s[y], vy = s[y_dot] + P.Omega * s[x];
    const S c = std::cos(P.Omega * t), si = std::sin(P.Omega * t);
    return {c * vx - si * vy, si * vx + c * vy};
}

}  // namespace

BOOST_AUTO_TEST_CASE(centre_turns_at_two_sevenths_of_the_table) {
    static_assert(Model::n_constraints == 2);
    ProjectedBall sys;
    rt::State<S> s(Model::initial_state.begin(), Model::initial_state.end());
    const std::vector<S> s0(s.begin(), s.end());
    const auto V0 = ground_velocity(0, s0);
    const S rate = 2 * P.Omega / 7;
    const rt::Tolerances tol{1e-11, 1e-13};
    rt::Dopri5<S> stepper;
    // The ground velocity is a pure rotation of V0: an error in it is carried along, not amplified.
    // So the error at a step is at most the sum of the local bounds so far on ẋ, ẏ and Ω·(x, y),
    // twice (each projection moves the state by no more than the local error it removes).
    S accumulated = 0, worst_ratio = 0, worst = 0;
    const auto steps = phys::run(stepper, sys, s, S(0), S(3), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        const auto& b = st.local_bound;
        accumulated += 2 * (b[x_dot] + b[y_dot] + P.Omega * (b[x] + b[y]));
        const auto V = ground_velocity(st.t_new, st.x_new);
        const S a = rate * st.t_new;
        const S ex = V[0] - (std::cos(a) * V0[0] - std::sin(a) * V0[1]);
        const S ey = V[1] - (std::sin(a) * V0[0] + std::cos(a) * V0[1]);
        const S error = std::hypot(ex, ey);
        worst = std::max(worst, error);
        worst_ratio = std::max(worst_ratio, error / (accumulated + 16 * eps * std::hypot(V0[0], V0[1])));
    });
    BOOST_TEST_MESSAGE("largest |V − R(2Ωt/7)V0| " << worst << " over " << steps.size() << " steps; largest error/bound "
                                                    << worst_ratio);
    BOOST_TEST(worst_ratio <= 1.0);
    // A real motion: the velocity has turned by 2Ω t/7 = 1.7 rad by the end.
    const auto V1 = ground_velocity(3, std::vector<S>(s.begin(), s.end()));
    BOOST_TEST(V1[0] * V0[0] + V1[1] * V0[1] < 0);
    // Both rows hold after the last projection.
    std::vector<S> residual(Model::n_constraints);
    Model::constraint_residuals(S(3), s.data(), residual.data(), P);
    for (S r : residual) BOOST_TEST(std::abs(r) <= 16 * eps * (std::abs(s[x_dot]) + std::abs(s[y_dot]) + 1));
}
