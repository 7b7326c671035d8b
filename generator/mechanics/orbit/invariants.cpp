#include "mechanics/orbit/invariants.hpp"

#include "mechanics/invariants.hpp"
#include "mechanics/relative/lagrange.hpp"
#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;

void add_orbit_invariants(const model::Model& model, Equations& eqs) {
    const ex h = jacobi_candidate(model, eqs);
    // The general prover judges the perturbation too: its high-precision stage sees a third
    // body's time dependence or a drag's work though they are 1e-13 of the Kepler terms.
    if (proven_conserved(model, eqs, h))
        eqs.invariants.push_back(
            {"energy", h, "h = |v|²/2 − μ/r − R = H0 − R (R independent of t, no non-conservative acceleration)"});
    // The angular momentum about the central body's axis z: conserved when the perturbations are
    // axisymmetric (zonal harmonics) and do no torque about z.
    const auto& c = model.coordinates;
    const ex h_z = c[0].q * c[1].q_dot - c[1].q * c[0].q_dot;
    if (proven_constant(model, eqs, h_z))
        eqs.invariants.push_back({"h_z", h_z, "h_z = x ẏ − y ẋ, the angular momentum about z (axisymmetric R)"});
}

}  // namespace eomc::mechanics
