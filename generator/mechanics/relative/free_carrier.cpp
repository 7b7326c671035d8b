#include "mechanics/relative/free_carrier.hpp"

#include <fmt/format.h>

#include "mechanics/relative/carried_motion.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

// A free carrier's six balance equations. P = ∂T/∂v_o and K = ∂T/∂ω are taken with every
// component of v_o and ω free (placeholders), then evaluated on the actual ones, so that a
// held component still has its momentum (and with it the reaction that holds it); see
// carrier_momenta, shared with a prescribed carrier's holding forces.
void add_free_carrier_equations(const model::Model& model, Equations& eqs) {
    const auto& c = *model.carrier;
    const CarrierMomenta momenta = carrier_momenta(model);
    const CarrierBalance balance = carrier_balance(model, momenta);
    for (int i = 0; i < 3; ++i) {
        eqs.momentum[i] = momenta.P[std::size_t(i)];
        eqs.angular_momentum[i] = momenta.K[std::size_t(i)];
    }
    const Vec3& w = c.angular_velocity;
    const Vec3& v = c.pole_velocity;
    for (const bool angular : {false, true}) {
        for (int i = 0; i < 3; ++i) {
            CarrierEquation e;
            e.name = fmt::format("{}_{}", angular ? "moment" : "force", i + 1);
            e.lhs = (angular ? balance.moment : balance.force)[std::size_t(i)];
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
