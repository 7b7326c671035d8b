// `eomc bench`: work-precision sweeps of every integrator on one scene, ours and Boost.Odeint's
// side by side on the same emitted kernel.
//
// The sweep itself runs in a generated program, templates/bench_driver.cpp compiled with the
// kernel header and a small configuration header (the model's struct, whether it is autonomous,
// the closed-form reference of the scene's [reference] printed as C++). This module validates
// the request, builds (or finds in the cache) that program, runs it, and turns its CSV into
// DIR/work_precision.csv, DIR/work_precision.png (gnuplot) and a table.
#pragma once

#include <array>
#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace eomc::cli {

// Every method the driver knows, ours first, then Boost.Odeint's under their own names.
inline constexpr std::array<std::string_view, 13> bench_method_names{
    "rk4",      "dopri5",   "dop853",
    "gl4",      "gl6",      "gl8",
    "verlet",   "yoshida6", "kahanli8",
    "runge_kutta_dopri5", "runge_kutta_fehlberg78", "bulirsch_stoer", "symplectic_rkn_sb3a_mclachlan"};

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
};

// One run of one method at one setting (one CSV row).
struct BenchRow {
    std::string method, library, kind;  // kind: "tolerance" | "steps"
    double setting = 0;                 // rtol = atol, or the number of steps over [0, t_end]
    double error = 0;                   // max-norm distance of the final state from the reference
    double drift = 0;                   // max over the run and the invariants of |I - I0| / |I0|; NaN: no invariants
    std::size_t rhs_evals = 0, steps = 0, rejected = 0;
    double seconds = 0;                 // median wall time of one run
    int repetitions = 0;
};

struct BenchResult {
    std::vector<BenchRow> rows;
    std::vector<std::string> notes;  // the reference used, methods skipped, settings that failed
    std::string csv_path, png_path;  // png_path "" when no plot was made
    std::string driver_path;
    bool cache_hit = false;
};

// The CSV header of work_precision.csv.
inline constexpr const char* bench_csv_header =
    "method,library,kind,setting,error,max_invariant_drift,rhs_evals,steps,rejected,wall_seconds,repetitions";

// Throws eomc::InputError for a bad request (an unknown method, with the nearest name; a bad
// end time, tolerance or step count) before compiling anything; std::runtime_error when the
// driver does not compile or fails. Nothing is left in out_dir on failure. When gnuplot is
// missing (or fails) the CSV is still written and a note says why there is no plot.
BenchResult bench(const BenchRequest& request);

// bench_config.hpp for a request (exposed for tests).
std::string bench_config_source(const BenchRequest& request);

// Per method: the cheapest run (wall time) reaching each of a few error levels, the best error,
// and the largest invariant drift; then the notes.
void print_bench_table(const BenchResult& result, std::ostream& out);

}  // namespace eomc::cli
