#include "host/bench.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "codegen/templates.hpp"
#include "host/bench_io.hpp"
#include "host/bench_plot.hpp"
#include "host/gnuplot.hpp"
#include "eomc/runtime/registry.hpp"
#include "host/toolchain.hpp"
#include "support/diagnostic.hpp"
#include "support/output_file.hpp"
#include "support/input_file.hpp"

namespace eomc::host {

namespace fs = std::filesystem;
using namespace bench_io;
using bench_plot::formulation_gnuplot_script;
using bench_plot::gnuplot_script;

namespace {

std::vector<std::string> method_names() { return {bench_method_names.begin(), bench_method_names.end()}; }

// Everything that can be checked before compiling, so that a typo costs no compile.
void validate(const BenchRequest& r) {
    // The directory reaches the plot script; a line break there would end its quoted string.
    if (has_control_character(r.out_dir))
        throw InputError(SourcePos{"-o"}, fmt::format("the output directory '{}' contains a control character",
                                                       codegen::comment_text(r.out_dir)));
    const std::vector<std::string> known = method_names();
    for (const auto& m : r.methods) {
        if (std::find(known.begin(), known.end(), m) != known.end()) continue;
        const std::string near = nearest_name(m, known);
        throw InputError(SourcePos{"--methods"}, fmt::format("unknown method '{}'{} (expected one of {})", m,
                                                             near.empty() ? "" : "; did you mean '" + near + "'?",
                                                             join(known)));
    }
    if (!(std::isfinite(r.t_end) && r.t_end > 0.0))
        throw InputError(SourcePos{"--t-end"}, fmt::format("the end time must be positive and finite, not {}", r.t_end));
    for (double tol : r.tolerances)
        if (!(tol > 0.0 && tol < 1.0))
            throw InputError(SourcePos{"--tolerances"}, fmt::format("a tolerance must lie in (0, 1), not {}", tol));
    for (double n : r.steps)
        if (!(n >= 1.0 && n <= 1e9 && n == std::floor(n)))
            throw InputError(SourcePos{"--steps"}, fmt::format("a step count must be a whole number from 1 to 1e9, not {}", n));
    if (!(r.min_time >= 0.0 && std::isfinite(r.min_time)))
        throw InputError(SourcePos{"--min-time"}, fmt::format("--min-time must be >= 0, not {}", r.min_time));
    if (r.repeats < 1) throw InputError(SourcePos{"--repeats"}, fmt::format("--repeats must be >= 1, not {}", r.repeats));
    for (std::size_t i = 0; i < r.formulations.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (r.formulations[i].name == r.formulations[j].name)
                throw InputError(SourcePos{"--formulations"},
                                 fmt::format("the formulation '{}' is listed twice", r.formulations[i].name));
    if (!(r.reference_tolerance > 0.0 && r.reference_tolerance < 1e-3))
        throw InputError(SourcePos{"--reference-tolerance"},
                         fmt::format("the reference tolerance must lie in (0, 1e-3), not {}", r.reference_tolerance));
}

std::string indent(const std::string& text, int spaces) {
    std::string out, pad(static_cast<std::size_t>(spaces), ' ');
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out += (line.empty() ? "" : pad + line) + "\n";
    return out;
}

// The request for one formulation's kernel: the same sweep on another header.
BenchRequest with_kernel(const BenchRequest& request, const BenchFormulation& f) {
    BenchRequest r = request;
    r.header_text = f.header_text;
    r.struct_name = f.struct_name;
    r.scene_name = f.scene_name;
    r.autonomous = f.autonomous;
    r.reference_body.clear();
    r.formulations.clear();
    return r;
}

// The reference of a formulation bench: its judged columns at t_end and their spread, from the
// cache when this kernel, end time, tolerance and columns have been run before (it takes minutes
// on long runs).
struct FormulationReference {
    std::string values;  // V1,...,Vn in full float128 precision
    double spread = 0.0;
    std::string note;
};

FormulationReference formulation_reference(const BenchRequest& request, const fs::path& driver) {
    const std::string judged = join(request.axis.judged, ",");
    const fs::path cached =
        driver.parent_path() / fmt::format("{}.reference-{:.17g}-{:.3g}-{}.txt", driver.filename().string(), request.t_end,
                                           request.reference_tolerance, join(request.axis.judged, "_"));
    std::string text;
    if (fs::exists(cached)) {
        text = read_whole_file(cached);
    } else {
        std::cerr << "computing the float128 " << request.axis.reference << " reference for " << request.scene_name
                  << " over t = 0 .. " << fmt::format("{:.6g}", request.t_end) << " (once; it is cached as "
                  << cached.string() << ")\n";
        text = run_driver({driver.string(), "--reference-only", "--budget-s", fmt::format("{:.17g}", request.budget_s),
                           "--t-end", fmt::format("{:.17g}", request.t_end),
                           "--reference-tolerance", fmt::format("{:.17g}", request.reference_tolerance), "--judge",
                           judged});
        write_file_atomically(cached, text);
    }
    FormulationReference ref;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("# ", 0) == 0) {
            ref.note = line.substr(2);
        } else if (line.rfind("reference_values,", 0) == 0) {
            const std::vector<std::string> f = split(line, ',');
            if (f.size() != request.axis.judged.size() + 2) break;
            ref.values = join(std::vector<std::string>(f.begin() + 1, f.end() - 1), ",");
            ref.spread = parse_double(f.back());
        }
    }
    if (ref.values.empty() || ref.note.empty())
        throw std::runtime_error("the reference run wrote no values (" + cached.string() + "):\n" + text);
    return ref;
}

// Step counts for fixed-step methods: 8 .. 2048 per period (an orbit's revolution, a body's turn)
// in half octaves (fewer than 8 steps per period only measure divergence).
std::vector<double> period_steps(const BenchRequest& request) {
    std::vector<double> steps;
    const double periods = request.t_end / request.axis.period;
    for (int k = 6; k <= 22; ++k) steps.push_back(std::max(1.0, std::round(periods * std::pow(2.0, k / 2.0))));
    steps.erase(std::unique(steps.begin(), steps.end()), steps.end());
    return steps;
}

// The formulations are compared by the explicit methods, whose cost per step is the kernel's calls
// alone: those with a real stability boundary (the catalogue's explicit Runge-Kutta methods),
// highest order first.
std::vector<std::string> formulation_bench_methods() {
    std::vector<const runtime::IntegratorInfo*> explicit_methods;
    for (const runtime::IntegratorInfo& info : runtime::integrator_infos)
        if (info.stability_limited()) explicit_methods.push_back(&info);
    std::stable_sort(explicit_methods.begin(), explicit_methods.end(),
                     [](const auto* a, const auto* b) { return a->order > b->order; });
    std::vector<std::string> names;
    for (const auto* info : explicit_methods) names.emplace_back(info->name);
    return names;
}

BenchResult formulation_bench(const BenchRequest& request) {
    BenchResult result;
    const FormulationAxis& axis = request.axis;
    result.table_levels = axis.table_levels;
    const std::vector<std::string> methods = request.methods.empty() ? formulation_bench_methods() : request.methods;
    const std::vector<double> steps = request.steps.empty() && axis.period > 0.0 ? period_steps(request) : request.steps;

    // The reference: the request's own kernel (the axis's reference formulation) in float128.
    const fs::path reference_driver = driver_for(request, result.cache_hit);
    result.driver_path = reference_driver.string();
    const FormulationReference ref = formulation_reference(request, reference_driver);
    result.reference_spread = ref.spread;
    result.notes.push_back(ref.note);
    if (!axis.exact.empty()) {
        // The float128 run against the closed form: the reference is checked, not trusted.
        const std::vector<std::string> values = split(ref.values, ',');
        double distance = 0.0, size = 0.0;
        for (std::size_t k = 0; k < axis.exact.size() && k < values.size(); ++k) {
            distance = std::max(distance, std::abs(parse_double(values[k]) - axis.exact[k]));
            size = std::max(size, std::abs(axis.exact[k]));
        }
        result.notes.push_back(fmt::format("the reference agrees with {} to {:.2g} (max-norm; {:.2g} relative)",
                                           axis.exact_source, distance, size > 0 ? distance / size : distance));
    }
    result.notes.insert(result.notes.end(), request.skipped.begin(), request.skipped.end());

    std::string csv = bench_formulation_csv_header(axis) + "\n";
    for (const BenchFormulation& f : request.formulations) {
        bool hit = false;
        const BenchRequest kernel = with_kernel(request, f);
        const fs::path driver = driver_for(kernel, hit);
        std::cerr << "formulation " << f.name << "\n";
        std::vector<std::string> argv{driver.string()};
        for (std::string& a : sweep_arguments(kernel, methods, steps)) argv.push_back(std::move(a));
        argv.insert(argv.end(), {"--judge", join(axis.judged, ","), "--reference-values", ref.values});
        if (!axis.drift_invariants.empty()) argv.insert(argv.end(), {"--drift-invariants", join(axis.drift_invariants, ",")});
        collect(run_driver(argv), f.name, f.name + ": ", result, csv);
    }

    // The reference must be far more accurate than anything it judges.
    double best = std::numeric_limits<double>::infinity();
    for (const BenchRow& r : result.rows) best = std::min(best, r.error);
    if (std::isfinite(best))
        result.notes.push_back(fmt::format("{}the reference's spread ({:.2g}) is {} the smallest error measured ({:.2g})",
                                           ref.spread * 100.0 <= best ? "" : "warning: ", ref.spread,
                                           ref.spread * 100.0 <= best ? fmt::format("{:.2g} times below", best / ref.spread)
                                                                      : std::string("not 100 times below"),
                                           best));
    // An error as large as the judged vector itself only says that the run lost it (an orbit's
    // coarse steps fly off to 1e8 km, or fall in): such runs are left out of the plot, whose scale
    // stays with the others.
    double radius2 = 0.0;
    for (const std::string& c : split(ref.values, ',')) radius2 += parse_double(c) * parse_double(c);
    const double error_cap = std::sqrt(radius2);
    write_outputs(request, result, csv, [&](const std::string& terminal, const fs::path& output) {
        return formulation_gnuplot_script(request, result, error_cap, terminal, output);
    });
    return result;
}

}  // namespace

