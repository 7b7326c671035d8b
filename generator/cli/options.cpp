#include "cli/options.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "eomc/runtime/integrate.hpp"
#include "eomc/runtime/registry_info.hpp"
#include "model/model.hpp"
#include "scene/scene.hpp"

namespace eomc::cli {

namespace {

// Blanks (spaces, tabs) around a --set name or value, or a list item, are dropped.
std::string_view trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t");
    return first == std::string_view::npos ? std::string_view{} : text.substr(first, last - first + 1);
}

}  // namespace

// --set NAME=VALUE, checked for shape here; the names are checked against the kernel, the values
// against the scene (check_overrides_against_scene).
std::vector<std::pair<std::string, double>> parse_overrides(const std::vector<std::string>& items) {
    std::vector<std::pair<std::string, double>> out;
    for (const auto& item : items) {
        const auto eq = item.find('=');
        SourcePos where{"--set " + item, 0, 0};
        const std::string_view name = eq == std::string::npos ? std::string_view{} : trimmed(std::string_view(item).substr(0, eq));
        if (name.empty()) throw InputError(where, "expected NAME=VALUE");
        out.emplace_back(std::string(name), parse_decimal(std::string_view(item).substr(eq + 1), where));
    }
    return out;
}

// The scene's own checks on the values --set gives its parameters: a body's mass must stay
// positive, and so must an orbit's μ and radius, as when the scene itself gives them. The scene
// is built again with those values as its parameters' (only when --set names a parameter).
void check_overrides_against_scene(const std::string& scene_path, const host::FrontEndOptions& front,
                                   const std::vector<std::string>& items) {
    const auto overrides = parse_overrides(items);
    scene::Scene s = scene::parse_scene_file(scene_path);
    if (!front.orbit_formulation.empty())
        scene::set_orbit_formulation(s, front.orbit_formulation, SourcePos{"--orbit-formulation " + front.orbit_formulation});
    if (!front.rigid_formulation.empty())
        scene::set_rigid_formulation(s, front.rigid_formulation, SourcePos{"--rigid-formulation " + front.rigid_formulation});
    std::string given;
    for (std::size_t i = 0; i < overrides.size(); ++i)
        for (auto& parameter : s.parameters)
            if (parameter.name == overrides[i].first) {
                parameter.value = overrides[i].second;
                given += (given.empty() ? "--set " : " --set ") + items[i];
            }
    if (given.empty()) return;
    try {
        (void)model::build_model(s);
    } catch (const InputError& e) {
        std::string message = e.message();
        const std::string defaults = "with the default parameters";
        if (const auto at = message.find(defaults); at != std::string::npos)
            message.replace(at, defaults.size(), "with the values --set gives");
        throw InputError(SourcePos{given}, fmt::format("{} (checked as in {})", message, to_string(e.where())));
    }
}

namespace {

// The --help texts list what the runtime's registry (eomc/runtime/registry.hpp) holds.
using runtime::integrator_list;
bool adaptive(const runtime::IntegratorInfo& info) { return !info.fixed_step(); }
bool fixed_step(const runtime::IntegratorInfo& info) { return info.fixed_step(); }

// CLI11 would read "0x10" and "inf" as numbers: the numeric options take parse_decimal's grammar.
const CLI::Validator decimal(
    [](std::string& text) {
        try {
            (void)parse_decimal(text, SourcePos{});
            return std::string();
        } catch (const InputError& e) {
            return e.message();
        }
    },
    "DECIMAL");

}  // namespace

