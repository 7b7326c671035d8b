#include "mechanics/lagrange.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
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
    for (const auto& v : model.quasi_velocities) d += derivative(F, v.symbol) * v.rate;
    return d;
}

namespace {

// Elementary rotation about a body axis by `angle`: carrier components = R · body components.
GiNaC::matrix elementary_rotation(char axis, const ex& angle) {
    const ex c = GiNaC::cos(angle), s = GiNaC::sin(angle);
    switch (axis) {
        case 'x': return GiNaC::matrix(3, 3, GiNaC::lst{1, 0, 0, 0, c, -s, 0, s, c});
        case 'y': return GiNaC::matrix(3, 3, GiNaC::lst{c, 0, s, 0, 1, 0, -s, 0, c});
        default: return GiNaC::matrix(3, 3, GiNaC::lst{c, -s, 0, s, c, 0, 0, 0, 1});
    }
}

}  // namespace

// The relative angular velocity chain-wise, Σ_k (R_{k+1} … R_m)ᵀ θ̇_k e_k: each angle's rate
// about its own axis, carried into the final body axes (no simplification of RᵀṘ needed).
BodyRotation body_rotation(const model::Model& model, const model::Particle& body) {
    BodyRotation out{GiNaC::ex_to<GiNaC::matrix>(GiNaC::unit_matrix(3)), {0, 0, 0}};
    std::vector<GiNaC::matrix> R;
    for (const auto& [axis, angle] : body.orientation) {
        R.push_back(elementary_rotation(axis, angle));
        out.R = out.R.mul(R.back());
    }
    for (std::size_t k = 0; k < R.size(); ++k) {
        const auto& [axis, angle] = body.orientation[k];
        const ex rate = total_derivative(model, angle);  // the angle depends on q and t only
        Vec3 term{axis == 'x' ? rate : 0, axis == 'y' ? rate : 0, axis == 'z' ? rate : 0};
        for (std::size_t j = k + 1; j < R.size(); ++j) term = transpose_times(R[j], term);
        out.relative_angular_velocity = out.relative_angular_velocity + term;
    }
    return out;
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

// A free carrier's v_o or ω with each quasi-velocity replaced by its rate: the derivative.
Vec3 quasi_rates(const model::Model& model, const Vec3& v) {
    GiNaC::exmap rates;
    for (const auto& q : model.quasi_velocities) rates[q.symbol] = q.rate;
    return {v[0].subs(rates), v[1].subs(rates), v[2].subs(rates)};
}

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

// The rigid bodies' rotational kinetic energy ½ Ωᵀ I Ω, Ω = Rᵀω + ω_rel in body axes, split
// by degree in q̇ as the particles' is (FORMULAS §1): T_e = ½ (Rᵀω)ᵀI(Rᵀω), T_m = (Rᵀω)ᵀ I ω_rel,
// T_r = ½ ω_relᵀ I ω_rel. `omega` may be placeholder symbols.
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

// The rigid bodies' share of each effect, one entry per equation s. ε_s(T_r) is the relative
// effect and ε_s(T_e) = −∂T_e/∂q_s the centrifugal one; ε_s(T_m) splits into the part from the
// change of ω (euler: d/dt acting on ω) and the rest (coriolis, linear in q̇ and ω). To tell them
// apart ω is a placeholder W while differentiating, then W → ω and Ẇ → ω̇.
struct RotationalEffects {
    ex relative = 0, euler = 0, centrifugal = 0, coriolis = 0;
};

std::vector<RotationalEffects> rotational_effects(const model::Model& model, const CarrierMotion& carrier) {
    std::vector<RotationalEffects> effects(model.coordinates.size());
    if (!has_rigid_bodies(model)) return effects;
    const EnergySplit actual = rotational_energy(model, carrier.omega);
    const GiNaC::symbol W[3] = {GiNaC::symbol("W_1"), GiNaC::symbol("W_2"), GiNaC::symbol("W_3")};
    const GiNaC::symbol W_dot[3] = {GiNaC::symbol("W_dot_1"), GiNaC::symbol("W_dot_2"), GiNaC::symbol("W_dot_3")};
    const ex T_m = rotational_energy(model, {W[0], W[1], W[2]}).T_m;
    GiNaC::exmap back;
    for (int i = 0; i < 3; ++i) {
        back[W[i]] = carrier.omega[std::size_t(i)];
        back[W_dot[i]] = carrier.omega_dot[std::size_t(i)];
    }
    for (std::size_t s = 0; s < effects.size(); ++s) {
        RotationalEffects& r = effects[s];
        r.relative = euler_operator(model, actual.T_r, s);
        if (!model.carrier) continue;
        r.centrifugal = euler_operator(model, actual.T_e, s);
        const ex A = derivative(T_m, model.coordinates[s].q_dot);
        ex euler = 0;
        for (int i = 0; i < 3; ++i) euler += W_dot[i] * derivative(A, W[i]);
        r.euler = euler.subs(back);
        r.coriolis = (total_derivative(model, A) - derivative(T_m, model.coordinates[s].q)).subs(back);
    }
    return effects;
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

// The particles' share of an effect (the rigid bodies' rotation adds RotationalEffects).
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

ex rotational_share(Effect effect, const RotationalEffects& r) {
    switch (effect) {
        case Effect::relative: return r.relative;
        case Effect::translation: return 0;
        case Effect::euler: return r.euler;
        case Effect::centrifugal: return r.centrifugal;
        case Effect::coriolis: return r.coriolis;
    }
    return 0;
}

// The Jacobi-type integral of the kept equations (FORMULAS §1): for the full equations
// h = Σ u ∂L/∂u − L over all velocities (q̇ and a free carrier's quasi-velocities), which is
// T_r − T_e + V for a steadily moving carrier and T + V for a free one. When effects are
// dropped, the kept ones that are potential-like (centrifugal and translation under steady
// carrier motion) contribute their potentials and coriolis contributes nothing (no work).
// Whether h is actually conserved is proven afterwards, never assumed.
ex jacobi_candidate(const model::Model& model, const Equations& eqs, const CarrierMotion& carrier,
                    const std::vector<ParticleKinematics>& particles) {
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
        for (const auto& v : model.quasi_velocities) h += v.symbol * derivative(eqs.T, v.symbol);
        return h;
    }
    const EnergySplit rotation = rotational_energy(model, carrier.omega);
    // Σ q̇ ∂T_r/∂q̇ − T_r = T_r: the particles' part by projection, the rotation's directly.
    ex h = legendre_V() - eqs.T_r + 2 * rotation.T_r;
    for (std::size_t s = 0; s < model.coordinates.size(); ++s)
        h += model.coordinates[s].q_dot * project(particles, s, [](const ParticleKinematics& k) { return k.r_dot; });
    if (model.keeps(Effect::centrifugal)) h -= rotation.T_e;
    for (const auto& k : particles) {
        if (model.keeps(Effect::centrifugal)) h -= k.mass * dot(cross(carrier.omega, k.r), cross(carrier.omega, k.r)) / 2;
        if (model.keeps(Effect::translation)) h += k.mass * dot(carrier.pole_acceleration, k.r);
    }
    return h;
}

// The velocities u (q̇, then the quasi-velocities) with the residual E = lhs − rhs of the
// equation each one's rate comes from.
std::vector<std::pair<ex, ex>> velocity_residuals(const model::Model& model, const Equations& eqs) {
    std::vector<std::pair<ex, ex>> out;
    for (std::size_t s = 0; s < eqs.equations.size(); ++s)
        out.emplace_back(model.coordinates[s].q_dot, eqs.equations[s].lhs - eqs.equations[s].rhs);
    for (const auto& v : model.quasi_velocities)
        for (const auto& c : eqs.carrier_equations)
            if (c.quasi_velocity == v.name) out.emplace_back(v.symbol, c.lhs - c.applied);
    return out;
}

// dh/dt − Σ u_s E_s vanishes identically iff h is conserved along every motion (the
// equations are linear in u̇, so this is an identity in u̇ too). Probed at random points with
// a relative tolerance far above round-off and far below any real residual.
bool proven_conserved(const model::Model& model, const Equations& eqs, const ex& h) {
    ex power = 0;
    for (const auto& [u, E] : velocity_residuals(model, eqs)) power += u * E;
    for (const auto& point : probe_points(model, 6)) {
        const double a = evaluate_rate(h, point), b = evaluate(power, point);
        if (!std::isfinite(a) || !std::isfinite(b)) return false;
        if (std::abs(a - b) > 1e-9 * (1.0 + std::abs(a) + std::abs(b))) return false;
    }
    return true;
}


// Whether h(t, q, q̇) is constant along the solutions: at random states q̈ is solved from
// M q̈ = f numerically and dh/dt must vanish there, relative to the size of its terms
// (round-off), far below any real rate. For coordinates without quasi-velocities only.
bool proven_constant(const model::Model& model, const Equations& eqs, const ex& h) {
    const std::size_t n = model.coordinates.size();
    if (!model.quasi_velocities.empty()) return false;
    for (auto point : probe_points(model, 6, 0xc0457)) {
        Eigen::MatrixXd M(n, n);
        Eigen::VectorXd f(n);
        for (std::size_t i = 0; i < n; ++i) {
            f(Eigen::Index(i)) = evaluate(eqs.forcing[i], point);
            for (std::size_t j = 0; j < n; ++j) M(Eigen::Index(i), Eigen::Index(j)) = evaluate(eqs.mass_matrix(unsigned(i), unsigned(j)), point);
        }
        const Eigen::VectorXd a = M.fullPivLu().solve(f);
        double scale = 0;
        for (std::size_t s = 0; s < n; ++s) {
            const auto& c = model.coordinates[s];
            point.values[c.q_ddot] = a(Eigen::Index(s));
            point.rates[c.q_dot] = a(Eigen::Index(s));
            scale += std::abs(evaluate(derivative(h, c.q), point) * point.values[c.q_dot]) +
                     std::abs(evaluate(derivative(h, c.q_dot), point) * a(Eigen::Index(s)));
        }
        scale += std::abs(evaluate(derivative(h, model.t), point));
        const double rate = evaluate_rate(h, point);
        if (!std::isfinite(rate) || !std::isfinite(scale) || std::abs(rate) > 1e-9 * (1.0 + scale)) return false;
    }
    return true;
}

// The checks above compare a rate with the size of all its terms. In an orbit the Kepler term
// dwarfs a perturbation by many orders of magnitude (a third body's R is 1e-13 of μ/r at the
// probe points), so a perturbation that breaks an integral could pass them. The perturbation is
// therefore judged on its own: the energy H0 − R needs R independent of t and no
// non-conservative acceleration (a conservative reading: an acceleration that does no work
// is not looked for).
bool orbit_energy_conserved(const model::Model& model) {
    const model::Orbit& o = *model.orbit;
    if (!derivative(o.R, model.t).expand().is_zero()) return false;
    return std::all_of(o.acceleration.begin(), o.acceleration.end(), [](const ex& a) { return a.is_zero(); });
}

// h_z needs no torque about z from R and from the accelerations: x ∂R/∂y − y ∂R/∂x and
// x a_y − y a_x vanish. Each effect is judged on its own, against the size of its own two
// terms: in a sum, J2's torque terms (each ~1e10 at the probe points, cancelling exactly)
// would hide a third body's real torque (~1e-13) in their rounding.
bool orbit_axisymmetric(const model::Model& model) {
    const model::Orbit& o = *model.orbit;
    const auto& c = model.coordinates;
    const ex x = c[0].q, y = c[1].q;
    std::vector<std::pair<ex, ex>> torques;
    for (const auto& term : o.disturbing)
        torques.emplace_back(x * derivative(term.value, c[1].q), y * derivative(term.value, c[0].q));
    for (const auto& a : o.accelerations) torques.emplace_back(x * a.value[1], y * a.value[0]);
    for (const auto& point : probe_points(model, 6, 0xa215)) {
        for (const auto& [a, b] : torques) {
            const double va = evaluate(a, point), vb = evaluate(b, point);
            if (!std::isfinite(va) || !std::isfinite(vb) || std::abs(va - vb) > 1e-12 * (std::abs(va) + std::abs(vb)))
                return false;
        }
    }
    return true;
}

// M must be regular for the equations to be solvable for u̇. Checked numerically at
// several random states with the default parameters; singular at all of them means
// singular as a function (a degenerate kinetic energy), not an unlucky point.
void require_regular_mass_matrix(const model::Model& model, const GiNaC::matrix& M) {
    const std::size_t n = M.rows();
    const auto points = probe_points_at_defaults(model, 3, 0xa55e55);
    Eigen::VectorXd null_direction;
    for (const auto& point : points) {
        Eigen::MatrixXd A(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) A(i, j) = evaluate(M(unsigned(i), unsigned(j)), point);
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
        const Eigen::VectorXd lambda = eig.eigenvalues().cwiseAbs();
        Eigen::Index k = 0;
        lambda.minCoeff(&k);
        const double scale = lambda.maxCoeff();
        if (scale > 0 && lambda(k) > 1e-12 * scale) return;  // regular here, so regular as a function
        null_direction = eig.eigenvectors().col(k);
    }
    const std::vector<std::string> all = model.velocity_names();
    std::string names;
    for (std::size_t i = 0; i < n; ++i) {
        if (null_direction.size() == 0 || std::abs(null_direction(Eigen::Index(i))) > 1e-6) {
            names += (names.empty() ? "'" : ", '") + all[i] + "'";
        }
    }
    throw InputError(model.kinetic_pos,
                     fmt::format("the mass matrix ∂²T/∂q̇∂q̇ is singular: the kinetic energy does not determine the "
                                 "accelerations of {} (check that every coordinate moves some mass, and that "
                                 "[effects] keeps \"relative\")",
                                 names));
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
    if (model.free_carrier()) {
        // The carrier's own energy does not depend on q̇: it belongs to T_e.
        const auto& c = *model.carrier;
        const Vec3 Jw = times(c.inertia, carrier.omega);
        split.T_e += c.mass * dot(carrier.v_o, carrier.v_o) / 2 + c.mass * dot(carrier.v_o, cross(carrier.omega, c.center)) +
                     dot(carrier.omega, Jw) / 2;
    }
    return split;
}

// A free carrier's six balance equations. P = ∂T/∂v_o and K = ∂T/∂ω are taken with every
// component of v_o and ω free (placeholders), then evaluated on the actual ones, so that a
// held component still has its momentum (and with it the reaction that holds it).
void add_carrier_equations(const model::Model& model, Equations& eqs) {
    const auto& c = *model.carrier;
    const GiNaC::symbol V[3] = {GiNaC::symbol("V_1"), GiNaC::symbol("V_2"), GiNaC::symbol("V_3")};
    const GiNaC::symbol W[3] = {GiNaC::symbol("W_1"), GiNaC::symbol("W_2"), GiNaC::symbol("W_3")};
    model::Model placeholder = model;
    placeholder.carrier->pole_velocity = {V[0], V[1], V[2]};
    placeholder.carrier->angular_velocity = {W[0], W[1], W[2]};
    const CarrierMotion free_motion = carrier_motion(placeholder);
    const EnergySplit split = split_kinetic_energy(placeholder, free_motion, particle_kinematics(placeholder));
    const ex T = split.T_e + split.T_m + split.T_r;
    GiNaC::exmap actual;
    for (int i = 0; i < 3; ++i) {
        actual[V[i]] = c.pole_velocity[std::size_t(i)];
        actual[W[i]] = c.angular_velocity[std::size_t(i)];
    }
    Vec3 P, K;
    for (int i = 0; i < 3; ++i) {
        P[std::size_t(i)] = derivative(T, V[i]).subs(actual);
        K[std::size_t(i)] = derivative(T, W[i]).subs(actual);
        eqs.momentum[i] = P[std::size_t(i)];
        eqs.angular_momentum[i] = K[std::size_t(i)];
    }
    const Vec3& w = c.angular_velocity;
    const Vec3& v = c.pole_velocity;
    const Vec3 force = cross(w, P), moment = cross(w, K) + cross(v, P);
    for (const bool angular : {false, true}) {
        for (int i = 0; i < 3; ++i) {
            CarrierEquation e;
            e.name = fmt::format("{}_{}", angular ? "moment" : "force", i + 1);
            const ex& momentum = angular ? K[std::size_t(i)] : P[std::size_t(i)];
            e.lhs = total_derivative(model, momentum) + (angular ? moment : force)[std::size_t(i)];
            e.applied = (angular ? c.moment : c.resultant)[std::size_t(i)];
            const ex& component = (angular ? w : v)[std::size_t(i)];
            e.held = component.is_zero();
            if (e.held) {
                e.reaction = GiNaC::symbol(fmt::format("{}{}", angular ? "N" : "R", i + 1),
                                           fmt::format("{}_{}", angular ? "N" : "R", i + 1));
            } else {
                e.quasi_velocity = GiNaC::ex_to<GiNaC::symbol>(component).get_name();
            }
            eqs.carrier_equations.push_back(std::move(e));
        }
    }
}

}  // namespace

