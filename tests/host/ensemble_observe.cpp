// --observe (host/observation.hpp): expression columns on the members' final states, an event's
// first time, the LEO re-entry spread under a 5 % drag uncertainty, and the refusals.
#define BOOST_TEST_MODULE ensemble_observe
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <string>

#include "host/ensemble.hpp"
#include "support/diagnostic.hpp"

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

std::size_t column(const EnsembleResult& r, const std::string& name) {
    for (std::size_t i = 0; i < r.observed_names.size(); ++i)
        if (r.observed_names[i] == name) return i;
    BOOST_FAIL("no observed column " + name);
    return 0;
}

}  // namespace

// Each expression sees its own member: the swept omega, the scene's g and R, the final θ. Past the
// pitchfork cos θ = g/(Rω²) at rest (the derivation in tests/host/ensemble.cpp): the column
// cos(theta) − g/(R omega^2) is the equilibrium's residual, below the run's 2e-7 in θ.
BOOST_AUTO_TEST_CASE(expressions_are_evaluated_on_each_members_final_state) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleRequest r = request_for(k, 40.0);
    r.spec.grid = {parse_grid("omega=5:8:4")};
    r.observe = {parse_observation("deg=theta*180/Pi"), parse_observation("w2=omega^2"),
                 parse_observation("residual=cos(theta) - g/(R*omega^2)")};
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST(e.observed_names == (std::vector<std::string>{"deg", "w2", "residual"}));
    for (const auto& m : e.members) {
        BOOST_TEST_INFO("omega = " << m.inputs[0]);
        const double eps = std::numeric_limits<double>::epsilon();
        BOOST_TEST(std::abs(m.observed[column(e, "deg")] - m.state[0] * 180 / std::numbers::pi) <= 4 * eps * 180);
        BOOST_TEST(m.observed[column(e, "w2")] == m.inputs[0] * m.inputs[0]);
        BOOST_TEST(std::abs(m.observed[column(e, "residual")]) < 2e-7);
    }
    const std::string csv = ensemble_csv(e);
    BOOST_TEST(csv.rfind("member,omega,status,t,theta,theta_dot,deg,w2,residual,events,message\n", 0) == 0);
    BOOST_TEST(ensemble_statistics(e).back().name == "residual");
    BOOST_TEST(ensemble_column(e, "w2").size() == 4u);
}

// The spread of the bundled LEO's re-entry time under a 5 % uncertainty in CdA/m, N = 32 draws.
// The lifetime goes as 1/(CdA/m) (the orbit-averaged decay; tests/host/ensemble.cpp), so for
// CdA/m = μ(1 + δ), δ ~ normal(0, 0.05), E[t] = t(μ) E[1/(1 + δ)] ≈ t(μ)(1 + 0.05²): the sample mean
// must lie within 3 standard errors s/√N of t(μ)(1 + 0.0025), widened by one orbital period P for
// where in its last orbit each member meets the surface.
BOOST_AUTO_TEST_CASE(the_leo_re_entry_spread_under_five_percent_drag) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("leo_drag"));
    EnsembleRequest r = request_for(k, 2592000.0);
    r.base.integrator = "dop853";
    r.base.rtol = 1e-10;
    r.base.atol = 1e-9;
    r.observe = {parse_observation("event:re_entry")};
    r.spec.grid = {parse_grid("CdA_m=0.022")};
    const EnsembleResult one = run_ensemble(r);
    BOOST_TEST_REQUIRE(one.members.size() == 1u);
    const double t_mean_drag = one.members[0].observed[0];
    BOOST_TEST(t_mean_drag == one.members[0].t);  // the terminal event ends the run

    r.spec.grid.clear();
    r.spec.vary = {parse_variation("CdA_m=normal(0.022,0.0011)")};
    r.spec.samples = 32;
    r.spec.seed = 7;
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST(e.observed_names == std::vector<std::string>{"t_re_entry"});
    for (const auto& m : e.members) {
        BOOST_TEST(m.status == "stopped");
        BOOST_TEST(m.observed[0] == m.t);
    }
    const ColumnStatistics s = ensemble_statistics(e).back();
    BOOST_TEST(s.name == "t_re_entry");
    BOOST_TEST_REQUIRE(s.count == 32u);
    BOOST_TEST(s.std > 0.02 * t_mean_drag);  // a 5 % spread in drag is a ~5 % spread in lifetime
    BOOST_TEST(s.std < 0.10 * t_mean_drag);
    const double period = 2 * std::numbers::pi * std::sqrt(std::pow(6628.137, 3) / 398600.4418);
    BOOST_TEST(std::abs(s.mean - t_mean_drag * (1 + 0.05 * 0.05)) < 3 * s.std / std::sqrt(32.0) + period);
}

BOOST_AUTO_TEST_CASE(bad_observations_are_refused_at_the_flag) {
    const auto refused = [](const auto& f, const std::string& where, const std::string& why) {
        try {
            f();
            BOOST_FAIL("accepted: " + where);
        } catch (const eomc::InputError& e) {
            BOOST_TEST(eomc::to_string(e.where()).rfind(where, 0) == 0, eomc::to_string(e.where()));
            BOOST_TEST(std::string(e.what()).find(why) != std::string::npos, e.what());
        }
    };
    refused([] { (void)parse_observation("theta*2"); }, "--observe theta*2", "expected NAME=EXPR");
    refused([] { (void)parse_observation("2x=theta"); }, "--observe 2x=theta", "not a column name");
    refused([] { (void)parse_observation("event:"); }, "--observe event:", "not an event name");
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleRequest r = request_for(k, 1.0);
    r.spec.grid = {parse_grid("omega=5:6:2")};
    const auto with = [&](const char* text) {
        return [&r, text] {
            EnsembleRequest q = r;
            q.observe = {parse_observation(text)};
            (void)run_ensemble(q);
        };
    };
    // The column of the unknown name: "deg=" is 4 characters, "thta" starts at column 5.
    refused(with("deg=thta*2"), "--observe deg=thta*2:1:5", "did you mean 'theta'");
    refused(with("deg=theta*"), "--observe deg=theta*", "");
    refused(with("event:re_entry"), "--observe event:re_entry", "no events");
    refused(with("theta=2*theta"), "--observe theta=2*theta", "already in the CSV");
}
