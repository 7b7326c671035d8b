// `eomc sweep --equilibria` (host/equilibria_sweep.hpp): the relative equilibria and their verdicts
// over a parameter grid, against the bead on a spinning hoop's pitchfork (Mei §1.3): the bottom
// θ = 0 is stable while ω² < g/R and unstable past it, where the two off-bottom equilibria
// cos θ* = g/(R ω²) appear, stable; the top θ = π is unstable throughout.
#define BOOST_TEST_MODULE equilibria_sweep
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "host/equilibria_sweep.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "support/diagnostic.hpp"

#include "scenes.hpp"
#include "simulation.hpp"

using namespace eomc;
using namespace eomc::host;

namespace {

const mechanics::Equilibrium* at(const EquilibriumPoint& p, double q) {
    for (const auto& e : p.equilibria)
        if (std::abs(e.q[0] - q) < 1e-6) return &e;
    return nullptr;
}

}  // namespace

// ω from 0 to 8 in steps of 0.25 brackets ω_c = √(g/R) = 4.429… between 4.25 and 4.5. The
// off-bottom equilibria come from the closed form acos(g/(Rω²)) (confirmed by Newton), so they
// must match it to round-off: 1e-12 allows a few hundred ulps of acos's conditioning near ω_c.
BOOST_AUTO_TEST_CASE(the_hoop_pitchfork_at_omega_squared_g_over_r) {
    const model::Model model = test_support::model_of(test_support::bundled_scene("bead_on_hoop_damped"));
    EnsembleSpec spec;
    spec.grid = {parse_grid("omega=0:8:33")};
    const EquilibriumSweep sweep = sweep_equilibria(model, mechanics::derive(model), spec);
    BOOST_TEST_REQUIRE(sweep.points.size() == 33u);
    const double g = 9.81, R = 0.5;
    std::size_t below = 0, above = 0;
    for (const auto& p : sweep.points) {
        const double w = p.inputs[0];
        BOOST_TEST_INFO("omega = " << w);
        BOOST_TEST(p.error.empty());
        const auto* bottom = at(p, 0.0);
        const auto* top = at(p, std::numbers::pi);
        BOOST_TEST_REQUIRE(bottom);
        BOOST_TEST_REQUIRE(top);
        BOOST_TEST(top->verdict == "unstable");
        if (w * w < g / R) {
            ++below;
            BOOST_TEST(bottom->verdict == "stable");
            BOOST_TEST(p.equilibria.size() == 2u);
        } else {
            ++above;
            BOOST_TEST(bottom->verdict == "unstable");
            BOOST_TEST(largest_growth(*bottom) > 0.0);
            BOOST_TEST_REQUIRE(p.equilibria.size() == 4u);
            const double expected = std::acos(g / (R * w * w));
            for (double sign : {-1.0, 1.0}) {
                const auto* off = at(p, sign * expected);
                BOOST_TEST_REQUIRE(off);
                BOOST_TEST(std::abs(off->q[0] - sign * expected) < 1e-12);
                BOOST_TEST(off->verdict == "stable");
            }
        }
    }
    BOOST_TEST(below == 18u);  // ω = 0 … 4.25
    BOOST_TEST(above == 15u);  // ω = 4.5 … 8
    // One CSV row per equilibrium, after the header.
    const std::string csv = equilibria_csv(sweep);
    BOOST_TEST(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) == 1 + 18 * 2 + 15 * 4);
    BOOST_TEST(csv.rfind("point,omega,equilibria,theta,verdict,growth\n", 0) == 0);
}

