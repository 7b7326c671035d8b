// The motion of what a carrier carries, in carrier axes: the carrier's own motion (ω, ω̇, v_o and
// the pole's acceleration), each carried particle's relative kinematics, and the split of the
// kinetic energy T = T_e + T_m + T_r by degree in q̇ (Mei, §1.1). Shared by the equations of
// relative motion and a free carrier's balance equations.
#pragma once

#include <cstddef>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"
#include "symbolic/vector3.hpp"

namespace eomc::mechanics {

using model::Vec3;

// Kinetic energy parts of carried particles and bodies; zero carrier motion when the model has
// no carrier.
struct EnergySplit {
    GiNaC::ex T_e, T_m, T_r;
};

// Kinematics of one carried particle, all in carrier axes.
struct ParticleKinematics {
    GiNaC::ex mass;
    Vec3 r;                 // r'
    Vec3 r_dot;             // ṙ' (relative velocity)
    std::vector<Vec3> e;    // e_s = ∂r'/∂q_s
    Vec3 a_rest;            // relative acceleration without the q̈ terms: a_r = Σ e_k q̈_k + a_rest
};

struct CarrierMotion {
    Vec3 omega = symbolic::zero_vector(), omega_dot = symbolic::zero_vector();
    Vec3 v_o = symbolic::zero_vector(), pole_acceleration = symbolic::zero_vector();  // v̇_o + ω × v_o
};

CarrierMotion carrier_motion(const model::Model& model);
std::vector<ParticleKinematics> particle_kinematics(const model::Model& model);

// Σ_i m_i w_i · e_is for each s, where w_i is the acceleration-like vector of one effect.
template <class PerParticle>
GiNaC::ex project(const std::vector<ParticleKinematics>& particles, std::size_t s, PerParticle w) {
    GiNaC::ex sum = 0;
    for (const auto& k : particles) sum += k.mass * symbolic::dot(w(k), k.e[s]);
    return sum;
}

bool has_rigid_bodies(const model::Model& model);

// The rigid bodies' rotational kinetic energy ½ Ωᵀ I Ω, Ω = Rᵀω + ω_rel in body axes, split by
// degree in q̇ as the particles' is: T_e = ½ (Rᵀω)ᵀI(Rᵀω), T_m = (Rᵀω)ᵀ I ω_rel,
// T_r = ½ ω_relᵀ I ω_rel. `omega` may be placeholder symbols.
EnergySplit rotational_energy(const model::Model& model, const Vec3& omega);

// T_e, T_m, T_r of the carried particles and bodies (and a free carrier's own energy, in T_e).
EnergySplit split_kinetic_energy(const model::Model& model, const CarrierMotion& carrier,
                                 const std::vector<ParticleKinematics>& particles);
EnergySplit split_kinetic_energy(const model::Model& model);

// The carrier's own kinetic energy ½ M v_o² + M v_o · (ω × ρ_C) + ½ ωᵀ J ω (J about o, ρ_C its
// mass centre); zero when the model gives the carrier no mass or inertia (Mei, (1.1.13)).
GiNaC::ex carrier_own_energy(const model::Model& model, const CarrierMotion& carrier);

// The whole system's momentum P = ∂T/∂v_o and angular momentum about o K = ∂T/∂ω (Mei,
// (1.1.14)–(1.1.15)), T the carried bodies' and the carrier's own kinetic energy: the derivatives
// are taken with every component of v_o and ω a free placeholder, then evaluated on the model's
// own v_o and ω (quasi-velocities, 0 for a held component, or the prescribed functions of t), so
// that a held or prescribed component still has its momentum.
struct CarrierMomenta {
    Vec3 P, K;
};
CarrierMomenta carrier_momenta(const model::Model& model);

// The inertial sides of the balance equations in carrier axes (Mei, (1.1.14)–(1.1.15)):
// force = dP/dt + ω × P, moment = dK/dt + ω × K + v_o × P, d/dt the total derivative along the
// motion (t, q, q̇ → q̈, quasi-velocities → their rates). They equal the external resultant V
// (1.1.17) and its moment m⁰ about o (1.1.24) on the carrier and everything it carries.
struct CarrierBalance {
    Vec3 force, moment;
};
CarrierBalance carrier_balance(const model::Model& model, const CarrierMomenta& momenta);

}  // namespace eomc::mechanics
