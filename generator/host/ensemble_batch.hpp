// `eomc ensemble --batch` / `eomc sweep --batch`: members run a SIMD batch at a time through the
// kernel's batched rhs (KernelLibrary::rhs_batch, one member per lane), in lock step
// (runtime/batch/lock_step.hpp): rk4 gives each lane the bits of its run alone, dopri5 one step
// size for the batch (every lane within its tolerances). The lanes that fail are handed back, to be
// run one at a time for their diagnosis.
#pragma once

#include <cstddef>
#include <vector>

#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"

namespace eomc::host {

// Throws InputError at --batch when the members of `request` cannot run as a batch: a kernel that
// is not batchable (it solves M u̇ = f at run time, or has constraint rows, contacts, programs), one
// with events, singular sets or a projection, a method other than rk4 or dopri5, compensated sums.
void check_batchable(const SimulationRequest& request, const KernelLibrary& lib);

struct LaneStart {
    std::vector<double> parameters, x;  // in parameter_names / state_names order
};
struct LaneEnd {
    bool ok = false;  // false: run this member alone (its state or error stopped being finite, or the
                      // batch stopped short: a step underflow, the step budget)
    double t = 0.0;
    std::vector<double> state, drifts;  // the final state, each invariant's max |I(t) − I(0)|
};

// Integrates up to lib.batch_width() members over [0, request.t_end] with request's method (rk4 at
// request.step, dopri5 at request.rtol/atol); empty lanes of a short batch copy the first start.
std::vector<LaneEnd> run_lanes(const SimulationRequest& request, const KernelLibrary& lib,
                               const std::vector<LaneStart>& starts);

}  // namespace eomc::host
