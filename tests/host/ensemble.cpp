// Ensembles end to end (issue 18): one compiled kernel run for every member of a sweep or a
// Monte-Carlo ensemble, against closed forms; the same bytes for any thread count or rank split;
// failures recorded without stopping the others; bad specifications refused.
#define BOOST_TEST_MODULE ensemble
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

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

// A member's final value of `name` (a state variable).
double final_value(const EnsembleResult& r, const MemberResult& m, const std::string& name) {
    for (std::size_t i = 0; i < r.state_names.size(); ++i)
        if (r.state_names[i] == name) return m.state[i];
    BOOST_FAIL("no state variable " + name);
    return 0;
}

}  // namespace

// The bundled damped oscillator ẍ = −γẋ − w²x from x = 1 at rest, swept over w: underdamped,
// x(t) = e^{−γt/2} (cos ω_d t + γ/(2ω_d) sin ω_d t), ω_d = √(w² − γ²/4). dopri5 at rtol 1e-10,
// atol 1e-12 keeps each step's local error near 1e-10 relative; this contracting linear flow does
// not amplify it, so the global error after the < 2000 steps of these runs stays below 2000 ×
// 1e-10 = 2e-7 (in practice ~1e-9); the bound 2e-7 fails for any member with a wrong w.
BOOST_AUTO_TEST_CASE(a_sweep_of_the_damped_oscillator_matches_the_closed_form) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("damped_oscillator"));
    EnsembleRequest r = request_for(k, 20.0);
    r.spec.grid = {parse_grid("w=1:3:9")};
    r.threads = 2;
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST_REQUIRE(e.members.size() == 9u);
    const double gamma = 0.1, t = 20.0;
    for (const auto& m : e.members) {
        BOOST_TEST_INFO("member " << m.index << ", w = " << m.inputs[0]);
        BOOST_TEST(m.status == "ok");
        BOOST_TEST(m.inputs[0] == 1.0 + 0.25 * static_cast<double>(m.index));
        const double w = m.inputs[0], wd = std::sqrt(w * w - gamma * gamma / 4), decay = std::exp(-gamma * t / 2);
        const double x = decay * (std::cos(wd * t) + gamma / (2 * wd) * std::sin(wd * t));
        const double v = -decay * (w * w / wd) * std::sin(wd * t);  // ẋ of the same solution
        BOOST_TEST(std::abs(final_value(e, m, "x") - x) < 2e-7);
        BOOST_TEST(std::abs(final_value(e, m, "x_dot") - v) < 2e-7 * w);
        BOOST_TEST(m.t == t);
    }
}

// The same ensemble on 1 and 2 threads, and split over 2 "ranks" (index % 2) then merged: the CSV
// and the statistics must be the same bytes.
BOOST_AUTO_TEST_CASE(results_do_not_depend_on_threads_or_ranks) {
    const Kernel k = oscillator();
    EnsembleRequest r = request_for(k, 5.0);
    r.spec.vary = {parse_variation("k=lognormal(0,0.3)"), parse_variation("q=uniform(-1,1)")};
    r.spec.samples = 200;
    r.spec.seed = 7;
    r.threads = 1;
    const EnsembleResult one = run_ensemble(r);
    r.threads = 2;
    const EnsembleResult two = run_ensemble(r);
    BOOST_TEST(one.threads == 1u);
    BOOST_TEST(two.threads == 2u);
    const std::string csv = ensemble_csv(one);
    BOOST_TEST(csv == ensemble_csv(two));
    std::ostringstream s1, s2;
    // The JSON summary less its timings (the last fields before "statistics" differ run to run).
    const auto statistics = [](const EnsembleResult& e) {
        std::ostringstream s;
        print_ensemble_summary(e, "json", s);
        return s.str().substr(s.str().find("\"statistics\""));
    };
    BOOST_TEST(statistics(one) == statistics(two));

    EnsembleResult merged = one;
    merged.members.clear();
    r.ranks = 2;
    r.rank = 0;
    const EnsembleResult even = run_ensemble(r);
    r.rank = 1;
    const EnsembleResult odd = run_ensemble(r);
    BOOST_TEST_REQUIRE(even.members.size() + odd.members.size() == 200u);
    for (std::size_t i = 0; i < 200; ++i) merged.members.push_back(i % 2 ? odd.members[i / 2] : even.members[i / 2]);
    BOOST_TEST(ensemble_csv(merged) == csv);
    BOOST_TEST(csv.substr(0, csv.find('\n')) == "member,k,q,status,t,q,q_dot,energy_max_drift,events,message");
}

