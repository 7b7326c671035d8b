// Issue 16's worked examples end to end from their bundled scenes, through eomc simulate: the §6.7
// ratchet (a kinematic unilateral row) with both contact drivers; a rod striking the floor; Newton's
// cradle under the simultaneous and the sequential impact laws. Known answers checked with mpmath
// (Mei, Special Topics in Analytical Mechanics, ch. 6).
#define BOOST_TEST_MODULE simulate_contact_examples
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "host/simulate.hpp"
#include "support/diagnostic.hpp"

#include "scenes.hpp"
#include "simulation.hpp"

namespace {

eomc::host::SimulationRequest request(const std::string& scene, double t_end, double rtol = 1e-12) {
    auto r = test_support::simulation_request(test_support::kernel_of(test_support::bundled_scene(scene)), t_end);
    r.rtol = rtol;
    r.atol = rtol * 1e-2;
    return r;
}

std::vector<const eomc::host::ContactEventReport*> events_of(const eomc::host::SimulationResult& result,
                                                             const std::string& kind) {
    std::vector<const eomc::host::ContactEventReport*> out;
    for (const auto& e : result.contact_events)
        if (e.kind == kind) out.push_back(&e);
    return out;
}

constexpr double half_pi = std::numbers::pi / 2;

}  // namespace

// scenes/ratchet.toml, event-driven: free until ẏ = 2 sin 2t returns to zero at π/2, located on
// dopri5's dense output at rtol 1e-12 (atol 1e-14): the time and y = 1 carry the smooth phase's
// global error, about rtol per step over a few hundred steps, bounded by 1e-10; then the contact
// phase holds y (ẏ = 0 to round-off, the projection) with λ = 4 m y, no impact.
BOOST_AUTO_TEST_CASE(ratchet_event_driven) {
    const auto result = eomc::host::simulate(request("ratchet", 3.0));
    const auto contacts = events_of(result, "contact");
    BOOST_REQUIRE(contacts.size() == 1u);
    BOOST_TEST(std::abs(contacts[0]->t - half_pi) <= 1e-10);
    BOOST_TEST(contacts[0]->lambda == 4.0, boost::test_tools::tolerance(1e-10));
    BOOST_TEST(events_of(result, "impact").empty());
    BOOST_TEST(events_of(result, "separation").empty());
    BOOST_TEST(std::abs(result.value("y") - 1.0) <= 1e-10);
    BOOST_TEST(std::abs(result.value("y_dot")) <= 1e-14);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_ratchet") == 4.0, boost::test_tools::tolerance(1e-10));
}

// Moreau–Jean (θ = 1/2, h = 1e-3): the row φ = ẏ ≥ 0 is imposed on every step's end velocity. Free
// flight is the θ-method on the oscillator (error O(h²) over π/2); the step that catches ẏ at zero
// starts with ẏ ≤ |ÿ| h = 4h, so y overshoots 1 by at most 4h² (measured 3e-7 in all); the contact
// event falls within two steps of π/2. Held, u_free = −4 y h exactly and P = 4 m y h, so λ = P/h =
// 4 m y to round-off, ẏ = 0 exactly.
BOOST_AUTO_TEST_CASE(ratchet_moreau_jean) {
    auto r = request("ratchet", 3.0);
    r.contact_method = "moreau_jean";
    r.step = 1e-3;
    const auto result = eomc::host::simulate(r);
    const auto contacts = events_of(result, "contact");
    BOOST_REQUIRE(contacts.size() == 1u);
    BOOST_TEST(std::abs(contacts[0]->t - half_pi) <= 2 * r.step);
    BOOST_TEST(events_of(result, "impact").empty());
    BOOST_TEST(events_of(result, "separation").empty());
    const double y = result.value("y");
    BOOST_TEST(std::abs(y - 1.0) <= 4 * r.step * r.step);
    BOOST_TEST(result.value("y_dot") == 0.0);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_ratchet") == 4.0 * y, boost::test_tools::tolerance(1e-12));
}

