// A rigid body's first integrals beyond the classical three: the polynomial ones that
// integral_search finds in the Euler–Poisson variables at the scene's parameter values
// (Kovalevskaya's quartic, Lagrange's r, Goryachev–Chaplygin's cubic on the zero level of the
// area integral), each turned into an invariant the kernel tracks.
#pragma once

#include <cstddef>
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

// The search's work budget in the elimination's entry operations, over all degrees together (a
// count, not a clock: the verdict is the same on every machine). The heavy gyrostat takes
// 3.5·10⁵ to degree 4, 3.5·10⁶ to 5 and 5.3·10⁷ to 6 (23–35 s); degree 7 would take over 900 s.
// The default admits degree 6 with a third to spare and stops degree 7 within about a minute.
inline constexpr std::size_t default_search_work = 70'000'000;

struct RigidIntegrals {
    unsigned degree = 0;  // the degree asked for
    // Non-empty when the budget stopped the search: "undecided at degree N …". `found` then holds
    // the integrals of the degrees below N, which were decided.
    std::string undecided;
    std::size_t work = 0;  // entry operations spent
    std::vector<FoundIntegral> found;  // in the state (p, q, r, gamma1..3), at the parameters' defaults
    std::string not_searched;          // why there was no search (a parameter that is no short decimal), else ""
    // Per found integral: its invariant name, and whether the kernel tracks it (unconditional, or
    // conditional with the initial state on its level).
    std::vector<std::string> names;
    std::vector<bool> tracked;
};

RigidIntegrals search_rigid_integrals(const model::Model& model, const EulerPoisson& system, unsigned degree,
                                      std::size_t work_budget = default_search_work);

// The tracked ones as invariants (in p, q, r, gamma1..3), for the Equations record.
std::vector<Invariant> tracked_invariants(const RigidIntegrals& integrals);

}  // namespace eomc::mechanics::rigid
