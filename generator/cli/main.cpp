// eomc: the command line. It only wires the pipeline stages together:
//   scene --parse--> Scene --build--> Model --derive--> Equations --lower--> KernelIR --emit--> header
// Exit codes: 0 success, 2 bad input (file:line:column: error: …), 1 any other failure.
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include <sys/personality.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "codegen/cpp_emitter.hpp"
#include "codegen/cpp_text.hpp"
#include "codegen/kernel_ir.hpp"
#include "host/bench.hpp"
#include "host/simulate.hpp"
#include "mechanics/canonical/hamiltonian.hpp"
#include "mechanics/derive.hpp"
#include "mechanics/inverse/inverse_problem.hpp"
#include "mechanics/relative/equilibria.hpp"
#include "model/model.hpp"
#include "report/derivation_printer.hpp"
#include "report/inverse_printer.hpp"
#include "scene/scene.hpp"
#include "support/cleanup.hpp"
#include "support/diagnostic.hpp"
#include "support/json.hpp"
#include "support/output_file.hpp"
#include "symbolic/expression_text.hpp"

namespace fs = std::filesystem;
using namespace eomc;

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

// Seconds per pipeline stage, for `eomc generate --timings` and the benchmarks.
class StageClock {
public:
    void lap(const char* stage) {
        const auto now = std::chrono::steady_clock::now();
        stages_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
        last_ = now;
    }
    void add(const char* stage, double seconds) { stages_.emplace_back(stage, seconds); }
    void print(std::ostream& out) const {
        double total = 0;
        for (const auto& [stage, seconds] : stages_) {
            out << fmt::format("timing {} {:.6f}\n", stage, seconds);
            if (std::string_view(stage) != "lower") total += seconds;  // lower is the sum of its parts
        }
        out << fmt::format("timing total {:.6f}\n", total);
    }

private:
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
    std::vector<std::pair<const char*, double>> stages_;
};

struct Pipeline {
    model::Model model;
    mechanics::Equations equations;
    std::optional<mechanics::CanonicalEquations> canonical;  // the Hamiltonian formulation, when asked for
    bool variational = false;                                // emit variational_rhs too (--variational)
};

// `orbit_formulation` ("" = the scene's own) is --orbit-formulation.
// `flag` names the option that chose it, for messages (bench's --formulations).
Pipeline front_end(const std::string& scene_path, bool hamiltonian, const std::string& orbit_formulation,
                   StageClock* clock = nullptr, const char* flag = "--orbit-formulation") {
    scene::Scene scene = scene::parse_scene_file(scene_path);
    if (!orbit_formulation.empty())
        scene::set_orbit_formulation(scene, orbit_formulation, SourcePos{std::string(flag) + " " + orbit_formulation});
    Pipeline p{model::build_model(scene), {}, std::nullopt};
    for (const auto& w : p.model.warnings) std::cerr << format_warning(w) << "\n";
    if (clock) clock->lap("parse");
    p.equations = mechanics::derive(p.model);
    const std::string formulation = p.model.orbit ? p.model.orbit->formulation : "";
    if (formulation == "equinoctial" && (hamiltonian || p.model.hamiltonian))
        throw InputError(p.model.orbit->formulation_pos,
                         "the equinoctial formulation integrates Gauss's equations, not Hamilton's; use formulation = "
                         "\"cowell\" with the Hamiltonian formulation");
    if (formulation == "encke" && (hamiltonian || p.model.hamiltonian))
        throw InputError(p.model.orbit->formulation_pos,
                         "the encke formulation integrates the deviation from a reference orbit, not Hamilton's "
                         "equations; use formulation = \"cowell\" with the Hamiltonian formulation");
    if (hamiltonian || p.model.hamiltonian) p.canonical = mechanics::canonical_equations(p.model, p.equations);

    if (clock) clock->lap("derive");
    return p;
}

