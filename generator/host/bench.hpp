// `eomc bench`: work-precision sweeps of every integrator on one scene, ours and Boost.Odeint's
// side by side on the same emitted kernel.
//
// On an orbit or a rigid-body scene the sweep has a second axis, the formulation: one such program
// per formulation's kernel, all judged by a few columns at t_end (an orbit's Cartesian position, a
// body's ω and γ) against one float128 run of a reference formulation (Cowell's, Euler–Poisson's;
// cached), so that their accuracy and cost compare directly.
//
// The sweep itself runs in a generated program, templates/bench_driver.cpp compiled with the
// kernel header and a small configuration header (the model's struct, whether it is autonomous,
// the closed-form reference of the scene's [reference] printed as C++). This module validates
// the request, builds (or finds in the cache) that program, runs it, and turns its CSV into
// DIR/work_precision.csv, DIR/work_precision.png (gnuplot) and a table.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "eomc/runtime/registry.hpp"

namespace eomc::host {

// Boost.Odeint's methods the driver also runs, under their own names.
inline constexpr std::array<std::string_view, 4> odeint_method_names{
    "runge_kutta_dopri5", "runge_kutta_fehlberg78", "bulirsch_stoer", "symplectic_rkn_sb3a_mclachlan"};

// Every method the driver knows: ours, the runtime's registry (eomc/runtime/registry.hpp) in its
// order, then Boost.Odeint's.
inline constexpr auto bench_method_names = [] {
    std::array<std::string_view, runtime::integrator_names.size() + odeint_method_names.size()> all{};
    std::size_t k = 0;
    for (std::string_view name : runtime::integrator_names) all[k++] = name;
    for (std::string_view name : odeint_method_names) all[k++] = name;
    return all;
}();

// One formulation of an orbit or a rigid-body scene: its kernel, judged by the axis's columns (the
// state's components of those names, or else its outputs).
struct BenchFormulation {
    std::string name;         // "cowell", "equinoctial", …
    std::string header_text;  // its emitted kernel
    std::string struct_name;  // "LeoJ2Equinoctial"
    std::string scene_name;   // "leo_j2_equinoctial"
    bool autonomous = true;
};

// What the formulations of one family (orbit, rigid body) are judged by, and how it is reported.
struct FormulationAxis {
    std::string reference = "cowell";              // the formulation whose float128 run judges the others
    std::vector<std::string> judged{"x", "y", "z"};  // the columns compared at t_end
    std::string judged_what = "position";          // for the plot and the notes
    std::string error_column = "position_error";   // the CSV's name of the error
    std::string drift_column = "max_invariant_drift";
    std::vector<std::string> drift_invariants;     // the invariants whose drift is measured; empty: all
    std::vector<double> table_levels{1.0, 1e-3, 1e-6};  // the table's error levels
    // A characteristic period (an orbit's, a body's turn 2π/|ω0|): fixed-step methods default to 8 ..
    // 2048 steps per period; 0: unknown (the driver's own default).
    double period = 0.0;
    std::string lost = "runs that lost the orbit, error > its radius";  // what an error above |reference| means
    // The judged columns at t_end in closed form, when the scene has one (a free rigid body: the
    // Euler–Poinsot motion), which the float128 reference is checked against; empty otherwise.
    std::vector<double> exact;
    std::string exact_source;
};

struct BenchRequest {
    std::string header_text;     // the emitted kernel, as `eomc generate` writes it
    std::string struct_name;     // "KeplerE06"
    std::string scene_name;      // "kepler_e06"
    std::string scene_path;      // for messages and the reference's provenance
    std::string reference_body;  // codegen::emit_reference_body(); "" when the scene has no [reference]
    bool autonomous = true;      // the equations do not depend on t explicitly
    double t_end = 1.0;
    std::vector<std::string> methods;  // a subset of bench_method_names; empty: all of them
    std::vector<double> tolerances;    // rtol = atol of the adaptive methods; empty: 1e-3 .. 1e-15
    std::vector<double> steps;         // step counts of the fixed-step methods; empty: 16 .. 2^20
    bool odeint_array = false;         // odeint on std::array<double, n_state> instead of std::vector
    double min_time = 0.02;            // each run is repeated until the repetitions add up to this ...
    int repeats = 3;                   // ... and at least this often; the median is reported
    std::string out_dir = ".";
    std::string cache_dir;             // "" = default_cache_dir()
    // An orbit or rigid-body scene's formulation axis. Non-empty: the kernel above must be the
    // axis's reference formulation's; it gives the reference, and every formulation listed here is
    // swept (methods empty: dop853, dopri5, rk4; steps empty: 8 .. 2048 per axis.period when > 0).
    std::vector<BenchFormulation> formulations;
    std::vector<std::string> skipped;   // formulations that do not take the scene, with the reason (notes)
    FormulationAxis axis;
    double reference_tolerance = 1e-26; // rtol = atol of the float128 reference run
    double budget_s = 3600.0;           // one run's projected seconds, the reference's too (--budget-s)
};

// One run of one method at one setting (one CSV row).
struct BenchRow {
    std::string formulation;            // "" outside a formulation bench
    std::string method, library, kind;  // kind: "tolerance" | "steps"
    double setting = 0;                 // rtol = atol, or the number of steps over [0, t_end]
    double error = 0;                   // max-norm distance of the final state from the reference; formulation
                                        // bench: Euclidean distance of the judged columns at t_end
    double drift = 0;                   // max over the run and the (measured) invariants of |I - I0| / |I0|; NaN: none
    std::size_t rhs_evals = 0, steps = 0, rejected = 0;
    double seconds = 0;                 // median wall time of one run
    int repetitions = 0;
};

struct BenchResult {
    std::vector<BenchRow> rows;
    std::vector<std::string> notes;  // the reference used, methods skipped, settings that failed
    std::string csv_path, png_path;  // png_path "" when no plot was made
    std::string driver_path;            // formulation bench: the reference formulation's driver
    bool cache_hit = false;
    // Formulation bench: how far the judged columns of a reference run 1000 times looser end from
    // the reference's (a bound on its error); NaN otherwise.
    double reference_spread = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> table_levels;   // formulation bench: the axis's; empty: 1e-6, 1e-9, 1e-12
};

// The CSV header of work_precision.csv.
inline constexpr const char* bench_csv_header =
    "method,library,kind,setting,error,max_invariant_drift,rhs_evals,steps,rejected,wall_seconds,repetitions";
// ... and of a formulation bench's: the formulation first, the error as the judged columns' distance
// from the reference at t_end (an orbit's position_error in the scene's length unit), the drift of
// the measured invariants under the axis's names.
std::string bench_formulation_csv_header(const FormulationAxis& axis);

// Throws eomc::InputError for a bad request (an unknown method, with the nearest name; a bad
// end time, tolerance or step count) before compiling anything; std::runtime_error when the
// driver does not compile or fails. Nothing is left in out_dir on failure. When gnuplot is
// missing (or fails) the CSV is still written and a note says why there is no plot.
BenchResult bench(const BenchRequest& request);

// bench_config.hpp for a request (exposed for tests).
std::string bench_config_source(const BenchRequest& request);

// Per method (per formulation and method on a formulation bench): the cheapest run (wall time) reaching each of a few error levels, the best error,
// and the largest invariant drift; then the notes.
void print_bench_table(const BenchResult& result, std::ostream& out);

}  // namespace eomc::host
