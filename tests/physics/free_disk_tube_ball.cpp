// The seed's example with the disc free (Mei 1988, §1.1, (1.1.36) and (1.1.38)): no
// loads act, so along every motion
//   * the angular momentum about the disc's axis K_2 = (M r²/2 + m q²) w is constant (moment_2
//     with m⁰ = 0), and so is the sliding momentum (M + m) v0 (force_2 with V = 0);
//   * the energy T = ½(M + m) v0² + ¼ M r² w² + ½ m (q̇² + q² w²) is constant (the kernel's
//     `energy`, proven by the generator);
//   * the reactions are the seed's left-hand sides: R_1 = m(q̈ − q w²) = 0 for a smooth tube,
//     R_3 = −m(q ẇ + 2 q̇ w), N_1 = 0, N_3 = m q v̇0 = 0;
//   * the attitude turns about y' only: e = (cos θ/2, 0, sin θ/2, 0) with θ̇ = w, and the pole
//     moves along the inertial direction of y' — which stays fixed, so at v0 constant it
//     advances by v0 t.
// Drifts are bounded as in physics_support.hpp from the accepted steps' tolerances.
#define BOOST_TEST_MODULE physics_free_disk_tube_ball
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <vector>

#include "free_disk_tube_ball.hpp"
#include "physics_support.hpp"

using Model = eomc::models::FreeDiskTubeBall;
namespace rt = eomc::runtime;
using S = double;

namespace {

const Model::Parameters P{};
enum { q, q_dot, v0, w, e0, e1, e2, e3, px, py, pz };

S spin_momentum(const std::vector<S>& x) { return (P.M * P.r * P.r / 2 + P.m * x[q] * x[q]) * x[w]; }
S energy(const std::vector<S>& x) { return Model::energy(S(0), x.data(), P); }

}  // namespace

BOOST_AUTO_TEST_CASE(momenta_energy_and_reactions) {
    static_assert(Model::n_state == 11 && Model::n_velocities == 3 && Model::n_outputs == 4);
    BOOST_TEST(std::string(Model::output_names[1]) == "reaction_force_3");
    const rt::Tolerances tol{1e-11, 1e-13};
    phys::KernelSystem<Model, S> sys;
    std::vector<S> x(Model::initial_state.begin(), Model::initial_state.end());
    const std::vector<S> x0 = x;
    S worst_reaction = 0, worst_norm = 0;
    rt::Dopri5<S> stepper;
    const auto steps = phys::run(stepper, sys, x, S(0), S(5), tol, [&](const phys::Step<S>& st, const rt::Dopri5<S>&) {
        const auto& y = st.x_new;
        std::vector<S> rate(Model::n_state), out(Model::n_outputs);
        Model::rhs(st.t_new, y.data(), rate.data(), P);
        Model::outputs(st.t_new, y.data(), out.data(), P);
        const S w_dot = rate[w];
        // Scale of the terms in each reaction: m (|q| |ẇ| + 2 |q̇| |w|).
        const S scale = P.m * (std::abs(y[q] * w_dot) + 2 * std::abs(y[q_dot] * y[w])) + 1;
        worst_reaction = std::max({worst_reaction, std::abs(out[0]) / scale,
                                   std::abs(out[1] + P.m * (y[q] * w_dot + 2 * y[q_dot] * y[w])) / scale,
                                   std::abs(out[2]), std::abs(out[3]) / scale});
        worst_norm = std::max(worst_norm, std::abs(y[e0] * y[e0] + y[e1] * y[e1] + y[e2] * y[e2] + y[e3] * y[e3] - 1));
    });
    // The ball runs out along the tube and the disc slows down: a real motion, not a rest state.
    BOOST_TEST(x[q] > 5 * x0[q]);
    BOOST_TEST(x[w] < 0.9 * x0[w]);

    const S K0 = spin_momentum(x0), K1 = spin_momentum(x);
    const S K_bound = phys::invariant_drift_bound<S>(steps, spin_momentum, K0);
    BOOST_TEST_MESSAGE("K_2 drift " << std::abs(K1 - K0) << " (bound " << K_bound << ")");
    BOOST_TEST(std::abs(K1 - K0) <= K_bound);
    const S E0 = energy(x0), E1 = energy(x);
    const S E_bound = phys::invariant_drift_bound<S>(steps, energy, E0);
    BOOST_TEST_MESSAGE("energy drift " << std::abs(E1 - E0) << " (bound " << E_bound << ")");
    BOOST_TEST(std::abs(E1 - E0) <= E_bound);
    // v̇0 = 0 exactly (force_2 with V_2 = 0 has no other term).
    BOOST_TEST(x[v0] == x0[v0]);
    // The reactions are evaluated from the same rates: agreement to rounding (16 ulp of the scale).
    BOOST_TEST(worst_reaction <= 16 * std::numeric_limits<S>::epsilon());

    // Attitude: a rotation about y' by θ(t) = ∫ w dt. Its norm is conserved by ė = ½ e ⊗ ω exactly
    // in exact arithmetic; the integrator lets it move by at most the local error bounds summed.
    S norm_bound = 0;
    for (const auto& st : steps) norm_bound += 2 * (st.local_bound[e0] + st.local_bound[e2]);
    BOOST_TEST(worst_norm <= norm_bound);
    BOOST_TEST(x[e1] == 0.0);
    BOOST_TEST(x[e3] == 0.0);
    // The pole moves along the carrier's y' axis, which the rotation about y' leaves fixed in
    // space: inertial displacement (0, v0 t, 0). Its rate v0 (e0² + e2²)/|e|² is v0 to rounding,
    // so only the update's rounding accumulates: ≤ 4 ε |y| per step (as in local_bound).
    const S y_end = x0[v0] * 5.0;
    BOOST_TEST(std::abs(x[py] - y_end) <= S(steps.size()) * 4 * std::numeric_limits<S>::epsilon() * y_end);
    // R(e) v_o has no x or z part while e1 = e3 = 0: those rates are exact zeros.
    BOOST_TEST(x[px] == 0.0);
    BOOST_TEST(x[pz] == 0.0);
}
