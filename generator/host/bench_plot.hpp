// The benchmark's pictures (gnuplot scripts): work against precision per method, and per
// formulation. Internal to host/bench*.cpp.
#pragma once

#include <filesystem>
#include <string>

#include "host/bench.hpp"

namespace eomc::host::bench_plot {

// Two panels, log-log, one curve per method against the median wall time of a run: the error of
// the final state, and the largest relative drift of the invariants. Ours solid, odeint dashed.
std::string gnuplot_script(const BenchRequest& request, const BenchResult& result, const std::string& terminal,
                           const std::filesystem::path& output);

// The formulations' panels; errors above `error_cap` are left out of the plot (they are in the
// CSV and the table).
std::string formulation_gnuplot_script(const BenchRequest& request, const BenchResult& result, double error_cap,
                                       const std::string& terminal, const std::filesystem::path& output);

}  // namespace eomc::host::bench_plot
