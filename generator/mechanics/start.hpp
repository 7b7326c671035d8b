// A run's start checked the same way wherever its values come from: the scene's own initial
// values, --set, an ensemble member. What the model alone decides (the rows hold, the bodies'
// inertias) is model/'s check, shared with build_model; what needs the equations (M positive
// definite, the rows' Jacobian of full rank) is here.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <ginac/ginac.h>

#include "mechanics/equations.hpp"
#include "model/model.hpp"

namespace eomc::mechanics {

// The model's values at a start: the scene's (model::initial_values) with `overrides` applied by
// name (a parameter; a coordinate q or its rate q_dot; a quasi-velocity; a rigid body's p, q, r,
// gamma1..3, e0..e3). state_known is false when an override names a state variable that is not a
// symbol of the model (an orbit's elements, Andoyer's variables): then only what depends on the
// parameters alone can be checked.
struct StartValues {
    GiNaC::exmap values;
    bool state_known = true;
};
StartValues start_values(const model::Model& model, const std::vector<std::pair<std::string, double>>& overrides);

// Throws InputError at the scene's place of what fails, `at` saying whose values they are ("at the
// initial values and the default parameters"):
// - every [[constraint]] row holds (model::check_constraint_start);
// - the rows' Jacobian W = ∂φ/∂u has full rank (no row vanishes, none depends on the others): the
//   constraint qualification, without which the reactions λ of M u̇ − Wᵀλ = f, W u̇ = r are not
//   determined (Nocedal and Wright, Numerical Optimization, 2nd ed., Def. 12.4, LICQ);
// - M is positive definite (a scene given by its energies, or a rigid body): T a positive definite
//   form in the velocities, else M u̇ = f is not a motion (a negative mass falls through its floor);
// - every body's inertia has positive principal moments satisfying the triangle inequalities.
void check_start(const model::Model& model, const Equations& eqs, const StartValues& start, const std::string& at);

}  // namespace eomc::mechanics
