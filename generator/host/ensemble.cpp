#include "host/ensemble.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "eomc/runtime/errors.hpp"
#include "host/ensemble_batch.hpp"
#include "host/ensemble_budget.hpp"
#include "host/kernel_loader.hpp"
#include "host/simulate/output.hpp"

namespace eomc::host {

namespace {

using Clock = std::chrono::steady_clock;


// One member: the base run with the member's inputs as --set overrides.
MemberResult run_member(const SimulationRequest& proto, const KernelLibrary& lib, const EnsembleSpec& spec,
                        const std::vector<std::string>& names, const BoundObservations& observe, std::size_t index) {
    MemberResult m;
    m.index = index;
    m.inputs = spec.inputs(index);
    SimulationRequest r = proto;
    for (std::size_t k = 0; k < names.size(); ++k) r.overrides.emplace_back(names[k], m.inputs[k]);
    const std::size_t n_state = lib.state_names().size(), n_inv = lib.invariant_names().size();
    m.observed.assign(observe.size(), MemberResult::nan);
    try {
        const SimulationResult s = simulate_loaded(r, lib);
        for (std::size_t i = 0; i < observe.size(); ++i) {  // event:NAME, its first time
            if (observe.event(i) < 0) continue;
            const std::string& event = lib.event_names()[static_cast<std::size_t>(observe.event(i))];
            const auto first = std::find_if(s.events.begin(), s.events.end(), [&](const EventReport& e) { return e.name == event; });
            if (first != s.events.end()) m.observed[i] = first->t;
        }
        m.t = s.t;
        for (std::size_t i = 0; i < n_state && i < s.state.size(); ++i) m.state.push_back(s.state[i].second);
        for (const auto& inv : s.invariants) m.drifts.push_back(inv.max_abs_drift);
        m.events = s.events.size() + s.contact_events.size();
        m.status = s.stopped_by.empty() ? "ok" : "stopped";
        m.message = s.stopped_by;
    } catch (const runtime::IntegrationError& e) {
        m.t = e.t();
        m.message = e.what();
    } catch (const InputError& e) {  // this member's values refused (a start below a surface, …)
        m.message = e.what();
        m.refused = true;
        m.refused_at = e.where();
        m.refusal = e.message();
    } catch (const std::exception& e) {
        m.message = e.what();
    } catch (...) {  // nothing may leave a pool thread (std::terminate)
        m.message = "an unknown error";
    }
    if (m.state.size() != n_state) m.state.assign(n_state, MemberResult::nan);
    if (m.drifts.size() != n_inv) m.drifts.assign(n_inv, MemberResult::nan);
    return m;
}

// Members first .. first + count (count ≤ the batch width) as one SIMD batch; a member whose start
// is refused, or whose lane fails, runs alone through run_member (the same row as without --batch).
void run_batch(const SimulationRequest& proto, const KernelLibrary& lib, const EnsembleSpec& spec,
               const std::vector<std::string>& names, const BoundObservations& observe,
               const std::vector<std::size_t>& indices, MemberResult* out) {
    std::vector<LaneStart> starts;
    std::vector<std::size_t> lane_of;  // position in `indices` of each lane
    std::vector<std::size_t> alone;
    for (std::size_t j = 0; j < indices.size(); ++j) {
        SimulationRequest r = proto;
        const std::vector<double> inputs = spec.inputs(indices[j]);
        for (std::size_t k = 0; k < names.size(); ++k) r.overrides.emplace_back(names[k], inputs[k]);
        LaneStart s;
        try {
            resolve_start(r, lib, s.parameters, s.x);
        } catch (const InputError&) {
            alone.push_back(j);
            continue;
        }
        starts.push_back(std::move(s));
        lane_of.push_back(j);
    }
    if (!starts.empty()) {
        const std::vector<LaneEnd> ends = run_lanes(proto, lib, starts);
        for (std::size_t k = 0; k < ends.size(); ++k) {
            const std::size_t j = lane_of[k];
            if (!ends[k].ok) {
                alone.push_back(j);
                continue;
            }
            MemberResult& m = out[j];
            m.index = indices[j];
            m.inputs = spec.inputs(indices[j]);
            m.status = "ok";
            m.t = ends[k].t;
            m.state = ends[k].state;
            m.drifts = ends[k].drifts;
            m.observed.assign(observe.size(), MemberResult::nan);  // no events in a batch; expressions later
        }
    }
    for (std::size_t j : alone) out[j] = run_member(proto, lib, spec, names, observe, indices[j]);
}

// The --observe expressions on the final states, here: GiNaC's expressions are not thread-safe.
void observe_final_states(const SimulationRequest& proto, const KernelLibrary& lib, const BoundObservations& observe,
                          EnsembleResult& result) {
    for (auto& m : result.members) {
        if (m.status == "failed") continue;
        std::vector<double> parameters, x;
        SimulationRequest r = proto;
        r.check_start = nullptr;  // checked when the member started
        for (std::size_t k = 0; k < result.input_names.size(); ++k) r.overrides.emplace_back(result.input_names[k], m.inputs[k]);
        resolve_start(r, lib, parameters, x);
        for (std::size_t i = 0; i < observe.size(); ++i)
            if (observe.event(i) < 0) m.observed[i] = observe.evaluate(i, m.t, parameters, m.state);
    }
}

}  // namespace

EnsembleResult run_ensemble(const EnsembleRequest& request) {
    const RunSettings settings = resolve_settings(request.base);  // before the compile: a typo costs none
    if (request.ranks == 0 || request.rank >= request.ranks)
        throw std::invalid_argument(fmt::format("rank {} of {}", request.rank, request.ranks));
    const std::size_t total = request.spec.members();
    const KernelLibrary lib =
        KernelLibrary::load(request.base.header_text, request.base.struct_name, request.base.cache_dir, request.batch);
    check_names(request.spec, lib.parameter_names(), lib.state_names(), request.base.overrides);
    check_separable(*settings.method, request.base.integrator_pos, lib.separable(), lib.scene_name());
    if (request.batch) check_batchable(request.base, lib);
    std::vector<std::string> taken{"member", "status", "t", "events", "message"};
    for (const auto& names : {request.spec.input_names(), lib.state_names()}) taken.insert(taken.end(), names.begin(), names.end());
    for (const auto& n : lib.invariant_names()) taken.push_back(n + "_max_drift");
    const BoundObservations observe(request.observe, lib.parameter_names(), lib.state_names(), lib.event_names(), taken);

    EnsembleResult result;
    result.scene_name = lib.scene_name();
    result.input_names = request.spec.input_names();
    result.state_names = lib.state_names();
    result.invariant_names = lib.invariant_names();
    result.observed_names = observe.columns();
    result.compile_s = lib.seconds();
    result.cache_hit = lib.cache_hit();
    result.method = describe_method(settings, false);
    result.lanes = request.batch ? static_cast<std::size_t>(lib.batch_width()) : 1;
    if (request.batch) result.method += fmt::format(", batches of {} in lock step", result.lanes);

    SimulationRequest proto = request.base;
    proto.header_text.clear();  // the members share the loaded kernel: no copy of its text each
    proto.csv_path.clear();
    proto.progress = false;
    proto.budget_s = 0;  // the ensemble's own budget (check_work_budget) bounds its members

    // This rank's members: index = rank + k·ranks.
    const std::size_t mine = total > request.rank ? (total - request.rank + request.ranks - 1) / request.ranks : 0;
    result.members.resize(mine);
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t wanted = request.threads ? request.threads : hardware;
    const std::size_t batches = request.batch ? (mine + lib.batch_width() - 1) / lib.batch_width() : mine;
    const unsigned threads = static_cast<unsigned>(std::clamp<std::size_t>(std::min(wanted, batches), 1, wanted));
    result.threads = threads;
    std::atomic<std::size_t> next{0}, done{0};
    // Members done out of all.
    ProgressBar progress(
        request.progress, double(mine), [](double done, double all) { return fmt::format("{} / {} runs", done, all); }, 1,
        request.progress_always);
    const auto start = Clock::now();
    // Each thread takes the next index (the next batch of `lanes`); every member writes its own
    // slot, so the order in which they finish changes nothing.
    const std::size_t lanes = result.lanes, units = (mine + lanes - 1) / lanes;
    const auto run_unit = [&](std::size_t u) {  // the members run, as many as it holds
        const std::size_t k = u * lanes, count = std::min(lanes, mine - k);
        if (request.batch) {
            std::vector<std::size_t> indices;
            for (std::size_t j = 0; j < count; ++j) indices.push_back(request.rank + (k + j) * request.ranks);
            run_batch(proto, lib, request.spec, result.input_names, observe, indices, &result.members[k]);
        } else {
            result.members[k] =
                run_member(proto, lib, request.spec, result.input_names, observe, request.rank + k * request.ranks);
        }
        return count;
    };
    const auto work = [&](bool reports) {
        for (std::size_t u; (u = next.fetch_add(1, std::memory_order_relaxed)) < units;) {
            const std::size_t count = run_unit(u);
            const std::size_t d = done.fetch_add(count, std::memory_order_relaxed) + count;
            if (reports) progress.update(double(d));
        }
    };
    if (units > 0) {  // the first, timed: the whole estimated from it, refused past --budget-s before the rest run
        next = 1;
        done = run_unit(0);
        check_work_budget(units, std::chrono::duration<double>(Clock::now() - start).count(), threads,
                          request.budget_s, request.members_flag, request.batch ? "batch of members" : "member");
    }
    {
        std::vector<std::jthread> pool;
        for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work, false);
        work(true);
    }
    progress.update(double(mine));  // all done, whichever thread ran the last
    observe_final_states(proto, lib, observe, result);
    result.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
    // Bad input for every member is bad input for the command, not a table of identical failures
    // (with several ranks, rank 0 decides once it holds them all).
    if (request.ranks == 1) refuse_if_all_refused(result);
    return result;
}

}  // namespace eomc::host