// scenes/rod_floor_impact.toml: the impact at t = 0 (the end on the floor, approaching) is one
// row's Newton law in closed form, P = −(1 + e) ḟ⁻/G; no force acts after it, so the velocities at
// t_end are the post-impact ones exactly. Everything to round-off: 1e-13 relative (absolute for ẋ).
// The issue's signs hold with θ counterclockwise and the lower end at (x − l cos θ, y − l sin θ):
// the floor's upward impulse at the left end turns the rod clockwise, θ̇⁺ < 0.
BOOST_AUTO_TEST_CASE(rod_strikes_the_floor) {
    const auto result = eomc::host::simulate(request("rod_floor_impact", 0.25));
    const auto impacts = events_of(result, "impact");
    BOOST_REQUIRE(impacts.size() == 1u);
    const auto& e = *impacts[0];
    BOOST_TEST(e.t == 0.0);
    BOOST_TEST(e.impulse == 0.923076923076923, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(e.rate_before == -2.0, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(e.rate_after == 1.0, boost::test_tools::tolerance(1e-13));  // −e ḟ⁻
    BOOST_TEST(std::abs(result.value("x_dot")) <= 1e-13);
    BOOST_TEST(result.value("y_dot") == -1.07692307692308, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(result.value("theta_dot") == -4.79644839019074, boost::test_tools::tolerance(1e-13));
    // Carnot: ΔT = −((1 − e)/(1 + e)) ½ Δq̇ᵀ M Δq̇ with Δq̇ = (0, P/m, −l cos θ P/I), I = 1/12; by hand
    // −(1/3)(P²/2)(1 + 12 l² cos²θ) = −(1/3)(P²/2)(13/4) = −6/13.
    BOOST_TEST(e.energy_change == -6.0 / 13.0, boost::test_tools::tolerance(1e-13));
    BOOST_TEST(e.carnot == -6.0 / 13.0, boost::test_tools::tolerance(1e-13));
}

// scenes/newtons_cradle.toml (e = 1, both gaps closed at t = 0, the left approaching at 1): the
// scene's sequential law gives two two-body impacts of unit impulse and (0, 0, 1); Moreau's
// simultaneous LCP gives P = (4/3, 2/3) and (−1/3, 2/3, 2/3) (Lemke on a 2 × 2 LCP: round-off).
// Both keep T = 1/2, and the summary names the law used.
BOOST_AUTO_TEST_CASE(newtons_cradle_sequential_and_simultaneous) {
    struct Case {
        const char* law;
        double v[3], P[2];
    };
    for (const Case& c : {Case{"sequential", {0.0, 0.0, 1.0}, {1.0, 1.0}},
                          Case{"simultaneous", {-1.0 / 3, 2.0 / 3, 2.0 / 3}, {4.0 / 3, 2.0 / 3}}}) {
        BOOST_TEST_CONTEXT(c.law) {
            auto r = request("newtons_cradle", 1.0);
            r.impact_law = c.law;
            const auto result = eomc::host::simulate(r);
            BOOST_TEST(result.impact_law == c.law);
            const char* names[] = {"x1_dot", "x2_dot", "x3_dot"};
            for (int i = 0; i < 3; ++i) BOOST_TEST(std::abs(result.value(names[i]) - c.v[i]) <= 1e-14);
            const auto impacts = events_of(result, "impact");
            BOOST_REQUIRE(impacts.size() == 2u);
            for (int k = 0; k < 2; ++k) {
                BOOST_TEST(impacts[std::size_t(k)]->t == 0.0);
                BOOST_TEST(impacts[std::size_t(k)]->impulse == c.P[k], boost::test_tools::tolerance(1e-14));
                BOOST_TEST(std::abs(impacts[std::size_t(k)]->energy_change) <= 1e-15);
                BOOST_TEST(std::abs(impacts[std::size_t(k)]->carnot) <= 1e-15);
            }
            std::ostringstream text, json;
            eomc::host::print_summary(result, "text", text);
            eomc::host::print_summary(result, "json", json);
            BOOST_TEST(text.str().find(std::string("event_driven, ") + c.law + " impacts") != std::string::npos);
            BOOST_TEST(json.str().find(std::string("\"impact_law\": \"") + c.law + "\"") != std::string::npos);
        }
    }
}

// The sequential law belongs to the event-driven method: Moreau–Jean refuses it, naming the law.
BOOST_AUTO_TEST_CASE(sequential_law_needs_event_driven) {
    auto r = request("newtons_cradle", 1.0);
    r.contact_method = "moreau_jean";
    r.impact_law = "sequential";
    BOOST_CHECK_EXCEPTION(eomc::host::simulate(r), eomc::InputError, [](const eomc::InputError& e) {
        return std::string(e.what()).find("sequential impact law needs contact method event_driven") != std::string::npos;
    });
}

// Scene [events] beside a unilateral row: the bouncing ball of issue 16 (h0 = 2, e = 0.7, g = 9.81)
// with its apexes recorded (ẏ going down through 0) and a terminal event at t = 2. Free flight
// is a quadratic in t that dopri5 follows exactly, so each apex is the located root of ẏ, linear
// on the dense output: at t_k + e^k v1/g with height e^(2k) h0 (v1 = √(2 g h0)), to the round-off
// of the impact times before it (1e-11, as the impact times themselves) and 1e-12 in height (ẏ = 0
// there). The run stops at t = 2 exactly, between the second and the third impact, in the state of
// the closed form y = v2 (t − t2) − g (t − t2)²/2 (1e-11).
BOOST_AUTO_TEST_CASE(scene_events_beside_a_bouncing_ball) {
    const std::string scene = R"toml([scene]
name = "bouncing_ball_events"
[parameters]
m = 1.0
g = 9.81
e = 0.7
[coordinates]
y = { initial = 2.0, rate = 0.0 }
[lagrangian]
T = "m*y_dot^2/2"
V = "m*g*y"
[[unilateral]]
name = "floor"
gap = "y"
restitution = "e"
[events]
apex = { when = "y_dot", direction = "down" }
stop = { when = "t - 2", direction = "up", terminal = true }
)toml";
    auto r = test_support::simulation_request(test_support::kernel_of(scene), 5.0);
    r.rtol = 1e-12;
    r.atol = 1e-14;
    const auto result = eomc::host::simulate(r);
    const double g = 9.81, h0 = 2.0, e = 0.7, v1 = std::sqrt(2 * g * h0);
    const double t1 = 0.638550856814101, t2 = 1.53252205635384;  // the impacts (mpmath)
    BOOST_REQUIRE(result.events.size() == 3u);
    const double apex_t[] = {t1 + e * v1 / g, t2 + e * e * v1 / g}, apex_y[] = {e * e * h0, e * e * e * e * h0};
    for (int k = 0; k < 2; ++k) {
        const auto& ev = result.events[std::size_t(k)];
        BOOST_TEST(ev.name == "apex");
        BOOST_TEST(std::abs(ev.t - apex_t[k]) <= 1e-11);
        BOOST_TEST(std::abs(ev.state[0] - apex_y[k]) <= 1e-12);
        BOOST_TEST(std::abs(ev.state[1]) <= 1e-12);
    }
    BOOST_TEST(result.events[2].name == "stop");
    BOOST_TEST(result.events[2].terminal);
    BOOST_TEST(result.stopped_by == "stop");
    BOOST_TEST(std::abs(result.t - 2.0) <= 1e-14);
    const double v2 = e * e * v1, s = result.t - t2;
    BOOST_TEST(std::abs(result.value("y") - (v2 * s - g * s * s / 2)) <= 1e-11);
    BOOST_TEST(std::abs(result.value("y_dot") - (v2 - g * s)) <= 1e-11);
    BOOST_TEST(events_of(result, "impact").size() == 2u);

    // Moreau–Jean does not locate scene events yet: refused, naming them.
    r.contact_method = "moreau_jean";
    BOOST_CHECK_EXCEPTION(eomc::host::simulate(r), eomc::InputError, [](const eomc::InputError& err) {
        return std::string(err.what()).find("scene events (apex, stop)") != std::string::npos;
    });
}