// q̈ = −q from q0 ~ normal(μ, σ) at rest: q(T) = q0 cos T is linear in q0, so over N members its
// sample mean lies within 5 standard errors σ|cos T|/√N of μ cos T (plus the integrator's 1e-8),
// and its sample standard deviation within 5 σ|cos T|/√(2(N − 1)) of σ|cos T|. The seed is fixed.
BOOST_AUTO_TEST_CASE(the_ensemble_mean_and_spread_of_a_linear_output) {
    const Kernel k = oscillator();
    EnsembleRequest r = request_for(k, 2.0);
    const double mu = 0.8, sigma = 0.2, c = std::cos(2.0);
    const std::size_t n = 2000;
    r.spec.vary = {parse_variation("q=normal(0.8,0.2)")};
    r.spec.samples = n;
    r.spec.seed = 12345;
    const EnsembleResult e = run_ensemble(r);
    const auto stats = ensemble_statistics(e);
    BOOST_TEST_REQUIRE(stats[1].name == "q");
    BOOST_TEST(stats[1].count == n);
    const double se = sigma * std::abs(c) / std::sqrt(double(n));
    BOOST_TEST(std::abs(stats[1].mean - mu * c) < 5 * se + 1e-8);
    BOOST_TEST(std::abs(stats[1].std - sigma * std::abs(c)) < 5 * sigma * std::abs(c) / std::sqrt(2.0 * (n - 1)) + 1e-8);
    // The quantiles are ordered and the median is near μ cos T (c < 0 mirrors the distribution).
    BOOST_TEST(stats[1].min <= stats[1].q05);
    BOOST_TEST(stats[1].q05 <= stats[1].q50);
    BOOST_TEST(stats[1].q50 <= stats[1].q95);
    BOOST_TEST(stats[1].q95 <= stats[1].max);
    BOOST_TEST(std::abs(stats[1].q50 - mu * c) < 0.1 * sigma);
}

// q̈ = a q³ from q = 1 at rest: for a = 4 q reaches infinity at t* = K(1/√2)/2 ≈ 0.927 < 2; the
// others (a = −4, 0) run to the end. The failure is recorded and the other members are kept.
BOOST_AUTO_TEST_CASE(a_failing_member_is_recorded_and_the_others_run) {
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
    EnsembleRequest r = request_for(k, 2.0);
    r.spec.grid = {parse_grid("a=-4:4:3")};
    r.threads = 2;
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST_REQUIRE(e.members.size() == 3u);
    BOOST_TEST(e.members[0].status == "ok");
    BOOST_TEST(e.members[1].status == "ok");
    BOOST_TEST(final_value(e, e.members[1], "q") == 1.0);  // a = 0: q stays at 1 exactly
    BOOST_TEST(e.members[2].status == "failed");
    BOOST_TEST(e.members[2].t < 0.93);
    BOOST_TEST(!e.members[2].message.empty());
    BOOST_TEST(std::isnan(final_value(e, e.members[2], "q")));
    BOOST_TEST(ensemble_statistics(e)[1].count == 2u);
    const std::string csv = ensemble_csv(e);
    BOOST_TEST(csv.find("\n2,4,failed,") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(bad_specifications_are_refused_before_any_run) {
    const Kernel k = oscillator();
    EnsembleRequest r = request_for(k, 1.0);
    r.spec.grid = {parse_grid("kk=1:2:3")};
    try {
        run_ensemble(r);
        BOOST_FAIL("an unknown name was accepted");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.where().file == "--grid kk=1:2:3");
        BOOST_TEST(e.message().find("did you mean 'k'") != std::string::npos);
    }
    // exp(1000) overflows: every member's q is infinite and refused, so the command is refused.
    r.spec.grid.clear();
    r.spec.vary = {parse_variation("q=lognormal(1000,1)")};
    r.spec.samples = 4;
    BOOST_CHECK_THROW(run_ensemble(r), eomc::InputError);
    r.spec.vary = {parse_variation("q=normal(0,1)")};
    r.base.integrator = "dopri7";
    BOOST_CHECK_THROW(run_ensemble(r), eomc::InputError);
}

// The bundled damped bead on a spinning hoop swept over ω: it settles at θ = 0 below the pitchfork
// ω² = g/R and at cos θ* = g/(R ω²) above it (θ* > 0: from θ = 0.1 at rest, with ω² above
// (g/R)·2/(1 + cos 0.1), the bead's energy is already below the barrier's at θ = 0). At every grid
// point here the drag rate c/(mR²) = 2 s⁻¹ damps the approach at e⁻ᵗ (ω = 4 and 4.5, the nearest,
// are underdamped), so at t = 40 the transient is ~0.1 e⁻⁴⁰ ≈ 4e-19; dopri5's global error at
// rtol 1e-10, atol 1e-12 over < 2000 steps is below 2e-7, the bound used.
BOOST_AUTO_TEST_CASE(the_hoop_pitchfork_from_a_sweep) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleRequest r = request_for(k, 40.0);
    r.spec.grid = {parse_grid("omega=0:8:17")};
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST_REQUIRE(e.members.size() == 17u);
    const double g = 9.81, R = 0.5;
    for (const auto& m : e.members) {
        const double w = m.inputs[0];
        BOOST_TEST_INFO("omega = " << w);
        BOOST_TEST(m.status == "ok");
        const double expected = w * w <= g / R ? 0.0 : std::acos(g / (R * w * w));
        BOOST_TEST(std::abs(final_value(e, m, "theta") - expected) < 2e-7);
    }
}

