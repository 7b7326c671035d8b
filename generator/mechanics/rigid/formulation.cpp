#include "mechanics/rigid/formulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "mechanics/rigid/euler_poisson.hpp"
#include "mechanics/rigid/integrals.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/simplify.hpp"
#include "symbolic/vector3.hpp"

namespace eomc::mechanics::rigid {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

using K = RigidFormulationKind;

// In RigidFormulationKind order.
const std::array<RigidFormulation, 4> registry{{
    {K::euler_poisson, scene::name(K::euler_poisson),
     "Euler–Poisson: ω and the vertical γ in body axes, I ω̇ = K × ω + P γ × r_c, γ̇ = γ × ω; |γ| = 1 kept by "
     "project()",
     euler_poisson_form, false, false},
    {K::quaternion, scene::name(K::quaternion),
     "ω and the attitude quaternion e (body → space), ė = ½ e ⊗ (0, ω), γ = R(e)ᵀ e_Z/|e|²; |e| = 1 kept by project()",
     quaternion_form, false, false},
    {K::euler_angles, scene::name(K::euler_angles),
     "Lagrange's equations in the ZXZ Euler angles φ, θ, ψ (singular at sin θ = 0, gimbal lock)", euler_angles_form,
     true, true},
    {K::andoyer_deprit, scene::name(K::andoyer_deprit),
     "Andoyer–Deprit canonical variables (l, g, h, L, G, H) by Hamilton's equations (singular at L = ±G, H = ±G)",
     andoyer_deprit_form, false, true},
}};

// What every formulation adds once ω(x) and γ(x) are known: the outputs p, q, r, gamma1..3 that
// are not state variables, the integrals and the events in the state, and an integral that the
// variables keep identically (|γ|² = 1 where γ is computed from an attitude) dropped.
void complete(const model::Model& model, const Equations& eqs, const GiNaC::exmap& body_of_state, FirstOrderForm& form) {
    const model::RigidBody& body = *model.rigid;
    const char* names[6] = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};
    for (std::size_t i = 0; i < 6; ++i) {
        const GiNaC::symbol& s = i < 3 ? body.omega[i] : body.gamma[i - 3];
        if (body_of_state.count(s)) form.outputs.push_back({names[i], s.subs(body_of_state)});
    }
    for (const auto& inv : eqs.invariants) {
        const ex value = inv.value.subs(body_of_state);
        if (!GiNaC::is_a<GiNaC::numeric>(simplified(value))) form.invariants.push_back({inv.name, value, inv.description});
    }
    for (const auto& e : model.events) form.events.push_back({e.name, e.when.subs(body_of_state), e.direction, e.terminal});
}

// A state of explicit rates only (no velocity block).
void set_state(FirstOrderForm& form, const std::vector<StateComponent>& state, const std::vector<ex>& rates) {
    form.state = state;
    form.n_coordinates = state.size();
    form.velocity_offset = state.size();
    form.mass_matrix = GiNaC::matrix(0, 0);
    for (std::size_t j = 0; j < rates.size(); ++j) form.explicit_rates.emplace_back(j, rates[j]);
}

// With programs (Mei §3.2): ω becomes the velocity block, solved from I ω̇ = f + D λ, Ā ω̇ = c by
// the control chapter's kernel (mechanics/control), the other components keep their explicit
// rates. `body_of_state` writes γ in the state (the quaternion's), empty when γ is a state.
void add_programs(const Equations& eqs, const GiNaC::exmap& body_of_state, const model::RigidBody& body,
                  FirstOrderForm& form) {
    if (eqs.programs.empty()) return;
    const char* names[3] = {"p_dot", "q_dot", "r_dot"};
    for (std::size_t i = 0; i < 3; ++i) form.velocity_rates.push_back({names[i], body.omega_rate[i], 0.0});
    form.velocity_offset = 0;
    form.mass_matrix = eqs.mass_matrix;
    for (const auto& f : eqs.forcing) form.forcing.push_back(f.subs(body_of_state));
    form.explicit_rates.erase(form.explicit_rates.begin(), form.explicit_rates.begin() + 3);
    form.programs = eqs.programs;
    for (auto& p : form.programs) {
        p.row.position = p.row.position.subs(body_of_state);
        p.row.velocity = p.row.velocity.subs(body_of_state);
        p.row.bias = p.row.bias.subs(body_of_state);
        p.target = p.target.subs(body_of_state);
        for (auto& w : p.row.W) w = w.subs(body_of_state);
        for (auto& column : p.columns)
            for (auto& d : column) d = d.subs(body_of_state);
    }
    // The free body's ω̇ no longer describes the motion: the kernel solves for it.
    std::erase_if(form.derivation, [](const NamedExpression& e) { return e.name == "dp/dt" || e.name == "dq/dt" || e.name == "dr/dt"; });
    form.redundant_programs = eqs.redundant_programs;
}

}  // namespace

