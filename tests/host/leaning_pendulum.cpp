// The pendulum leaning on a wall (issue 16; Mei, ch. 6, §6.4–§6.5), end to end from the bundled
// scene scenes/pendulum_leaning_wall.toml: l = 0.5, g = 9.81, m = 1, released at rest at 30° above a
// wall θ ≥ θ_w = 10° with e = 0.6. Its impacts accumulate (Zeno) at t∞ = 1.76155662459086, then it
// leans on the wall with λ = m g l sin θ_w = 0.851744311456293 — the λ the KKT conditions of §6.4
// give for the same scene.
//
// t∞ by mpmath (40 digits): t∞ = t_1 + Σ_k τ(e^k v_1), t_1 the fall from 30° to the wall, v_1 its
// speed there, τ(v) the flight up from the wall at speed v and back, each a quadrature of
// dt = dφ / (ω √(1 − k² sin² φ)) with sin(θ/2) = k sin φ (136 terms, the last below 1e-30).
#define BOOST_TEST_MODULE simulate_leaning_pendulum
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "host/simulate.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/unilateral/equilibria.hpp"

#include "simulation.hpp"

namespace {

constexpr double zeno_time = 1.76155662459086, first_impact = 0.283159951866184;
constexpr double lambda_wall = 0.851744311456293;  // m g l sin 10°, m = 1
constexpr double theta_w = 10 * std::numbers::pi / 180;

}  // namespace

// Event-driven, dopri5 at rtol 1e-12, atol 1e-14 to t = 3. The first impact is a located root of
// the dense output: its error is the integration's, rtol |t| ≈ 1e-12 over one fall, bounded by 1e-11.
// The Zeno point is the series' sum from the last impacts, within the driver's own estimate of the
// extrapolation error (Δt_k δr/(1 − r)²) plus the impacts' location errors it starts from, about
// 1e-12 each (round-off of ε |θ|/|θ̇⁻| grows as the bounces shrink to 1e-4 rad/s: 1e-12). The
// ratio tends to e (the flights shorten as v, decelerated by g sin θ_w/l at the wall). After it, the
// contact phase holds θ = θ_w with λ the static balance m g l sin θ_w, to round-off (1e-12 relative).
BOOST_AUTO_TEST_CASE(zeno_then_leaning_with_the_kkt_multiplier) {
    const std::string scene = test_support::bundled_scene("pendulum_leaning_wall");
    auto r = test_support::simulation_request(test_support::kernel_of(scene), 3.0);
    r.rtol = 1e-12;
    r.atol = 1e-14;
    const auto result = eomc::host::simulate(r);
    std::vector<const eomc::host::ContactEventReport*> impacts, zeno, contact;
    for (const auto& e : result.contact_events) {
        if (e.kind == "impact") impacts.push_back(&e);
        if (e.kind == "zeno") zeno.push_back(&e);
        if (e.kind == "contact") contact.push_back(&e);
    }
    BOOST_REQUIRE(!impacts.empty());
    BOOST_TEST_MESSAGE("first impact at " << impacts[0]->t << ", error " << impacts[0]->t - first_impact);
    BOOST_TEST(std::abs(impacts[0]->t - first_impact) <= 1e-11);
    BOOST_REQUIRE(zeno.size() == 1u);
    const double bound = zeno[0]->extrapolation_error + 1e-12 * double(impacts.size());
    BOOST_TEST_MESSAGE("Zeno at " << zeno[0]->t << ", error " << zeno[0]->t - zeno_time << " after " << impacts.size()
                                  << " impacts, extrapolation estimate " << zeno[0]->extrapolation_error);
    BOOST_TEST(std::abs(zeno[0]->t - zeno_time) <= bound);
    BOOST_TEST(zeno[0]->extrapolation_error <= 1e-9);  // the driver waited until the series was summed
    BOOST_TEST(zeno[0]->ratio == 0.6, boost::test_tools::tolerance(1e-3));
    for (const auto* e : impacts) BOOST_TEST(e->t < zeno[0]->t);
    BOOST_REQUIRE(!contact.empty());
    BOOST_TEST(contact[0]->t == zeno[0]->t);

    // Leaning on the wall: θ = θ_w at rest, the contact active with the KKT multiplier.
    BOOST_TEST(result.value("theta") == theta_w, boost::test_tools::tolerance(1e-12));
    BOOST_TEST(std::abs(result.value("theta_dot")) <= 1e-12);
    BOOST_REQUIRE(result.contacts.size() == 1u);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_wall") == lambda_wall, boost::test_tools::tolerance(1e-12));

    // The KKT equilibria of the same scene: the only stable one is on the wall, with that λ.
    const auto model = test_support::bundled_model("pendulum_leaning_wall");
    const auto kkt = eomc::mechanics::unilateral::kkt_equilibria(model, eomc::mechanics::derive(model));
    std::vector<const eomc::mechanics::unilateral::KktEquilibrium*> stable;
    for (const auto& e : kkt.equilibria)
        if (e.verdict == "stable") stable.push_back(&e);
    BOOST_REQUIRE(stable.size() == 1u);
    BOOST_TEST(stable[0]->point.q[0] == result.value("theta"), boost::test_tools::tolerance(1e-12));
    BOOST_TEST(stable[0]->point.lambda[0] == result.value("lambda_wall"), boost::test_tools::tolerance(1e-12));
}
