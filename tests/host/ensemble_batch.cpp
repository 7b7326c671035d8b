// Ensembles in SIMD batches (--batch, host/ensemble_batch.hpp): the members' rows against the
// same ensemble run one member at a time, the bead's pitchfork in lock-step dopri5, the lanes that
// fail rerun alone, and the refusals.
#define BOOST_TEST_MODULE ensemble_batch
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "host/ensemble.hpp"
#include "support/diagnostic.hpp"

#include "oscillator.hpp"
#include "simulation.hpp"

using namespace eomc::host;
using test_support::Kernel;

namespace {

EnsembleRequest request_for(const Kernel& k, double t_end) {
    EnsembleRequest r;
    r.base = test_support::simulation_request(k, t_end);
    r.progress = false;
    return r;
}

Kernel oscillator() {
    test_support::Oscillator o;
    o.parameter = "k";
    o.stiffness = "k";
    return test_support::kernel_of(test_support::oscillator_scene(o));
}

}  // namespace

// A linear kernel's rates are + − × alone, the IEEE operations of the scalar run lane by lane: rk4
// in batches writes the very bytes of the one-at-a-time CSV. Ten members: two full batches of four
// and a short one, over two threads.
BOOST_AUTO_TEST_CASE(rk4_batches_write_the_one_at_a_time_csv) {
    const Kernel k = oscillator();
    EnsembleRequest r = request_for(k, 5.0);
    r.base.integrator = "rk4";
    r.base.step = 0.01;
    r.spec.grid = {parse_grid("k=1:4:10")};
    r.threads = 2;
    const std::string alone = ensemble_csv(run_ensemble(r));
    r.batch = true;
    const EnsembleResult batched = run_ensemble(r);
    BOOST_TEST(batched.lanes == 4u);
    BOOST_TEST(ensemble_csv(batched) == alone);
}

// The bead's rates call sin and cos, which the SIMD type evaluates with its own vectorised
// polynomials (within an ulp or two of libm's, not the same bits). A rate perturbed by a few ulps
// per step on this contracting flow moves the state by at most (steps) × a few ulps: with 2000
// steps, 2000 × 8 eps × max(1, |x|) bounds the difference; a lane given another member's inputs or
// a wrong step would be off by O(1).
BOOST_AUTO_TEST_CASE(rk4_batches_of_the_hoop_agree_with_one_at_a_time_to_round_off) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleRequest r = request_for(k, 20.0);
    r.base.integrator = "rk4";
    r.base.step = 0.01;
    r.spec.grid = {parse_grid("omega=2:8:10"), parse_grid("theta=0.1:0.3:2")};
    const EnsembleResult alone = run_ensemble(r);
    r.batch = true;
    const EnsembleResult batched = run_ensemble(r);
    BOOST_TEST_REQUIRE(batched.members.size() == alone.members.size());
    const double steps = 2000, eps = std::numeric_limits<double>::epsilon();
    for (std::size_t i = 0; i < alone.members.size(); ++i) {
        const MemberResult &a = alone.members[i], &b = batched.members[i];
        BOOST_TEST_INFO("member " << i);
        BOOST_TEST(b.status == "ok");
        BOOST_TEST(a.status == "ok");
        BOOST_TEST(b.inputs == a.inputs);
        BOOST_TEST(b.t == a.t);
        for (std::size_t j = 0; j < a.state.size(); ++j)
            BOOST_TEST(std::abs(b.state[j] - a.state[j]) <= steps * 8 * eps * std::max(1.0, std::abs(a.state[j])));
    }
}

// A three-link chain: M is dense and state-dependent, solved by the kernel's unrolled LDLᵀ
// (codegen/solve_plan), straight-line code over S, so the kernel is batchable. Its rates call sin
// and cos (the SIMD type's own, within an ulp or two of libm's); at these amplitudes the motion is
// near the linear normal modes, where a perturbation is carried, not amplified, over 2 s: 200 steps
// of a few ulps each, bounded as for the hoop above by steps × 8 eps × max(1, |x|) with steps = 2000.
BOOST_AUTO_TEST_CASE(rk4_batches_of_a_chain_solved_by_the_unrolled_ldlt_agree_to_round_off) {
    const Kernel k = test_support::kernel_of(R"toml([scene]
name = "chain3"
[parameters]
g = 9.81
[coordinates]
th1 = { initial = 0.2, rate = 0.0 }
th2 = { initial = 0.1, rate = 0.0 }
th3 = { initial = 0.0, rate = 0.0 }
[[body]]
name = "bob1"
mass = "1"
position = ["sin(th1)", "-cos(th1)", "0"]
[[body]]
name = "bob2"
mass = "1"
position = ["sin(th1) + sin(th2)", "-(cos(th1) + cos(th2))", "0"]
[[body]]
name = "bob3"
mass = "1"
position = ["sin(th1) + sin(th2) + sin(th3)", "-(cos(th1) + cos(th2) + cos(th3))", "0"]
[forces]
potential = "-g*(3*cos(th1) + 2*cos(th2) + cos(th3))"
)toml");
    BOOST_TEST_REQUIRE(k.header.find("unrolled") != std::string::npos);
    BOOST_TEST_REQUIRE(k.header.find("static constexpr bool batchable = true;") != std::string::npos);
    EnsembleRequest r = request_for(k, 2.0);
    r.base.integrator = "rk4";
    r.base.step = 0.01;
    r.spec.grid = {parse_grid("g=9:10:3"), parse_grid("th1=0.1:0.3:3")};
    const EnsembleResult alone = run_ensemble(r);
    r.batch = true;
    const EnsembleResult batched = run_ensemble(r);
    BOOST_TEST(batched.lanes == 4u);
    BOOST_TEST_REQUIRE(batched.members.size() == alone.members.size());
    const double steps = 2000, eps = std::numeric_limits<double>::epsilon();
    for (std::size_t i = 0; i < alone.members.size(); ++i) {
        const MemberResult &a = alone.members[i], &b = batched.members[i];
        BOOST_TEST_INFO("member " << i);
        BOOST_TEST(b.status == "ok");
        BOOST_TEST(a.status == "ok");
        BOOST_TEST(b.inputs == a.inputs);
        for (std::size_t j = 0; j < a.state.size(); ++j)
            BOOST_TEST(std::abs(b.state[j] - a.state[j]) <= steps * 8 * eps * std::max(1.0, std::abs(a.state[j])));
    }
}

