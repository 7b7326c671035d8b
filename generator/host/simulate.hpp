// `eomc simulate`: compile an emitted kernel header (cached), integrate it with the runtime,
// watch its invariants, write a CSV and print a summary. The request says what was asked, by name
// (the flags and the scene's defaults); resolve_settings turns it into the runtime's types, checked
// once; host/simulate/ runs it along the runtime's seams (request, smooth run, contact run,
// watches, output, summary).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "eomc/runtime/contact/method.hpp"
#include "eomc/runtime/registry_info.hpp"
#include "eomc/runtime/state.hpp"
#include "support/diagnostic.hpp"

namespace eomc::host {

struct SimulationRequest {
    std::string header_text;                                // emitted kernel header
    std::string struct_name;                                // e.g. "DiskTubeBall"
    std::vector<std::pair<std::string, double>> overrides;  // --set NAME=VALUE: parameters, or initial values "q" / "q_dot"; later wins
    // The checks a start passes beyond what the kernel knows (the rows hold, their Jacobian has full
    // rank, M is positive definite, the inertias are a body's: cli::member_start_check), called by
    // resolve_start with the overrides once their names and values are accepted; throws InputError.
    // Empty: none. An ensemble calls it from several threads at once.
    std::function<void(const std::vector<std::pair<std::string, double>>&)> check_start;
    // The initial values and rates the scene gives as expressions of the parameters, at the
    // overrides' values (model::initial_overrides through cli::derived_start), applied after them by
    // resolve_start. Empty: none. Called from several threads at once, like check_start.
    std::function<std::vector<std::pair<std::string, double>>(const std::vector<std::pair<std::string, double>>&)>
        derived_start;
    double t_end = 10.0;
    std::string integrator{runtime::default_integrator};    // a name in runtime::integrator_infos
    SourcePos integrator_pos{"--integrator"};               // where it was chosen: the flag, or the scene's [simulate] integrator
    double rtol = 1e-10, atol = 1e-12;                      // the adaptive methods
    double step = 1e-3;                                     // the fixed-step methods
    std::optional<bool> compensated;                        // absent: the integrator's compensated_by_default
    std::string csv_path;                                   // "" = no CSV
    std::string summary_format = "text";                    // "text" | "json"
    std::string cache_dir;                                  // "" = $XDG_CACHE_HOME/eomc or ~/.cache/eomc
    bool progress = true;  // progress bar on stderr, only when stderr is a terminal and the run lasts > ~1 s
    bool progress_always = false;  // --progress: from the start, wherever stderr goes (a line per update)
    // Wall-clock seconds the run may take, projected from its pace once it has run budget_probe_s
    // (the time so far × t_end / t): past it the run stops with the projection, and no CSV. 0: none
    // (the library's default; the command line's is default_budget_s).
    double budget_s = 0.0;
    static constexpr double budget_probe_s = 2.0;
    // Integrate the state-transition matrix too: the state is (x, Φ) with Φ(0) = I, Φ row-major,
    // its entries named Phi_<i>_<j> (indices into the kernel's state). The kernel must have been
    // generated with --variational.
    bool variational = false;
    // Kernels with unilateral rows (contacts) only: "event_driven" (runtime::contact::
    // integrate_event_driven, with the adaptive dense-output integrator dopri5 or dop853 and
    // rtol/atol) or "moreau_jean" (runtime::integrate_moreau_jean, fixed `step`, θ-method with
    // `theta`). The scene's [contact] table sets them, or --contact-method.
    std::string contact_method{runtime::contact::name(runtime::contact::ContactMethod::event_driven)};
    SourcePos contact_method_pos{"--contact-method"};
    double theta = 0.5;
    // event_driven: Moreau's simultaneous LCP on the closed contacts of an impact ("simultaneous") or
    // sequential two-body impacts ("sequential"); Moreau–Jean is simultaneous by construction.
    std::string impact_law{runtime::contact::name(runtime::contact::ImpactLaw::simultaneous)};
    SourcePos impact_law_pos{"--impact-law"};
    // event_driven: a geometric accumulation of impacts (Zeno) is extrapolated once zeno_ratios
    // successive interval ratios agree and the intervals are no longer resolved (runtime::contact::
    // EventDrivenOptions); 0 never extrapolates (the run is then refused where its impacts
    // accumulate faster than the integration resolves them).
    int zeno_ratios = 3;
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

// The request's choices as the runtime's types, each checked once, by one rule
// (resolve_settings): what the runs read instead of the request's names.
struct RunSettings {
    const runtime::IntegratorInfo* method = nullptr;  // never null once resolved
    runtime::Tolerances tolerances;                   // the adaptive methods'
    double step = 0.0;                                // the fixed-step methods' and Moreau–Jean's
    bool compensated = false;                         // the request's, else the method's default
    runtime::contact::ContactMethod contact_method = runtime::contact::ContactMethod::event_driven;
    runtime::contact::ImpactLaw impact_law = runtime::contact::ImpactLaw::simultaneous;
    double theta = 0.5;                               // Moreau–Jean's θ
};

// The request checked and resolved before anything is compiled (a typo costs no compile): the
// integrator, contact method and impact law by their tables (with the nearest name), the end time,
// step and tolerances (positive and finite), the step and row budgets of a fixed-step run, θ and
// the summary format. Throws InputError at the option or scene value that chose the setting.
RunSettings resolve_settings(const SimulationRequest& request);

// The method with its step or tolerances, as summaries print it: "dop853 (rtol 1e-10, atol
// 1e-12)", "gl6 (step 0.01, compensated)".
std::string describe_method(const RunSettings& settings, bool show_compensated = true);

// A fixed-step run of ceil(t_end / step) steps (an integrator's or Moreau–Jean's) refused at --step
// when it exceeds the request's step budget, and at --output when its CSV would exceed max_rows.
void check_fixed_step_budget(const SimulationRequest& request, std::string_view method, double step);

struct InvariantReport {
    std::string name;
    double initial = 0.0;        // I(0)
    double final = 0.0;          // I(t_end)
    // max over accepted steps of |I(t) − I(0)|; with jumps (impacts, Zeno points) of |I(t) − I at
    // the start of the smooth phase holding t|: the integrator's drift, not the jumps' physics.
    double max_abs_drift = 0.0;
    std::size_t jumps = 0;     // the jumps of the state between observed points
    double jump_change = 0.0;  // Σ of I after − I before, over the jumps
    // max_abs_drift / |I(0)|, NaN when I(0) = 0.
    double relative_drift() const;
};

// One constraint row of the kernel: the largest |residual| (f for a holonomic row, φ for a
// kinematic one) seen at the observed points of the run.
struct ConstraintReport {
    std::string name;
    double max_abs_residual = 0.0;
};

// One program of the kernel (Mei ch. 3): its residual at t0 (ω0, ω̇0 or φ0), the largest |residual|
// and the largest departure |ω(t) − ω_E(t)| of the run from Erugin's closed-form law ω_E with the
// same initial values (runtime/program/erugin.hpp), over the observed points.
struct ProgramReport {
    std::string name;
    std::string law;             // "omega_ddot + 2 omega_dot + 4 omega = 0", "phi_dot + 1 phi = 0", or "open loop"
    double initial = 0.0, initial_rate = 0.0;
    double final = 0.0;
    double max_abs_residual = 0.0;
    double max_departure = 0.0;
};

// One located event (a zero crossing of the scene's g), with the state there.
struct EventReport {
    std::string name;
    double t = 0.0;
    int direction = 0;  // +1 g went up through zero, -1 down
    bool terminal = false;
    std::vector<double> state;
};

// One event of a unilateral row (kernels with contacts): kind is "impact", "contact",
// "separation" or "zeno". For an impact: the row's rate ḟ⁻ and ḟ⁺ (φ for a kinematic row), its
// percussion P (a generalized impulse, Δ(∂T/∂q̇) = P ∂f/∂q), the kinetic energy change T⁺ − T⁻ of
// the impact and Carnot's prediction −((1 − e)/(1 + e)) ½ ΔuᵀMΔu (Mei ch. 6). For a contact: λ
// where the contact phase starts. For a Zeno point: the ratio of the impact intervals and the
// extrapolation's error bound.
struct ContactEventReport {
    std::string kind, name;
    double t = 0.0;
    double rate_before = 0.0, rate_after = 0.0, impulse = 0.0, energy_change = 0.0, carnot = 0.0;
    double lambda = 0.0;
    double ratio = 0.0, extrapolation_error = 0.0;
};

// One unilateral row at the end of the run: λ (a generalized force, M u̇ = f + Wᵀλ; Moreau–Jean:
// the step's impulse over the step) and whether it is in the active set.
struct ContactReport {
    std::string name;
    bool kinematic = false;
    double restitution = 0.0;
    double lambda = 0.0;
    bool active = false;
    std::size_t impacts = 0;
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
    std::vector<ProgramReport> programs;                  // the kernel's programs (none for most)
    // Kernels with unilateral rows: the method, each row at the end, and every contact event in
    // time order (the CSV has the same as rows labelled kind:name in its event column).
    std::string contact_method;
    std::string impact_law;  // with unilateral rows: "simultaneous" or "sequential"
    std::vector<ContactReport> contacts;
    std::vector<ContactEventReport> contact_events;
    std::string stopped_by;                               // the terminal event that ended the run, "" if none
    std::size_t steps = 0, rejected = 0, rhs_evals = 0;   // accepted steps, rejected attempts, system calls
    // An explicit adaptive run whose steps sat at the method's stability boundary: the hint to use
    // radau5 ("" otherwise).
    std::string hint;
    // What the run could not vouch for (an event function that would not resolve; events compared
    // at the ends of fixed steps only), each a sentence.
    std::vector<std::string> warnings;
    double wall_s = 0.0;     // integration, including the observer (invariants, CSV)
    double compile_s = 0.0;  // compiling or finding the kernel in the cache, and loading it
    bool cache_hit = false;
    std::string library_path;
    std::string csv_path;    // "" when no CSV was written
    std::size_t csv_rows = 0;

