#include "host/linearize_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "host/ensemble_budget.hpp"
#include "host/gnuplot.hpp"
#include "host/simulate/output.hpp"
#include "support/diagnostic.hpp"
#include "support/json.hpp"

namespace eomc::host {

namespace {

std::string json_number(double v) { return std::isfinite(v) ? number(v) : "null"; }

double largest_real(const LinearizePoint& p) {
    double r = -std::numeric_limits<double>::infinity();
    for (const auto& l : p.eigenvalues) r = std::max(r, l.real());
    return p.eigenvalues.empty() ? std::numeric_limits<double>::quiet_NaN() : r;
}

}  // namespace

LinearizeInputs scene_inputs(const model::Model& model) {
    LinearizeInputs in;
    for (const auto& p : model.parameters) in.parameters.push_back(p.value);
    for (const auto& c : model.coordinates) in.q.push_back(c.initial), in.u.push_back(c.rate);
    return in;
}

void set_input(const model::Model& model, LinearizeInputs& inputs, const std::string& name, double value,
               const SourcePos& where) {
    for (std::size_t i = 0; i < model.parameters.size(); ++i)
        if (model.parameters[i].name == name) {
            inputs.parameters[i] = value;
            return;
        }
    std::string known;
    for (std::size_t k = 0; k < model.coordinates.size(); ++k) {
        const std::string& q = model.coordinates[k].name;
        if (q == name) {
            inputs.q[k] = value;
            return;
        }
        if (q + "_dot" == name) {
            inputs.u[k] = value;
            return;
        }
        known += fmt::format("{}{}, {}_dot", known.empty() ? "" : ", ", q, q);
    }
    for (const auto& p : model.parameters) known += ", " + p.name;
    throw InputError(where, fmt::format("'{}' is neither a parameter, a coordinate nor a coordinate's rate of {} "
                                        "(known: {})",
                                        name, model.name, known));
}

LinearizeSweep sweep_linearize(const mechanics::Linearizer& linearizer, const model::Model& model,
                               const EnsembleSpec& spec, mechanics::OperatingPointKind about,
                               const LinearizeInputs& base,
                               const std::vector<std::pair<std::string, double>>& base_overrides,
                               const SweepLimits& limits) {
    if (!spec.vary.empty())
        throw InputError(spec.vary.front().where, "--linearize sweeps a grid (--grid), not random draws");
    LinearizeInputs probe = base;  // every axis's name checked before the first point
    for (const auto& axis : spec.grid) set_input(model, probe, axis.name, 0.0, axis.where);
    LinearizeSweep sweep;
    sweep.scene_name = model.name;
    sweep.about = about == mechanics::OperatingPointKind::equilibrium ? "equilibrium" : "initial";
    sweep.input_names = spec.input_names();
    const std::size_t points = spec.members();
    ProgressBar progress(
        limits.progress, double(points), [](double done, double all) { return fmt::format("{} / {} grid points", done, all); },
        1, limits.always);
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < points; ++i) {
        LinearizePoint point;
        point.index = i;
        point.inputs = spec.inputs(i);
        LinearizeInputs in = base;
        std::vector<std::pair<std::string, double>> given = base_overrides;
        for (std::size_t k = 0; k < spec.grid.size(); ++k) {
            set_input(model, in, spec.grid[k].name, point.inputs[k], spec.grid[k].where);
            given.emplace_back(spec.grid[k].name, point.inputs[k]);
        }
        try {
            for (const auto& [name, value] : model::initial_overrides(model, given)) set_input(model, in, name, value, {});
            const auto lin = linearizer.linearize(in.parameters, about, in.q, in.u, SourcePos{"--grid"});
            point.eigenvalues = lin.eigenvalues;
            point.verdict = mechanics::stability_name(lin.verdict);
            for (std::size_t k : lin.ignorable) point.ignorable.push_back(model.coordinates[k].name);
        } catch (const InputError& e) {
            point.error = e.message();  // this point's operating point, not the scene: the sweep goes on
        }
        sweep.eigenvalue_count = std::max(sweep.eigenvalue_count, point.eigenvalues.size());
        sweep.points.push_back(std::move(point));
        if (i == 0)
            check_work_budget(points, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                              1, limits.budget_s, SourcePos{"--grid"}, "grid point");
        progress.update(double(i + 1));
    }
    return sweep;
}