// The emitted header; `ir` (when given) receives the kernel IR it was printed from.
std::string kernel_header(const Pipeline& p, StageClock* clock = nullptr, codegen::KernelIR* ir_out = nullptr) {
    codegen::LoweringTimes lowering;
    const codegen::KernelIR ir = p.canonical ? codegen::lower(p.model, p.canonical->form, &lowering)
                                             : codegen::lower(p.model, p.equations, &lowering);
    if (ir_out) *ir_out = ir;
    if (clock) {
        clock->lap("lower");
        clock->add("cse_mass_forcing", lowering.mass_and_forcing);
        clock->add("jacobian", lowering.jacobian);
        clock->add("invariants", lowering.invariants);
    }
    std::string header = codegen::emit_header(ir, {EOMC_VERSION, p.variational});
    if (clock) clock->lap("emit");
    return header;
}

report::DerivationFormat derivation_format(const std::string& name) {
    if (name == "latex") return report::DerivationFormat::latex;
    if (name == "json") return report::DerivationFormat::json;
    return report::DerivationFormat::text;
}

// The runtime's integrators (eomc/runtime/registry.hpp) that satisfy `keep`, in the registry's
// order, joined by `separator`: the --help texts list what the registry holds.
template <class Keep>
std::string integrators_where(Keep keep, std::string_view separator = ", ") {
    std::string out;
    for (const runtime::IntegratorInfo& info : runtime::integrator_infos)
        if (keep(info)) {
            if (!out.empty()) out += separator;
            out += info.name;
        }
    return out;
}
bool adaptive(const runtime::IntegratorInfo& info) { return !info.fixed_step(); }
bool fixed_step(const runtime::IntegratorInfo& info) { return info.fixed_step(); }

// Blanks (spaces, tabs) around a --set name or value, or a list item, are dropped.
std::string_view trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t");
    return first == std::string_view::npos ? std::string_view{} : text.substr(first, last - first + 1);
}

