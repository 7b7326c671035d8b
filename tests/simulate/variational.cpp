// `simulate` with the variational equations (kernels generated with --variational), against two
// theorems on the state-transition matrix Φ of the polar Kepler kernel over one orbit:
//  * Liouville for the Lagrangian state x = (r, φ, ṙ, φ̇): d ln det Φ/dt = tr ∂ẋ/∂x = ∂φ̈/∂φ̇
//    = −2ṙ/r, so det Φ(t) = (r0/r(t))² (phase volume is conserved in (q, p), and p_φ = r² φ̇).
//  * Symplecticity for the canonical state (r, φ, p_r, p_φ): Φᵀ J Φ = J.
// Dopri5 at rtol = atol = tol = 1e-12. Each accepted step maps (x, Φ) with a local error below
// √m·tol per component (m = 20 components of y, physics_support.hpp), so the step's map of the
// variations, Φ_k → (I + d_k) Φ_k, has |d_k| ≲ √m·tol. Then ln det Φ is off by Σ tr d_k ≤
// steps·n·√m·tol (n = 4), and Φᵀ J Φ − J by Σ Φ_kᵀ (d_kᵀ J + J d_k) Φ_k ≤ steps·2√m·tol·max|Φ|².
// Both bounds are computed from the run; a wrong Jacobian entry breaks them at O(1).
#define BOOST_TEST_MODULE simulate_variational
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <Eigen/Dense>

#include "codegen/cpp_emitter.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/simulate.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"
#include "support/diagnostic.hpp"

namespace {

using eomc::host::SimulationRequest;
using eomc::host::SimulationResult;

SimulationRequest kepler_request(bool hamiltonian) {
    std::ifstream in(EOMC_SOURCE_DIR "/scenes/kepler_orbit.toml");
    std::stringstream text;
    text << in.rdbuf();
    const auto model = eomc::model::build_model(eomc::scene::parse_scene_string(text.str(), "kepler_orbit.toml"));
    const auto eqs = eomc::mechanics::derive(model);
    const auto ir = hamiltonian ? eomc::codegen::lower(model, eomc::mechanics::canonical_equations(model, eqs).form)
                                : eomc::codegen::lower(model, eqs);
    SimulationRequest r;
    r.header_text = eomc::codegen::emit_header(ir, {EOMC_VERSION, true});
    r.struct_name = model.struct_name;
    r.t_end = 2 * M_PI;  // one period (a = 1, μ = 1)
    r.rtol = r.atol = 1e-12;
    r.cache_dir = std::string(EOMC_BINARY_DIR) + "/test-cache";
    r.progress = false;
    r.variational = true;
    return r;
}

Eigen::Matrix4d phi(const SimulationResult& r) {
    Eigen::Matrix4d m;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) m(i, j) = r.value("Phi_" + std::to_string(i) + "_" + std::to_string(j));
    return m;
}

}  // namespace

BOOST_AUTO_TEST_CASE(liouville_in_lagrangian_variables) {
    SimulationRequest req = kepler_request(false);
    for (const double t_end : {M_PI / 2, M_PI, 2 * M_PI}) {
        req.t_end = t_end;
        const SimulationResult r = eomc::host::simulate(req);
        const double r0 = 0.5, rt = r.value("r");
        const Eigen::Matrix4d P = phi(r);
        BOOST_TEST_MESSAGE("t = " << t_end << ": det Φ = " << P.determinant() << ", (r0/r)² = " << r0 * r0 / (rt * rt)
                                  << ", relative " << P.determinant() / (r0 * r0 / (rt * rt)) - 1 << ", |Φ| = "
                                  << P.cwiseAbs().maxCoeff() << ", steps " << r.steps);
        const double bound = double(r.steps) * 4 * std::sqrt(20.0) * 1e-12;
        BOOST_TEST(std::abs(P.determinant() / (r0 * r0 / (rt * rt)) - 1) <= bound);
        BOOST_TEST(P.cwiseAbs().maxCoeff() > 2.0);  // the shear of the period with energy: Φ is not near I
    }
}

BOOST_AUTO_TEST_CASE(symplectic_in_canonical_variables) {
    const SimulationResult r = eomc::host::simulate(kepler_request(true));
    const Eigen::Matrix4d P = phi(r);
    Eigen::Matrix4d J = Eigen::Matrix4d::Zero();
    J.topRightCorner<2, 2>().setIdentity();
    J.bottomLeftCorner<2, 2>() = -Eigen::Matrix2d::Identity();
    const double defect = (P.transpose() * J * P - J).cwiseAbs().maxCoeff();
    // Φ grows secularly (the period's shear with energy; in the Lagrangian run above its largest
    // entry is 15, 39 and 653 at T/4, T/2 and T), so the run's largest entry is the end's up to
    // the periodic part, which the factor 2 covers.
    const double largest = 2 * P.cwiseAbs().maxCoeff();
    const double bound = double(r.steps) * 2 * std::sqrt(20.0) * 1e-12 * largest * largest;
    BOOST_TEST_MESSAGE("|Φᵀ J Φ − J| = " << defect << ", bound " << bound << ", |Φ| = " << P.cwiseAbs().maxCoeff());
    BOOST_TEST(defect <= bound);
    BOOST_TEST(P.cwiseAbs().maxCoeff() > 2.0);
}

BOOST_AUTO_TEST_CASE(splitting_methods_cannot_carry_the_variational_equations) {
    SimulationRequest req = kepler_request(false);
    req.integrator = "verlet";
    BOOST_CHECK_THROW(eomc::host::simulate(req), eomc::InputError);
}
