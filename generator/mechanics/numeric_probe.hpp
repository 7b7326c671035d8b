// Evaluation of expressions at reproducible pseudo-random points: how the generator decides
// questions that exact simplification cannot always settle (is M singular, is a quantity
// conserved) without guessing. The same seed gives the same points on every machine.
#pragma once

#include <cstdint>
#include <vector>

#include <ginac/ginac.h>

#include "model/model.hpp"

namespace eomc::mechanics {

struct ProbePoint {
    GiNaC::exmap values;  // t, q, q_dot, q_ddot and the parameters
};

// Points with t, q, q_dot, q_ddot drawn from [-1, 1] and parameters from their defaults
// scaled by a factor in [0.8, 1.25] (so a relation that holds only for the defaults is not
// mistaken for an identity); a parameter whose default is 0 gets a value in [0.3, 1.3].
std::vector<ProbePoint> probe_points(const model::Model& model, std::size_t count, std::uint64_t seed = 0x5eed);
// Points at the parameters' defaults exactly (for properties of the user's system).
std::vector<ProbePoint> probe_points_at_defaults(const model::Model& model, std::size_t count,
                                                 std::uint64_t seed = 0x5eed);

// The value as a double; throws std::runtime_error if it does not evaluate to a real number.
double evaluate(const GiNaC::ex& e, const ProbePoint& at);

}  // namespace eomc::mechanics
