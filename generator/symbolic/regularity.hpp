// Whether a square matrix of expressions is singular as a function of its arguments, not
// just at an unlucky point: the test behind "the mass matrix is singular" and "the
// fundamental form's A is singular".
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::symbolic {

// Evaluates A at a few random states with the parameters at their defaults (probe_points_at_defaults
// with `seed`): regular at any one of them means regular as a function (nullopt). Singular at
// all of them, the indices that carry the null direction of the last one (all indices when A
// was never finite). Singular values, not eigenvalues: A need not be symmetric.
std::optional<std::vector<std::size_t>> singular_as_function(const model::Model& model, const GiNaC::matrix& A,
                                                             std::uint64_t seed);

}  // namespace eomc::symbolic