// Over one axis the picture is the bifurcation diagram: every equilibrium a point, stable and
// unstable in two data blocks; over two a map; over three, refused.
BOOST_AUTO_TEST_CASE(the_pictures) {
    const model::Model model = test_support::model_of(test_support::bundled_scene("bead_on_hoop_damped"));
    const mechanics::Equations equations = mechanics::derive(model);
    EnsembleSpec spec;
    spec.grid = {parse_grid("omega=4:5:3")};
    const EquilibriumSweep one = sweep_equilibria(model, equations, spec);
    const std::string diagram = equilibria_plot_script(one, spec, "png", "out.png");
    BOOST_TEST(diagram.find("$stable << EOD\n") != std::string::npos);
    BOOST_TEST(diagram.find("$unstable << EOD\n") != std::string::npos);
    spec.grid.push_back(parse_grid("g=9:10:2"));
    const EquilibriumSweep two = sweep_equilibria(model, equations, spec);
    BOOST_TEST(two.points.size() == 6u);
    BOOST_TEST(equilibria_plot_script(two, spec, "png", "out.png").find("with image") != std::string::npos);
    spec.grid.push_back(parse_grid("R=0.4:0.5:2"));
    BOOST_CHECK_THROW(equilibria_plot_script(sweep_equilibria(model, equations, spec), spec, "png", "out.png"),
                      InputError);
}

BOOST_AUTO_TEST_CASE(initial_values_and_random_draws_are_refused) {
    const model::Model model = test_support::model_of(test_support::bundled_scene("bead_on_hoop_damped"));
    const mechanics::Equations equations = mechanics::derive(model);
    EnsembleSpec spec;
    spec.grid = {parse_grid("theta=0:1:3")};
    try {
        (void)sweep_equilibria(model, equations, spec);
        BOOST_FAIL("an initial value was swept");
    } catch (const InputError& e) {
        BOOST_TEST(e.where().file == "--grid theta=0:1:3");
    }
    spec.grid.clear();
    spec.vary = {parse_variation("omega=normal(5,1)")};
    spec.samples = 3;
    BOOST_CHECK_THROW(sweep_equilibria(model, equations, spec), InputError);
}

// The sleeping Lagrange top (scenes/lagrange_top.toml: A = 1.5, C = 0.6, P = 2) on its axis, γ = e3,
// ω = (0, 0, r0), is spectrally stable iff C² r0² > 4 A P z0 (Maievskii's criterion; Leimanis 1965,
// §4): swept over the spin and the centre height, each row of the grid must switch from unstable to
// stable once, between the two spins that bracket r0 = 2√(A P z0)/C. The hanging top (γ = −e3) is
// stable at every spin.
BOOST_AUTO_TEST_CASE(the_sleeping_top_boundary_from_a_sweep) {
    const model::Model model = test_support::model_of(test_support::bundled_scene("lagrange_top"));
    EnsembleSpec spec;
    spec.grid = {parse_grid("z0=0.05:0.5:10"), parse_grid("spin=0:6:61")};
    const EquilibriumSweep sweep = sweep_equilibria(model, mechanics::derive(model), spec);
    BOOST_TEST_REQUIRE(sweep.points.size() == 610u);
    BOOST_TEST(sweep.rigid);
    const double A = 1.5, C = 0.6, P = 2.0;
    for (std::size_t row = 0; row < 10; ++row) {
        const double z0 = sweep.points[row * 61].inputs[0];
        const double critical = 2 * std::sqrt(A * P * z0) / C;
        BOOST_TEST_INFO("z0 = " << z0 << ", critical spin " << critical);
        double last_unstable = -1, first_stable = -1;
        std::size_t switches = 0;
        bool previous = false;
        for (std::size_t j = 0; j < 61; ++j) {
            const EquilibriumPoint& p = sweep.points[row * 61 + j];
            BOOST_TEST_REQUIRE(p.error.empty());
            bool upright = false, hanging = false;
            for (const auto& r : p.rotations) {
                if (r.gamma[2] > 0.5) upright = r.verdict != "unstable";
                if (r.gamma[2] < -0.5) hanging = r.verdict != "unstable";
            }
            BOOST_TEST(hanging);
            if (!upright) last_unstable = p.inputs[1];
            if (upright && first_stable < 0) first_stable = p.inputs[1];
            if (j > 0 && upright != previous) ++switches;
            previous = upright;
        }
        BOOST_TEST(switches == 1u);
        BOOST_TEST(last_unstable < critical);
        BOOST_TEST(first_stable > critical);
        BOOST_TEST(first_stable - last_unstable == 0.1, boost::test_tools::tolerance(1e-9));
    }
    BOOST_TEST(equilibria_csv(sweep).rfind("point,z0,spin,rotations,rotation,gamma1,gamma2,gamma3,rotation_spin,verdict,growth\n", 0) == 0);
}