// One decimal grammar for every number given on the command line: [+|-] digits [. digits]
// [e|E [+|-] digits], the whole text, a finite double. Hex floats, "inf" and "nan" are not
// decimals; subnormal numbers are numbers. std::from_chars (C++17 [charconv.from.chars]) is
// locale-independent and reports out-of-range results, unlike strtod/stod, whose ERANGE also
// rejects subnormals. Throws InputError at `where` with the reason.
double parse_decimal(std::string_view text, const SourcePos& where) {
    const std::string_view t = trimmed(text);
    const auto not_a_number = [&] { return InputError(where, fmt::format("'{}' is not a number", text)); };
    if (t.empty() || t.find_first_not_of("0123456789.eE+-") != std::string_view::npos) throw not_a_number();
    std::string_view digits = t;
    if (digits.front() == '+') {  // from_chars takes no '+'; TOML (and people) write +1.5
        digits.remove_prefix(1);
        if (digits.empty() || digits.front() == '+' || digits.front() == '-') throw not_a_number();
    }
    double v = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, std::chars_format::general);
    if (end != digits.data() + digits.size() || ec == std::errc::invalid_argument) throw not_a_number();
    if (ec == std::errc::result_out_of_range)
        throw InputError(where, fmt::format("'{}' is outside the range of a double ({} in magnitude)", text,
                                            std::abs(std::strtod(std::string(digits).c_str(), nullptr)) > 1
                                                ? "above 1.8e308"
                                                : "below 4.9e-324, the smallest subnormal"));
    if (!std::isfinite(v)) throw not_a_number();
    // A subnormal double is a number, but not one the model's exact arithmetic takes: CLN
    // (under GiNaC) has no subnormal floats and stops with "floating point underflow".
    if (v != 0 && std::abs(v) < std::numeric_limits<double>::min())
        throw InputError(where, fmt::format("'{}' is a subnormal double (below 2.2e-308 in magnitude), which eomc's "
                                            "exact arithmetic cannot hold; use 0 or a normal number",
                                            text));
    return v;
}

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
void check_overrides_against_scene(const std::string& scene_path, const std::string& orbit_formulation,
                                   const std::vector<std::string>& items) {
    const auto overrides = parse_overrides(items);
    scene::Scene s = scene::parse_scene_file(scene_path);
    if (!orbit_formulation.empty())
        scene::set_orbit_formulation(s, orbit_formulation, SourcePos{"--orbit-formulation " + orbit_formulation});
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

struct SimulateOptions {
    std::optional<double> t_end, rtol, atol, step;
    std::string integrator, output, summary = "text", compensated;
    std::vector<std::string> overrides;
    std::string cache_dir;
    std::optional<std::size_t> max_steps;
    std::size_t max_rows = host::SimulationRequest::default_max_rows;
};

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

void add_simulate_options(CLI::App* cmd, SimulateOptions& o) {
    cmd->add_option("--t-end", o.t_end, "final time (default: [simulate] t_end)")->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--integrator", o.integrator,
                    fmt::format("{} (default: [simulate] integrator; {} need a separable system)",
                                integrators_where([](const auto&) { return true; }, " | "),
                                integrators_where([](const auto& i) { return i.needs_separable; })))
        ->check(CLI::IsMember(std::vector<std::string>(scene::integrator_names.begin(), scene::integrator_names.end())));
    cmd->add_option("--rtol", o.rtol, fmt::format("relative tolerance ({})", integrators_where(adaptive)))->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--atol", o.atol, fmt::format("absolute tolerance ({})", integrators_where(adaptive)))->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--step", o.step, fmt::format("step size ({})", integrators_where(fixed_step)))
        ->check(decimal)->check(CLI::PositiveNumber);
    cmd->add_option("--compensated", o.compensated,
                    "on | off: compensated (Kahan) summation of the state update (default: [simulate] compensated, "
                    "else on for gl4-8, verlet, yoshida6, kahanli8 and off for the others)")
        ->check(CLI::IsMember({"on", "off"}));
    cmd->add_option("--set", o.overrides, "NAME=VALUE: a parameter, or an initial value (q, q_dot)");
    cmd->add_option("--output", o.output, "trajectory CSV (t, state, invariants)");
    cmd->add_option("--summary", o.summary, "text | json")->check(CLI::IsMember({"text", "json"}));
    cmd->add_option("--cache-dir", o.cache_dir, "where compiled kernels are kept (default ~/.cache/eomc)");
    cmd->add_option("--max-steps", o.max_steps,
                    fmt::format("the most steps the run may take (default: {} for the fixed-step methods, refused "
                                "before the run when t_end/step is more; {} attempts for {})",
                                host::SimulationRequest::default_max_fixed_steps, runtime::Limits{}.max_steps,
                                integrators_where(adaptive, " and ")))
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-rows", o.max_rows,
                    fmt::format("the most rows the CSV may hold (default {}); a run that would write more leaves no CSV",
                                host::SimulationRequest::default_max_rows))
        ->check(CLI::PositiveNumber);
}

host::SimulationRequest simulation_request(const Pipeline& p, const std::string& header, const SimulateOptions& o) {
    const scene::Simulate& d = p.model.simulate;
    host::SimulationRequest r;
    r.header_text = header;
    r.struct_name = p.model.struct_name;
    r.overrides = parse_overrides(o.overrides);
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
    return r;
}

// A comma-separated list (--methods dop853,gl8); blanks around items are dropped.
std::vector<std::string> comma_list(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        const auto first = item.find_first_not_of(" \t"), last = item.find_last_not_of(" \t");
        if (first != std::string::npos) out.push_back(item.substr(first, last - first + 1));
    }
    return out;
}

// A comma-separated list of numbers (--tolerances 1e-6,1e-9), checked for shape here.
std::vector<double> number_list(const std::string& text, const char* option) {
    std::vector<double> out;
    for (const auto& item : comma_list(text)) out.push_back(parse_decimal(item, SourcePos{option}));
    return out;
}