    // The final value of a state component, or else of an output, or else lambda_<row> of a
    // unilateral row, by name; throws
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

// The checks simulate() makes before compiling: resolve_settings, its result dropped, and the
// CSV's target (a regular file or nothing).
void validate_request(const SimulationRequest& request);

// What a run's checks need to know of a kernel before it is compiled: the generator's IR has it,
// and so has a loaded library.
struct KernelShape {
    std::string scene_name;
    std::size_t contacts = 0;             // unilateral rows
    std::vector<std::string> event_names;  // the scene's [events]
};

// The checks of a run with unilateral rows that need only the kernel's shape and the settings:
// scene events only with the event-driven method, no --variational, at most 64 rows, the
// sequential impact law only event-driven, Moreau–Jean's step and step budget, an adaptive
// dense-output integrator for the event-driven method. Nothing for a kernel without contacts.
// Throws InputError at the option or scene table that chose the setting. The command line calls
// it before it writes or compiles anything; simulate() again on the loaded kernel.
void check_contact_settings(const KernelShape& kernel, const SimulationRequest& request, const RunSettings& settings);

class KernelLibrary;
// simulate() on a kernel already loaded (request.header_text, struct_name and cache_dir unused):
// the ensembles run their members through it, many at once on one library; it writes nothing
// unless request.csv_path is set, and reads no shared state.
SimulationResult simulate_loaded(const SimulationRequest& request, const KernelLibrary& lib);

// Where simulate_loaded() starts: the kernel's parameter defaults and initial state with the
// request's overrides applied (throws InputError at --set as it does), checked by
// request.check_start when it is set and there are overrides. The batched ensembles start their
// lanes from it.
void resolve_start(const SimulationRequest& request, const KernelLibrary& lib, std::vector<double>& parameters,
                   std::vector<double>& x);

// The splitting methods (verlet, yoshida6, kahanli8) step q̈ = a(t, q): throws InputError at
// `where` when `integrator` is one of them and the kernel is not separable. simulate() calls it
// on the compiled kernel; the command line calls it on the kernel IR before anything is written.
void check_separable(const runtime::IntegratorInfo& method, const SourcePos& where, bool separable,
                     const std::string& scene_name);

// format: "text" (for people) or "json" (one object, valid JSON: NaN and infinities as null).
void print_summary(const SimulationResult& result, const std::string& format, std::ostream& out);

}  // namespace eomc::host
