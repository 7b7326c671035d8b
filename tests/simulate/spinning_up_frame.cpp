// A free particle seen from a frame that spins up, ω = α t about z (FORMULAS §1 with every
// effect time dependent: Euler, centrifugal and Coriolis all act). In inertial axes the
// particle moves uniformly, X = X0 + U t; the frame has turned by θ = α t²/2, so in carrier
// axes r'(t) = R(−θ) (X0 + U t) (ω(0) = 0, so relative and inertial velocities agree at t = 0).
// Dopri5 at rtol = atol = 1e-12 over t = 4 (θ = 8 rad, ~400 steps): the global error is the sum
// of ≤ √n·tol local errors grown at most linearly (uniform motion), ≲ 1e-8 here.
#define BOOST_TEST_MODULE simulate_spinning_up_frame
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace {

const char* const scene = R"toml(
[scene]
name = "spinning_up"
[parameters]
m = 0.7
alpha = 1.0
[coordinates]
x = { initial = 1.0, rate = 0.3 }
y = { initial = -0.5, rate = 0.8 }
[carrier]
angular_velocity = ["0", "0", "alpha*t"]
[[body]]
name = "p"
mass = "m"
position = ["x", "y", "0"]
)toml";

}  // namespace

BOOST_AUTO_TEST_CASE(uniform_motion_seen_from_a_spinning_up_frame) {
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(scene, "spin.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    // Every effect but translation is present in the equations.
    for (const auto& term : eqs.equations[0].effects)
        if (term.effect != eomc::model::Effect::translation && term.effect != eomc::model::Effect::relative)
            BOOST_TEST(!term.value.expand().is_zero(), eomc::model::name(term.effect));
    BOOST_TEST(eqs.invariants.empty());  // ω depends on t: no Jacobi integral
    eomc::host::SimulationRequest r;
    r.header_text = eomc::codegen::emit_header(eomc::codegen::lower(model, eqs), {EOMC_VERSION});
    r.struct_name = model.struct_name;
    const double t = 4.0, alpha = 1.0;
    r.t_end = t;
    r.rtol = r.atol = 1e-12;
    r.cache_dir = std::string(EOMC_BINARY_DIR) + "/test-cache";
    r.progress = false;
    const auto result = eomc::host::simulate(r);
    const double X = 1.0 + 0.3 * t, Y = -0.5 + 0.8 * t, theta = alpha * t * t / 2;
    const double x = std::cos(theta) * X + std::sin(theta) * Y, y = -std::sin(theta) * X + std::cos(theta) * Y;
    BOOST_TEST_MESSAGE("x error " << result.value("x") - x << ", y error " << result.value("y") - y);
    BOOST_TEST(std::abs(result.value("x") - x) <= 1e-8);
    BOOST_TEST(std::abs(result.value("y") - y) <= 1e-8);
}
