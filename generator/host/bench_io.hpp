// The benchmark's driver program (templates/bench_driver.cpp with the kernel): built or found in
// the cache, run, its rows read back; the CSV and the picture written. Internal to host/bench*.cpp.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "host/bench.hpp"

namespace eomc::host::bench_io {

std::string join(const std::vector<std::string>& items, const char* separator = ", ");
// Every digit of each value, comma-separated (the driver's lists).
std::string number_list(const std::vector<double>& values);
std::vector<std::string> split(const std::string& line, char separator);
// A number as the driver writes it; "" is NaN.
double parse_double(const std::string& s);
BenchRow parse_row(const std::string& line, const std::string& formulation);

// The driver program of a request's kernel, compiled unless the cache has it.
std::filesystem::path driver_for(const BenchRequest& request, bool& cache_hit);
// Runs a driver; its standard output (CSV rows and '# ' notes).
std::string run_driver(const std::vector<std::string>& argv);
// The sweep's options, as the driver takes them.
std::vector<std::string> sweep_arguments(const BenchRequest& request, const std::vector<std::string>& methods,
                                         const std::vector<double>& steps);
// Rows (tagged with `formulation`) and notes (prefixed with `note_prefix`) of a driver's output;
// the rows as written, after "formulation," when there is one, are appended to `csv`.
void collect(const std::string& text, const std::string& formulation, const std::string& note_prefix,
             BenchResult& result, std::string& csv);
// DIR/work_precision.csv (`csv`: header and rows) and DIR/work_precision.png.
void write_outputs(const BenchRequest& request, BenchResult& result, const std::string& csv,
                   const std::function<std::string(const std::string&, const std::filesystem::path&)>& script_for);

}  // namespace eomc::host::bench_io
