#include "mechanics/relative/holding_forces.hpp"

#include <fmt/format.h>

#include "mechanics/relative/carried_motion.hpp"

namespace eomc::mechanics {

std::vector<HoldingOutput> holding_forces(const model::Model& model) {
    std::vector<HoldingOutput> out;
    if (!model.carrier || model.carrier->free) return out;
    // With [effects] dropping terms the equations are a deliberate approximation that the
    // balance of the whole motion would contradict (and dropped effects leave no code).
    for (const auto effect : model::all_effects)
        if (!model.keeps(effect)) return out;
    const auto& c = *model.carrier;
    // The balance equations (1.1.14)–(1.1.15) with v_o, ω prescribed: the inertial sides are the
    // external resultant V (1.1.17) and moment m⁰ (1.1.24); less the given loads, the drive's.
    const CarrierBalance balance = carrier_balance(model, carrier_momenta(model));
    for (std::size_t i = 0; i < 3; ++i)
        out.push_back({fmt::format("holding_force_{}", i + 1), balance.force[i] - c.resultant[i]});
    for (std::size_t i = 0; i < 3; ++i)
        out.push_back({fmt::format("holding_moment_{}", i + 1), balance.moment[i] - c.moment[i]});
    return out;
}

}  // namespace eomc::mechanics
