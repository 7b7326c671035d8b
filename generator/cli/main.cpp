// eomc: the command line. It parses options and wires one call of the library per command:
// the pipeline (host/pipeline), a printer (report/), a simulation or a benchmark (host/).
// Exit codes: 0 success, 2 bad input (file:line:column: error: …), 1 any other failure.
#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <sys/personality.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cli/options.hpp"
#include "codegen/cpp_text.hpp"
#include "host/bench.hpp"
#include "host/ensemble.hpp"
#include "host/equilibria_sweep.hpp"
#include "host/linearize_sweep.hpp"
#include "host/ensemble_mpi.hpp"
#include "host/gnuplot.hpp"
#include "host/orbit_bench.hpp"
#include "host/pipeline.hpp"
#include "host/rigid_bench.hpp"
#include "host/simulate.hpp"
#include "host/simulate/program_stiffness.hpp"
#include "mechanics/control/control.hpp"
#include "mechanics/inverse/inverse_problem.hpp"
#include "mechanics/linearize/linearize.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "mechanics/rigid/equilibria.hpp"
#include "mechanics/rigid/euler_poisson.hpp"
#include "mechanics/rigid/integrals.hpp"
#include "mechanics/unilateral/equilibria.hpp"
#include "report/control_printer.hpp"
#include "report/derivation_printer.hpp"
#include "report/equilibria_printer.hpp"
#include "report/inverse_printer.hpp"
#include "report/linearize_printer.hpp"
#include "report/rigid_printer.hpp"
#include "report/unilateral_equilibria_printer.hpp"
#include "scene/scene.hpp"
#include "support/cleanup.hpp"
#include "support/diagnostic.hpp"
#include "support/output_file.hpp"

namespace fs = std::filesystem;
using namespace eomc;
using host::Pipeline;

// In a sanitizer build (scripts/sanitize.sh), eomc also runs inside the build, where no
// LSAN_OPTIONS reach it: LeakSanitizer asks this hook for its suppressions, the same as
// scripts/lsan.supp's (CLN's start-up tables; GiNaC's objects half built when it throws).
#if defined(__SANITIZE_ADDRESS__)
#define EOMC_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define EOMC_ADDRESS_SANITIZER 1
#endif
#endif
#ifdef EOMC_ADDRESS_SANITIZER
extern "C" const char* __lsan_default_suppressions() { return "leak:libcln.so\nleak:libginac.so\n"; }
#endif