std::string bench_formulation_csv_header(const FormulationAxis& axis) {
    return fmt::format("formulation,method,library,kind,setting,{},{},rhs_evals,steps,rejected,wall_seconds,repetitions",
                       axis.error_column, axis.drift_column);
}

std::string bench_config_source(const BenchRequest& request) {
    const bool has_reference = !request.reference_body.empty();
    return fmt::format(
        "// Generated by eomc for `eomc bench` on {}. Do not edit.\n"
        "#pragma once\n\n#include \"kernel.hpp\"\n\nnamespace eomc::bench {{\n\n"
        "using Model = eomc::models::{};\n"
        "inline constexpr bool autonomous = {};\n"
        "inline constexpr bool has_reference = {};\n"
        "inline constexpr const char* reference_source = {};\n\n"
        "// The exact state at time t (the scene's [reference]).\n"
        "template <class S>\nvoid reference(S t, S* out, const Model::Parameters& p) {{\n{}}}\n\n"
        "}}  // namespace eomc::bench\n",
        request.scene_path.empty() ? request.scene_name : request.scene_path, request.struct_name,
        request.autonomous ? "true" : "false", has_reference ? "true" : "false",
        codegen::string_literal(has_reference ? "[reference] of " + (request.scene_path.empty() ? request.scene_name : request.scene_path)
                                 : "none"),
        indent(has_reference ? request.reference_body : "(void)t;\n(void)out;\n(void)p;", 4));
}