std::string linearize_csv(const LinearizeSweep& s) {
    std::string out = "point";
    for (const auto& n : s.input_names) out += "," + n;
    out += ",verdict";
    for (std::size_t j = 1; j <= s.eigenvalue_count; ++j) out += fmt::format(",re_{},im_{}", j, j);
    out += "\n";
    for (const auto& p : s.points) {
        out += std::to_string(p.index);
        for (double v : p.inputs) out += "," + number(v);
        out += "," + (p.error.empty() ? p.verdict : std::string("none"));
        for (std::size_t j = 0; j < s.eigenvalue_count; ++j)
            out += j < p.eigenvalues.size()
                       ? fmt::format(",{},{}", number(p.eigenvalues[j].real()), number(p.eigenvalues[j].imag()))
                       : std::string(",,");
        out += "\n";
    }
    return out;
}

std::string linearize_summary(const LinearizeSweep& s, const std::string& format) {
    if (format == "json") {
        std::string out = fmt::format("{{\"scene\": {}, \"about\": {}, \"points\": [", json_string(s.scene_name),
                                      json_string(s.about));
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            const auto& p = s.points[i];
            out += fmt::format("{}{{\"inputs\": {{", i ? ",\n " : "\n ");
            for (std::size_t k = 0; k < p.inputs.size(); ++k)
                out += fmt::format("{}{}: {}", k ? ", " : "", json_string(s.input_names[k]), json_number(p.inputs[k]));
            out += "}, \"eigenvalues\": [";
            for (std::size_t j = 0; j < p.eigenvalues.size(); ++j)
                out += fmt::format("{}[{}, {}]", j ? ", " : "", json_number(p.eigenvalues[j].real()),
                                   json_number(p.eigenvalues[j].imag()));
            out += fmt::format("], \"verdict\": {}, \"error\": {}}}", p.error.empty() ? json_string(p.verdict) : "null",
                               p.error.empty() ? "null" : json_string(p.error));
        }
        return out + "]}\n";
    }
    if (format != "text")
        throw InputError(SourcePos{"--format"}, fmt::format("unknown summary format '{}' (expected text or json)", format));
    std::string out = fmt::format("{}: linearised about {} at {} grid points\n", s.scene_name,
                                  s.about == "equilibrium" ? "the nearest equilibrium" : "the initial state",
                                  s.points.size());
    for (const auto& p : s.points) {
        std::string at;
        for (std::size_t k = 0; k < p.inputs.size(); ++k)
            at += fmt::format("{}{} = {:.6g}", k ? ", " : "", s.input_names[k], p.inputs[k]);
        out += p.error.empty() ? fmt::format("  {}: {} (largest Re λ = {:.6g})\n", at, p.verdict, largest_real(p))
                               : fmt::format("  {}: none ({})\n", at, p.error);
    }
    return out;
}

std::string linearize_plot_script(const LinearizeSweep& s, const EnsembleSpec& spec, const std::string& terminal,
                                  const std::filesystem::path& output) {
    std::vector<std::size_t> varied;
    for (std::size_t k = 0; k < spec.grid.size(); ++k)
        if (spec.grid[k].count > 1) varied.push_back(k);
    if (varied.size() != 1)
        throw InputError(SourcePos{"--plot"}, fmt::format("a picture of a linearisation sweep draws the real parts "
                                                          "against one axis; this grid varies {}",
                                                          varied.size()));
    const auto label = [](const std::string& text) { return gnuplot_quoted(gnuplot_text(text)); };
    std::string out = fmt::format("set terminal {} size 1000,700 font ',10'\nset output {}\nset grid\n$data << EOD\n",
                                  terminal, gnuplot_quoted(output.string()));
    for (const auto& p : s.points) {
        out += number(p.inputs[varied[0]]);
        for (std::size_t j = 0; j < s.eigenvalue_count; ++j)
            out += " " + (j < p.eigenvalues.size() ? number(p.eigenvalues[j].real()) : std::string("NaN"));
        out += "\n";
    }
    out += fmt::format("EOD\nset title {}\nset xlabel {}\nset ylabel 'Re(lambda)'\nset key outside\nplot ",
                       label(fmt::format("{}: real parts of the eigenvalues", s.scene_name)),
                       label(s.input_names[varied[0]]));
    for (std::size_t j = 0; j < s.eigenvalue_count; ++j)
        out += fmt::format("{}$data using 1:{} with linespoints pt 7 ps 0.6 title 'Re lambda_{}'", j ? ", " : "", j + 2,
                           j + 1);
    return out + (s.eigenvalue_count ? "\n" : "0 notitle\n");
}

}  // namespace eomc::host
