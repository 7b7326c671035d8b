// The command line's options: one decimal grammar for every number, --set overrides checked
// as the scene checks its own values, and the options `simulate` and `bench` share.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/bench.hpp"
#include "host/ensemble_budget.hpp"
#include "host/ensemble_spec.hpp"
#include "host/pipeline.hpp"
#include "host/simulate.hpp"
#include "support/decimal.hpp"
#include "support/diagnostic.hpp"

namespace eomc::cli {

// The one decimal grammar (support/decimal.hpp).
using eomc::parse_decimal;

// --set NAME=VALUE items, checked for shape.
std::vector<std::pair<std::string, double>> parse_overrides(const std::vector<std::string>& items);

// The scene's own checks on the values --set gives its parameters.
void check_overrides_against_scene(const std::string& scene_path, const host::FrontEndOptions& front,
                                   const std::vector<std::string>& items);

struct SimulateOptions {
    std::string contact_method;  // --contact-method; "" = the scene's [contact] method
    std::string impact_law;      // --impact-law; "" = the scene's [contact] impact_law
    std::optional<double> t_end, rtol, atol, step;
    std::string integrator, output, summary = "text", compensated;
    std::vector<std::string> overrides;
    std::string cache_dir;
    std::optional<std::size_t> max_steps;
    std::size_t max_rows = host::SimulationRequest::default_max_rows;
    double budget_s = host::default_budget_s;  // simulate/run --budget-s: the run's projected time
    bool progress = false;                     // simulate/run --progress
};

// The run's method and inputs (--t-end … --set, --cache-dir, --max-steps), shared with the ensembles.
void add_integration_options(CLI::App* cmd, SimulateOptions& o);
// add_integration_options and the trajectory's outputs (--output, --summary, --max-rows).
void add_simulate_options(CLI::App* cmd, SimulateOptions& o);
host::SimulationRequest simulation_request(const host::Pipeline& p, const std::string& header, const SimulateOptions& o);

// `eomc sweep` (--grid) and `eomc ensemble` (--vary, --samples, --seed); counts are taken as text
// so that a bad one is refused by the specification's own checks, at its flag.
struct EnsembleOptions {
    std::vector<std::string> grid, vary, observe;
    std::string samples, seed = "0";
    unsigned threads = 0;  // 0 = the hardware's
    bool batch = false;    // --batch: SIMD batches of members (host/ensemble_batch.hpp)
    bool linearize = false;   // sweep --linearize: eigenvalues per grid point (host/linearize_sweep.hpp)
    bool equilibria = false;  // sweep --equilibria: verdicts per grid point (host/equilibria_sweep.hpp)
    std::string output, format = "text";
    std::string plot, plot_column;  // --plot FILE.png, --plot-column NAME ("" = the first state variable)
    double budget_s = host::default_budget_s;  // --budget-s: the work estimated, refused past it
    std::optional<std::size_t> max_memory_mib;  // --max-memory-mib (default: half the physical memory)
    bool progress = false;  // --progress: a progress line on stderr even when it is not a terminal
};

void add_ensemble_options(CLI::App* cmd, EnsembleOptions& o, bool sweep);
host::EnsembleSpec ensemble_spec(const EnsembleOptions& o);
// The checks every start passes (mechanics::check_start: the rows hold and their Jacobian has full
// rank, M is positive definite, the inertias are a body's), on the scene's own initial values and,
// when `overrides` is not empty, on the values they give. Refused at the scene's place for the
// scene's values, at `given` (the flags, "--set x=5") for the overrides', naming the scene's place
// the check is made as.
void check_start(const host::Pipeline& p, const std::vector<std::pair<std::string, double>>& overrides,
                 const std::string& given);
// The same check of each ensemble member's start, for SimulationRequest::check_start (resolve_start
// calls it on the pool's threads; GiNaC is not thread-safe, so one at a time). A member refused
// names its values by the flag that gave each (--set, --grid, --vary).
std::function<void(const std::vector<std::pair<std::string, double>>&)> member_start_check(
    const host::Pipeline& p, const host::EnsembleSpec& spec);

// The initial values the scene gives as expressions of the parameters, recomputed at each run's
// overrides (SimulationRequest::derived_start); empty when the scene gives numbers only.
std::function<std::vector<std::pair<std::string, double>>(const std::vector<std::pair<std::string, double>>&)>
derived_start(const host::Pipeline& p);

// The scene's own checks (check_overrides_against_scene) on a grid's end points: the axes are
// linear, so a value the scene accepts at both ends it accepts between. Throws at the --grid.
void check_grid_against_scene(const std::string& scene_path, const host::FrontEndOptions& front,
                              const std::vector<std::string>& overrides, const host::EnsembleSpec& spec);

struct BenchOptions {
    std::optional<double> t_end;
    std::string methods, tolerances, steps, cache_dir, odeint_state = "vector", formulations;
    double reference_tolerance = 1e-26;
    double min_time = 0.02;
    int repeats = 3;
    double budget_s = host::default_budget_s;
};

void add_bench_options(CLI::App* cmd, BenchOptions& o);
// The request of a bench run on p's kernel `header` printed from `ir` (an orbit scene's formulation axis is added by
// host::add_orbit_formulations, a rigid-body scene's by host::add_rigid_formulations).
host::BenchRequest bench_request(const host::Pipeline& p, const std::string& header, const codegen::KernelIR& ir,
                                 const std::string& scene_path, const std::string& out_dir, const BenchOptions& o);

// A comma-separated list (--methods dop853,gl8); blanks around items are dropped.
std::vector<std::string> comma_list(const std::string& text);

}  // namespace eomc::cli
