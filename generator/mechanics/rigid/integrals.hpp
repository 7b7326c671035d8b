// A rigid body's first integrals beyond the classical three: the polynomial ones that
// integral_search finds in the Euler–Poisson variables at the scene's parameter values
// (Kovalevskaya's quartic, Lagrange's r, Goryachev–Chaplygin's cubic on the zero level of the
// area integral), each turned into an invariant the kernel tracks.
#pragma once

#include <string>
#include <vector>

#include "mechanics/equations.hpp"
#include "mechanics/rigid/euler_poisson.hpp"
#include "mechanics/rigid/integral_search.hpp"
#include "model/model.hpp"

namespace eomc::mechanics::rigid {

// The degree `eomc derive`, `generate` and `simulate` search to (Kovalevskaya's integral is
// quartic); `eomc integrals --degree` chooses another.
inline constexpr unsigned default_search_degree = 4;

struct RigidIntegrals {
    unsigned degree = 0;
    std::vector<FoundIntegral> found;  // in the state (p, q, r, gamma1..3), at the parameters' defaults
    std::string not_searched;          // why there was no search (a parameter that is no short decimal), else ""
    // Per found integral: its invariant name, and whether the kernel tracks it (unconditional, or
    // conditional with the initial state on its level).
    std::vector<std::string> names;
    std::vector<bool> tracked;
};

RigidIntegrals search_rigid_integrals(const model::Model& model, const EulerPoisson& system, unsigned degree);

// The tracked ones as invariants (in p, q, r, gamma1..3), for the Equations record.
std::vector<Invariant> tracked_invariants(const RigidIntegrals& integrals);

}  // namespace eomc::mechanics::rigid
