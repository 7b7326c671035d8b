#include "mechanics/relative/free_carrier.hpp"

#include <fmt/format.h>

#include "mechanics/kinematics/operators.hpp"
#include "mechanics/relative/carried_motion.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

// A free carrier's six balance equations. P = ∂T/∂v_o and K = ∂T/∂ω are taken with every
// component of v_o and ω free (placeholders), then evaluated on the actual ones, so that a
// held component still has its momentum (and with it the reaction that holds it).
void add_free_carrier_equations(const model::Model& model, Equations& eqs) {
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

}  // namespace eomc::mechanics
