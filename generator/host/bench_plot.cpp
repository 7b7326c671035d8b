#include "host/bench_plot.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "host/gnuplot.hpp"

namespace eomc::host::bench_plot {

namespace fs = std::filesystem;

// Two panels, log-log, one curve per method against the median wall time of a run: the error of
// the final state, and the largest relative drift of the invariants. Ours solid, odeint dashed.
std::string gnuplot_script(const BenchRequest& request, const BenchResult& result, const std::string& terminal,
                           const fs::path& output) {
    static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                   "#bcbd22", "#17becf", "#ff7f0e", "#393b79", "#637939", "#843c39"};
    std::vector<std::string> methods;
    for (const auto& r : result.rows)
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);

    std::string s = fmt::format("set terminal {} size 1600,700 font ',10'\nset output {}\n", terminal,
                                gnuplot_quoted(output.string()));
    bool any_drift = false;
    for (std::size_t m = 0; m < methods.size(); ++m) {
        std::vector<const BenchRow*> rows;
        for (const auto& r : result.rows)
            if (r.method == methods[m]) rows.push_back(&r);
        std::sort(rows.begin(), rows.end(), [](const BenchRow* a, const BenchRow* b) { return a->seconds < b->seconds; });
        s += fmt::format("$m{} << EOD\n", m);
        for (const BenchRow* r : rows) {
            // Zeros have no place on a log scale: NaN leaves the point out.
            const auto positive = [](double v) { return v > 0.0 && std::isfinite(v) ? fmt::format("{:.6g}", v) : "NaN"; };
            s += fmt::format("{} {} {}\n", positive(r->seconds), positive(r->error), positive(r->drift));
            any_drift = any_drift || (r->drift > 0.0 && std::isfinite(r->drift));
        }
        s += "EOD\n";
    }
    s += fmt::format("set multiplot layout 1,2 title {}\n",
                     gnuplot_quoted(gnuplot_text(
                         fmt::format("{}: work-precision over t = 0 .. {:.6g}", request.scene_name, request.t_end))));
    s += "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\nset key bottom left font ',9'\n"
         "set xlabel 'wall time per run (s, median)'\n";
    auto plot = [&](const char* ylabel, int column) {
        std::string p = fmt::format("set ylabel '{}'\nplot ", ylabel);
        for (std::size_t m = 0; m < methods.size(); ++m) {
            const std::string& library =
                std::find_if(result.rows.begin(), result.rows.end(), [&](const BenchRow& r) { return r.method == methods[m]; })
                    ->library;
            p += fmt::format("{}$m{} using 1:{} with linespoints lw 1.5 pt {} dt {} lc rgb '{}' title '{}{}'",
                             m ? ", \\\n     " : "", m, column, m % 13 + 1, library == "eomc" ? 1 : 2,
                             colors[m % 13], gnuplot_text(methods[m]), library == "eomc" ? "" : " (odeint)");
        }
        return p + "\n";
    };
    if (!methods.empty()) {
        s += plot("error of the final state (max norm)", 2);
        if (any_drift) {
            s += plot("max relative drift of the invariants", 3);
        } else {
            s += "unset logscale\nunset key\nunset xlabel\nunset ylabel\nset format x ''\nset format y ''\n"
                 "set label 1 'no invariants' at graph 0.5, 0.5 center\nplot [0:1] [0:1] NaN notitle\n";
        }
    }
    s += "unset multiplot\n";
    return s;
}