// The stiffness hint: an explicit adaptive method whose step count does not fall as the tolerance
// loosens is limited by stability, not accuracy (an accuracy-limited method of order p takes
// tol^(-1/(p+1)) steps: over three decades at least 2x fewer for p <= 8). Implicit methods are left out.
namespace {

std::vector<std::string> stiffness_notes(const std::vector<BenchRow>& rows) {
    std::vector<std::string> notes, seen;
    for (const BenchRow& r : rows) {
        if (r.kind != "tolerance" || std::find(seen.begin(), seen.end(), r.method) != seen.end()) continue;
        seen.push_back(r.method);
        if (const runtime::IntegratorInfo* info = runtime::find_integrator(r.method); info && info->uses_jacobian) continue;
        const BenchRow *tight = nullptr, *loose = nullptr;
        for (const BenchRow& q : rows)
            if (q.method == r.method && q.library == r.library && q.kind == "tolerance") {
                if (!tight || q.setting < tight->setting) tight = &q;
                if (!loose || q.setting > loose->setting) loose = &q;
            }
        if (loose->setting < 1e3 * tight->setting || tight->steps == 0) continue;
        if (2 * loose->steps > tight->steps)
            notes.push_back(fmt::format("{} ({}) takes {} steps at tolerance {:.0e} and {} at {:.0e}: its step is limited "
                                        "by stability, not accuracy; the system is stiff, try {}",
                                        r.method, r.library, loose->steps, loose->setting, tight->steps, tight->setting,
                                        runtime::integrator_list(
                                            [](const auto& i) { return i.implicit() && !i.fixed_step(); }, " or ")));
    }
    return notes;
}

}  // namespace