struct BenchOptions {
    std::optional<double> t_end;
    std::string methods, tolerances, steps, cache_dir, odeint_state = "vector", formulations;
    double reference_tolerance = 1e-26;
    double min_time = 0.02;
    int repeats = 3;
};

// The equations depend on t explicitly (a driven carrier, a time-dependent force).
bool depends_on_time(const Pipeline& p) {
    for (const auto& f : p.equations.forcing)
        if (f.has(p.model.t)) return true;
    for (unsigned i = 0; i < p.equations.mass_matrix.rows(); ++i)
        for (unsigned j = 0; j < p.equations.mass_matrix.cols(); ++j)
            if (p.equations.mass_matrix(i, j).has(p.model.t)) return true;
    return false;
}

// The period of an orbit scene's initial osculating ellipse (0 when it is no ellipse), from the
// Cowell model's initial state and μ at the parameters' defaults.
double orbit_period(const model::Model& m) {
    if (!m.orbit || m.coordinates.size() != 3) return 0.0;
    GiNaC::lst defaults;
    for (const auto& par : m.parameters) defaults.append(par.symbol == par.value);
    const GiNaC::ex mu = GiNaC::evalf(m.orbit->mu.subs(defaults));
    if (!GiNaC::is_a<GiNaC::numeric>(mu)) return 0.0;
    const double gm = GiNaC::ex_to<GiNaC::numeric>(mu).to_double();
    double r2 = 0, v2 = 0;
    for (const auto& c : m.coordinates) r2 += c.initial * c.initial, v2 += c.rate * c.rate;
    const double inverse_a = 2.0 / std::sqrt(r2) - v2 / gm;  // vis-viva
    if (!(gm > 0.0 && inverse_a > 0.0)) return 0.0;
    return 2.0 * M_PI * std::sqrt(1.0 / (inverse_a * inverse_a * inverse_a) / gm);
}

