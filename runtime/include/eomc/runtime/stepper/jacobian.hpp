#pragma once

// The Jacobian a system may offer the implicit steppers (Gauss-Legendre's simplified Newton,
// Radau IIA): sys.jacobian(t, x, J) writes df/dx at (t, x) into J, presized n x n and zeroed.

#include <Eigen/Dense>

#include "eomc/runtime/state.hpp"

namespace eomc::runtime {

template <class Sys, class S>
concept HasJacobian =
    System<Sys, S> && requires(Sys& sys, S t, const State<S>& x, Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& J) {
      sys.jacobian(t, x, J);
    };

}  // namespace eomc::runtime
