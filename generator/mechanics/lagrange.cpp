#include "mechanics/lagrange.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "mechanics/differentiation.hpp"
#include "mechanics/newtonian.hpp"
#include "mechanics/numeric_probe.hpp"
#include "mechanics/vector3.hpp"
#include "support/diagnostic.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using model::Effect;

ex total_derivative(const model::Model& model, const ex& F) {
    ex d = derivative(F, model.t);
    for (const auto& c : model.coordinates) d += derivative(F, c.q) * c.q_dot + derivative(F, c.q_dot) * c.q_ddot;
    return d;
}

ex euler_operator(const model::Model& model, const ex& F, std::size_t s) {
    const auto& c = model.coordinates.at(s);
    return total_derivative(model, derivative(F, c.q_dot)) - derivative(F, c.q);
}

namespace {

// Kinematics of one carried particle, all in carrier axes.
struct ParticleKinematics {
    ex mass;
    Vec3 r;                 // r'
    Vec3 r_dot;             // ṙ' (relative velocity)
    std::vector<Vec3> e;    // e_s = ∂r'/∂q_s
    Vec3 a_rest;            // relative acceleration without the q̈ terms: a_r = Σ e_k q̈_k + a_rest
};

struct CarrierMotion {
    Vec3 omega = zero_vector(), omega_dot = zero_vector();
    Vec3 v_o = zero_vector(), pole_acceleration = zero_vector();  // v̇_o + ω × v_o
};

CarrierMotion carrier_motion(const model::Model& model) {
    CarrierMotion m;
    if (!model.carrier) return m;
    m.omega = model.carrier->angular_velocity;
    m.v_o = model.carrier->pole_velocity;
    m.omega_dot = diff(m.omega, model.t);
    m.pole_acceleration = diff(m.v_o, model.t) + cross(m.omega, m.v_o);
    return m;
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

// Σ_i m_i w_i · e_is for each s, where w_i is the acceleration-like vector of one effect.
template <class PerParticle>
ex project(const std::vector<ParticleKinematics>& particles, std::size_t s, PerParticle w) {
    ex sum = 0;
    for (const auto& k : particles) sum += k.mass * dot(w(k), k.e[s]);
    return sum;
}

ex effect_term(Effect effect, const model::Model& model, const CarrierMotion& carrier,
               const std::vector<ParticleKinematics>& particles, std::size_t s) {
    switch (effect) {
        case Effect::relative:
            return project(particles, s, [&](const ParticleKinematics& k) {
                Vec3 a = k.a_rest;
                for (std::size_t j = 0; j < model.coordinates.size(); ++j) a = a + model.coordinates[j].q_ddot * k.e[j];
                return a;
            });
        case Effect::translation:
            return project(particles, s, [&](const ParticleKinematics&) { return carrier.pole_acceleration; });
        case Effect::euler:
            return project(particles, s, [&](const ParticleKinematics& k) { return cross(carrier.omega_dot, k.r); });
        case Effect::centrifugal:
            return project(particles, s,
                           [&](const ParticleKinematics& k) { return cross(carrier.omega, cross(carrier.omega, k.r)); });
        case Effect::coriolis:
            return project(particles, s,
                           [&](const ParticleKinematics& k) { return ex(2) * cross(carrier.omega, k.r_dot); });
    }
    return 0;
}

// The Jacobi-type integral of the kept equations (FORMULAS §1): for the full equations
// h = Σ q̇_s ∂L/∂q̇_s − L (= T_r − T_e + V for a steadily moving carrier). When effects are
// dropped, the kept ones that are potential-like (centrifugal and translation under steady
// carrier motion) contribute their potentials and coriolis contributes nothing (no work).
// Whether h is actually conserved is proven afterwards, never assumed.
ex jacobi_candidate(const model::Model& model, const Equations& eqs, const CarrierMotion& carrier,
                    const std::vector<ParticleKinematics>& particles) {
    // Σ q̇_s ∂F/∂q̇_s − F, with ∂T/∂q̇_s already known (eq.dT_dqdot) for the kinetic part.
    auto legendre_V = [&] {
        ex h = eqs.V;
        for (const auto& c : model.coordinates) h -= c.q_dot * derivative(eqs.V, c.q_dot);
        return h;
    };
    const bool all_kept = std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; });
    if (!eqs.from_particles || !eqs.has_carrier || all_kept) {
        ex h = legendre_V() - eqs.T;
        for (std::size_t s = 0; s < model.coordinates.size(); ++s)
            h += model.coordinates[s].q_dot * eqs.equations[s].dT_dqdot;
        return h;
    }
    ex h = legendre_V() - eqs.T_r;
    for (std::size_t s = 0; s < model.coordinates.size(); ++s)
        h += model.coordinates[s].q_dot * project(particles, s, [](const ParticleKinematics& k) { return k.r_dot; });
    for (const auto& k : particles) {
        if (model.keeps(Effect::centrifugal)) h -= k.mass * dot(cross(carrier.omega, k.r), cross(carrier.omega, k.r)) / 2;
        if (model.keeps(Effect::translation)) h += k.mass * dot(carrier.pole_acceleration, k.r);
    }
    return h;
}