// `eomc equilibria`: each relative equilibrium with its eigenvalues and verdict.
void print_equilibria(const model::Model& model, const std::vector<mechanics::Equilibrium>& found,
                      const std::string& format, std::ostream& out) {
    if (format == "json") {
        out << "{\"equilibria\": [";
        for (std::size_t i = 0; i < found.size(); ++i) {
            out << (i ? ",\n  " : "\n  ") << "{\"q\": {";
            for (std::size_t k = 0; k < found[i].q.size(); ++k)
                out << (k ? ", " : "") << json_string(model.coordinates[k].name) << fmt::format(": {:.17g}", found[i].q[k]);
            out << "}, \"free\": [";
            for (std::size_t k = 0, listed = 0; k < found[i].free.size(); ++k)
                if (found[i].free[k]) out << (listed++ ? ", " : "") << json_string(model.coordinates[k].name);
            out << "], \"eigenvalues\": [";
            for (std::size_t k = 0; k < found[i].eigenvalues.size(); ++k)
                out << (k ? ", " : "")
                    << fmt::format("[{:.17g}, {:.17g}]", found[i].eigenvalues[k].real(), found[i].eigenvalues[k].imag());
            out << "], \"verdict\": \"" << found[i].verdict << "\"";
            // The closed forms, in GiNaC syntax, when the equilibrium was solved symbolically.
            out << ", \"exact\": ";
            if (found[i].exact.empty()) {
                out << "null";
            } else {
                out << "{";
                for (std::size_t k = 0, listed = 0; k < found[i].exact.size(); ++k)
                    if (!found[i].free[k])
                        out << (listed++ ? ", " : "") << json_string(model.coordinates[k].name) << ": "
                            << json_string(symbolic::text(found[i].exact[k]));
                out << "}";
            }
            out << ", \"lambda_squared\": "
                << (found[i].lambda_squared ? json_string(symbolic::text(*found[i].lambda_squared)) : "null") << "}";
        }
        out << (found.empty() ? "]}\n" : "\n]}\n");
        return;
    }
    out << fmt::format("{} relative equilibri{} of {} (q̇ = 0, parameters at their defaults)\n", found.size(),
                       found.size() == 1 ? "um" : "a", model.name);
    if (!found.empty() && std::find(found[0].free.begin(), found[0].free.end(), true) != found[0].free.end())
        out << "(\"any\": a coordinate absent from the equations at rest; each equilibrium is a family in it)\n";
    for (const auto& e : found) {
        out << "\n ";
        for (std::size_t k = 0; k < e.q.size(); ++k)
            out << (e.free[k] ? fmt::format(" {} = any", model.coordinates[k].name)
                              : fmt::format(" {} = {:.12g}", model.coordinates[k].name, e.q[k]));
        for (std::size_t k = 0, listed = 0; k < e.exact.size(); ++k)
            if (!e.free[k])
                out << fmt::format("{}{} = {}", listed++ ? ", " : "\n    closed form: ", model.coordinates[k].name,
                                   symbolic::text(e.exact[k]));
        if (e.lambda_squared) out << "\n    λ² = (∂f/∂q)/M = " << symbolic::text(*e.lambda_squared);
        out << "\n    " << e.verdict;
        // Growth rates above the eigensolver's noise (the tolerance the verdict used).
        double largest = 0;
        for (const auto& l : e.eigenvalues) largest = std::max(largest, std::abs(l));
        std::string rates;
        for (const auto& l : e.eigenvalues) {
            if (e.verdict == "unstable" && l.real() > 1e-9 * (1 + largest)) rates += fmt::format(" {:.9g}", l.real());
            if (e.verdict != "unstable" && l.imag() > 0) rates += fmt::format(" {:.9g}", l.imag());
        }
        out << (e.verdict == "unstable" ? ": growth rates" : ": frequencies") << rates << "\n    eigenvalues";
        for (const auto& l : e.eigenvalues) out << fmt::format(" ({:.6g}{:+.6g}i)", l.real(), l.imag());
        out << "\n";
    }
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

    std::string scene_path, format = "text", output, out_dir = ".";
    bool hamiltonian = false;
    auto add_hamiltonian_flag = [&](CLI::App* cmd) {
        cmd->add_flag("--hamiltonian", hamiltonian,
                      "Hamilton's equations in (q, p) instead of Lagrange's in (q, q̇) (as [formulation] kind = "
                      "\"hamiltonian\")");
    };

    std::string orbit_formulation;
    auto add_orbit_formulation = [&](CLI::App* cmd) {
        cmd->add_option("--orbit-formulation", orbit_formulation,
                        "an orbit scene in another formulation (cowell, encke, lagrange, gauss, delaunay, equinoctial, "
                        "mean); the kernel's name gains _<formulation>");
    };

    auto* derive = app.add_subcommand("derive", "print the derivation (text, LaTeX or JSON)");
    derive->add_option("scene", scene_path, "scene file (TOML)")->required();
    derive->add_option("--format", format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    derive->add_option("-o,--output", output, "write to FILE instead of standard output");
    add_hamiltonian_flag(derive);
    add_orbit_formulation(derive);

    bool timings = false;
    auto* generate = app.add_subcommand("generate", "emit the C++ kernel header <name>.hpp");
    generate->add_option("scene", scene_path, "scene file (TOML)")->required();
    generate->add_option("-o,--output-dir", out_dir, "directory for the header (default: .)");
    generate->add_flag("--timings", timings, "print the time of each stage on stderr (`timing <stage> <seconds>`)");
    add_hamiltonian_flag(generate);
    add_orbit_formulation(generate);
    bool variational = false;
    auto add_variational_flag = [&](CLI::App* cmd, const char* what) { cmd->add_flag("--variational", variational, what); };
    add_variational_flag(generate, "also emit variational_rhs: the state extended by the state-transition matrix, "
                                   "Φ̇ = (∂ẋ/∂x) Φ (seed §2.9)");

    SimulateOptions sim;
    auto* simulate = app.add_subcommand("simulate", "generate, compile, integrate; write CSV and a summary");
    simulate->add_option("scene", scene_path, "scene file (TOML)")->required();
    add_simulate_options(simulate, sim);
    add_hamiltonian_flag(simulate);
    add_orbit_formulation(simulate);
    add_variational_flag(simulate, "integrate the state-transition matrix Φ too (Φ(0) = I; CSV columns Phi_<i>_<j>)");

    auto* equilibria = app.add_subcommand("equilibria", "relative equilibria of a steady carrier and their stability");
    equilibria->add_option("scene", scene_path, "scene file (TOML)")->required();
    equilibria->add_option("--format", format, "text | json")->check(CLI::IsMember({"text", "json"}));

    std::string emit_scene;
    auto* inverse = app.add_subcommand("inverse", "the inverse problem: self-adjointness, a multiplier, a Lagrangian");
    inverse->add_option("scene", scene_path, "scene file (TOML)")->required();
    inverse->add_option("--format", format, "text | latex | json")->check(CLI::IsMember({"text", "latex", "json"}));
    inverse->add_option("-o,--output", output, "write to FILE instead of standard output");
    inverse->add_option("--emit-scene", emit_scene, "write the constructed Lagrangian as a [lagrangian] scene to FILE");
    mechanics::inverse::SearchBudget search_budget;
    inverse
        ->add_option("--search-budget", search_budget.nodes,
                     "expression nodes the multiplier search may build before it stops undecided (default 1000000)")
        ->check(CLI::PositiveNumber);

    auto* run = app.add_subcommand("run", "derive + generate + simulate: the whole job on one scene");
    run->add_option("scene", scene_path, "scene file (TOML)")->required();
    run->add_option("-d,--dir", out_dir, "directory for the header and the CSV (default: .)");
    add_simulate_options(run, sim);
    add_hamiltonian_flag(run);
    add_orbit_formulation(run);
    add_variational_flag(run, "integrate the state-transition matrix Φ too (Φ(0) = I; CSV columns Phi_<i>_<j>)");

    BenchOptions bo;
    auto* bench = app.add_subcommand(
        "bench", "work-precision sweeps of every integrator, ours and Boost.Odeint's, on one scene: CSV, plot, table");
    bench->add_option("scene", scene_path, "scene file (TOML)")->required();
    bench->add_option("-o,--output-dir", out_dir, "directory for work_precision.csv and work_precision.png (default: .)");
    bench->add_option("--methods", bo.methods,
                      fmt::format("comma-separated subset of {} (default: all)",
                                  fmt::join(host::bench_method_names, ", ")));
    bench->add_option("--t-end", bo.t_end, "end time (default: [simulate] t_end)")->check(CLI::PositiveNumber);
    bench->add_option("--tolerances", bo.tolerances, "comma-separated rtol = atol of the adaptive methods "
                                                     "(default: 1e-3 .. 1e-15 in half decades)");
    bench->add_option("--steps", bo.steps, "comma-separated step counts of the fixed-step methods "
                                           "(default: 16 .. 2^20 in half octaves, until round-off)");
    bench->add_option("--min-time", bo.min_time, "seconds the timed repetitions of a run add up to at least (default 0.02)")
        ->check(CLI::NonNegativeNumber);
    bench->add_option("--repeats", bo.repeats, "fewest timed repetitions of a run (default 3)")->check(CLI::PositiveNumber);
    bench->add_option("--odeint-state", bo.odeint_state,
                      "vector (default: the container eomc's runtime steps) | array (std::array of the kernel's size)")
        ->check(CLI::IsMember({"vector", "array"}));
    bench->add_option("--cache-dir", bo.cache_dir, "where compiled programs are kept (default ~/.cache/eomc)");
    add_orbit_formulation(bench);
    bench->add_option("--formulations", bo.formulations,
                      "orbit scenes: comma-separated formulations to compare by their position at t_end against a "
                      "float128 Cowell run (default: all built: " +
                          std::string(fmt::format("{}", fmt::join(scene::orbit_formulation_names, ", "))) + ")");
    bench->add_option("--reference-tolerance", bo.reference_tolerance,
                      "orbit scenes: rtol = atol of the float128 Cowell reference (default 1e-26; checked against a run "
                      "1000 times looser)");

    // Bad flags and values are bad input like any other: exit 2 (CLI11 would use its own codes).
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }

    try {
        // An output that exists and is not a regular file is refused before any work is done.
        for (const std::string* path : {&output, &sim.output, &emit_scene})
            if (!path->empty()) check_output_target(*path);
        StageClock clock;
        Pipeline p = front_end(scene_path, hamiltonian, orbit_formulation, timings ? &clock : nullptr);
        p.variational = variational;
        // Φ would have to follow each rectification's change of variables, which it does not.
        if (variational && p.model.orbit && p.model.orbit->formulation == "encke")
            throw InputError(p.model.orbit->formulation_pos,
                             "--variational cannot follow the encke formulation's rectifications (each one changes "
                             "the state's variables); use formulation = \"cowell\" for the state-transition matrix");
        const mechanics::CanonicalEquations* canonical = p.canonical ? &*p.canonical : nullptr;
        if (derive->parsed()) {
            std::ostringstream text;
            report::print_derivation(p.model, p.equations, derivation_format(format), text, canonical);
            if (output.empty()) std::cout << text.str();
            else write_file_atomically(output, text.str());
        } else if (generate->parsed()) {
            const fs::path path = fs::path(out_dir) / (p.model.name + ".hpp");
            write_file_atomically(path, kernel_header(p, timings ? &clock : nullptr));
            if (timings) clock.print(std::cerr);
            std::cerr << "wrote " << path.string() << "\n";
        } else if (simulate->parsed()) {
            codegen::KernelIR ir;
            const std::string header = kernel_header(p, nullptr, &ir);
            const host::SimulationRequest request = simulation_request(p, header, sim);
            check_overrides_against_scene(scene_path, orbit_formulation, sim.overrides);
            host::check_separable(request.integrator, request.integrator_pos, ir.separable, ir.scene_name);
            const auto result = host::simulate(request);
            host::print_summary(result, sim.summary, std::cout);
        } else if (bench->parsed()) {
            codegen::KernelIR ir;
            host::BenchRequest r;
            r.header_text = kernel_header(p, nullptr, &ir);
            r.struct_name = p.model.struct_name;
            r.scene_name = p.model.name;
            r.scene_path = scene_path;
            if (!p.model.reference.empty()) r.reference_body = codegen::emit_reference_body(ir, p.model.reference);
            r.autonomous = !depends_on_time(p);
            r.t_end = bo.t_end.value_or(p.model.simulate.t_end);
            r.methods = comma_list(bo.methods);
            r.tolerances = number_list(bo.tolerances, "--tolerances");
            r.steps = number_list(bo.steps, "--steps");
            r.odeint_array = bo.odeint_state == "array";
            r.min_time = bo.min_time;
            r.repeats = bo.repeats;
            r.out_dir = out_dir;
            r.cache_dir = bo.cache_dir;
            r.reference_tolerance = bo.reference_tolerance;
            const std::vector<std::string> formulations = comma_list(bo.formulations);
            if (!bo.formulations.empty() && !p.model.orbit)
                throw InputError(SourcePos{"--formulations"},
                                 fmt::format("{} has no [orbit]; --formulations compares the formulations of an orbit "
                                             "scene", scene_path));
            if (!formulations.empty() && !orbit_formulation.empty())
                throw InputError(SourcePos{"--formulations"},
                                 "give the formulations either by --formulations or by --orbit-formulation, not both");
            if (!bo.formulations.empty() && formulations.empty())
                throw InputError(SourcePos{"--formulations"}, "the list is empty");
            if (p.model.orbit) {
                // The formulation axis: every kernel judged by its position against a float128 Cowell
                // run (the request's own kernel). Names are checked before anything is generated.
                std::vector<std::string> names = formulations;
                if (names.empty() && !orbit_formulation.empty()) names = {orbit_formulation};
                if (names.empty()) names.assign(scene::orbit_formulation_names.begin(), scene::orbit_formulation_names.end());
                for (const auto& name : names) scene::check_orbit_formulation(name, SourcePos{"--formulations"});
                const Pipeline cowell = front_end(scene_path, false, "cowell", nullptr, "--formulations");
                r.header_text = kernel_header(cowell);
                r.struct_name = cowell.model.struct_name;
                r.scene_name = scene::parse_scene_file(scene_path).name;  // not a formulation's kernel name
                r.reference_body.clear();
                r.orbit_period = orbit_period(cowell.model);
                const bool all_built = formulations.empty() && orbit_formulation.empty();
                for (const auto& name : names) {
                    try {
                        const Pipeline f =
                            name == "cowell" ? cowell : front_end(scene_path, false, name, nullptr, "--formulations");
                        r.formulations.push_back({name, name == "cowell" ? r.header_text : kernel_header(f),
                                                  f.model.struct_name, f.model.name, !depends_on_time(f)});
                    } catch (const InputError& e) {
                        // Asked for by name: bad input. Among "all built": a formulation that does not
                        // take this scene (mean with drag) is left out, and the table says why.
                        if (!all_built) throw;
                        r.skipped.push_back(fmt::format("{}: left out: {}", name, e.message()));
                    }
                }
                if (r.formulations.empty())
                    throw InputError(SourcePos{"--formulations"},
                                     "no formulation takes this scene: " + fmt::format("{}", fmt::join(r.skipped, "; ")));
            }
            host::print_bench_table(host::bench(r), std::cout);
        } else if (equilibria->parsed()) {
            print_equilibria(p.model, mechanics::relative_equilibria(p.model, p.equations), format, std::cout);
        } else if (inverse->parsed()) {
            const auto analysis = mechanics::inverse::analyse(p.model, p.equations, search_budget);
            // Everything is computed before anything is written: a refusal leaves no file behind.
            std::string scene_text;
            if (!emit_scene.empty()) {
                if (!analysis.construction || !analysis.construction->built || !analysis.construction->verified)
                    throw std::runtime_error(fmt::format("no verified Lagrangian to write to {}: {}", emit_scene,
                                                         analysis.reason));
                scene_text = report::lagrangian_scene(p.model, analysis);
            }
            std::ostringstream text;
            report::print_inverse(p.model, analysis, derivation_format(format), text);
            if (output.empty()) std::cout << text.str();
            else write_file_atomically(output, text.str());
            if (!emit_scene.empty()) write_file_atomically(emit_scene, scene_text);
        } else if (run->parsed()) {
            codegen::KernelIR ir;
            const std::string header = kernel_header(p, nullptr, &ir);
            const fs::path header_path = fs::path(out_dir) / (p.model.name + ".hpp");
            if (sim.output.empty()) sim.output = (fs::path(out_dir) / (p.model.name + ".csv")).string();
            const host::SimulationRequest request = simulation_request(p, header, sim);
            check_overrides_against_scene(scene_path, orbit_formulation, sim.overrides);
            host::check_separable(request.integrator, request.integrator_pos, ir.separable, ir.scene_name);
            report::print_derivation(p.model, p.equations, report::DerivationFormat::text, std::cout, canonical);
            write_file_atomically(header_path, header);
            std::cout << "\nKernel: " << header_path.string() << "\n\nSimulation\n";
            const auto result = host::simulate(request);
            host::print_summary(result, sim.summary, std::cout);
            std::cout << "Trajectory: " << sim.output << "\n";
        }
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const codegen::EmitError& e) {
        // The scene asks for what a kernel cannot hold (a constant beyond double's range, …).
        std::cerr << codegen::comment_text(scene_path) << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "eomc: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
