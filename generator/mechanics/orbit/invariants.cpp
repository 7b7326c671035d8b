#include "mechanics/orbit/invariants.hpp"

#include <algorithm>
#include <cmath>

#include "mechanics/invariants.hpp"
#include "mechanics/relative/lagrange.hpp"
#include "symbolic/differentiation.hpp"
#include "symbolic/numeric_probe.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using namespace eomc::symbolic;

namespace {

// The general proofs (mechanics/invariants) compare a rate with the size of its terms. In an orbit the Kepler term
// dwarfs a perturbation by many orders of magnitude (a third body's R is 1e-13 of μ/r at the
// probe points), so a perturbation that breaks an integral could pass them. The perturbation is
// therefore judged on its own: the energy H0 − R needs R independent of t and no
// non-conservative acceleration (a conservative reading: an acceleration that does no work
// is not looked for).
bool energy_rule_holds(const model::Model& model) {
    const model::Orbit& o = *model.orbit;
    if (!derivative(o.R, model.t).expand().is_zero()) return false;
    return std::all_of(o.acceleration.begin(), o.acceleration.end(), [](const ex& a) { return a.is_zero(); });
}

// h_z needs no torque about z from R and from the accelerations: x ∂R/∂y − y ∂R/∂x and
// x a_y − y a_x vanish. Each effect is judged on its own, against the size of its own two
// terms: in a sum, J2's torque terms (each ~1e10 at the probe points, cancelling exactly)
// would hide a third body's real torque (~1e-13) in their rounding.
bool axisymmetric(const model::Model& model) {
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

}  // namespace

void add_orbit_invariants(const model::Model& model, Equations& eqs) {
    const ex h = jacobi_candidate(model, eqs);
    if (proven_conserved(model, eqs, h) && energy_rule_holds(model))
        eqs.invariants.push_back(
            {"energy", h, "h = |v|²/2 − μ/r − R = H0 − R (R independent of t, no non-conservative acceleration)"});
    // The angular momentum about the central body's axis z: conserved when the perturbations are
    // axisymmetric (zonal harmonics) and do no torque about z.
    const auto& c = model.coordinates;
    const ex h_z = c[0].q * c[1].q_dot - c[1].q * c[0].q_dot;
    if (axisymmetric(model) && proven_constant(model, eqs, h_z))
        eqs.invariants.push_back({"h_z", h_z, "h_z = x ẏ − y ẋ, the angular momentum about z (axisymmetric R)"});
}

}  // namespace eomc::mechanics