// dh/dt − Σ q̇_s (lhs_s − rhs_s) vanishes identically iff h is conserved along every motion
// (the equations are linear in q̈, so this is an identity in q̈ too). Probed at random
// points with a relative tolerance far above round-off and far below any real residual.
bool proven_conserved(const model::Model& model, const Equations& eqs, const ex& h) {
    ex power = 0;
    for (std::size_t s = 0; s < eqs.equations.size(); ++s)
        power += model.coordinates[s].q_dot * (eqs.equations[s].lhs - eqs.equations[s].rhs);
    for (const auto& point : probe_points(model, 6)) {
        const double a = evaluate_rate(h, point), b = evaluate(power, point);
        if (!std::isfinite(a) || !std::isfinite(b)) return false;
        if (std::abs(a - b) > 1e-9 * (1.0 + std::abs(a) + std::abs(b))) return false;
    }
    return true;
}

// M must be regular for the equations to be solvable for q̈. Checked numerically at
// several random states with the default parameters; singular at all of them means
// singular as a function (a degenerate kinetic energy), not an unlucky point.
void require_regular_mass_matrix(const model::Model& model, const GiNaC::matrix& M) {
    const std::size_t n = model.coordinates.size();
    const auto points = probe_points_at_defaults(model, 3, 0xa55e55);
    Eigen::VectorXd null_direction;
    for (const auto& point : points) {
        Eigen::MatrixXd A(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) A(i, j) = evaluate(M(i, j), point);
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
        const Eigen::VectorXd lambda = eig.eigenvalues().cwiseAbs();
        Eigen::Index k = 0;
        lambda.minCoeff(&k);
        const double scale = lambda.maxCoeff();
        if (scale > 0 && lambda(k) > 1e-12 * scale) return;  // regular here, so regular as a function
        null_direction = eig.eigenvectors().col(k);
    }
    std::string names;
    for (std::size_t i = 0; i < n; ++i) {
        if (null_direction.size() == 0 || std::abs(null_direction(Eigen::Index(i))) > 1e-6) {
            names += (names.empty() ? "'" : ", '") + model.coordinates[i].name + "'";
        }
    }
    throw InputError(model.kinetic_pos,
                     fmt::format("the mass matrix ∂²T/∂q̇∂q̇ is singular: the kinetic energy does not determine the "
                                 "accelerations of {} (check that every coordinate moves some mass, and that "
                                 "[effects] keeps \"relative\")",
                                 names));
}

}  // namespace

namespace {

EnergySplit split_kinetic_energy(const CarrierMotion& carrier, const std::vector<ParticleKinematics>& particles) {
    EnergySplit split{0, 0, 0};
    for (const auto& k : particles) {
        const Vec3 transport = carrier.v_o + cross(carrier.omega, k.r);  // velocity of the carrier point under the particle
        split.T_e += k.mass * dot(transport, transport) / 2;
        split.T_m += k.mass * dot(transport, k.r_dot);
        split.T_r += k.mass * dot(k.r_dot, k.r_dot) / 2;
    }
    return split;
}

}  // namespace

EnergySplit split_kinetic_energy(const model::Model& model) {
    return split_kinetic_energy(carrier_motion(model), particle_kinematics(model));
}