namespace {

// GiNaC seeds its hash values with the addresses of type_info names, and the order it
// keeps terms in — which decides the form of some derived expressions — follows those
// hashes. With address-space randomisation two runs on the same scene could then print
// different (equal) kernels, so eomc re-executes itself once with randomisation off:
// same scene, same bytes (for this build of eomc: another build, a sanitizer build say,
// maps GiNaC elsewhere and may print other equal forms). If the system refuses, eomc
// carries on and says that its output may differ from run to run.
void ensure_reproducible_layout(char** argv) {
    const char* reason = nullptr;
    const int persona = ::personality(0xffffffff);
    if (std::getenv("EOMC_TEST_ASLR")) {
        reason = "EOMC_TEST_ASLR is set";
    } else if (persona == -1 || ::personality(static_cast<unsigned long>(persona | ADDR_NO_RANDOMIZE)) == -1) {
        reason = "the system refused personality(ADDR_NO_RANDOMIZE)";
    } else if (persona & ADDR_NO_RANDOMIZE) {
        return;
    } else {
        ::execv("/proc/self/exe", argv);
        reason = "eomc could not re-execute itself through /proc/self/exe";
    }
    std::cerr << "eomc: warning: address-space randomisation stays on (" << reason
              << "), so generated code may differ from run to run in the form of its expressions\n";
}


// Every option of every command; each command reads the ones it declares.
struct Options {
    std::string scene_path, format = "text", output, out_dir = ".", emit_scene;
    host::FrontEndOptions front;
    bool timings = false;
    cli::SimulateOptions simulate;
    cli::BenchOptions bench;
    cli::EnsembleOptions ensemble;
    mechanics::inverse::SearchBudget search_budget;
    unsigned degree = mechanics::rigid::default_search_degree;
    std::size_t integral_work = mechanics::rigid::default_search_work;
    std::optional<double> spin;  // equilibria of a rigid body: Ω of the sleeping families
    std::string about = "equilibrium";  // linearize, sweep --linearize: the operating point
    std::vector<std::string> set;       // linearize --set NAME=VALUE
};

struct Commands {
    CLI::App *derive, *generate, *simulate, *equilibria, *linearize, *inverse, *control, *integrals, *run, *bench, *sweep, *ensemble;
};

// `linearize`, and the operating point of `sweep --linearize`.
void declare_linearize(CLI::App& app, Options& o, Commands& c) {
    const char* about_help = "equilibrium: the rest state nearest the initial configuration (Newton's method); initial: "
                             "the initial state as given, an equilibrium or a steady motion (rates only of cyclic "
                             "coordinates, no accelerations)";
    c.linearize = app.add_subcommand("linearize", "linearise about an equilibrium or a steady motion, the [[constraint]] "
                                                  "rows eliminated: A, its eigenvalues and modes, a stability verdict");
    c.linearize->add_option("scene", o.scene_path, "scene file (TOML)")->required();
    c.linearize->add_option("--about", o.about, about_help)->check(CLI::IsMember({"equilibrium", "initial"}));
    c.linearize->add_option("--set", o.set, "NAME=VALUE: a parameter, a coordinate's initial value or its NAME_dot rate");
    c.linearize->add_option("--format", o.format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    c.linearize->add_option("-o,--output", o.output, "write to FILE instead of standard output");
    c.sweep->add_option("--about", o.about, std::string("with --linearize: ") + about_help)
        ->check(CLI::IsMember({"equilibrium", "initial"}));
}

Commands declare_commands(CLI::App& app, Options& o) {
    auto scene_argument = [&](CLI::App* cmd) { cmd->add_option("scene", o.scene_path, "scene file (TOML)")->required(); };
    auto hamiltonian_flag = [&](CLI::App* cmd) {
        cmd->add_flag("--hamiltonian", o.front.hamiltonian,
                      "Hamilton's equations in (q, p) instead of Lagrange's in (q, q̇) (as [formulation] kind = "
                      "\"hamiltonian\")");
    };
    auto orbit_formulation = [&](CLI::App* cmd) {
        cmd->add_option("--orbit-formulation", o.front.orbit_formulation,
                        "an orbit scene in another formulation (" +
                            fmt::format("{}", fmt::join(scene::orbit_formulation_names, ", ")) +
                            "); the kernel's name gains _<formulation>");
        cmd->add_option("--rigid-formulation", o.front.rigid_formulation,
                        "a rigid-body scene in another formulation (" +
                            fmt::format("{}", fmt::join(scene::rigid_formulation_names, ", ")) +
                            "); the kernel's name gains _<formulation>");
    };
    auto variational_flag = [&](CLI::App* cmd, const char* what) { cmd->add_flag("--variational", o.front.variational, what); };
    const char* integrate_phi = "integrate the state-transition matrix Φ too (Φ(0) = I; CSV columns Phi_<i>_<j>)";
    Commands c{};

    c.derive = app.add_subcommand("derive", "print the derivation (text, LaTeX or JSON)");
    scene_argument(c.derive);
    c.derive->add_option("--format", o.format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    c.derive->add_option("-o,--output", o.output, "write to FILE instead of standard output");
    hamiltonian_flag(c.derive);
    orbit_formulation(c.derive);

    c.generate = app.add_subcommand("generate", "emit the C++ kernel header <name>.hpp");
    scene_argument(c.generate);
    c.generate->add_option("-o,--output-dir", o.out_dir, "directory for the header (default: .)");
    c.generate->add_flag("--timings", o.timings, "print the time of each stage on stderr (`timing <stage> <seconds>`)");
    hamiltonian_flag(c.generate);
    orbit_formulation(c.generate);
    variational_flag(c.generate, "also emit variational_rhs: the state extended by the state-transition matrix, "
                                 "Φ̇ = (∂ẋ/∂x) Φ (seed §2.9)");
    c.generate->add_flag("--jacobian", o.front.jacobian,
                         "also emit jacobian(), ∂ẋ/∂x (for implicit methods; --variational implies it)");

    c.simulate = app.add_subcommand("simulate", "generate, compile, integrate; write CSV and a summary");
    scene_argument(c.simulate);
    cli::add_simulate_options(c.simulate, o.simulate);
    hamiltonian_flag(c.simulate);
    orbit_formulation(c.simulate);
    variational_flag(c.simulate, integrate_phi);

    c.sweep = app.add_subcommand("sweep", "one compiled kernel run over a grid of parameters or initial values: a "
                                          "CSV row per run, statistics printed");
    scene_argument(c.sweep);
    cli::add_integration_options(c.sweep, o.simulate);
    cli::add_ensemble_options(c.sweep, o.ensemble, true);
    c.ensemble = app.add_subcommand("ensemble", "Monte Carlo: one compiled kernel run for N random draws of "
                                                "parameters or initial values: a CSV row per run, statistics printed");
    scene_argument(c.ensemble);
    cli::add_integration_options(c.ensemble, o.simulate);
    cli::add_ensemble_options(c.ensemble, o.ensemble, false);

    c.equilibria = app.add_subcommand("equilibria", "relative equilibria of a steady carrier and their stability; "
                                                    "a rigid body's permanent rotations (Staude); with [[unilateral]] "
                                                    "gaps, the KKT equilibria (Mei §6.4)");
    scene_argument(c.equilibria);
    c.equilibria->add_option("--format", o.format, "text | json (| latex with [[unilateral]] gaps)")
        ->check(CLI::IsMember({"text", "latex", "json"}));
    c.equilibria->add_option("--spin", o.spin,
                             "a rigid body: the spin Ω at which the rotations about principal axes holding the mass "
                             "centre are linearised (default: ω0·γ0 of the scene)");

    declare_linearize(app, o, c);

    c.inverse = app.add_subcommand("inverse", "the inverse problem: self-adjointness, a multiplier, a Lagrangian");
    scene_argument(c.inverse);
    c.inverse->add_option("--format", o.format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    c.inverse->add_option("-o,--output", o.output, "write to FILE instead of standard output");
    c.inverse->add_option("--emit-scene", o.emit_scene, "write the constructed Lagrangian as a [lagrangian] scene to FILE");
    c.inverse
        ->add_option("--search-budget", o.search_budget.nodes,
                     "expression nodes the multiplier search may build before it stops undecided (default 1000000)")
        ->check(CLI::PositiveNumber);

    c.control = app.add_subcommand("control", "programmed motion: the controls realising the scene's [[program]] rows");
    scene_argument(c.control);
    c.control->add_option("--format", o.format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    c.control->add_option("-o,--output", o.output, "write to FILE instead of standard output");

    c.integrals = app.add_subcommand(
        "integrals", "a rigid body's first integrals: the classical ones proven, new polynomial ones searched for");
    scene_argument(c.integrals);
    c.integrals->add_option("--format", o.format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    c.integrals->add_option("--degree", o.degree, "the highest total degree searched (default 4; at most 8)")
        ->check(CLI::Range(1, 8));
    c.integrals
        ->add_option("--search-budget", o.integral_work,
                     fmt::format("entry operations the exact elimination may take, over all degrees, before the search "
                                 "stops undecided at the degree it was in (default {}, about a minute)",
                                 mechanics::rigid::default_search_work))
        ->check(CLI::PositiveNumber);
    orbit_formulation(c.integrals);

    c.run = app.add_subcommand("run", "derive + generate + simulate: the whole job on one scene");
    scene_argument(c.run);
    c.run->add_option("-d,--dir", o.out_dir, "directory for the header and the CSV (default: .)");
    cli::add_simulate_options(c.run, o.simulate);
    hamiltonian_flag(c.run);
    orbit_formulation(c.run);
    variational_flag(c.run, integrate_phi);

    c.bench = app.add_subcommand(
        "bench", "work-precision sweeps of every integrator, ours and Boost.Odeint's, on one scene: CSV, plot, table");
    scene_argument(c.bench);
    c.bench->add_option("-o,--output-dir", o.out_dir, "directory for work_precision.csv and work_precision.png (default: .)");
    cli::add_bench_options(c.bench, o.bench);
    orbit_formulation(c.bench);
    return c;
}

report::DerivationFormat derivation_format(const std::string& name) {
    if (name == "latex") return report::DerivationFormat::latex;
    if (name == "json") return report::DerivationFormat::json;
    return report::DerivationFormat::text;
}

// Standard output, or the file, written whole or not at all.
void deliver(const std::string& text, const std::string& output) {
    if (output.empty()) std::cout << text;
    else write_file_atomically(output, text);
}

// `eomc integrals`: the search runs on the Euler–Poisson field, whatever the formulation.
void integrals_command(const Pipeline& p, const Options& o) {
    if (!p.model.rigid)
        throw InputError(SourcePos{o.scene_path, 0, 0},
                         fmt::format("{} has no [rigid_body]; `eomc integrals` searches a rigid body's polynomial "
                                     "integrals (the invariants of any scene are in `eomc derive`)",
                                     o.scene_path));
    const auto system = mechanics::rigid::euler_poisson(*p.model.rigid);
    std::ostringstream text;
    report::print_rigid_integrals(p.model, mechanics::rigid::search_rigid_integrals(p.model, system, o.degree, o.integral_work),
                                  derivation_format(o.format), text);
    std::cout << text.str();
}

const mechanics::CanonicalEquations* canonical(const Pipeline& p) { return p.canonical ? &*p.canonical : nullptr; }

void derive_command(const Pipeline& p, const Options& o) {
    std::ostringstream text;
    report::print_derivation(p.model, p.equations, derivation_format(o.format), text, canonical(p));
    deliver(text.str(), o.output);
}

void generate_command(const Pipeline& p, const Options& o, host::StageClock* clock) {
    const fs::path path = fs::path(o.out_dir) / (p.model.name + ".hpp");
    write_file_atomically(path, host::kernel_header(p, clock));
    if (clock) clock->print(std::cerr);
    std::cerr << "wrote " << path.string() << "\n";
}

// "--set a=1 --set b=2": the flags that gave the overrides, where a refusal of their values points.
std::string set_flags(const std::vector<std::string>& items) {
    std::string out;
    for (const auto& item : items) out += (out.empty() ? "--set " : " --set ") + item;
    return out;
}

// `simulate`, and `run` (which also prints the derivation and writes the header first).
// The method a simulate, sweep or ensemble run uses: the command line's, else the scene's.
const std::string& chosen_integrator(const Pipeline& p, const Options& o) {
    return o.simulate.integrator.empty() ? p.model.simulate.integrator : o.simulate.integrator;
}

void simulate_command(const Pipeline& p, Options& o, bool whole_job) {
    codegen::KernelIR ir;
    const std::string header =
        host::kernel_header(p, nullptr, &ir, host::method_needs_jacobian(chosen_integrator(p, o)));
    const fs::path header_path = fs::path(o.out_dir) / (p.model.name + ".hpp");
    if (whole_job && o.simulate.output.empty()) o.simulate.output = (fs::path(o.out_dir) / (p.model.name + ".csv")).string();
    const host::SimulationRequest request = cli::simulation_request(p, header, o.simulate);
    cli::check_overrides_against_scene(o.scene_path, o.front, o.simulate.overrides);
    cli::check_start(p, request.overrides, set_flags(o.simulate.overrides));
    // Every check that can refuse, before the derivation is printed, the header written or the
    // kernel compiled.
    const host::RunSettings settings = host::resolve_settings(request);
    host::validate_request(request);
    host::check_separable(*settings.method, request.integrator_pos, ir.separable, ir.scene_name);
    host::check_contact_settings(host::KernelShape{ir.scene_name, ir.contact_names.size(), ir.event_names}, request,
                                 settings);
    if (whole_job) check_output_target(header_path);
    // Gains too large for the explicit integrator chosen (Mei ch. 3): warned, the run still made.
    for (const std::string& w : host::program_stiffness_warnings(p.model, *settings.method, settings.step, request.t_end))
        std::cerr << "eomc: warning: " << w << "\n";
    if (whole_job) {
        report::print_derivation(p.model, p.equations, report::DerivationFormat::text, std::cout, canonical(p));
        write_file_atomically(header_path, header);
        std::cout << "\nKernel: " << header_path.string() << "\n\nSimulation\n";
    }
    host::print_summary(host::simulate(request), o.simulate.summary, std::cout);
    if (whole_job) std::cout << "Trajectory: " << o.simulate.output << "\n";
}

// `sweep --equilibria`: the relative equilibria and their verdicts at every grid point, no kernel.
void equilibria_sweep_command(const Pipeline& p, const Options& o, const host::EnsembleSpec& spec) {
    if (!p.model.unilateral.empty())
        throw InputError(SourcePos{"--equilibria"}, "an equilibrium sweep takes the relative equilibria (or a rigid "
                                                    "body's permanent rotations), not the KKT equilibria of "
                                                    "[[unilateral]] gaps");
    const host::EquilibriumSweep sweep =
        host::sweep_equilibria(p.model, p.equations, spec, {o.ensemble.budget_s, true, o.ensemble.progress});
    const auto script = [&](const std::string& terminal, const fs::path& png) {
        return host::equilibria_plot_script(sweep, spec, terminal, png);
    };
    if (!o.ensemble.plot.empty()) (void)script("png", o.ensemble.plot);  // a bad picture is refused before any output
    const std::string summary = host::equilibria_summary(sweep, o.ensemble.format);
    if (!o.ensemble.output.empty()) write_file_atomically(o.ensemble.output, host::equilibria_csv(sweep));
    std::cout << summary;
    if (!o.ensemble.plot.empty())
        if (const std::string note = host::write_plot(script, o.ensemble.plot); !note.empty())
            std::cerr << "eomc: warning: " << note << "\n";
}

mechanics::OperatingPointKind operating_point(const Options& o) {
    return o.about == "initial" ? mechanics::OperatingPointKind::initial : mechanics::OperatingPointKind::equilibrium;
}

// The scene's parameters and initial state with `items` (--set NAME=VALUE) applied, each checked as
// the scene checks its own values.
host::LinearizeInputs linearize_inputs(const Pipeline& p, const Options& o, const std::vector<std::string>& items) {
    cli::check_overrides_against_scene(o.scene_path, o.front, items);
    host::LinearizeInputs in = host::scene_inputs(p.model);
    const auto overrides = cli::parse_overrides(items);
    for (std::size_t i = 0; i < overrides.size(); ++i)
        host::set_input(p.model, in, overrides[i].first, overrides[i].second, SourcePos{"--set " + items[i]});
    for (const auto& [name, value] : model::initial_overrides(p.model, overrides))  // initial values as expressions
        host::set_input(p.model, in, name, value, SourcePos{"--set"});
    return in;
}

// `eomc linearize`: everything computed before anything is written.
void linearize_command(const Pipeline& p, const Options& o) {
    const host::LinearizeInputs in = linearize_inputs(p, o, o.set);
    const mechanics::Linearizer linearizer(p.model, p.equations);
    const auto lin = linearizer.linearize(in.parameters, operating_point(o), in.q, in.u, SourcePos{"--about " + o.about});
    std::ostringstream text;
    report::print_linearization(p.model, lin, o.about, derivation_format(o.format), text);
    deliver(text.str(), o.output);
}

// `sweep --linearize`: the eigenvalues at every grid point, no kernel.
void linearize_sweep_command(const Pipeline& p, const Options& o, const host::EnsembleSpec& spec) {
    const host::LinearizeInputs base = linearize_inputs(p, o, o.simulate.overrides);
    cli::check_grid_against_scene(o.scene_path, o.front, o.simulate.overrides, spec);
    const mechanics::Linearizer linearizer(p.model, p.equations);
    const host::LinearizeSweep sweep =
        host::sweep_linearize(linearizer, p.model, spec, operating_point(o), base, cli::parse_overrides(o.simulate.overrides),
                              {o.ensemble.budget_s, true, o.ensemble.progress});
    const auto script = [&](const std::string& terminal, const fs::path& png) {
        return host::linearize_plot_script(sweep, spec, terminal, png);
    };
    if (!o.ensemble.plot.empty()) (void)script("png", o.ensemble.plot);  // a bad picture is refused before any output
    const std::string summary = host::linearize_summary(sweep, o.ensemble.format);
    if (!o.ensemble.output.empty()) write_file_atomically(o.ensemble.output, host::linearize_csv(sweep));
    std::cout << summary;
    if (!o.ensemble.plot.empty())
        if (const std::string note = host::write_plot(script, o.ensemble.plot); !note.empty())
            std::cerr << "eomc: warning: " << note << "\n";
}

// An error as main reports it: the exit status and the line printed (a JobError: as the MPI ranks
// agreed, its text on rank 0 only).
std::pair<int, std::string> error_report(std::exception_ptr error, const std::string& scene_path) {
    try {
        std::rethrow_exception(error);
    } catch (const host::JobError& e) {
        return {e.status(), e.text()};
    } catch (const InputError& e) {
        return {2, e.what()};
    } catch (const codegen::EmitError& e) {
        // The scene asks for what a kernel cannot hold (a constant beyond double's range, …).
        return {2, codegen::comment_text(scene_path) + ": error: " + e.what()};
    } catch (const std::exception& e) {
        return {1, std::string("eomc: error: ") + e.what()};
    }
}

// A `sweep` or `ensemble` request, everything checked before the first run; the memory its rows
// will hold (on rank 0, which gathers them from `ranks`) before anything is allocated or compiled.
host::EnsembleRequest ensemble_request(const Pipeline& p, const Options& o, const host::EnsembleSpec& spec,
                                       std::size_t ranks) {
    host::EnsembleRequest r;
    r.spec = spec;
    r.members_flag = SourcePos{spec.vary.empty() ? "--grid" : "--samples"};
    r.budget_s = o.ensemble.budget_s;
    r.progress_always = o.ensemble.progress;
    codegen::KernelIR ir;
    const std::string header =
        host::kernel_header(p, nullptr, &ir, host::method_needs_jacobian(chosen_integrator(p, o)));
    host::check_ensemble_memory(spec.members(),
                                host::ensemble_bytes_per_member(spec.input_names().size(), ir.state.size(),
                                                                ir.invariant_names.size(), o.ensemble.observe.size(), ranks),
                                o.ensemble.max_memory_mib ? *o.ensemble.max_memory_mib << 20 : host::default_memory_limit(),
                                r.members_flag);
    r.base = cli::simulation_request(p, header, o.simulate);
    std::vector<std::string> parameters, states;  // the kernel's names, known before it compiles
    for (const auto& s : ir.parameters) parameters.push_back(s.name);
    for (const auto& s : ir.state) states.push_back(s.name);
    host::check_names(r.spec, parameters, states, r.base.overrides);
    cli::check_overrides_against_scene(o.scene_path, o.front, o.simulate.overrides);
    cli::check_grid_against_scene(o.scene_path, o.front, o.simulate.overrides, r.spec);
    cli::check_start(p, r.base.overrides, set_flags(o.simulate.overrides));
    r.base.check_start = cli::member_start_check(p, r.spec);  // each member's start, as it is drawn
    host::check_separable(*host::resolve_settings(r.base).method, r.base.integrator_pos, ir.separable, ir.scene_name);
    r.threads = o.ensemble.threads;
    r.batch = o.ensemble.batch;
    for (const auto& text : o.ensemble.observe) r.observe.push_back(host::parse_observation(text));
    return r;
}

// `sweep` and `ensemble`: everything is checked before the first run, and the CSV written whole.
// Under mpirun every rank checks and runs its share, and an error on any rank ends the job with
// the one-process run's message (printed once, by rank 0) and exit status.
void ensemble_command(const Pipeline& p, const Options& o) {
    const host::MpiSession mpi([&](std::exception_ptr e) { return error_report(e, o.scene_path); });
    host::EnsembleRequest r;
    host::EnsembleResult result;
    bool equilibria = false, linearize = false;
    mpi.agree([&] {
        r.spec = cli::ensemble_spec(o.ensemble);
        if (!o.ensemble.output.empty()) check_output_target(o.ensemble.output);
        if (!o.ensemble.plot.empty()) check_output_target(o.ensemble.plot);
        if (host::has_control_character(o.ensemble.plot))  // the path reaches the plot script
            throw InputError(SourcePos{"--plot"}, "the path contains a control character");
        if (o.ensemble.linearize) {
            if (o.ensemble.equilibria || !o.ensemble.observe.empty() || o.ensemble.batch)
                throw InputError(SourcePos{"--linearize"}, "a linearisation sweep runs nothing: --equilibria, --observe "
                                                           "and --batch do not apply");
            linearize = true;
            return;
        }
        if (o.ensemble.equilibria) {
            if (!o.ensemble.observe.empty() || o.ensemble.batch)
                throw InputError(SourcePos{"--equilibria"}, "an equilibrium sweep runs nothing: --observe and --batch do not apply");
            equilibria = true;
            return;
        }
        r = ensemble_request(p, o, r.spec, mpi.size());
        r.rank = mpi.rank();
        r.ranks = mpi.size();
        // A test's way to fail one rank alone (tests/cli/ensemble.cpp): the job must still end.
        if (const char* rank = std::getenv("EOMC_TEST_FAIL_RANK"); rank && std::to_string(r.rank) == rank)
            throw InputError(SourcePos{"EOMC_TEST_FAIL_RANK"}, "this rank was asked to fail");
        result = host::run_ensemble(r);
    });
    if (equilibria || linearize) {  // no kernel, nothing to share: rank 0 sweeps
        if (mpi.rank() == 0) {
            if (linearize) linearize_sweep_command(p, o, r.spec);
            else equilibria_sweep_command(p, o, r.spec);
        }
        return;
    }
    if (!mpi.gather(result)) return;  // rank 0 writes and prints for all
    host::refuse_if_all_refused(result);
    const std::string& column = o.ensemble.plot_column.empty() && !result.state_names.empty()
                                    ? result.state_names.front() : o.ensemble.plot_column;
    const auto script = [&](const std::string& terminal, const fs::path& png) {
        return host::ensemble_plot_script(result, r.spec, column, terminal, png);
    };
    if (!o.ensemble.plot.empty()) (void)script("png", o.ensemble.plot);  // a bad picture is refused before any output
    if (!o.ensemble.output.empty()) write_file_atomically(o.ensemble.output, host::ensemble_csv(result));
    host::print_ensemble_summary(result, o.ensemble.format, std::cout);
    if (!o.ensemble.plot.empty())
        if (const std::string note = host::write_plot(script, o.ensemble.plot); !note.empty())
            std::cerr << "eomc: warning: " << note << "\n";
}

void bench_command(const Pipeline& p, const Options& o) {
    codegen::KernelIR ir;
    // The sweep runs every method of the catalogue.
    const bool jacobian = std::any_of(runtime::integrator_infos.begin(), runtime::integrator_infos.end(),
                                      [](const runtime::IntegratorInfo& info) { return info.uses_jacobian; });
    const std::string header = host::kernel_header(p, nullptr, &ir, jacobian);
    host::BenchRequest r = cli::bench_request(p, header, ir, o.scene_path, o.out_dir, o.bench);
    cli::check_start(p, {}, "");  // the bench runs the scene's own start
    const std::vector<std::string> formulations = cli::comma_list(o.bench.formulations);
    if (!o.bench.formulations.empty() && !p.model.orbit && !p.model.rigid)
        throw InputError(SourcePos{"--formulations"},
                         fmt::format("{} has no [orbit] or [rigid_body]; --formulations compares the formulations of "
                                     "an orbit or a rigid-body scene",
                                     o.scene_path));
    if (!formulations.empty() && !o.front.orbit_formulation.empty())
        throw InputError(SourcePos{"--formulations"},
                         "give the formulations either by --formulations or by --orbit-formulation, not both");
    if (!formulations.empty() && !o.front.rigid_formulation.empty())
        throw InputError(SourcePos{"--formulations"},
                         "give the formulations either by --formulations or by --rigid-formulation, not both");
    if (!o.bench.formulations.empty() && formulations.empty())
        throw InputError(SourcePos{"--formulations"}, "the list is empty");
    if (p.model.orbit) host::add_orbit_formulations(r, o.scene_path, formulations, o.front.orbit_formulation);
    if (p.model.rigid) host::add_rigid_formulations(r, o.scene_path, formulations, o.front.rigid_formulation);
    host::print_bench_table(host::bench(r), std::cout);
}

// `eomc equilibria`: the KKT equilibria with unilateral gaps, a rigid body's permanent rotations,
// or the relative equilibria.
void equilibria_command(const Pipeline& p, const Options& o) {
    if (!p.model.unilateral.empty()) {
        report::print_unilateral_equilibria(p.model, mechanics::unilateral::kkt_equilibria(p.model, p.equations),
                                            derivation_format(o.format), std::cout);
        return;
    }
    if (o.format == "latex")
        throw InputError(SourcePos{"--format"}, "`eomc equilibria` writes LaTeX for scenes with [[unilateral]] gaps only; "
                                                "use text or json");
    if (p.model.kind() == model::ModelKind::rigid)
        report::print_rigid_equilibria(p.model, mechanics::rigid::rigid_equilibria(p.model, o.spin), o.format, std::cout);
    else
        report::print_equilibria(p.model, mechanics::relative_equilibria(p.model, p.equations), o.format, std::cout);
}

void inverse_command(const Pipeline& p, const Options& o) {
    const auto analysis = mechanics::inverse::analyse(p.model, p.equations, o.search_budget);
    // Everything is computed before anything is written: a refusal leaves no file behind.
    std::string scene_text;
    if (!o.emit_scene.empty()) {
        if (!analysis.construction || !analysis.construction->built || !analysis.construction->verified)
            throw std::runtime_error(
                fmt::format("no verified Lagrangian to write to {}: {}", o.emit_scene, analysis.reason));
        scene_text = report::lagrangian_scene(p.model, analysis);
    }
    std::ostringstream text;
    report::print_inverse(p.model, analysis, derivation_format(o.format), text);
    deliver(text.str(), o.output);
    if (!o.emit_scene.empty()) write_file_atomically(o.emit_scene, scene_text);
}

// `eomc control`: a scene without [[program]] rows has nothing to realise.
void control_command(const Pipeline& p, const Options& o) {
    if (p.model.programs.empty())
        throw InputError(SourcePos{o.scene_path, 1, 1},
                         "the scene declares no [[program]]: eomc control realises programmed motions (Mei ch. 3)");
    std::ostringstream text;
    report::print_control(p.model, p.equations, mechanics::realise(p.model, p.equations), derivation_format(o.format),
                          text);
    deliver(text.str(), o.output);
}

}  // namespace

int main(int argc, char** argv) {
    // EOMC_TEST_ASLR keeps randomisation on: for measuring how far the output itself is
    // independent of GiNaC's hash order (see ensure_reproducible_layout).
    ensure_reproducible_layout(argv);
    // After the re-execution above: temporaries and the compiler go with a SIGINT/SIGTERM/SIGHUP.
    install_signal_cleanup();
    CLI::App app{"eomc — equations-of-motion compiler for analytical mechanics"};
    app.set_version_flag("--version", std::string(EOMC_VERSION));
    app.require_subcommand(1);
    Options o;
    const Commands c = declare_commands(app, o);

    // Bad flags and values are bad input like any other: exit 2 (CLI11 would use its own codes).
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }

    try {
        // An output that exists and is not a regular file is refused before any work is done.
        for (const std::string* path : {&o.output, &o.simulate.output, &o.emit_scene})
            if (!path->empty()) check_output_target(*path);
        if (c.sweep->parsed() && c.sweep->count("--about") && !o.ensemble.linearize)
            throw InputError(SourcePos{"--about"}, "--about chooses the operating point of `sweep --linearize`; "
                                                   "add --linearize or drop it");
        host::StageClock clock;
        host::StageClock* timing = o.timings ? &clock : nullptr;
        const Pipeline p = host::front_end(o.scene_path, o.front, timing);
        if (c.derive->parsed()) derive_command(p, o);
        else if (c.generate->parsed()) generate_command(p, o, timing);
        else if (c.simulate->parsed()) simulate_command(p, o, false);
        else if (c.run->parsed()) simulate_command(p, o, true);
        else if (c.bench->parsed()) bench_command(p, o);
        else if (c.sweep->parsed() || c.ensemble->parsed()) ensemble_command(p, o);
        else if (c.equilibria->parsed()) equilibria_command(p, o);
        else if (c.linearize->parsed()) linearize_command(p, o);
        else if (c.inverse->parsed()) inverse_command(p, o);
        else if (c.control->parsed()) control_command(p, o);
        else if (c.integrals->parsed()) integrals_command(p, o);
    } catch (const std::exception&) {
        const auto [status, text] = error_report(std::current_exception(), o.scene_path);
        if (!text.empty()) std::cerr << text << "\n";
        return status;
    }
    return 0;
}