void add_integration_options(CLI::App* cmd, SimulateOptions& o) {
    cmd->add_option("--t-end", o.t_end, "final time (default: [simulate] t_end)")->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--integrator", o.integrator,
                    fmt::format("{} (default: [simulate] integrator; {} need a separable system)",
                                integrator_list(" | "),
                                integrator_list([](const auto& i) { return i.needs_separable; })))
        ->check(CLI::IsMember(runtime::integrator_names_where([](const auto&) { return true; })));
    cmd->add_option("--rtol", o.rtol, fmt::format("relative tolerance ({})", integrator_list(adaptive)))
        ->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--atol", o.atol, fmt::format("absolute tolerance ({})", integrator_list(adaptive)))
        ->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--step", o.step, fmt::format("step size ({})", integrator_list(fixed_step)))
        ->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--contact-method", o.contact_method,
                    "unilateral rows: event_driven (impacts located, contact phases, Zeno) or moreau_jean (time "
                    "stepping at [simulate] step) (default: [contact] method)")
        ->check(CLI::IsMember(runtime::contact::contact_method_names()));
    cmd->add_option("--impact-law", o.impact_law,
                    "unilateral rows, event_driven: an impact on several closed contacts by Moreau's simultaneous "
                    "LCP or by sequential two-body impacts (default: [contact] impact_law, else simultaneous)")
        ->check(CLI::IsMember(runtime::contact::impact_law_names()));
    cmd->add_option("--compensated", o.compensated,
                    fmt::format("on | off: compensated (Kahan) summation of the state update (default: [simulate] "
                                "compensated, else on for {} and off for the others)",
                                integrator_list([](const auto& i) { return i.compensated_by_default; })))
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--set", o.overrides, "NAME=VALUE: a parameter, or an initial value (q, q_dot)");
    cmd->add_option("--cache-dir", o.cache_dir, "where compiled kernels are kept (default ~/.cache/eomc)");
    cmd->add_option("--max-steps", o.max_steps,
                    fmt::format("the most steps the run may take (default: {} for the fixed-step methods, refused "
                                "before the run when t_end/step is more; {} attempts for {})",
                                host::SimulationRequest::default_max_fixed_steps, runtime::Limits{}.max_steps,
                                integrator_list(adaptive, " and ")))
        ->check(CLI::PositiveNumber);
}

void add_simulate_options(CLI::App* cmd, SimulateOptions& o) {
    add_integration_options(cmd, o);
    cmd->add_option("--output", o.output, "trajectory CSV (t, state, invariants)");
    cmd->add_option("--summary", o.summary, "text | json")->check(CLI::IsMember({"text", "json"}));
    cmd->add_option("--budget-s", o.budget_s,
                    fmt::format("stop a run whose pace, once it has run for {:.0f} s, projects it past this many "
                                "seconds, with the projection (default {:.0f})",
                                host::SimulationRequest::budget_probe_s, host::default_budget_s))
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--progress", o.progress, "a progress line on stderr from the start, even when it is not a terminal "
                                            "(without it: a bar on a terminal, after a second)");
    cmd->add_option("--max-rows", o.max_rows,
                    fmt::format("the most rows the CSV may hold (default {}); a run that would write more leaves no CSV",
                                host::SimulationRequest::default_max_rows))
        ->check(CLI::PositiveNumber);
}

host::SimulationRequest simulation_request(const host::Pipeline& p, const std::string& header, const SimulateOptions& o) {
    const scene::Simulate& d = p.model.simulate;
    host::SimulationRequest r;
    r.header_text = header;
    r.struct_name = p.model.struct_name;
    r.overrides = parse_overrides(o.overrides);
    r.derived_start = derived_start(p);
    r.t_end = o.t_end.value_or(d.t_end);
    r.integrator = o.integrator.empty() ? d.integrator : o.integrator;
    r.integrator_pos = o.integrator.empty() ? d.integrator_pos : SourcePos{"--integrator"};
    r.variational = p.variational;
    if (!o.compensated.empty()) r.compensated = o.compensated == "on";
    else r.compensated = d.compensated;
    r.rtol = o.rtol.value_or(d.rtol);
    r.atol = o.atol.value_or(d.atol);
    r.step = o.step.value_or(d.step);
    r.csv_path = o.output;
    r.summary_format = o.summary;
    r.cache_dir = o.cache_dir;
    r.max_steps = o.max_steps;
    r.max_rows = o.max_rows;
    r.budget_s = o.budget_s;
    r.progress_always = o.progress;
    // A scene with unilateral rows: its [contact] method, unless --contact-method chose.
    if (!o.contact_method.empty()) {
        r.contact_method = o.contact_method;
        r.contact_method_pos = SourcePos{"--contact-method"};
    } else {
        r.contact_method = runtime::contact::name(p.model.contact_method);
        r.contact_method_pos = p.model.contact_method_pos;
    }
    r.theta = p.model.theta;
    if (!o.impact_law.empty()) {
        r.impact_law = o.impact_law;
        r.impact_law_pos = SourcePos{"--impact-law"};
    } else {
        r.impact_law = runtime::contact::name(p.model.impact_law);
        r.impact_law_pos = p.model.impact_law_pos;
    }
    return r;
}

