#include "host/bench_io.hpp"

#include <sys/wait.h>

#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "codegen/templates.hpp"
#include "host/gnuplot.hpp"
#include "host/toolchain.hpp"
#include "support/input_file.hpp"
#include "support/output_file.hpp"

namespace eomc::host::bench_io {

namespace fs = std::filesystem;

std::string join(const std::vector<std::string>& items, const char* separator) {
    std::string out;
    for (const auto& s : items) {
        if (!out.empty()) out += separator;
        out += s;
    }
    return out;
}

std::string number_list(const std::vector<double>& values) {
    std::string out;
    for (double v : values) {
        if (!out.empty()) out += ',';
        out += fmt::format("{:.17g}", v);
    }
    return out;
}

std::vector<std::string> split(const std::string& line, char separator) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (;;) {
        const std::size_t at = line.find(separator, start);
        out.push_back(line.substr(start, at == std::string::npos ? std::string::npos : at - start));
        if (at == std::string::npos) return out;
        start = at + 1;
    }
}

double parse_double(const std::string& s) {
    if (s.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size()) throw std::runtime_error("not a number: " + s);
    return v;
}

BenchRow parse_row(const std::string& line, const std::string& formulation) {
    const std::vector<std::string> f = split(line, ',');
    if (f.size() != 11) throw std::runtime_error("the benchmark driver wrote a malformed row: " + line);
    BenchRow r;
    r.formulation = formulation;
    r.method = f[0];
    r.library = f[1];
    r.kind = f[2];
    r.setting = parse_double(f[3]);
    r.error = parse_double(f[4]);
    r.drift = parse_double(f[5]);
    r.rhs_evals = std::stoull(f[6]);
    r.steps = std::stoull(f[7]);
    r.rejected = std::stoull(f[8]);
    r.seconds = parse_double(f[9]);
    r.repetitions = std::stoi(f[10]);
    return r;
}

// The driver program of a request's kernel, compiled unless the cache has it.
fs::path driver_for(const BenchRequest& request, bool& cache_hit) {
    CompileRequest build;
    build.files = {{"bench_driver.cpp", codegen::bench_driver_template()},
                   {"kernel.hpp", request.header_text},
                   {"bench_config.hpp", bench_config_source(request)}};
    if (request.odeint_array) build.flags = {"-DEOMC_BENCH_ODEINT_ARRAY"};
    build.libraries = {"-lquadmath"};
    build.what = "the benchmark driver";
    const fs::path driver = cached_path(build, request.cache_dir);
    cache_hit = fs::exists(driver);
    if (!cache_hit) {
        std::cerr << "compiling the benchmark driver for " << request.scene_name
                  << " (once per kernel; it is cached as " << driver.string() << ")\n";
        compile(build, driver);
    }
    return driver;
}

// Runs a driver; its standard output (CSV rows and '# ' notes).
std::string run_driver(const std::vector<std::string>& argv) {
    TempDir work("eomc-bench-");
    const fs::path output = work.path() / "driver.csv";
    const int status = run_process(argv, output, false);
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0))
        throw std::runtime_error(fmt::format("the benchmark driver {} {}", argv.front(), describe_status(status)));
    return read_whole_file(output);
}

// The sweep's options, as the driver takes them.
std::vector<std::string> sweep_arguments(const BenchRequest& request, const std::vector<std::string>& methods,
                                         const std::vector<double>& steps) {
    std::vector<std::string> argv{"--t-end", fmt::format("{:.17g}", request.t_end)};
    if (!methods.empty()) argv.insert(argv.end(), {"--methods", join(methods, ",")});
    if (!request.tolerances.empty()) argv.insert(argv.end(), {"--tolerances", number_list(request.tolerances)});
    if (!steps.empty()) argv.insert(argv.end(), {"--steps", number_list(steps)});
    argv.insert(argv.end(), {"--min-time", fmt::format("{:.17g}", request.min_time == 0.0 ? 1e-9 : request.min_time),
                             "--repeats", std::to_string(request.repeats), "--budget-s",
                             fmt::format("{:.17g}", request.budget_s)});
    return argv;
}

// Rows (tagged with `formulation`) and notes (prefixed with `note_prefix`) of a driver's output;
// the rows as written, after "formulation," when there is one, are appended to `csv`.
void collect(const std::string& text, const std::string& formulation, const std::string& note_prefix,
             BenchResult& result, std::string& csv) {
    bool header_seen = false;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("# ", 0) == 0) {
            result.notes.push_back(note_prefix + line.substr(2));
        } else if (!header_seen) {
            if (line != bench_csv_header)
                throw std::runtime_error("the benchmark driver wrote an unexpected header: " + line);
            header_seen = true;
        } else if (!line.empty()) {
            result.rows.push_back(parse_row(line, formulation));
            csv += (formulation.empty() ? "" : formulation + ",") + line + "\n";
        }
    }
    if (!header_seen) throw std::runtime_error("the benchmark driver wrote no CSV header");
}

// DIR/work_precision.csv (`csv`: header and rows) and DIR/work_precision.png.
void write_outputs(const BenchRequest& request, BenchResult& result, const std::string& csv,
                   const std::function<std::string(const std::string&, const fs::path&)>& script_for) {
    const fs::path dir = request.out_dir.empty() ? fs::path(".") : fs::path(request.out_dir);
    const fs::path csv_path = dir / "work_precision.csv", png_path = dir / "work_precision.png";
    write_file_atomically(csv_path, csv);
    result.csv_path = csv_path.string();
    const std::string no_plot = write_plot(script_for, png_path);
    if (no_plot.empty()) {
        result.png_path = png_path.string();
    } else {
        std::cerr << "eomc: warning: " << no_plot << "\n";
        result.notes.push_back(no_plot.substr(0, no_plot.find('\n')));
    }
}

}  // namespace eomc::host::bench_io
