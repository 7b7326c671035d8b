// Hamilton's equations (Mei §1.9) against Lagrange's for the same scene: both kernels are
// generated, compiled and integrated with Dopri5 at rtol = atol = 1e-12, and must give the
// same q(t_end), the same p = ∂L/∂q̇ and the same conserved energy. Each run's global error
// is bounded by its accumulated local errors (≤ √n·tol per step, ~10³ steps here) times the
// growth of perturbations over t_end (Lyapunov factor ≲ 10² for these regular motions), so
// 1e-7 separates "the same solution" from any formulation error (an O(1) discrepancy).
#define BOOST_TEST_MODULE simulate_hamiltonian
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace {

const std::string cache_dir = std::string(EOMC_BINARY_DIR) + "/test-cache";

std::string read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A particle on a spring in a frame turning at Ω about z: Coriolis and centrifugal terms
// make p = m(q̇ + ω × r) differ from m q̇, which is what the Legendre transform must get right.
const char* const rotating_spring = R"toml(
[scene]
name = "rotating_spring"
[parameters]
m = 1.3
k = 5.0
Omega = 0.7
[coordinates]
x = { initial = 1.0, rate = 0.1 }
y = { initial = 0.0, rate = 0.4 }
[carrier]
angular_velocity = ["0", "0", "Omega"]
[[body]]
name = "p"
mass = "m"
position = ["x", "y", "0"]
[forces]
potential = "k*(x^2 + y^2)/2"
)toml";

eomc::host::SimulationResult run(const std::string& toml, bool hamiltonian, double t_end) {
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(toml, "test.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    const auto ir = hamiltonian ? eomc::codegen::lower(model, eomc::mechanics::canonical_equations(model, eqs).form)
                                : eomc::codegen::lower(model, eqs);
    eomc::host::SimulationRequest r;
    r.header_text = eomc::codegen::emit_header(ir, {EOMC_VERSION});
    r.struct_name = model.struct_name;
    r.t_end = t_end;
    r.rtol = r.atol = 1e-12;
    r.cache_dir = cache_dir;
    r.progress = false;
    return eomc::host::simulate(r);
}

void compare(const std::string& toml, double t_end) {
    const auto lagrange = run(toml, false, t_end);
    const auto hamilton = run(toml, true, t_end);
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(toml, "test.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    const auto canonical = eomc::mechanics::canonical_equations(model, eqs);
    GiNaC::exmap at_end{{model.t, t_end}};
    for (const auto& p : model.parameters) at_end[p.symbol] = p.value;
    for (const auto& c : model.coordinates) {
        BOOST_TEST(std::abs(lagrange.value(c.name) - hamilton.value(c.name)) <= 1e-7, lagrange.scene_name << " " << c.name);
        at_end[c.q] = lagrange.value(c.name);
        at_end[c.q_dot] = lagrange.value(c.name + "_dot");
    }
    for (std::size_t s = 0; s < model.coordinates.size(); ++s) {
        const double p = GiNaC::ex_to<GiNaC::numeric>(canonical.momentum[s].subs(at_end).evalf()).to_double();
        BOOST_TEST(std::abs(p - hamilton.value("p_" + model.coordinates[s].name)) <= 1e-7 * (1 + std::abs(p)));
    }
    BOOST_REQUIRE_EQUAL(lagrange.invariants.size(), 1u);
    BOOST_REQUIRE_EQUAL(hamilton.invariants.size(), 1u);
    // h(q, q̇) and H(q, p) are the same function on corresponding states.
    BOOST_TEST(std::abs(lagrange.invariants[0].initial - hamilton.invariants[0].initial) <=
               1e-12 * (1 + std::abs(lagrange.invariants[0].initial)));
    BOOST_TEST(hamilton.invariants[0].max_abs_drift <= 1e-8 * (1 + std::abs(hamilton.invariants[0].initial)));
}

}  // namespace

BOOST_AUTO_TEST_CASE(same_trajectory_in_a_rotating_frame) { compare(rotating_spring, 10.0); }

BOOST_AUTO_TEST_CASE(same_trajectory_for_the_bundled_scenes) {
    for (const char* scene : {"bead_on_hoop", "double_pendulum", "kepler_orbit", "disk_tube_ball"})
        compare(read(std::string(EOMC_SOURCE_DIR) + "/scenes/" + scene + ".toml"), 3.0);
}

BOOST_AUTO_TEST_CASE(refusals_name_the_reason) {
    const std::string dropped = std::string(rotating_spring) + "[effects]\nkeep = [\"relative\", \"coriolis\"]\n";
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(dropped, "test.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    BOOST_CHECK_EXCEPTION(eomc::mechanics::canonical_equations(model, eqs), eomc::InputError,
                          [](const eomc::InputError& e) { return std::string(e.what()).find("[effects]") != std::string::npos; });
    // T = x_dot^4: the velocity Hessian depends on the velocity; no quadratic Legendre transform.
    const char* quartic = R"toml(
[scene]
name = "quartic"
[coordinates]
x = { initial = 1.0, rate = 0.5 }
[lagrangian]
T = "x_dot^4/12 + x_dot^2/2"
V = "x^2/2"
)toml";
    const auto m2 = eomc::model::build_model(eomc::scene::parse_scene_string(quartic, "test.toml"));
    const auto e2 = eomc::mechanics::derive(m2);
    BOOST_CHECK_EXCEPTION(eomc::mechanics::canonical_equations(m2, e2), eomc::InputError,
                          [](const eomc::InputError& e) { return std::string(e.what()).find("quadratic") != std::string::npos; });
}
