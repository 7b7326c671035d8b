#include "host/rigid_bench.hpp"

#include <array>
#include <cmath>

#include "eomc/runtime/rigid/euler_poinsot.hpp"

#include "host/formulation_bench.hpp"
#include "host/pipeline.hpp"
#include "scene/scene.hpp"

namespace eomc::host {

namespace {

// The period 2π/|ω(0)| of a turn at the initial rate (0 at rest): the scale of the default step
// counts.
double turn_period(const model::Model& m) {
    if (!m.rigid) return 0.0;
    double w2 = 0.0;
    for (double w : m.rigid->omega0) w2 += w * w;
    return w2 > 0.0 ? 2.0 * M_PI / std::sqrt(w2) : 0.0;
}

// A free body (no weight, no rotor, principal axes) moves in closed form (Euler–Poinsot,
// runtime/rigid/euler_poinsot.hpp): (ω, γ) at t_end, at the parameters' defaults, for the axis to
// check its float128 reference against.
void add_free_body_solution(BenchRequest& r, const model::Model& m) {
    const model::RigidBody& body = *m.rigid;
    if (!body.principal || !body.weight.is_zero()) return;
    for (const auto& k : body.gyrostat)
        if (!k.is_zero()) return;
    const GiNaC::exmap defaults = m.parameter_defaults();
    std::array<double, 3> inertia{};
    for (unsigned i = 0; i < 3; ++i) {
        const GiNaC::ex v = body.inertia(i, i).subs(defaults).evalf();
        if (!GiNaC::is_a<GiNaC::numeric>(v)) return;
        inertia[i] = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
    }
    const auto exact = runtime::FreeRigidBody::from(inertia, body.omega0, body.attitude0).at(r.t_end);
    const auto& e = exact.quaternion;
    // γ = R(e)ᵀ e_Z, the third row of the attitude matrix.
    r.axis.exact = {exact.omega[0], exact.omega[1], exact.omega[2], 2 * (e[1] * e[3] - e[0] * e[2]),
                    2 * (e[2] * e[3] + e[0] * e[1]), e[0] * e[0] - e[1] * e[1] - e[2] * e[2] + e[3] * e[3]};
    r.axis.exact_source = "the exact Euler-Poinsot motion (Jacobi's elliptic functions; runtime/rigid/euler_poinsot.hpp)";
}

}  // namespace

void add_rigid_formulations(BenchRequest& r, const std::string& scene_path, const std::vector<std::string>& asked,
                            const std::string& rigid_formulation) {
    r.axis = FormulationAxis{};
    r.axis.reference = "euler_poisson";
    r.axis.judged = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};
    r.axis.judged_what = "(ω, γ)";
    r.axis.error_column = "omega_gamma_error";
    // The energy is the one integral every formulation's kernel carries (|γ|² and the area hold by
    // construction in some of them): the drift is measured on it alone, so that it compares.
    r.axis.drift_column = "max_energy_drift";
    r.axis.drift_invariants = {"energy"};
    r.axis.table_levels = {1e-3, 1e-6, 1e-9};
    r.axis.lost = "runs whose error exceeds |(ω, γ)|";
    const FormulationFamily rigid{scene::rigid_formulation_names, &FrontEndOptions::rigid_formulation,
                                  scene::check_rigid_formulation};
    const Pipeline euler_poisson = add_formulations(r, scene_path, rigid, asked, rigid_formulation);
    r.axis.period = turn_period(euler_poisson.model);
    add_free_body_solution(r, euler_poisson.model);
}

}  // namespace eomc::host
