#include "mechanics/derive.hpp"

#include <stdexcept>

#include "mechanics/inverse/given_equations.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "mechanics/orbit/invariants.hpp"
#include "mechanics/relative/lagrange.hpp"

namespace eomc::mechanics {

Equations derive(const model::Model& model) {
    switch (model.kind()) {
        case model::ModelKind::energies: return derive_lagrange(model);
        case model::ModelKind::given_equations: return derive_given_equations(model);
        case model::ModelKind::orbit: {
            // Cowell's form: Lagrange's equations in Cartesian coordinates, with the orbit's own
            // integrals (the other formulations start from the model, mechanics/first_order).
            check_state_names_free(model);
            Equations eqs = lagrange_equations(model);
            add_orbit_invariants(model, eqs);
            return eqs;
        }
    }
    throw std::logic_error("derive: unknown model kind");
}

}  // namespace eomc::mechanics
