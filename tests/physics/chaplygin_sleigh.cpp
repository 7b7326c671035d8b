// Chaplygin's sleigh (scenes/chaplygin_sleigh.toml): a knife edge at (x, y) that cannot slide
// sideways, −sin φ ẋ + cos φ ẏ = 0, the mass centre a ahead of it. With v = ẋ cos φ + ẏ sin φ and
// ω = φ̇ the motion obeys v̇ = a ω², ω̇ = −(m a/J) v ω, J = I + m a² (Chaplygin 1911; Neimark and
// Fufaev, Dynamics of Nonholonomic Systems, 1972, ch. 3), whose energy E = (m v² + J ω²)/2 is
// conserved, so that v is a Riccati equation with the closed form
//     v(t) = V tanh(s),  ω(t) = ±√(m/J) V sech(s),  s = a m V t/J + artanh(v0/V),  V = √(2E/m):
// the sleigh straightens out and runs on at V. Integrated with the generated kernel, whose
// project() keeps the knife edge to round-off after every step.
#define BOOST_TEST_MODULE physics_chaplygin_sleigh
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "chaplygin_sleigh.hpp"
#include "physics_support.hpp"

using Model = eomc::models::ChaplyginSleigh;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
enum { x, y, phi, x_dot, y_dot, phi_dot };
constexpr S eps = std::numeric_limits<S>::epsilon();

// The kernel as a runtime system that projects onto the constraint after every accepted step.
struct ProjectedSleigh {
    void operator()(S t, const rt::State<S>& s, rt::State<S>& ds) const { Model::rhs(t, s.data(), ds.data(), P); }
    void project(S t, rt::State<S>& s) const { Model::project(t, s.data(), P); }
};

S forward_speed(const std::vector<S>& s) { return s[x_dot] * std::cos(s[phi]) + s[y_dot] * std::sin(s[phi]); }
S energy(const std::vector<S>& s) { return Model::energy(S(0), s.data(), P); }

}  // namespace

BOOST_AUTO_TEST_CASE(straightens_out_at_the_closed_form_speed) {
    static_assert(Model::n_constraints == 1);
    const S J = P.I + P.m * P.a * P.a;
    ProjectedSleigh sys;
    rt::State<S> s(Model::initial_state.begin(), Model::initial_state.end());
    const std::vector<S> s0(s.begin(), s.end());
    const S v0 = forward_speed(s0), w0 = s0[phi_dot], E0 = energy(s0);
    const S V = std::sqrt(2 * E0 / P.m);
    BOOST_TEST(E0 == (P.m * v0 * v0 + J * w0 * w0) / 2, boost::test_tools::tolerance(4 * eps));

    const rt::Tolerances tol{1e-11, 1e-13};
    const S t_end = 20;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, s, S(0), t_end, tol);
    const std::vector<S> s1(s.begin(), s.end());

    // The knife edge after the last projection: round-off of the residual's two products.
    const S lateral = -std::sin(s1[phi]) * s1[x_dot] + std::cos(s1[phi]) * s1[y_dot];
    BOOST_TEST(std::abs(lateral) <= 8 * eps * (std::abs(s1[x_dot]) + std::abs(s1[y_dot])));

    // Energy: each step's local error moves it by at most the propagated local bound; the
    // projection moves the state back towards the exact solution's manifold by no more than that
    // local error again, hence twice the bound.
    const S E_bound = 2 * phys::invariant_drift_bound<S>(steps, energy, E0);
    const S E1 = energy(s1);
    BOOST_TEST_MESSAGE("energy drift " << std::abs(E1 - E0) << " (bound " << E_bound << ")");
    BOOST_TEST(std::abs(E1 - E0) <= E_bound);

    // v and ω against the closed form. Both equations contract (∂v̇/∂v = −2amv/J < 0 through
    // V² − v², ∂ω̇/∂ω = −(ma/J)v < 0 for v > 0), so a local error is not amplified later: the
    // global error is at most the sum of the local bounds, plus the cross-coupling of each
    // variable's error into the other over the total turn Δφ = ∫ω dt (first order), plus the
    // shift of V that the energy's own error makes, δV = δE/(mV).
    S local_v = 0, local_w = 0;
    for (const auto& st : steps) {
        local_v += st.local_bound[x_dot] + st.local_bound[y_dot] + std::abs(forward_speed(st.x_new)) * st.local_bound[phi];
        local_w += st.local_bound[phi_dot];
    }
    const S turn = std::abs(s1[phi] - s0[phi]);
    const S dV = E_bound / (P.m * V);
    const S w_bound = local_w + P.m * P.a / J * (local_v + dV) * turn;
    const S v_bound = local_v + dV + 2 * P.a * std::abs(w0) * w_bound * turn;
    const S arg = P.a * P.m * V * t_end / J + std::atanh(v0 / V);
    const S v_exact = V * std::tanh(arg), w_exact = std::sqrt(P.m / J) * V / std::cosh(arg);
    BOOST_TEST_MESSAGE("v error " << std::abs(forward_speed(s1) - v_exact) << " (bound " << v_bound << "), ω error "
                                  << std::abs(s1[phi_dot] - w_exact) << " (bound " << w_bound << ")");
    BOOST_TEST(std::abs(forward_speed(s1) - v_exact) <= v_bound);
    BOOST_TEST(std::abs(s1[phi_dot] - w_exact) <= w_bound);
    // It has straightened out: ω is down by many orders of magnitude, v is at V.
    BOOST_TEST(std::abs(s1[phi_dot]) < 1e-8 * std::abs(w0));
    BOOST_TEST(std::abs(forward_speed(s1) - V) <= v_bound + V * 2 / std::exp(2 * arg));
}
