// Linear systems over expressions, knowing no mechanics: unknown constants chosen so that
// given expressions vanish identically in some variables (the method of undetermined
// coefficients), as the multiplier ansätze of the inverse problem need.
#pragma once

#include <optional>
#include <vector>

#include <ginac/ginac.h>

namespace eomc::symbolic {

// The unknown constants u of `conditions` (each linear in u, its coefficients functions of
// `variables`) such that every condition vanishes identically in `variables`: each
// condition's numerator is expanded, its terms grouped by their variable-dependent factor,
// and the coefficient of each group set to zero (exact; at worst stricter than needed, when
// groups are dependent functions such as sin², cos² and 1). The result maps every unknown to
// its value in terms of the free ones (a free one to itself); nullopt when the system has no
// solution or GiNaC cannot solve it.
std::optional<GiNaC::exmap> solve_identically(const std::vector<GiNaC::ex>& conditions,
                                              const std::vector<GiNaC::symbol>& unknowns,
                                              const std::vector<GiNaC::symbol>& variables);

}  // namespace eomc::symbolic
