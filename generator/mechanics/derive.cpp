#include "mechanics/derive.hpp"

#include <stdexcept>
#include <utility>

#include "mechanics/constraints/constraints.hpp"
#include "mechanics/control/control.hpp"
#include "mechanics/unilateral/unilateral.hpp"
#include "mechanics/inverse/given_equations.hpp"
#include "mechanics/orbit/formulation.hpp"
#include "mechanics/orbit/invariants.hpp"
#include "mechanics/relative/lagrange.hpp"
#include "mechanics/rigid/euler_poisson.hpp"
#include "mechanics/rigid/cyclic.hpp"
#include "mechanics/rigid/last_multiplier.hpp"

namespace eomc::mechanics {

namespace {

// Any Lagrangian system: the momenta of its cyclic coordinates (proven, mechanics/rigid/cyclic)
// and the sets where det M = 0, which the kernel watches (mechanics/rigid/last_multiplier).
Equations with_integrals(const model::Model& model, Equations eqs) {
    rigid::add_cyclic_momenta(model, eqs);
    eqs.singular_sets = rigid::singular_sets(model, eqs);
    return eqs;
}

}  // namespace

Equations derive(const model::Model& model) {
    switch (model.kind()) {
        case model::ModelKind::energies: {
            Equations eqs = derive_lagrange(model);
            if (!model.programs.empty()) {
                // The controls Q_c = D λ(t, q, q̇) do work and break symmetries: no integral of the free
                // system is kept ([[constraint]] rows beside programs are ideal programs: model/programs.cpp).
                eqs.programs = program_rows(model, eqs);
                eqs.redundant_programs = redundant_ideal(model, eqs);
                eqs.invariants.clear();
                eqs.singular_sets = rigid::singular_sets(model, eqs);
                return eqs;
            }
            if (model.constraints.empty() && model.unilateral.empty()) return with_integrals(model, std::move(eqs));
            // The rows stay beside the equations: lhs/rhs, M and f are those of the free system,
            // the reactions Σ λ_α W_αs are added by whoever reads eqs.constraints.
            if (!model.constraints.empty()) eqs.constraints = constraint_rows(model);
            // The unilateral rows likewise (Mei, ch. 6): off the boundary they do nothing, on it they
            // react as bilateral rows with λ ≥ 0, and at impacts they change the velocities.
            eqs.unilateral = unilateral_rows(model);
            // The energy integral was proven for the free system; the ideal reactions (no virtual
            // work: Lur'e, ch. 2; Chetaev 1932 for the kinematic rows) still do work at the rate
            // −Σ λ_α ∂_t f_α or −Σ λ_α b_α along the motion, so the integral survives only when
            // every row is scleronomic and homogeneous (Mei, §6.6). A unilateral row's contact-phase
            // reaction is such a reaction; its impacts lose Carnot's T⁻ − T⁺ whenever e < 1 (Mei,
            // §6.5), so with unilateral rows the energy is an integral between impacts only.
            const bool keeps_energy = reactions_do_no_work(model, eqs.constraints) &&
                                      unilateral_reactions_do_no_work(model, eqs.unilateral);
            for (auto it = eqs.invariants.begin(); it != eqs.invariants.end();) {
                if (it->name != "energy") {
                    ++it;
                } else if (keeps_energy) {
                    if (!eqs.constraints.empty())
                        it->description += "; the constraints are scleronomic and homogeneous, so their ideal "
                                           "reactions do no work";
                    if (!eqs.unilateral.empty())
                        it->description += "; the unilateral constraints are scleronomic, so their reactions do no "
                                           "work in contact: conserved between impacts only, since an impact with "
                                           "e < 1 loses T- - T+ = ((1 - e)/(1 + e)) (1/2) dqdot^T M dqdot (Carnot)";
                    ++it;
                } else {
                    it = eqs.invariants.erase(it);
                }
            }
            return with_integrals(model, std::move(eqs));
        }
        case model::ModelKind::given_equations: return derive_given_equations(model);
        case model::ModelKind::orbit: {
            // Cowell's form: Lagrange's equations in Cartesian coordinates, with the orbit's own
            // integrals (the other formulations start from the model, mechanics/first_order).
            check_state_names_free(model);
            Equations eqs = lagrange_equations(model);
            add_orbit_invariants(model, eqs);
            return eqs;
        }
        case model::ModelKind::rigid:
            // In Euler angles the body is a Lagrangian system like any other; the other formulations
            // start from Euler's and Poisson's equations.
            if (model.rigid->formulation == scene::RigidFormulationKind::euler_angles) {
                Equations eqs = with_integrals(model, derive_lagrange(model));
                rigid::add_body_integrals_in_angles(model, eqs);
                return eqs;
            }
            if (!model.programs.empty()) {
                // Programs on ω (Mei §3.2): Euler's equations I ω̇ = f + D λ with torques in the
                // directions D; the controls do work and turn the body, so no integral is kept.
                Equations eqs = rigid::derive_rigid(model);
                eqs.programs = program_rows(model, eqs);
                eqs.redundant_programs = redundant_ideal(model, eqs);
                eqs.invariants.clear();
                return eqs;
            }
            return rigid::derive_rigid(model);
    }
    throw std::logic_error("derive: unknown model kind");
}

}  // namespace eomc::mechanics
