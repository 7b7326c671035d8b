#include "mechanics/relative/carried_motion.hpp"

#include <algorithm>

#include "mechanics/kinematics/operators.hpp"
#include "mechanics/kinematics/rotations.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

// A free carrier's v_o or ω with each quasi-velocity replaced by its rate: the derivative.
Vec3 quasi_rates(const model::Model& model, const Vec3& v) {
    GiNaC::exmap rates;
    for (const auto& q : model.quasi_velocities) rates[q.symbol] = q.rate;
    return {v[0].subs(rates), v[1].subs(rates), v[2].subs(rates)};
}

}  // namespace

CarrierMotion carrier_motion(const model::Model& model) {
    CarrierMotion m;
    if (!model.carrier) return m;
    m.omega = model.carrier->angular_velocity;
    m.v_o = model.carrier->pole_velocity;
    const bool free = model.carrier->free;
    m.omega_dot = free ? quasi_rates(model, m.omega) : diff(m.omega, model.t);
    m.pole_acceleration = (free ? quasi_rates(model, m.v_o) : diff(m.v_o, model.t)) + cross(m.omega, m.v_o);
    return m;
}

bool has_rigid_bodies(const model::Model& model) {
    return std::any_of(model.particles.begin(), model.particles.end(), [](const model::Particle& p) { return p.rigid; });
}

EnergySplit rotational_energy(const model::Model& model, const Vec3& omega) {
    EnergySplit e{0, 0, 0};
    for (const auto& p : model.particles) {
        if (!p.rigid) continue;
        const BodyRotation rotation = body_rotation(model, p);
        const Vec3 carried = transpose_times(rotation.R, omega);
        const Vec3& rel = rotation.relative_angular_velocity;
        const Vec3 I_rel = times(p.inertia, rel);
        e.T_e += dot(carried, times(p.inertia, carried)) / 2;
        e.T_m += dot(carried, I_rel);
        e.T_r += dot(rel, I_rel) / 2;
    }
    return e;
}

std::vector<ParticleKinematics> particle_kinematics(const model::Model& model) {
    std::vector<ParticleKinematics> out;
    for (const auto& p : model.particles) {
        ParticleKinematics k{p.mass, p.position, diff(p.position, model.t), {}, zero_vector()};
        for (const auto& c : model.coordinates) {
            k.e.push_back(diff(p.position, c.q));
            k.r_dot = k.r_dot + c.q_dot * k.e.back();
        }
        k.a_rest = diff(k.r_dot, model.t);
        for (const auto& c : model.coordinates) k.a_rest = k.a_rest + c.q_dot * diff(k.r_dot, c.q);
        out.push_back(std::move(k));
    }
    return out;
}

EnergySplit split_kinetic_energy(const model::Model& model, const CarrierMotion& carrier,
                                 const std::vector<ParticleKinematics>& particles) {
    EnergySplit split = rotational_energy(model, carrier.omega);
    for (const auto& k : particles) {
        const Vec3 transport = carrier.v_o + cross(carrier.omega, k.r);  // velocity of the carrier point under the particle
        split.T_e += k.mass * dot(transport, transport) / 2;
        split.T_m += k.mass * dot(transport, k.r_dot);
        split.T_r += k.mass * dot(k.r_dot, k.r_dot) / 2;
    }
    // The carrier's own energy does not depend on q̇: it belongs to T_e. A prescribed carrier's is
    // a function of t alone and stays out of the Lagrangian (and its energy integrals).
    if (model.free_carrier()) split.T_e += carrier_own_energy(model, carrier);
    return split;
}

ex carrier_own_energy(const model::Model& model, const CarrierMotion& carrier) {
    if (!model.carrier) return 0;
    const auto& c = *model.carrier;
    const Vec3 Jw = times(c.inertia, carrier.omega);
    return c.mass * dot(carrier.v_o, carrier.v_o) / 2 + c.mass * dot(carrier.v_o, cross(carrier.omega, c.center)) +
           dot(carrier.omega, Jw) / 2;
}

CarrierMomenta carrier_momenta(const model::Model& model) {
    const auto& c = *model.carrier;
    const GiNaC::symbol V[3] = {GiNaC::symbol("V_1"), GiNaC::symbol("V_2"), GiNaC::symbol("V_3")};
    const GiNaC::symbol W[3] = {GiNaC::symbol("W_1"), GiNaC::symbol("W_2"), GiNaC::symbol("W_3")};
    model::Model placeholder = model;
    placeholder.carrier->pole_velocity = {V[0], V[1], V[2]};
    placeholder.carrier->angular_velocity = {W[0], W[1], W[2]};
    const CarrierMotion free_motion = carrier_motion(placeholder);
    const EnergySplit split = split_kinetic_energy(placeholder, free_motion, particle_kinematics(placeholder));
    ex T = split.T_e + split.T_m + split.T_r;
    if (!model.free_carrier()) T += carrier_own_energy(placeholder, free_motion);  // a free carrier's is in T_e
    GiNaC::exmap actual;
    for (int i = 0; i < 3; ++i) {
        actual[V[i]] = c.pole_velocity[std::size_t(i)];
        actual[W[i]] = c.angular_velocity[std::size_t(i)];
    }
    CarrierMomenta out;
    for (int i = 0; i < 3; ++i) {
        out.P[std::size_t(i)] = derivative(T, V[i]).subs(actual);
        out.K[std::size_t(i)] = derivative(T, W[i]).subs(actual);
    }
    return out;
}

CarrierBalance carrier_balance(const model::Model& model, const CarrierMomenta& momenta) {
    const Vec3& w = model.carrier->angular_velocity;
    const Vec3& v = model.carrier->pole_velocity;
    const Vec3 turning = cross(w, momenta.P), turning_K = cross(w, momenta.K) + cross(v, momenta.P);
    CarrierBalance out;
    for (std::size_t i = 0; i < 3; ++i) {
        out.force[i] = total_derivative(model, momenta.P[i]) + turning[i];
        out.moment[i] = total_derivative(model, momenta.K[i]) + turning_K[i];
    }
    return out;
}

EnergySplit split_kinetic_energy(const model::Model& model) {
    return split_kinetic_energy(model, carrier_motion(model), particle_kinematics(model));
}

}  // namespace eomc::mechanics