// The pictures' scripts: one row of data per member (a failed one as NaN, which gnuplot leaves
// out), a map over two varied axes, a histogram whose counts add up to the members that ran.
BOOST_AUTO_TEST_CASE(the_pictures_hold_every_member) {
    const Kernel k = oscillator();
    EnsembleRequest r = request_for(k, 1.0);
    r.spec.grid = {parse_grid("k=1:4:4")};
    const EnsembleResult line = run_ensemble(r);
    const std::string s1 = ensemble_plot_script(line, r.spec, "q", "png", "out.png");
    BOOST_TEST(s1.find("set output 'out.png'") != std::string::npos);
    BOOST_TEST(s1.find("plot $d using 1:2 with linespoints") != std::string::npos);
    for (const auto& m : line.members)  // each member's (k, q(1)) row, as the CSV has it
        BOOST_TEST(s1.find(fmt::format("\n{:.17g} {:.17g}\n", m.inputs[0], m.state[0])) != std::string::npos);
    BOOST_CHECK_THROW(ensemble_plot_script(line, r.spec, "p", "png", "out.png"), eomc::InputError);

    r.spec.grid = {parse_grid("k=1:4:4"), parse_grid("q=0.5:1:3")};
    const EnsembleResult map = run_ensemble(r);
    const std::string s2 = ensemble_plot_script(map, r.spec, "energy_max_drift", "png", "out.png");
    BOOST_TEST(s2.find("with image") != std::string::npos);
    r.spec.grid.push_back(parse_grid("q_dot=0:1:2"));
    const EnsembleResult cube = run_ensemble(r);
    try {
        (void)ensemble_plot_script(cube, r.spec, "q", "png", "out.png");
        BOOST_FAIL("a picture of a three-axis grid was drawn");
    } catch (const eomc::InputError& e) {
        BOOST_TEST(e.where().file == "--plot");
    }

    r.spec.grid.clear();
    r.spec.vary = {parse_variation("q=normal(0,1)")};
    r.spec.samples = 400;
    const EnsembleResult draws = run_ensemble(r);
    const std::string s3 = ensemble_plot_script(draws, r.spec, "q", "png", "out.png");
    const std::size_t from = s3.find("$h << EOD\n") + 10;
    const std::string data = s3.substr(from, s3.find("EOD\n", from) - from);
    std::istringstream rows(data);
    std::size_t total = 0, bins = 0;
    for (double centre, count, width; rows >> centre >> count >> width; ++bins) total += static_cast<std::size_t>(count);
    BOOST_TEST(bins == 20u);  // √400
    BOOST_TEST(total == 400u);
}

// The bundled LEO under drag, swept ±5 % in CdA/m: each run stops at the re_entry event
// ("stopped"). In the orbit-averaged decay da/dt ∝ (CdA/m) ρ(a), so the lifetime goes as
// 1/(CdA/m) and t·(CdA/m) is the same for every member, but for where in its last orbit each
// meets the surface: at most one period P = 2π √(a³/μ) ≈ 5.4e3 s, so they agree within P/t_min.
BOOST_AUTO_TEST_CASE(the_leo_lifetime_goes_as_the_inverse_ballistic_coefficient) {
    const Kernel k = test_support::kernel_of(test_support::bundled_scene("leo_drag"));
    EnsembleRequest r = request_for(k, 2592000.0);
    r.base.integrator = "dop853";
    r.base.rtol = 1e-10;
    r.base.atol = 1e-9;
    r.spec.grid = {parse_grid("CdA_m=0.0209:0.0231:3")};
    const EnsembleResult e = run_ensemble(r);
    BOOST_TEST_REQUIRE(e.members.size() == 3u);
    const double period = 2 * std::numbers::pi * std::sqrt(std::pow(6628.137, 3) / 398600.4418);
    double t_min = e.members.back().t;
    for (const auto& m : e.members) {
        BOOST_TEST(m.status == "stopped");
        BOOST_TEST(m.message == "re_entry");
        BOOST_TEST(m.events == 1u);
        t_min = std::min(t_min, m.t);
    }
    BOOST_TEST(t_min > 3e5);  // days, not the whole 30 days nor minutes
    const double reference = e.members[1].t * e.members[1].inputs[0];
    for (const auto& m : e.members)
        BOOST_TEST(std::abs(m.t * m.inputs[0] / reference - 1) < period / t_min, "member " << m.index);
}