void add_ensemble_options(CLI::App* cmd, EnsembleOptions& o, bool sweep) {
    if (sweep) {
        cmd->add_flag("--equilibria", o.equilibria, "the relative equilibria and their verdicts at every grid point "
                                                    "(parameters only) instead of runs; --plot draws a bifurcation "
                                                    "diagram over one axis, a stability map over two");
        cmd->add_flag("--linearize", o.linearize, "the linearisation's eigenvalues and verdict at every grid point "
                                                  "(see `eomc linearize`, and --about) instead of runs; --plot draws "
                                                  "the real parts against the one axis varied");
        cmd->add_option("--grid", o.grid, "NAME=a:b:n (n points from a to b inclusive) or NAME=value: a parameter "
                                          "or an initial value; several make a grid, the last varying fastest")
            ->required();
    } else {
        cmd->add_option("--vary", o.vary, "NAME=normal(mu,sigma) | uniform(a,b) | lognormal(mu,sigma): a parameter "
                                          "or an initial value drawn for each member")
            ->required();
        cmd->add_option("--samples", o.samples, "the number of members")->required();
        cmd->add_option("--seed", o.seed, "the random seed, 0 to 2^64 - 1 (default 0); member i draws from "
                                          "splitmix64(seed, i), the same on any thread");
    }
    cmd->add_option("--threads", o.threads, "threads running members (default: the hardware's)")
        ->check(CLI::Range(1u, 4096u));
    cmd->add_option("--observe", o.observe, "NAME=EXPR: a column of EXPR (the scene's syntax, over t, the parameters "
                                            "and the state) at each member's end; event:NAME: the time of its first "
                                            "NAME event (column t_NAME)");
    cmd->add_flag("--batch", o.batch,
                  fmt::format("run the members a SIMD batch at a time through the kernel's batched rhs, in lock step "
                              "({}; a fixed step gives the same rows as without, an adaptive one one step size per "
                              "batch)",
                              integrator_list([](const auto& i) { return i.batch; })));
    cmd->add_option("-o,--output", o.output, "one CSV row per member (inputs, status, final state, invariant drifts, "
                                             "events, message)");
    cmd->add_option("--format", o.format, "summary statistics as text | json")->check(CLI::IsMember({"text", "json"}));
    cmd->add_option("--plot", o.plot, sweep ? "a PNG (gnuplot) of --plot-column against the one varied axis (a "
                                              "bifurcation diagram), or a map of it over two"
                                            : "a PNG (gnuplot): the histogram of --plot-column");
    cmd->add_option("--plot-column", o.plot_column, "t, a state variable or <invariant>_max_drift (default: the "
                                                    "first state variable)");
    cmd->add_option("--budget-s", o.budget_s,
                    fmt::format("refuse work estimated above this many seconds: the first {} timed, times their "
                                "number (default {:.0f})",
                                sweep ? "run (or, with --equilibria, grid point)" : "member", host::default_budget_s))
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-memory-mib", o.max_memory_mib, "refuse an ensemble whose rows, CSV and statistics are "
                                                          "estimated above this many MiB, before it compiles "
                                                          "(default: half the physical memory)")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--progress", o.progress, "a progress line on stderr from the start, even when it is not a terminal "
                                            "(without it: a bar on a terminal, after a second)");
}

host::EnsembleSpec ensemble_spec(const EnsembleOptions& o) {
    host::EnsembleSpec spec;
    for (const auto& g : o.grid) spec.grid.push_back(host::parse_grid(g));
    for (const auto& v : o.vary) spec.vary.push_back(host::parse_variation(v));
    if (!o.vary.empty()) {
        spec.samples = host::parse_samples(o.samples);
        spec.seed = host::parse_seed(o.seed);
    }
    (void)spec.members();  // a grid too large is refused now
    return spec;
}

void check_grid_against_scene(const std::string& scene_path, const host::FrontEndOptions& front,
                              const std::vector<std::string>& overrides, const host::EnsembleSpec& spec) {
    for (const auto& axis : spec.grid)
        for (double end : {axis.first, axis.last}) {
            std::vector<std::string> items = overrides;
            items.push_back(fmt::format("{}={:.17g}", axis.name, end));
            try {
                check_overrides_against_scene(scene_path, front, items);
            } catch (const InputError& e) {
                throw InputError(axis.where, fmt::format("at {} = {}: {}", axis.name, end, e.message()));
            }
        }
}

