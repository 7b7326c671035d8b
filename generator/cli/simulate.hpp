// `eomc simulate`: compile an emitted kernel header (cached), integrate it with the runtime,
// watch its invariants, write a CSV and print a summary.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "eomc/runtime/state.hpp"

namespace eomc::cli {

struct SimulationRequest {
    std::string header_text;                                // emitted kernel header
    std::string struct_name;                                // e.g. "DiskTubeBall"
    std::vector<std::pair<std::string, double>> overrides;  // --set NAME=VALUE: parameters, or initial values "q" / "q_dot"; later wins
    double t_end = 10.0;
    std::string integrator = "dopri5";                      // "rk4" | "dopri5"
    double rtol = 1e-10, atol = 1e-12;                      // dopri5
    double step = 1e-3;                                     // rk4
    std::string csv_path;                                   // "" = no CSV
    std::string summary_format = "text";                    // "text" | "json"
    std::string cache_dir;                                  // "" = $XDG_CACHE_HOME/eomc or ~/.cache/eomc
    bool progress = true;  // progress bar on stderr, only when stderr is a terminal and the run lasts > ~1 s
};

struct InvariantReport {
    std::string name;
    double initial = 0.0;        // I(0)
    double final = 0.0;          // I(t_end)
    double max_abs_drift = 0.0;  // max over accepted steps of |I(t) − I(0)|
    // max_abs_drift / |I(0)|, NaN when I(0) = 0.
    double relative_drift() const;
};

struct SimulationResult {
    std::string scene_name;
    std::string integrator;
    double t = 0.0;                                       // final time reached
    std::vector<std::pair<std::string, double>> state;    // final state, in state_names order
    std::vector<std::pair<std::string, double>> parameters;  // the values used, in parameter_names order
    std::vector<InvariantReport> invariants;
    std::size_t steps = 0, rejected = 0, rhs_evals = 0;   // accepted steps, rejected attempts, system calls
    double wall_s = 0.0;     // integration, including the observer (invariants, CSV)
    double compile_s = 0.0;  // compiling or finding the kernel in the cache, and loading it
    bool cache_hit = false;
    std::string library_path;
    std::string csv_path;    // "" when no CSV was written
    std::size_t csv_rows = 0;
    // Why the run ended before t_end ("" when it reached t_end): an orbit that meets its central
    // body's surface stops there ("re-entered at t = …"). Then `rejected` is not counted.
    std::string stop_reason;

    // The final value of a state component by name; throws std::out_of_range if absent.
    double value(const std::string& name) const;
};

// Throws eomc::InputError for a bad request (unknown override name, with the nearest known
// name; unknown integrator; bad t_end, step or tolerances), std::runtime_error when the kernel
// does not compile (with the compiler's output) or the CSV cannot be written, and
// runtime::IntegrationError when the integration fails (then no CSV is left behind).
SimulationResult simulate(const SimulationRequest& request);

// format: "text" (for people) or "json" (one object, valid JSON: NaN and infinities as null).
void print_summary(const SimulationResult& result, const std::string& format, std::ostream& out);

}  // namespace eomc::cli
