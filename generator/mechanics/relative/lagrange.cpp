#include "mechanics/relative/lagrange.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "mechanics/invariants.hpp"
#include "mechanics/kinematics/operators.hpp"
#include "mechanics/relative/carried_motion.hpp"
#include "mechanics/relative/free_carrier.hpp"
#include "support/diagnostic.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/regularity.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using model::Effect;
using namespace eomc::symbolic;

namespace {

// The rigid bodies' share of each effect, one entry per equation s. ε_s(T_r) is the relative
// effect and ε_s(T_e) = −∂T_e/∂q_s the centrifugal one; ε_s(T_m) splits into the part from the
// change of ω (euler: d/dt acting on ω) and the rest (coriolis, linear in q̇ and ω). To tell them
// apart ω is a placeholder W while differentiating, then W → ω and Ẇ → ω̇.
struct RotationalEffects {
    ex relative = 0, euler = 0, centrifugal = 0, coriolis = 0;
    // relative = Σ_k relative_rates[k] u̇_k + relative_rest (kinematics/operators: euler_operator_split)
    ex relative_rest = 0;
    std::vector<ex> relative_rates;
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
    const EulerOperatorSplit relative = euler_operator_split(model, actual.T_r);
    for (std::size_t s = 0; s < effects.size(); ++s) {
        RotationalEffects& r = effects[s];
        r.relative = relative.value(model, s);
        r.relative_rest = relative.rest[s];
        r.relative_rates = relative.rates[s];
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

// M must be regular for the equations to be solvable for u̇.
void require_regular_mass_matrix(const model::Model& model, const GiNaC::matrix& M) {
    const auto involved = singular_as_function(model, M, 0xa55e55);
    if (!involved) return;
    const std::vector<std::string> all = model.velocity_names();
    std::string names;
    for (const std::size_t i : *involved) names += (names.empty() ? "'" : ", '") + all[i] + "'";
    throw InputError(model.kinetic_pos,
                     fmt::format("the mass matrix ∂²T/∂q̇∂q̇ is singular: the kinetic energy does not determine the "
                                 "accelerations of {} (check that every coordinate moves some mass, and that "
                                 "[effects] keeps \"relative\")",
                                 names));
}

}  // namespace

// The Jacobi-type integral of the kept equations: for the full equations
// h = Σ u ∂L/∂u − L over all velocities (q̇ and a free carrier's quasi-velocities), which is
// T_r − T_e + V for a steadily moving carrier and T + V for a free one. When effects are
// dropped, the kept ones that are potential-like (centrifugal and translation under steady
// carrier motion) contribute their potentials and coriolis contributes nothing (no work).
// Whether h is actually conserved is proven afterwards, never assumed.
ex jacobi_candidate(const model::Model& model, const Equations& eqs) {
    const CarrierMotion carrier = carrier_motion(model);
    const auto particles = particle_kinematics(model);
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

Equations lagrange_equations(const model::Model& model) {
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
    // A given T: ε_s(T) with its u̇ terms apart, from T as written (no expansion of its squares).
    const EulerOperatorSplit given =
        eqs.from_particles ? EulerOperatorSplit{} : euler_operator_split(model, eqs.T);
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
                                         : given.momenta[s];
        eq.rhs = model.generalized_forces[s] + euler_operator(model, eqs.V, s);  // ε_s(V) = −∂V/∂q_s for V(q)
        if (eqs.from_particles) {
            const RotationalEffects& rot = rotational[s];
            eq.lhs = 0;
            for (Effect effect : model::all_effects) {
                if (!model.keeps(effect)) continue;
                if (!eqs.has_carrier && effect != Effect::relative) continue;  // inertial frame: nothing else exists
                const ex term = effect_term(effect, model, carrier, particles, s) + rotational_share(effect, rot);
                eq.effects.push_back({effect, term});
                eq.lhs += term;
            }
        } else {
            eq.lhs = given.value(model, s);
        }
        eqs.equations.push_back(std::move(eq));
    }
    if (model.free_carrier()) add_free_carrier_equations(model, eqs);

    // M u̇ = f from E_s = lhs_s − rhs_s, which is linear in u̇. For particles the q̈ terms
    // are known by construction (only the relative effect has them: M_sk = Σ m e_k·e_s, and the
    // rotation's from its split), and for a given T from the split of ε_s(T), so M and f are
    // assembled directly instead of differentiating and substituting large sums; only what the
    // applied side adds (a potential in q̇) is differentiated.
    std::vector<ex> rates;  // u̇: q̈, then the quasi-velocities' rates
    for (const auto& c : model.coordinates) rates.push_back(c.q_ddot);
    for (const auto& v : model.quasi_velocities) rates.push_back(v.rate);
    const std::size_t nu = rates.size();
    GiNaC::exmap no_acceleration;
    GiNaC::exset rate_set;
    for (const auto& r : rates) {
        no_acceleration[r] = 0;
        rate_set.insert(r);
    }
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
        // The u̇ coefficients known from a split, and what may still need u̇ extracted by differentiation.
        const std::vector<ex>* split_rates = direct                ? &rotational[s].relative_rates
                                             : !eqs.from_particles ? &given.rates[s]
                                                                   : nullptr;
        const ex E = direct ? eq.rhs - inertial_rest - rotational[s].relative_rest
                     : eqs.from_particles ? eq.lhs - eq.rhs
                                          : given.rest[s] - eq.rhs;
        const bool E_has_rates = symbolic::depends_on_any(E, rate_set);
        for (std::size_t k = 0; k < nu; ++k) {
            ex m_sk = 0;
            if (direct && k < n)
                for (const auto& p : particles) m_sk += p.mass * dot(p.e[k], p.e[s]);
            if (split_rates && !split_rates->empty()) m_sk += (*split_rates)[k];
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
    return eqs;
}

Equations derive_lagrange(const model::Model& model) {
    Equations eqs = lagrange_equations(model);
    const ex h = jacobi_candidate(model, eqs);
    if (proven_conserved(model, eqs, h)) {
        eqs.invariants.push_back(
            {"energy", h,
             !eqs.has_carrier ? "h = Σ q̇ ∂L/∂q̇ − L, the Jacobi integral (T + V when T is quadratic in q̇)"
             : model.free_carrier() ? "h = T + V, the energy of carrier and carried bodies together"
             : std::all_of(model.keep.begin(), model.keep.end(), [](bool k) { return k; })
                 ? "Jacobi integral h = Σ q̇ ∂L/∂q̇ − L = T_r − T_e + V"
                 : "Jacobi integral of the kept equations"});
    }
    return eqs;
}

}  // namespace eomc::mechanics