// The pitchfork of tests/host/ensemble.cpp (its derivation there) in lock-step dopri5: every lane
// takes the step of the most demanding one, so each meets its tolerances at least as well as alone;
// the closed form θ* = acos(g/(Rω²)) past ω² = g/R, 0 before, within the same 2e-7.
BOOST_AUTO_TEST_CASE(the_hoop_pitchfork_in_lock_step_dopri5) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleRequest r = request_for(k, 40.0);
    r.spec.grid = {parse_grid("omega=0:8:17")};
    r.batch = true;
    r.threads = 2;
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST_REQUIRE(e.members.size() == 17u);
    const double g = 9.81, R = 0.5;
    for (const auto& m : e.members) {
        const double w = m.inputs[0];
        BOOST_TEST_INFO("omega = " << w);
        BOOST_TEST(m.status == "ok");
        const double expected = w * w <= g / R ? 0.0 : std::acos(g / (R * w * w));
        BOOST_TEST(std::abs(m.state[0] - expected) < 2e-7);
    }
}

// q̈ = a q³ (tests/host/ensemble.cpp): a = 4 blows up before t = 0.93; its lane leaves the batch
// and the member runs alone, so its row (status, time, message) is the one-at-a-time row.
BOOST_AUTO_TEST_CASE(a_failing_lane_is_rerun_alone) {
    const Kernel k = test_support::kernel_of(R"([scene]
name = "cubic"
[parameters]
a = 1.0
[coordinates]
q = { initial = 1.0, rate = 0.0 }
[lagrangian]
T = "q_dot^2/2"
V = "0"
[forces]
generalized = { q = "a*q^3" }
)");
    for (const char* method : {"rk4", "dopri5"}) {
        EnsembleRequest r = request_for(k, 2.0);
        r.base.integrator = method;
        r.base.step = 0.001;
        r.spec.grid = {parse_grid("a=-4:4:3")};
        const EnsembleResult alone = run_ensemble(r);
        r.batch = true;
        const EnsembleResult batched = run_ensemble(r);
        BOOST_TEST_INFO(method);
        BOOST_TEST_REQUIRE(batched.members.size() == 3u);
        BOOST_TEST(batched.members[0].status == "ok");
        BOOST_TEST(batched.members[1].status == "ok");
        BOOST_TEST(batched.members[1].state[0] == 1.0);  // a = 0: q stays at 1 exactly
        const MemberResult &a = alone.members[2], &b = batched.members[2];
        BOOST_TEST(b.status == "failed");
        BOOST_TEST(b.t == a.t);
        BOOST_TEST(b.message == a.message);
    }
}

BOOST_AUTO_TEST_CASE(kernels_and_methods_that_cannot_batch_are_refused) {
    const auto refused = [](EnsembleRequest r, const std::string& why) {
        r.batch = true;
        try {
            (void)run_ensemble(r);
            BOOST_FAIL("ran as a batch: " + why);
        } catch (const eomc::InputError& e) {
            BOOST_TEST(e.where().file == "--batch");
            BOOST_TEST(std::string(e.what()).find(why) != std::string::npos, e.what());
        }
    };
    // pendulum_cartesian solves M u̇ − Wᵀλ = f, W u̇ = r at run time (the Schur complement, Eigen).
    EnsembleRequest rows = request_for(test_support::kernel_of(test_support::bundled_scene("pendulum_cartesian")), 1.0);
    refused(rows, "solves for its rates at run time");
    // leo_drag's M = I is solved in straight-line code, but its re-entry event needs locating.
    EnsembleRequest leo = request_for(test_support::kernel_of(test_support::bundled_scene("leo_drag")), 10.0);
    leo.spec.grid = {parse_grid("CdA_m=0.02:0.03:2")};
    refused(leo, "the scene has events");
    EnsembleRequest r = request_for(oscillator(), 1.0);
    r.spec.grid = {parse_grid("k=1:2:2")};
    r.base.integrator = "dop853";
    refused(r, "not dop853");
    r.base.integrator = "rk4";
    r.base.compensated = true;
    refused(r, "compensated");
}
