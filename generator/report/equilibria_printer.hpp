// `eomc equilibria`: each relative equilibrium with its closed form (where solved), its
// eigenvalues and verdict, as text or JSON.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "mechanics/relative/equilibria.hpp"
#include "mechanics/rigid/equilibria.hpp"
#include "model/model.hpp"

namespace eomc::report {

// format: "text" or "json".
void print_equilibria(const model::Model& model, const std::vector<mechanics::Equilibrium>& found,
                      const std::string& format, std::ostream& out);

// A rigid-body scene: Staude's cone, the permanent rotations about the principal axes and through
// the initial state with their eigenvalues and verdicts, the Lagrange case's criterion.
void print_rigid_equilibria(const model::Model& model, const mechanics::rigid::RigidEquilibria& found,
                            const std::string& format, std::ostream& out);

}  // namespace eomc::report