std::vector<std::string> comma_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        const auto first = item.find_first_not_of(" \t"), last = item.find_last_not_of(" \t");
        if (first != std::string::npos) out.push_back(item.substr(first, last - first + 1));
    }
    return out;
}



namespace {

// A comma-separated list of numbers (--tolerances 1e-6,1e-9), checked for shape here.
std::vector<double> number_list(const std::string& text, const char* option) {
    std::vector<double> out;
    for (const auto& item : comma_list(text)) out.push_back(parse_decimal(item, SourcePos{option}));
    return out;
}

}  // namespace

void add_bench_options(CLI::App* cmd, BenchOptions& o) {
    cmd->add_option("--methods", o.methods,
                    fmt::format("comma-separated subset of {} (default: all)", fmt::join(host::bench_method_names, ", ")));
    cmd->add_option("--t-end", o.t_end, "end time (default: [simulate] t_end)")->check(CLI::PositiveNumber);
    cmd->add_option("--tolerances", o.tolerances, "comma-separated rtol = atol of the adaptive methods "
                                                     "(default: 1e-3 .. 1e-15 in half decades)");
    cmd->add_option("--steps", o.steps, "comma-separated step counts of the fixed-step methods "
                                           "(default: 16 .. 2^20 in half octaves, until round-off)");
    cmd->add_option("--min-time", o.min_time, "seconds the timed repetitions of a run add up to at least (default 0.02)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--repeats", o.repeats, "fewest timed repetitions of a run (default 3)")->check(CLI::PositiveNumber);
    cmd->add_option("--budget-s", o.budget_s,
                    "stop a run (the reference's too) once its pace, after 2 s, projects it past this many seconds, "
                    "with the projection (default 3600)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--odeint-state", o.odeint_state,
                      "vector (default: the container eomc's runtime steps) | array (std::array of the kernel's size)")
        ->check(CLI::IsMember({"vector", "array"}));
    cmd->add_option("--cache-dir", o.cache_dir, "where compiled programs are kept (default ~/.cache/eomc)");
    cmd->add_option("--formulations", o.formulations,
                      "orbit scenes: comma-separated formulations to compare by their position at t_end against a "
                      "float128 Cowell run (default: all built: " +
                          std::string(fmt::format("{}", fmt::join(scene::orbit_formulation_names, ", "))) +
                          "); rigid-body scenes: by ω and γ at t_end against a float128 Euler-Poisson run, and by "
                          "the drift of the energy (default: all built: " +
                          std::string(fmt::format("{}", fmt::join(scene::rigid_formulation_names, ", "))) + ")");
    cmd->add_option("--reference-tolerance", o.reference_tolerance,
                      "orbit and rigid-body scenes: rtol = atol of the float128 reference run (Cowell, Euler-Poisson; "
                      "default 1e-26; checked against a run 1000 times looser)");
}

host::BenchRequest bench_request(const host::Pipeline& p, const std::string& header, const codegen::KernelIR& ir,
                                 const std::string& scene_path, const std::string& out_dir, const BenchOptions& o) {
    host::BenchRequest r;
    r.header_text = header;
    r.struct_name = p.model.struct_name;
    r.scene_name = p.model.name;
    r.scene_path = scene_path;
    if (!p.model.reference.empty()) r.reference_body = codegen::emit_reference_body(ir, p.model.reference);
    r.autonomous = !host::depends_on_time(p);
    r.t_end = o.t_end.value_or(p.model.simulate.t_end);
    r.methods = comma_list(o.methods);
    r.tolerances = number_list(o.tolerances, "--tolerances");
    r.steps = number_list(o.steps, "--steps");
    r.odeint_array = o.odeint_state == "array";
    r.min_time = o.min_time;
    r.repeats = o.repeats;
    r.out_dir = out_dir;
    r.cache_dir = o.cache_dir;
    r.reference_tolerance = o.reference_tolerance;
    r.budget_s = o.budget_s;
    return r;
}

}  // namespace eomc::cli