BenchResult bench(const BenchRequest& request) {
    validate(request);
    if (!request.formulations.empty()) return formulation_bench(request);
    BenchResult result;
    const fs::path driver = driver_for(request, result.cache_hit);
    result.driver_path = driver.string();
    std::vector<std::string> argv{driver.string()};
    for (std::string& a : sweep_arguments(request, request.methods, request.steps)) argv.push_back(std::move(a));
    std::string csv = std::string(bench_csv_header) + "\n";
    collect(run_driver(argv), "", "", result, csv);
    for (std::string& n : stiffness_notes(result.rows)) result.notes.push_back(std::move(n));
    write_outputs(request, result, csv, [&](const std::string& terminal, const fs::path& output) {
        return gnuplot_script(request, result, terminal, output);
    });
    return result;
}

void print_bench_table(const BenchResult& result, std::ostream& out) {
    // Formulation benches: one line per formulation and method, at the axis's error levels (an
    // orbit's position errors of a unit, a km in the bundled scenes, a thousandth and a millionth).
    const bool axis = std::any_of(result.rows.begin(), result.rows.end(),
                                   [](const BenchRow& r) { return !r.formulation.empty(); });
    std::vector<std::pair<std::string, std::string>> lines;
    for (const auto& r : result.rows) {
        const std::pair<std::string, std::string> key{r.formulation, r.method};
        if (std::find(lines.begin(), lines.end(), key) == lines.end()) lines.push_back(key);
    }
    const std::vector<double> targets =
        !result.table_levels.empty() ? result.table_levels : std::vector<double>{1e-6, 1e-9, 1e-12};
    const int width = axis ? 20 : 18;
    std::string s = axis ? fmt::format("{:<14} {:<8} {:>4}  {:>10}", "formulation", "method", "runs", "best error")
                          : fmt::format("{:<30} {:<7} {:>4}  {:>10}", "method", "library", "runs", "best error");
    for (double t : targets) s += fmt::format("  {:>{}}", fmt::format("to {:.0e}: ms, rhs", t), width);
    s += fmt::format("  {:>12}\n", "drift (best)");
    for (const auto& [formulation, method] : lines) {
        std::vector<const BenchRow*> rows;
        for (const auto& r : result.rows)
            if (r.formulation == formulation && r.method == method) rows.push_back(&r);
        const BenchRow* best = *std::min_element(rows.begin(), rows.end(),
                                                 [](const BenchRow* a, const BenchRow* b) { return a->error < b->error; });
        s += axis ? fmt::format("{:<14} {:<8} {:>4}  {:>10.2e}", formulation, method, rows.size(), best->error)
                   : fmt::format("{:<30} {:<7} {:>4}  {:>10.2e}", method, rows.front()->library, rows.size(), best->error);
        for (double t : targets) {
            // The cheapest run (wall time) whose error is at most t.
            const BenchRow* cheapest = nullptr;
            for (const BenchRow* r : rows)
                if (r->error <= t && (!cheapest || r->seconds < cheapest->seconds)) cheapest = r;
            s += cheapest ? fmt::format("  {:>{}}",
                                        fmt::format("{:.3g} {:>{}}", cheapest->seconds * 1e3, cheapest->rhs_evals, axis ? 9 : 7),
                                        width)
                          : fmt::format("  {:>{}}", "-", width);
        }
        s += std::isnan(best->drift) ? fmt::format("  {:>12}\n", "-") : fmt::format("  {:>12.2e}\n", best->drift);
    }
    for (const auto& n : result.notes) s += "note: " + n + "\n";
    s += "csv: " + result.csv_path + "\n";
    if (!result.png_path.empty()) s += "plot: " + result.png_path + "\n";
    out << s;
}

}  // namespace eomc::host
