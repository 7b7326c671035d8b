// `eomc sweep` and `eomc ensemble`: one compiled kernel, many runs. Each member is a simulate()
// run (simulate_loaded, no trajectory CSV) with its inputs from the specification, run on a pool
// of threads; its summary is one CSV row, and the summaries' statistics are printed. Results are
// the same, bit for bit, whatever the thread count: a member's inputs depend on its index alone,
// and everything is gathered and reduced in index order.
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "host/ensemble_budget.hpp"
#include "host/ensemble_spec.hpp"
#include "host/observation.hpp"
#include "host/simulate.hpp"

namespace eomc::host {

struct EnsembleRequest {
    SimulationRequest base;  // the scene's run: method, tolerances, t_end, --set; its csv_path is not used
    EnsembleSpec spec;
    unsigned threads = 0;    // 0 = std::thread::hardware_concurrency()
    // This process runs the members with index % ranks == rank (MPI: one rank of several).
    std::size_t rank = 0, ranks = 1;
    bool progress = true;    // a bar on stderr when it is a terminal and the run lasts > ~1 s
    bool progress_always = false;  // --progress: from the start, wherever stderr goes
    // --budget-s: the members' time, estimated from the first one's (run before the others start),
    // refused past it as InputError at `members_flag` (--samples, --grid).
    double budget_s = default_budget_s;
    SourcePos members_flag;
    // Members a SIMD batch at a time (host/ensemble_batch.hpp; InputError at --batch where the
    // kernel or the method does not allow it). The CSV is the same as without for rk4, bit for bit.
    bool batch = false;
    std::vector<Observation> observe;  // --observe: extra columns (host/observation.hpp)
};

struct MemberResult {
    static constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    std::size_t index = 0;
    std::vector<double> inputs;  // in spec.input_names() order
    // "ok"; "stopped" when a terminal event ended the run (message: the event); "failed" (message:
    // why; state and drifts NaN, t the last accepted time when known).
    std::string status = "failed";
    std::string message;
    double t = nan;
    std::vector<double> state;   // the final state, in state_names order
    std::vector<double> drifts;  // each invariant's max |I(t) − I(0)|
    std::size_t events = 0;      // located events (and contact events)
    std::vector<double> observed;  // the --observe columns (NaN: none, or the member failed)
    bool refused = false;        // failed as bad input (its values refused), not in the integration
    SourcePos refused_at;        // then the InputError's place and message (`message` is the whole line)
    std::string refusal;
};

struct EnsembleResult {
    std::string scene_name, method;
    std::vector<std::string> input_names, state_names, invariant_names, observed_names;
    std::vector<MemberResult> members;  // by index (only this rank's when ranks > 1)
    unsigned threads = 1;        // per rank
    std::size_t lanes = 1;       // members per kernel call (--batch)
    std::size_t ranks = 1;       // MPI ranks whose members were gathered here
    double wall_s = 0.0, compile_s = 0.0;
    bool cache_hit = false;
};

// Throws InputError for a bad request or specification (unknown names, a bad method, …) before
// any member runs, and, in one process, when every member is refused as bad input
// (refuse_if_all_refused); a member that fails otherwise is recorded and the others run on.
EnsembleResult run_ensemble(const EnsembleRequest& request);

// Throws InputError when every member was refused as bad input: then the specification is bad,
// not the members. At the first member's place: "every member was refused; member 0: …" (run_ensemble
// calls it in one process; after an MPI gather, rank 0 does: the same line).
void refuse_if_all_refused(const EnsembleResult& result);

// One row per member: member, the inputs, status, t, the final state, <invariant>_max_drift, the
// --observe columns, events, message (quoted). Numbers to 17 significant digits; a failed member's empty cells.
std::string ensemble_csv(const EnsembleResult& result);

// Over the members that did not fail, in index order: t, each state variable, each drift, each
// --observe column.
struct ColumnStatistics {
    std::string name;
    std::size_t count = 0;  // finite values among them
    double mean = MemberResult::nan, std = MemberResult::nan;  // std: the sample's (n − 1)
    double min = MemberResult::nan, q05 = MemberResult::nan, q50 = MemberResult::nan, q95 = MemberResult::nan,
           max = MemberResult::nan;  // quantiles interpolated linearly between order statistics
};
std::vector<ColumnStatistics> ensemble_statistics(const EnsembleResult& result);

// format: "text" or "json" (one object; NaN as null).
void print_ensemble_summary(const EnsembleResult& result, const std::string& format, std::ostream& out);

// A column of the CSV per member (NaN for a failed one): t, a state variable,
// <invariant>_max_drift or an --observe column. Throws InputError at --plot-column when there is no such column.
std::vector<double> ensemble_column(const EnsembleResult& result, const std::string& column);

// The picture (a gnuplot script for `terminal`, writing `output`): over a grid that varies one
// axis, `column` against it (a bifurcation diagram); over two, a map of `column` on the grid; for
// random draws, the histogram of `column`. Throws InputError at --plot for a grid that varies no
// axis or more than two, at --plot-column for an unknown column.
std::string ensemble_plot_script(const EnsembleResult& result, const EnsembleSpec& spec, const std::string& column,
                                 const std::string& terminal, const std::filesystem::path& output);

}  // namespace eomc::host