// Two panels, log-log, one curve per formulation and method: the error of the judged columns at
// t_end against the median wall time of a run, and against its rhs evaluations; a third, the drift
// of the measured invariants against the wall time, when the axis names them. Colour:
// formulation; point and dash: method.
// Errors above `error_cap` are left out of the plot (they are in the CSV and the table).
std::string formulation_gnuplot_script(const BenchRequest& request, const BenchResult& result, double error_cap,
                                       const std::string& terminal, const fs::path& output) {
    static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                   "#bcbd22", "#17becf", "#ff7f0e"};
    std::vector<std::string> formulations, methods;
    std::vector<std::pair<std::string, std::string>> curves;
    for (const auto& r : result.rows) {
        if (std::find(formulations.begin(), formulations.end(), r.formulation) == formulations.end())
            formulations.push_back(r.formulation);
        if (std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);
        const std::pair<std::string, std::string> c{r.formulation, r.method};
        if (std::find(curves.begin(), curves.end(), c) == curves.end()) curves.push_back(c);
    }
    const auto index = [](const std::vector<std::string>& v, const std::string& x) {
        return static_cast<std::size_t>(std::find(v.begin(), v.end(), x) - v.begin());
    };
    const auto positive = [](double v) { return v > 0.0 && std::isfinite(v) ? fmt::format("{:.6g}", v) : "NaN"; };
    std::string s = fmt::format("set terminal {} size 1600,700 font ',10'\nset output {}\n", terminal,
                                gnuplot_quoted(output.string()));
    for (std::size_t c = 0; c < curves.size(); ++c) {
        std::vector<const BenchRow*> rows;
        for (const auto& r : result.rows)
            if (r.formulation == curves[c].first && r.method == curves[c].second) rows.push_back(&r);
        // In sweep order (tolerances falling, step counts rising); a run that lost the orbit is a
        // gap in its curve.
        s += fmt::format("$c{} << EOD\n", c);
        for (const BenchRow* r : rows)
            s += fmt::format("{} {} {} {}\n", positive(r->seconds), positive(static_cast<double>(r->rhs_evals)),
                             r->error <= error_cap ? positive(r->error) : "NaN", positive(r->drift));
        s += "EOD\n";
    }
    const FormulationAxis& axis = request.axis;
    const bool drift_panel = !axis.drift_invariants.empty();
    s += fmt::format("set multiplot layout 1,{} title {}\n", drift_panel ? 3 : 2,
                     gnuplot_quoted(gnuplot_text(fmt::format("{}: {} error at t = {:.6g} against a float128 {} run ({}, "
                                                             "left out)",
                                                             request.scene_name, axis.judged_what, request.t_end,
                                                             axis.reference, axis.lost))));
    s += "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\nset key bottom left font ',9'\n";
    s += fmt::format("set ylabel {}\n", gnuplot_quoted(gnuplot_text(axis.judged_what + " error at the end time")));
    if (std::isfinite(error_cap)) s += fmt::format("set yrange [:{:.3g}]\n", 2.0 * error_cap);
    const auto panel = [&](const char* xlabel, int column, int y) {
        std::string p = fmt::format("set xlabel '{}'\nplot ", xlabel);
        for (std::size_t c = 0; c < curves.size(); ++c) {
            const std::size_t f = index(formulations, curves[c].first), m = index(methods, curves[c].second);
            p += fmt::format("{}$c{} using {}:{} with linespoints lw 1.5 pt {} dt {} lc rgb '{}' title '{} {}'",
                             c ? ", \\\n     " : "", c, column, y, m % 13 + 1, m % 5 + 1, colors[f % 10],
                             gnuplot_text(curves[c].first), gnuplot_text(curves[c].second));
        }
        return p + "\n";
    };
    if (!curves.empty()) {
        s += panel("wall time per run (s, median)", 1, 3);
        s += panel("rhs evaluations per run", 2, 3);
        if (drift_panel) {
            s += "unset yrange\n";
            s += fmt::format("set ylabel {}\n", gnuplot_quoted(gnuplot_text(fmt::format(
                                                  "max relative drift of {}", fmt::join(axis.drift_invariants, ", ")))));
            s += panel("wall time per run (s, median)", 1, 4);
        }
    }
    s += "unset multiplot\n";
    return s;
}

}  // namespace eomc::host::bench_plot