EnergySplit split_kinetic_energy(const model::Model& model) {
    return split_kinetic_energy(model, carrier_motion(model), particle_kinematics(model));
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
        const EnergySplit split = split_kinetic_energy(model, carrier, particles);
        eqs.T_e = split.T_e;
        eqs.T_m = split.T_m;
        eqs.T_r = split.T_r;
        eqs.T = split.T_e + split.T_m + split.T_r;
    } else {
        eqs.T = *model.kinetic_energy;
        eqs.T_e = eqs.T_m = eqs.T_r = 0;
    }
    const EnergySplit rotation = rotational_energy(model, carrier.omega);
    const ex T_rotation = rotation.T_e + rotation.T_m + rotation.T_r;

    const std::vector<RotationalEffects> rotational = rotational_effects(model, carrier);
    std::vector<ex> rigid_relative(n, 0);  // the rotation's relative effect, kept apart for M
    for (std::size_t s = 0; s < n; ++s) {
        Equation eq;
        eq.coordinate = model.coordinates[s].name;
        // ∂T/∂q̇_s = Σ m v·e_s with v the absolute velocity (by projection, not by
        // differentiating the expanded T), plus the rotation's; for a given Lagrangian, by
        // differentiation.
        eq.dT_dqdot = eqs.from_particles ? project(particles, s,
                                                   [&](const ParticleKinematics& k) {
                                                       return carrier.v_o + cross(carrier.omega, k.r) + k.r_dot;
                                                   }) + derivative(T_rotation, model.coordinates[s].q_dot)
                                         : derivative(eqs.T, model.coordinates[s].q_dot);
        eq.rhs = model.generalized_forces[s] + euler_operator(model, eqs.V, s);  // ε_s(V) = −∂V/∂q_s for V(q)
        if (eqs.from_particles) {
            const RotationalEffects& rot = rotational[s];
            rigid_relative[s] = rot.relative;
            eq.lhs = 0;
            for (Effect effect : model::all_effects) {
                if (!model.keeps(effect)) continue;
                if (!eqs.has_carrier && effect != Effect::relative) continue;  // inertial frame: nothing else exists
                const ex term = effect_term(effect, model, carrier, particles, s) + rotational_share(effect, rot);
                eq.effects.push_back({effect, term});
                eq.lhs += term;
            }
        } else {
            eq.lhs = euler_operator(model, eqs.T, s);
        }
        eqs.equations.push_back(std::move(eq));
    }
    if (model.free_carrier()) add_carrier_equations(model, eqs);

    // M u̇ = f from E_s = lhs_s − rhs_s, which is linear in u̇. For particles the q̈ terms
    // are known by construction (only the relative effect has them: M_sk = Σ m e_k·e_s), so
    // M and f are assembled directly instead of differentiating and substituting large sums.
    std::vector<ex> rates;  // u̇: q̈, then the quasi-velocities' rates
    for (const auto& c : model.coordinates) rates.push_back(c.q_ddot);
    for (const auto& v : model.quasi_velocities) rates.push_back(v.rate);
    const std::size_t nu = rates.size();
    GiNaC::exmap no_acceleration;
    for (const auto& r : rates) no_acceleration[r] = 0;
    auto has_rates = [&](const ex& e) {
        return std::any_of(rates.begin(), rates.end(), [&](const ex& r) { return e.has(r); });
    };
    eqs.mass_matrix = GiNaC::matrix(unsigned(nu), unsigned(nu));
    const bool direct = eqs.from_particles && model.keeps(Effect::relative);
    for (std::size_t s = 0; s < n; ++s) {
        const Equation& eq = eqs.equations[s];
        ex inertial_rest = 0;  // the inertial side without its u̇ terms (but for the rotation's relative effect)
        if (direct) {
            for (const auto& term : eq.effects)
                inertial_rest += term.effect == Effect::relative
                                     ? project(particles, s, [](const ParticleKinematics& k) { return k.a_rest; })
                                     : term.value;
        }
        // What still needs u̇ extracted by differentiation.
        const ex E = direct ? eq.rhs - inertial_rest - rigid_relative[s] : eq.lhs - eq.rhs;
        const bool E_has_rates = has_rates(E);
        for (std::size_t k = 0; k < nu; ++k) {
            ex m_sk = 0;
            if (direct && k < n)
                for (const auto& p : particles) m_sk += p.mass * dot(p.e[k], p.e[s]);
            if (E_has_rates) m_sk += (direct ? -1 : 1) * derivative(E, GiNaC::ex_to<GiNaC::symbol>(rates[k]));
            eqs.mass_matrix(unsigned(s), unsigned(k)) = m_sk;
        }
        const ex E0 = E_has_rates ? E.subs(no_acceleration) : E;
        eqs.forcing.push_back(direct ? E0 : -E0);
    }
    // The rows of the unknown quasi-velocities: their carrier equations, E = lhs − applied.
    const auto residuals = velocity_residuals(model, eqs);
    for (std::size_t row = n; row < nu; ++row) {
        const ex& E = residuals[row].second;
        for (std::size_t k = 0; k < nu; ++k)
            eqs.mass_matrix(unsigned(row), unsigned(k)) = derivative(E, GiNaC::ex_to<GiNaC::symbol>(rates[k]));
        eqs.forcing.push_back(-E.subs(no_acceleration));
    }
    require_regular_mass_matrix(model, eqs.mass_matrix);

    const ex h = jacobi_candidate(model, eqs, carrier, particles);
    if (proven_conserved(model, eqs, h) && (!model.orbit || orbit_energy_conserved(model))) {
        eqs.invariants.push_back(
            {"energy", h,
             model.orbit ? "h = |v|²/2 − μ/r − R = H0 − R (R independent of t, no non-conservative acceleration)"
             : !eqs.has_carrier ? "h = Σ q̇ ∂L/∂q̇ − L, the Jacobi integral (T + V when T is quadratic in q̇)"
             : model.free_carrier() ? "h = T + V, the energy of carrier and carried bodies together"
             : std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; })
                 ? "Jacobi integral h = Σ q̇ ∂L/∂q̇ − L = T_r − T_e + V"
                 : "Jacobi integral of the kept equations"});
    }
    // An orbit's angular momentum about the central body's axis z: conserved when the
    // perturbations are axisymmetric (zonal harmonics) and do no torque about z.
    if (model.orbit) {
        const auto& c = model.coordinates;
        const ex h_z = c[0].q * c[1].q_dot - c[1].q * c[0].q_dot;
        if (orbit_axisymmetric(model) && proven_constant(model, eqs, h_z))
            eqs.invariants.push_back({"h_z", h_z, "h_z = x ẏ − y ẋ, the angular momentum about z (axisymmetric R)"});
    }
    return eqs;
}

}  // namespace eomc::mechanics
