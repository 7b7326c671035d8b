// Housner's rocking block (scenes/rocking_block.toml) through eomc simulate, event-driven: the block
// 0.4 wide and 1.2 tall (b = 0.2, h = 0.6, R = √(b² + h²), α = atan(b/h)) rocks about a corner by
// θ̈ = −p² sin(α − θ), p² = 3g/(4R), the unilateral system θ ≥ 0 with Housner's coefficient
// ω⁺/ω⁻ = 1 − (3/2) sin²α = 0.85 (G. W. Housner, "The behavior of inverted pendulum structures
// during earthquakes", Bull. Seismol. Soc. Am. 53(2) (1963) 403–417). References from
// bench/contact_reference.py (mpmath, 90 digits: each flight's time as a quadrature).
#define BOOST_TEST_MODULE simulate_rocking_block
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "csv.hpp"
#include "simulation.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double m = 1.0, g = 9.81, b = 0.2, h = 0.6;
constexpr double rtol = 1e-12, atol = 1e-14;

// From θ0 = α/2 at rest: impact k at t_k with |θ̇⁻_k| (mpmath).
struct Impact {
    double t, rate;
};
constexpr Impact reference[] = {
    {0.38729507631479312, 0.94526650296485589}, {0.94306967883223288, 0.8034765275201275},
    {1.3771006308584158, 0.68295504839210838},  {1.7278421754840572, 0.58051179113329212},
    {2.0164340250603142, 0.4934350224632983},   {2.2564500131553418, 0.41941976909380356},
    {2.457433538350902, 0.35650680372973302},   {2.6264953187384797, 0.30303078317027307},
    {2.7691439795059483, 0.25757616569473211},  {2.8897632122638531, 0.21893974084052229},
    {2.9919078027759249, 0.18609877971444395},  {3.0784990467659629, 0.15818396275727736},
    {3.1519605520883421, 0.13445636834368575},  {3.2143167399973753, 0.11428791309213289},
    {3.2672668625280537, 0.097144726128312957},
};
constexpr double zeno_time = 3.5667622617538924;  // the sum of all flights (mpmath, 320 of them)
constexpr double theta_at_1 = 0.033134346707879298, rate_at_1 = 0.48456338285007438;

eomc::host::SimulationRequest request(double t_end) {
    auto r = test_support::simulation_request(test_support::kernel_of(test_support::bundled_scene("rocking_block")), t_end);
    r.rtol = rtol;
    r.atol = atol;
    return r;
}

// The bound on the time of impact k, from the error control. Each accepted dopri5 step commits a
// local error ≤ rtol |x| + atol with |x| ≤ 1 here (|θ| ≤ α, |θ̇| ≤ 0.95). Within a flight the error
// grows at most by e^{p Δt} (p² bounds ∂θ̈/∂θ = p² cos(α − θ)), Δt ≤ 0.56 the longest flight. Each
// flight starts afresh at θ = 0 with its speed's error scaled by e < 1, so the flights' time errors
// add without compounding: after n steps, a state error ≤ n (rtol + atol) e^{p Δt}, a time error
// that divided by |θ̇⁻_k|.
double time_bound(std::size_t steps, double rate) {
    const double p = std::sqrt(3 * g / (4 * std::sqrt(b * b + h * h)));
    return double(steps) * (rtol + atol) * std::exp(p * 0.56) / rate;
}

}  // namespace

// The impacts through the Zeno point, then rest on the corner.
BOOST_AUTO_TEST_CASE(rocking_block_impacts_and_zeno) {
    auto r = request(5.0);
    const fs::path csv = fs::path(EOMC_BINARY_DIR) / "test-output" / "rocking_block.csv";
    fs::create_directories(csv.parent_path());
    r.csv_path = csv.string();
    const auto result = eomc::host::simulate(r);

    // The steps taken before each time, from the CSV (one row per accepted step and per event).
    std::vector<double> row_times;
    const auto lines = test_support::read_lines(csv);
    for (std::size_t i = 1; i < lines.size(); ++i) row_times.push_back(std::stod(lines[i].substr(0, lines[i].find(','))));
    const auto steps_before = [&](double t) {
        std::size_t n = 0;
        for (double s : row_times) n += s <= t;
        return n;
    };

    std::vector<const eomc::host::ContactEventReport*> impacts;
    const eomc::host::ContactEventReport* zeno = nullptr;
    for (const auto& e : result.contact_events) {
        if (e.kind == "impact") impacts.push_back(&e);
        if (e.kind == "zeno") zeno = &e;
    }
    constexpr std::size_t k_ref = std::size(reference);
    BOOST_REQUIRE(impacts.size() >= k_ref);
    const double e_housner = 1 - 1.5 * std::pow(std::sin(std::atan(b / h)), 2);
    BOOST_TEST(e_housner == 0.85, boost::test_tools::tolerance(1e-15));
    for (std::size_t k = 0; k < k_ref; ++k) {
        const double bound = time_bound(steps_before(reference[k].t), reference[k].rate);
        BOOST_TEST_MESSAGE("impact " << k + 1 << ": t = " << impacts[k]->t << ", error " << impacts[k]->t - reference[k].t
                                     << ", bound " << bound);
        BOOST_TEST(std::abs(impacts[k]->t - reference[k].t) <= bound);
        BOOST_TEST(std::abs(-impacts[k]->rate_before - reference[k].rate) <= bound * reference[k].rate);
    }
    // Newton's law in closed form: ω⁺/ω⁻ = −0.85 to round-off, at every impact.
    for (const auto* e : impacts) BOOST_TEST(e->rate_after / e->rate_before == -0.85, boost::test_tools::tolerance(1e-12));

    // Zeno: the flights shrink like the speed, by 0.85 each, so the impacts accumulate. The limit's
    // error is the last located impact's, bounded as above with that impact's speed, plus the
    // extrapolation's own bound.
    BOOST_REQUIRE(zeno);
    const double zeno_bound =
        time_bound(steps_before(zeno->t), std::abs(impacts.back()->rate_before)) + zeno->extrapolation_error;
    BOOST_TEST_MESSAGE("Zeno at " << zeno->t << " after " << impacts.size() << " impacts, error " << zeno->t - zeno_time
                                  << ", bound " << zeno_bound);
    BOOST_TEST(std::abs(zeno->t - zeno_time) <= zeno_bound);
    BOOST_TEST(zeno->ratio == 0.85, boost::test_tools::tolerance(1e-6));
    // Then at rest on the corner: λ is the weight's moment about it, m g b (a torque).
    BOOST_TEST(std::abs(result.value("theta")) <= 1e-12);
    BOOST_TEST(std::abs(result.value("theta_dot")) <= 1e-12);
    BOOST_REQUIRE(result.contacts.size() == 1u);
    BOOST_TEST(result.contacts[0].active);
    BOOST_TEST(result.value("lambda_corner") == m * g * b, boost::test_tools::tolerance(1e-12));
}

// The state at t = 1, between the second and third impacts, bounded like the impact times.
BOOST_AUTO_TEST_CASE(rocking_block_state_at_one) {
    const auto result = eomc::host::simulate(request(1.0));
    const double bound = time_bound(result.steps, 1.0);
    BOOST_TEST_MESSAGE("theta(1) error " << result.value("theta") - theta_at_1 << ", theta_dot(1) error "
                                         << result.value("theta_dot") - rate_at_1 << ", bound " << bound);
    BOOST_TEST(std::abs(result.value("theta") - theta_at_1) <= bound);
    BOOST_TEST(std::abs(result.value("theta_dot") - rate_at_1) <= bound);
}