const RigidFormulation& rigid_formulation(RigidFormulationKind kind) { return registry[static_cast<std::size_t>(kind)]; }
std::span<const RigidFormulation> rigid_formulations() { return registry; }

FirstOrderForm euler_poisson_form(const model::Model& model, const Equations& eqs) {
    const model::RigidBody& body = *model.rigid;
    const EulerPoisson s = euler_poisson(body);
    FirstOrderForm form;
    form.description = "The Euler-Poisson equations of a heavy rigid body about a fixed point: x = (ω, γ) in body axes, "
                       "I ω̇ = (Iω + k) × ω + P γ × r_c, γ̇ = γ × ω; project() keeps |γ| = 1.";
    const char* names[6] = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};
    std::vector<StateComponent> state;
    for (std::size_t i = 0; i < 3; ++i) state.push_back({names[i], body.omega[i], body.omega0[i]});
    for (std::size_t i = 0; i < 3; ++i) state.push_back({names[3 + i], body.gamma[i], body.vertical0[i]});
    set_state(form, state, {s.omega_rate[0], s.omega_rate[1], s.omega_rate[2], s.gamma_rate[0], s.gamma_rate[1],
                            s.gamma_rate[2]});
    form.unit_vectors.push_back(3);
    for (std::size_t i = 0; i < 3; ++i) form.derivation.push_back({fmt::format("d{}/dt", names[i]), s.omega_rate[i]});
    for (std::size_t i = 0; i < 3; ++i) form.derivation.push_back({fmt::format("d{}/dt", names[3 + i]), s.gamma_rate[i]});
    complete(model, eqs, {}, form);
    add_programs(eqs, {}, body, form);
    return form;
}

FirstOrderForm quaternion_form(const model::Model& model, const Equations& eqs) {
    const model::RigidBody& body = *model.rigid;
    FirstOrderForm form;
    form.description = "Euler's equations with the attitude quaternion e (body to space): x = (ω, e), I ω̇ = (Iω + k) "
                       "× ω + P γ × r_c, ė = ½ e ⊗ (0, ω), γ = R(e)ᵀ e_Z/|e|²; project() keeps |e| = 1.";
    // The model's own symbols, which attitude programs and events may hold.
    const auto& [e0, e1, e2, e3] = body.attitude.value();
    const ex n2 = e0 * e0 + e1 * e1 + e2 * e2 + e3 * e3;
    // The third row of R(e), divided by |e|²: exactly the unit vertical for any |e| ≠ 0.
    const Vec3 gamma{2 * (e1 * e3 - e0 * e2) / n2, 2 * (e2 * e3 + e0 * e1) / n2,
                     (e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3) / n2};
    GiNaC::exmap to_state;
    for (std::size_t i = 0; i < 3; ++i) to_state[body.gamma[i]] = gamma[i];
    const EulerPoisson s = euler_poisson(body);
    std::vector<StateComponent> state;
    const char* names[3] = {"p", "q", "r"};
    for (std::size_t i = 0; i < 3; ++i) state.push_back({names[i], body.omega[i], body.omega0[i]});
    const GiNaC::symbol es[4] = {e0, e1, e2, e3};
    for (std::size_t k = 0; k < 4; ++k) state.push_back({es[k].get_name(), es[k], body.attitude0[k]});
    std::vector<ex> rates{s.omega_rate[0].subs(to_state), s.omega_rate[1].subs(to_state), s.omega_rate[2].subs(to_state)};
    const auto kinematics = body.attitude_rates();  // γ̇ (three), then ė = ½ e ⊗ (0, ω) (four)
    for (std::size_t k = 3; k < 7; ++k) rates.push_back(kinematics[k].second);
    set_state(form, state, rates);
    form.unit_quaternions.push_back(3);
    for (std::size_t i = 0; i < 3; ++i) form.derivation.push_back({fmt::format("gamma{}", i + 1), gamma[i]});
    complete(model, eqs, to_state, form);
    add_programs(eqs, to_state, body, form);
    return form;
}

