#include "host/ensemble_batch.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "eomc/runtime/batch/lock_step.hpp"
#include "host/simulate/watches.hpp"
#include "support/diagnostic.hpp"

namespace eomc::host {

namespace {

namespace rb = runtime::batch;
constexpr std::size_t W = 4;  // the adapter's batch_width

// The batch system: the lanes laid out lane-minor for the C interface, and back.
struct LaneSystem {
    const KernelLibrary& lib;
    const KernelLibrary::Parameters& parameters;
    std::vector<double> in, out;
    void operator()(double t, const rb::BatchState<W>& x, rb::BatchState<W>& dxdt) {
        for (std::size_t i = 0; i < x.size(); ++i) x[i].copy_to(in.data() + i * W, std::experimental::element_aligned);
        lib.rhs_batch(t, in.data(), out.data(), parameters);
        for (std::size_t i = 0; i < x.size(); ++i)
            dxdt[i].copy_from(out.data() + i * W, std::experimental::element_aligned);
    }
};

}  // namespace

void check_batchable(const SimulationRequest& r, const KernelLibrary& lib) {
    const SourcePos where{"--batch"};
    const auto refuse = [&](const std::string& why) {
        throw InputError(where, fmt::format("the members of {} cannot run as a SIMD batch: {}; run without --batch",
                                            lib.scene_name(), why));
    };
    if (lib.batch_width() == 0)
        refuse("its kernel solves for its rates at run time (or has constraint rows, contacts or programs)");
    if (static_cast<std::size_t>(lib.batch_width()) != W)
        refuse(fmt::format("its kernel batches {} lanes, this eomc {}", lib.batch_width(), W));
    const RunSettings s = resolve_settings(r);
    if (!s.method->batch)
        refuse(fmt::format("the batch runs {} (one step size per batch), not {}",
                           runtime::integrator_list([](const runtime::IntegratorInfo& i) { return i.batch; }, " or "),
                           s.method->name));
    if (s.compensated) refuse("the batch does not carry compensated sums");
    if (r.variational) refuse("the batch does not integrate the state-transition matrix");
    if (!lib.event_names().empty()) refuse("the scene has events, which the batch does not locate");
    if (!lib.singular_set_names().empty()) refuse("the scene has singular sets, which the batch does not watch");
    if (lib.projects()) refuse("the kernel projects its state after every step");
}

std::vector<LaneEnd> run_lanes(const SimulationRequest& request, const KernelLibrary& lib,
                               const std::vector<LaneStart>& starts) {
    if (starts.empty() || starts.size() > W)
        throw std::invalid_argument(fmt::format("run_lanes: {} members for {} lanes", starts.size(), W));
    const std::size_t n = lib.state_names().size(), n_par = lib.parameter_names().size(),
                      n_inv = lib.invariant_names().size();
    std::vector<double> values(n_par * W);
    rb::BatchState<W> x(n);
    for (std::size_t k = 0; k < W; ++k) {
        const LaneStart& s = starts[k < starts.size() ? k : 0];
        for (std::size_t j = 0; j < n_par; ++j) values[j * W + k] = s.parameters[j];
        for (std::size_t i = 0; i < n; ++i) x[i][k] = s.x[i];
    }
    const KernelLibrary::Parameters parameters = lib.make_batch_parameters(values);
    LaneSystem sys{lib, parameters, std::vector<double>(n * W), std::vector<double>(n * W)};

    // The invariants after every step, as simulate()'s observer watches them.
    std::vector<double> in(n * W), inv(n_inv * W), inv0(n_inv * W), drift(n_inv * W, 0.0);
    bool first = true;
    const auto observer = [&](double t, const rb::BatchState<W>& xs, const rb::Alive<W>&) {
        if (n_inv == 0) return;
        for (std::size_t i = 0; i < n; ++i) xs[i].copy_to(in.data() + i * W, std::experimental::element_aligned);
        lib.invariants_batch(t, in.data(), inv.data(), parameters);
        if (first) inv0 = inv, first = false;
        for (std::size_t j = 0; j < inv.size(); ++j) drift[j] = track_max(drift[j], std::abs(inv[j] - inv0[j]));
    };
    rb::Alive<W> alive(true);
    rb::BatchStop stop;
    // The batch drivers of batch/lock_step.hpp: one fixed-step, one adaptive (check_batchable).
    const RunSettings s = resolve_settings(request);
    if (s.method->fixed_step()) {
        rb::integrate_rk4_batch<W>(sys, x, 0.0, request.t_end, s.step, alive, observer);
    } else {
        runtime::Limits limits;  // the budget simulate() gives an adaptive method
        if (request.max_steps) limits.max_steps = *request.max_steps;
        rb::integrate_dopri5_batch<W>(sys, x, 0.0, request.t_end, s.tolerances, limits.max_steps, alive, stop, observer);
    }
    std::vector<LaneEnd> ends(starts.size());
    for (std::size_t k = 0; k < starts.size(); ++k) {
        LaneEnd& e = ends[k];
        e.ok = alive[k] && !stop.stopped;
        if (!e.ok) continue;
        e.t = request.t_end;
        for (std::size_t i = 0; i < n; ++i) e.state.push_back(x[i][k]);
        for (std::size_t j = 0; j < n_inv; ++j) e.drifts.push_back(drift[j * W + k]);
    }
    return ends;
}

}  // namespace eomc::host
