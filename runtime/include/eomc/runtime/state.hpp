#pragma once

// Plain value types shared by every part of the runtime: the state vector, tolerances,
// limits of the no-progress checker, and the counters an integration reports.

#include <concepts>
#include <cstddef>
#include <vector>

namespace eomc::runtime {

// A state is a plain std::vector; generated kernels read it through data().
template <class S>
using State = std::vector<S>;

// Mixed error control: component i of the local error is measured against
// atol + rtol * max(|x_i|, |x_new_i|) (Hairer-Norsett-Wanner I, Sect. II.4).
struct Tolerances {
  double rtol = 1e-10;
  double atol = 1e-12;
};

// Limits of one integrate_* call, enforced by NoProgressChecker (checker.hpp).
struct Limits {
  // Step attempts allowed in one call, accepted and rejected together: a controller that keeps
  // rejecting is making no progress just as surely as one that creeps forward.
  std::size_t max_steps = 10'000'000;
  // Step underflow: a step proposal h fails when
  //   |h| < underflow_factor * eps(S) * max(|t|, |h_first|),
  // eps(S) the machine epsilon of the scalar, h_first the first step of the call. At |t| >= |h_first|
  // a step that small changes t only in its last four bits (16 = 2^4), so the solution is
  // essentially not advancing (Hairer's DOPRI5 gives up at 10*eps*|t|). h_first supplies the
  // scale while t is near 0, where eps*|t| would allow arbitrarily small steps.
  double underflow_factor = 16.0;
  // Upper bound on |h| for the adaptive drivers; 0 means no bound beyond the interval length.
  double max_step = 0.0;
};

// Work counters of one integrate_* call. rhs_evals counts every call of the system, including
// the one made to choose the initial step.
struct Stats {
  std::size_t accepted = 0, rejected = 0, rhs_evals = 0;
};

// A system is any callable sys(t, x, dxdt) that writes all components of dxdt (presized to x.size()).
template <class Sys, class S>
concept System = std::invocable<Sys&, S, const State<S>&, State<S>&>;

// An observer is called as obs(t, x).
template <class Obs, class S>
concept Observer = std::invocable<Obs&, S, const State<S>&>;

}  // namespace eomc::runtime
