#include "mechanics/kinematics/operators.hpp"

#include "symbolic/differentiation.hpp"

namespace eomc::mechanics {

using GiNaC::ex;
using symbolic::derivative;

ex total_derivative(const model::Model& model, const ex& F) {
    ex d = derivative(F, model.t);
    for (const auto& c : model.coordinates) d += derivative(F, c.q) * c.q_dot + derivative(F, c.q_dot) * c.q_ddot;
    for (const auto& v : model.quasi_velocities) d += derivative(F, v.symbol) * v.rate;
    return d;
}

ex euler_operator(const model::Model& model, const ex& F, std::size_t s) {
    const auto& c = model.coordinates.at(s);
    return total_derivative(model, derivative(F, c.q_dot)) - derivative(F, c.q);
}

}  // namespace eomc::mechanics