Equations derive(const model::Model& model) {
    if (model.newtonian) return derive_newtonian(model);  // equations given, not energies
    Equations eqs;
    const std::size_t n = model.coordinates.size();
    eqs.from_particles = !model.particles.empty();
    eqs.has_carrier = model.carrier.has_value();
    eqs.V = model.potential;

    const CarrierMotion carrier = carrier_motion(model);
    const auto particles = particle_kinematics(model);
    if (eqs.from_particles) {
        const EnergySplit split = split_kinetic_energy(carrier, particles);
        eqs.T_e = split.T_e;
        eqs.T_m = split.T_m;
        eqs.T_r = split.T_r;
        eqs.T = split.T_e + split.T_m + split.T_r;
    } else {
        eqs.T = *model.kinetic_energy;
        eqs.T_e = eqs.T_m = eqs.T_r = 0;
    }

    for (std::size_t s = 0; s < n; ++s) {
        Equation eq;
        eq.coordinate = model.coordinates[s].name;
        // ∂T/∂q̇_s = Σ m v·e_s with v the absolute velocity (by projection, not by
        // differentiating the expanded T); for a given Lagrangian, by differentiation.
        eq.dT_dqdot = eqs.from_particles ? project(particles, s,
                                                   [&](const ParticleKinematics& k) {
                                                       return carrier.v_o + cross(carrier.omega, k.r) + k.r_dot;
                                                   })
                                         : derivative(eqs.T, model.coordinates[s].q_dot);
        eq.rhs = model.generalized_forces[s] + euler_operator(model, eqs.V, s);  // ε_s(V) = −∂V/∂q_s for V(q)
        if (eqs.from_particles) {
            eq.lhs = 0;
            for (Effect effect : model::all_effects) {
                if (!model.keeps(effect)) continue;
                if (!eqs.has_carrier && effect != Effect::relative) continue;  // inertial frame: nothing else exists
                const ex term = effect_term(effect, model, carrier, particles, s);
                eq.effects.push_back({effect, term});
                eq.lhs += term;
            }
        } else {
            eq.lhs = euler_operator(model, eqs.T, s);
        }
        eqs.equations.push_back(std::move(eq));
    }

    // M q̈ = f from E_s = lhs_s − rhs_s, which is linear in q̈. For particles the q̈ terms
    // are known by construction (only the relative effect has them: M_sk = Σ m e_k·e_s), so
    // M and f are assembled directly instead of differentiating and substituting large sums.
    GiNaC::exmap no_acceleration;
    for (const auto& c : model.coordinates) no_acceleration[c.q_ddot] = 0;
    eqs.mass_matrix = GiNaC::matrix(unsigned(n), unsigned(n));
    const bool direct = eqs.from_particles && model.keeps(Effect::relative);
    for (std::size_t s = 0; s < n; ++s) {
        const Equation& eq = eqs.equations[s];
        ex inertial_rest = 0;  // the inertial side without its q̈ terms
        if (direct) {
            for (const auto& term : eq.effects)
                inertial_rest += term.effect == Effect::relative
                                     ? project(particles, s, [](const ParticleKinematics& k) { return k.a_rest; })
                                     : term.value;
        }
        const ex E = direct ? eq.rhs : eq.lhs - eq.rhs;  // what still needs q̈ extracted by differentiation
        const bool rhs_has_acceleration = [&] {
            for (const auto& c : model.coordinates)
                if (E.has(c.q_ddot)) return true;
            return false;
        }();
        for (std::size_t k = 0; k < n; ++k) {
            ex m_sk = 0;
            if (direct) {
                for (const auto& p : particles) m_sk += p.mass * dot(p.e[k], p.e[s]);
                if (rhs_has_acceleration) m_sk -= derivative(E, model.coordinates[k].q_ddot);
            } else {
                m_sk = derivative(E, model.coordinates[k].q_ddot);
            }
            eqs.mass_matrix(unsigned(s), unsigned(k)) = m_sk;
        }
        eqs.forcing.push_back(direct ? (rhs_has_acceleration ? E.subs(no_acceleration) : E) - inertial_rest
                                     : -E.subs(no_acceleration));
    }
    require_regular_mass_matrix(model, eqs.mass_matrix);

    const ex h = jacobi_candidate(model, eqs, carrier, particles);
    if (proven_conserved(model, eqs, h)) {
        eqs.invariants.push_back(
            {"energy", h,
             !eqs.has_carrier ? "h = Σ q̇ ∂L/∂q̇ − L, the Jacobi integral (T + V when T is quadratic in q̇)"
             : std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; })
                 ? "Jacobi integral h = Σ q̇ ∂L/∂q̇ − L = T_r − T_e + V"
                 : "Jacobi integral of the kept equations"});
    }
    return eqs;
}

}  // namespace eomc::mechanics