FirstOrderForm euler_angles_form(const model::Model& model, const Equations& eqs) {
    const model::RigidBody& body = *model.rigid;
    FirstOrderForm form = lagrange_form(model, eqs);
    form.description = "Lagrange's equations of the heavy rigid body in the ZXZ Euler angles (φ precession, θ nutation, "
                       "ψ spin), x = (φ, θ, ψ, φ̇, θ̇, ψ̇); M is singular at sin θ = 0 (gimbal lock).";
    // The events are stated in p, q, r, gamma1..3: written in the angles, as the outputs.
    form.events.clear();
    for (const auto& e : model.events)
        form.events.push_back({e.name, e.when.subs(body.in_angles), e.direction, e.terminal});
    const char* names[6] = {"p", "q", "r", "gamma1", "gamma2", "gamma3"};
    for (std::size_t i = 0; i < 6; ++i)
        form.outputs.push_back({names[i], (i < 3 ? body.omega[i] : body.gamma[i - 3]).subs(body.in_angles)});
    return form;
}

// Hamilton's equations of 𝓗 = ½ (K − k)·I⁻¹(K − k) + P r_c·γ in the Andoyer–Deprit variables
// (runtime/rigid/andoyer_deprit.hpp has the frames; Deprit, Am. J. Phys. 35 (1967) 424, eq. 20).
FirstOrderForm andoyer_deprit_form(const model::Model& model, const Equations& eqs) {
    const model::RigidBody& body = *model.rigid;
    FirstOrderForm form;
    form.description = "Hamilton's equations of the heavy rigid body in the Andoyer-Deprit variables (l, g, h, L, G, "
                       "H): G = |K|, L = K·e3, H = K·e_Z; singular at L = ±G and H = ±G.";
    const GiNaC::symbol l("l"), g("g"), h("h"), L("L"), G("G"), H("H");
    const ex s1 = GiNaC::sqrt(G * G - L * L) / G, c1 = L / G, s2 = GiNaC::sqrt(G * G - H * H) / G, c2 = H / G;
    const Vec3 K{G * s1 * sin(l), G * s1 * cos(l), L};
    // γ = R_z(l)ᵀ R_x(I1)ᵀ R_z(g)ᵀ (0, sin I2, cos I2).
    const Vec3 u{s2 * sin(g), s2 * cos(g), c2};
    const Vec3 v{u[0], c1 * u[1] + s1 * u[2], -s1 * u[1] + c1 * u[2]};
    const Vec3 gamma{cos(l) * v[0] + sin(l) * v[1], -sin(l) * v[0] + cos(l) * v[1], v[2]};
    const GiNaC::matrix inverse = body.inertia.inverse();
    Vec3 omega = times(inverse, K - body.gyrostat);
    for (auto& w : omega) w = normalized(w);
    const ex hamiltonian = dot(K - body.gyrostat, omega) / 2 + body.weight * dot(body.center, gamma);
    const GiNaC::symbol q[3] = {l, g, h}, p[3] = {L, G, H};
    std::vector<ex> rates(6);
    for (std::size_t j = 0; j < 3; ++j) {
        rates[j] = derivative(hamiltonian, p[j]);
        rates[3 + j] = -derivative(hamiltonian, q[j]);
    }
    const auto& a = body.andoyer0;  // the model's, at the defaults
    set_state(form, {{"l", l, a[0]}, {"g", g, a[1]}, {"h", h, a[2]}, {"L", L, a[3]}, {"G", G, a[4]}, {"H", H, a[5]}},
              rates);
    form.derivation.push_back({"Hamiltonian", hamiltonian});
    GiNaC::exmap to_state;
    for (std::size_t i = 0; i < 3; ++i) to_state[body.omega[i]] = omega[i], to_state[body.gamma[i]] = gamma[i];
    complete(model, eqs, to_state, form);
    add_programs(eqs, to_state, body, form);
    return form;
}

}  // namespace eomc::mechanics::rigid
