// A free rigid body in every formulation against the exact Euler–Poinsot motion
// (runtime/rigid/euler_poinsot.hpp: Jacobi's elliptic functions for ω, the elliptic integral of
// the third kind for the attitude): the outputs p, q, r, gamma1..3 of each kernel, and the
// quaternion formulation's attitude itself, end where the closed form says. A sign or a
// convention wrong in one formulation's frames gives errors of order 1.
#define BOOST_TEST_MODULE simulate_rigid_formulations
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <string>

#include "eomc/runtime/rigid/euler_poinsot.hpp"
#include "simulation.hpp"

namespace {

constexpr double phi0 = 0.3, theta0 = 1.1, psi0 = -0.4;
constexpr std::array<double, 3> inertia{2, 3, 5}, omega0{0.4, 0.3, 0.8};

std::string scene(const std::string& formulation) {
    return "[scene]\nname = \"free_body\"\n[parameters]\nA = 2.0\nB = 3.0\nC = 5.0\n[rigid_body]\n"
           "inertia = [\"A\", \"B\", \"C\"]\nformulation = \"" +
           formulation + "\"\n[rigid_body.initial]\nomega = [0.4, 0.3, 0.8]\nattitude = { zxz = [0.3, 1.1, -0.4] }\n";
}

// The body → space quaternion of R_z(φ) R_x(θ) R_z(ψ) (Goldstein §4.4).
std::array<double, 4> zxz(double phi, double theta, double psi) {
    return {std::cos(theta / 2) * std::cos((phi + psi) / 2), std::sin(theta / 2) * std::cos((phi - psi) / 2),
            std::sin(theta / 2) * std::sin((phi - psi) / 2), std::cos(theta / 2) * std::sin((phi + psi) / 2)};
}

// γ = R(e)ᵀ e_Z, the third row of R(e).
std::array<double, 3> vertical(const std::array<double, 4>& e) {
    return {2 * (e[1] * e[3] - e[0] * e[2]), 2 * (e[2] * e[3] + e[0] * e[1]),
            e[0] * e[0] - e[1] * e[1] - e[2] * e[2] + e[3] * e[3]};
}

eomc::host::SimulationResult run(const std::string& formulation, double t_end, bool hamiltonian = false) {
    auto r = test_support::simulation_request(test_support::kernel_of(scene(formulation), {.hamiltonian = hamiltonian}),
                                              t_end);
    r.integrator = "dop853";
    r.rtol = 1e-12;
    r.atol = 1e-14;
    return eomc::host::simulate(r);
}

}  // namespace

// dop853 at rtol 1e-12 keeps each step's error below 1e-12 of the O(1) state; over the few hundred
// steps of these runs the global error stays below 1e-12 × 10³, so 1e-9 bounds it with room for the
// error's growth along a period (the body's motion is stable off the separatrix).
BOOST_AUTO_TEST_CASE(every_formulation_follows_the_exact_motion) {
    const auto exact = eomc::runtime::FreeRigidBody::from(inertia, omega0, zxz(phi0, theta0, psi0));
    for (const char* formulation : {"euler_poisson", "quaternion", "euler_angles", "andoyer_deprit"}) {
        // Euler angles meet gimbal lock when the body's axis 3 passes the vertical: a shorter run.
        const double t_end = std::string(formulation) == "euler_angles" ? 3.0 : 20.0;
        const auto result = run(formulation, t_end);
        const auto state = exact.at(t_end);
        const auto gamma = vertical(state.quaternion);
        BOOST_TEST_CONTEXT(formulation << " at t = " << t_end) {
            BOOST_TEST(result.t == t_end);
            const char* w[3] = {"p", "q", "r"};
            const char* g[3] = {"gamma1", "gamma2", "gamma3"};
            for (int i = 0; i < 3; ++i) {
                BOOST_TEST(std::abs(result.value(w[i]) - state.omega[i]) < 1e-9);
                BOOST_TEST(std::abs(result.value(g[i]) - gamma[i]) < 1e-9);
            }
        }
        if (std::string(formulation) == "quaternion") {
            // The attitude itself, up to the quaternion's sign.
            const char* e[4] = {"e0", "e1", "e2", "e3"};
            double same = 0, opposite = 0;
            for (int k = 0; k < 4; ++k) {
                same = std::max(same, std::abs(result.value(e[k]) - state.quaternion[k]));
                opposite = std::max(opposite, std::abs(result.value(e[k]) + state.quaternion[k]));
            }
            BOOST_TEST(std::min(same, opposite) < 1e-9);
        }
    }
    // Hamilton's equations of the Euler-angle Lagrangian, (φ, θ, ψ, p_φ, p_θ, p_ψ): the same body,
    // its outputs ω and γ written through the momenta.
    const auto result = run("euler_angles", 3.0, true);
    const auto state = exact.at(3.0);
    const auto gamma = vertical(state.quaternion);
    BOOST_TEST(std::abs(result.value("r") - state.omega[2]) < 1e-9);
    BOOST_TEST(std::abs(result.value("gamma3") - gamma[2]) < 1e-9);
    BOOST_TEST(std::abs(result.value("p") - state.omega[0]) < 1e-9);
}
