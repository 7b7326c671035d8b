// `eomc simulate`: compile an emitted kernel header (cached), integrate it with the runtime,
// watch its invariants, write a CSV and print a summary.
#pragma once

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "eomc/runtime/state.hpp"
#include "support/diagnostic.hpp"

namespace eomc::host {

struct SimulationRequest {
    std::string header_text;                                // emitted kernel header
    std::string struct_name;                                // e.g. "DiskTubeBall"
    std::vector<std::pair<std::string, double>> overrides;  // --set NAME=VALUE: parameters, or initial values "q" / "q_dot"; later wins
    double t_end = 10.0;
    std::string integrator = "dopri5";                      // one of scene::integrator_names
    SourcePos integrator_pos{"--integrator"};               // where it was chosen: the flag, or the scene's [simulate] integrator
    double rtol = 1e-10, atol = 1e-12;                      // dopri5, dop853
    double step = 1e-3;                                     // the fixed-step methods
    std::optional<bool> compensated;                        // absent: scene::compensated_by_default(integrator)
    std::string csv_path;                                   // "" = no CSV
    std::string summary_format = "text";                    // "text" | "json"
    std::string cache_dir;                                  // "" = $XDG_CACHE_HOME/eomc or ~/.cache/eomc
    bool progress = true;  // progress bar on stderr, only when stderr is a terminal and the run lasts > ~1 s
    // Integrate the state-transition matrix too: the state is (x, Φ) with Φ(0) = I, Φ row-major,
    // its entries named Phi_<i>_<j> (indices into the kernel's state). The kernel must have been
    // generated with --variational.
    bool variational = false;
    // Bounds on the work a request can ask for (a hostile or mistyped --t-end 1e300, --step 1e-15).
    // Step attempts: absent = default_max_fixed_steps for the fixed-step methods, whose count
    // ceil(t_end/step) is known and checked before anything is compiled, and the runtime's own
    // budget (runtime::Limits, 10^7 attempts) for the adaptive ones, which fail when it runs out.
    std::optional<std::size_t> max_steps;
    // CSV rows (the header not counted): a fixed-step run that would write more is refused before
    // it starts; an adaptive one stops when it reaches the limit, and leaves no CSV.
    std::size_t max_rows = default_max_rows;

    static constexpr std::size_t default_max_fixed_steps = 100'000'000;
    static constexpr std::size_t default_max_rows = 10'000'000;  // ~1 GB for a handful of columns
};

struct InvariantReport {
    std::string name;
    double initial = 0.0;        // I(0)
    double final = 0.0;          // I(t_end)
    double max_abs_drift = 0.0;  // max over accepted steps of |I(t) − I(0)|
    // max_abs_drift / |I(0)|, NaN when I(0) = 0.
    double relative_drift() const;
};

// One constraint row of the kernel: the largest |residual| (f for a holonomic row, φ for a
// kinematic one) seen at the observed points of the run.
struct ConstraintReport {
    std::string name;
    double max_abs_residual = 0.0;
};

// One located event (a zero crossing of the scene's g), with the state there.
struct EventReport {
    std::string name;
    double t = 0.0;
    int direction = 0;  // +1 g went up through zero, -1 down
    bool terminal = false;
    std::vector<double> state;
};

struct SimulationResult {
    std::string scene_name;
    std::string integrator;
    bool compensated = false;
    double t = 0.0;                                       // final time reached
    std::vector<std::pair<std::string, double>> state;    // final state, in state_names order
    // The kernel's outputs at the final state (an element formulation's Cartesian x … z_dot, a
    // free carrier's reactions), in output_names order.
    std::vector<std::pair<std::string, double>> outputs;
    std::vector<std::pair<std::string, double>> parameters;  // the values used, in parameter_names order
    std::vector<InvariantReport> invariants;
    std::vector<EventReport> events;                      // every located event, in time order
    std::vector<ConstraintReport> constraints;            // the kernel's constraint rows (none for most)
    std::string stopped_by;                               // the terminal event that ended the run, "" if none
    std::size_t steps = 0, rejected = 0, rhs_evals = 0;   // accepted steps, rejected attempts, system calls
    double wall_s = 0.0;     // integration, including the observer (invariants, CSV)
    double compile_s = 0.0;  // compiling or finding the kernel in the cache, and loading it
    bool cache_hit = false;
    std::string library_path;
    std::string csv_path;    // "" when no CSV was written
    std::size_t csv_rows = 0;

    // The final value of a state component, or else of an output, by name; throws
    // std::out_of_range if neither has it.
    double value(const std::string& name) const;
};

// Throws eomc::InputError for a bad request (unknown override name, with the nearest known
// name; unknown integrator; bad t_end, step or tolerances; a fixed-step run longer than its step
// budget or its CSV row limit; an output path that is not a regular file; a splitting method on a kernel that
// is not separable, at request.integrator_pos), std::runtime_error when the kernel
// does not compile (with the compiler's output) or the CSV cannot be written, and
// runtime::IntegrationError when the integration fails (then no CSV is left behind).
SimulationResult simulate(const SimulationRequest& request);

// The splitting methods (verlet, yoshida6, kahanli8) step q̈ = a(t, q): throws InputError at
// `where` when `integrator` is one of them and the kernel is not separable. simulate() calls it
// on the compiled kernel; the command line calls it on the kernel IR before anything is written.
void check_separable(const std::string& integrator, const SourcePos& where, bool separable,
                     const std::string& scene_name);

// format: "text" (for people) or "json" (one object, valid JSON: NaN and infinities as null).
void print_summary(const SimulationResult& result, const std::string& format, std::ostream& out);

}  // namespace eomc::host
