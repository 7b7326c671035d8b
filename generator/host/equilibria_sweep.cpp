#include "host/equilibria_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "host/gnuplot.hpp"
#include "host/simulate/output.hpp"
#include "support/diagnostic.hpp"
#include "support/json.hpp"

namespace eomc::host {

namespace {

std::string json_number(double v) { return std::isfinite(v) ? number(v) : "null"; }

}  // namespace

double largest_growth(const mechanics::Equilibrium& e) {
    double growth = -std::numeric_limits<double>::infinity();
    for (const auto& l : e.eigenvalues) growth = std::max(growth, l.real());
    return e.eigenvalues.empty() ? std::numeric_limits<double>::quiet_NaN() : growth;
}

double largest_growth(const mechanics::rigid::PermanentRotation& r) {
    double growth = -std::numeric_limits<double>::infinity();
    for (const auto& l : r.reduced) growth = std::max(growth, l.real());
    return r.reduced.empty() ? std::numeric_limits<double>::quiet_NaN() : growth;
}

namespace {

constexpr std::size_t spin_axis = static_cast<std::size_t>(-1);

// Point i: the equilibria with its parameter values (set in `at_point`, a copy of the model).
EquilibriumPoint solve_point(const mechanics::Equations& equations, const EnsembleSpec& spec,
                             const std::vector<std::size_t>& parameter_of, bool rigid, std::size_t i,
                             model::Model& at_point) {
    EquilibriumPoint point;
    point.index = i;
    point.inputs = spec.inputs(i);
    std::optional<double> spin;
    for (std::size_t k = 0; k < parameter_of.size(); ++k) {
        if (parameter_of[k] == spin_axis) spin = point.inputs[k];
        else at_point.parameters[parameter_of[k]].value = point.inputs[k];
    }
    try {
        if (rigid) point.rotations = mechanics::rigid::rigid_equilibria(at_point, spin).rotations;
        else point.equilibria = mechanics::relative_equilibria(at_point, equations);
    } catch (const InputError&) {
        throw;  // the scene, not the point: the same everywhere
    } catch (const std::exception& e) {
        point.error = e.what();
    }
    return point;
}

}  // namespace

EquilibriumSweep sweep_equilibria(const model::Model& model, const mechanics::Equations& equations,
                                  const EnsembleSpec& spec, const SweepLimits& limits) {
    if (!spec.vary.empty())
        throw InputError(spec.vary.front().where, "--equilibria sweeps a grid of parameters (--grid), not random draws");
    const bool rigid = model.kind() == model::ModelKind::rigid;
    std::vector<std::size_t> parameter_of;
    for (const auto& axis : spec.grid) {
        if (rigid && axis.name == "spin") {
            parameter_of.push_back(spin_axis);
            continue;
        }
        const auto at = std::find_if(model.parameters.begin(), model.parameters.end(),
                                     [&](const model::Parameter& p) { return p.name == axis.name; });
        if (at == model.parameters.end())
            throw InputError(axis.where, fmt::format("'{}' is not a parameter of {}: an equilibrium sweep varies "
                                                     "parameters only (equilibria have no initial values){}",
                                                     axis.name, model.name, rigid ? ", and spin" : ""));
        parameter_of.push_back(static_cast<std::size_t>(at - model.parameters.begin()));
    }
    EquilibriumSweep sweep;
    sweep.scene_name = model.name;
    sweep.input_names = spec.input_names();
    sweep.rigid = rigid;
    if (rigid) sweep.coordinate_names = {"gamma1", "gamma2", "gamma3", "spin"};
    else
        for (const auto& c : model.coordinates) sweep.coordinate_names.push_back(c.name);
    model::Model at_point = model;  // the equations stay symbolic; only the values change
    const std::size_t points = spec.members();
    ProgressBar progress(
        limits.progress, double(points), [](double done, double all) { return fmt::format("{} / {} grid points", done, all); },
        1, limits.always);
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < points; ++i) {
        sweep.points.push_back(solve_point(equations, spec, parameter_of, rigid, i, at_point));
        if (i == 0)  // the first point's time × the points: refused before the second runs
            check_work_budget(points, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                              1, limits.budget_s, SourcePos{"--grid"}, "grid point");
        progress.update(double(i + 1));
    }
    return sweep;
}

std::string equilibria_csv(const EquilibriumSweep& s) {
    if (s.rigid) {
        std::string out = "point";
        for (const auto& n : s.input_names) out += "," + n;
        out += ",rotations,rotation,gamma1,gamma2,gamma3,rotation_spin,verdict,growth\n";
        for (const auto& p : s.points) {
            std::string head = std::to_string(p.index);
            for (double v : p.inputs) head += fmt::format(",{}", number(v));
            head += fmt::format(",{}", p.rotations.size());
            if (p.rotations.empty()) out += head + ",,,,,,,\n";
            for (const auto& r : p.rotations)
                out += fmt::format("{},{},{},{},{},{},{},{}\n", head, r.label, number(r.gamma[0]), number(r.gamma[1]),
                                   number(r.gamma[2]), number(r.spin), r.verdict, number(largest_growth(r)));
        }
        return out;
    }
    std::string out = "point";
    for (const auto& n : s.input_names) out += "," + n;
    out += ",equilibria";
    for (const auto& n : s.coordinate_names) out += "," + n;
    out += ",verdict,growth\n";
    for (const auto& p : s.points) {
        std::string head = std::to_string(p.index);
        for (double v : p.inputs) head += fmt::format(",{}", number(v));
        head += fmt::format(",{}", p.equilibria.size());
        if (p.equilibria.empty()) {
            out += head + std::string(s.coordinate_names.size() + 2, ',') + "\n";
            continue;
        }
        for (const auto& e : p.equilibria) {
            out += head;
            for (double q : e.q) out += fmt::format(",{}", number(q));
            out += fmt::format(",{},{}\n", e.verdict, number(largest_growth(e)));
        }
    }
    return out;
}

std::string equilibria_summary(const EquilibriumSweep& s, const std::string& format) {
    const auto count = [](const EquilibriumPoint& p, bool stable) {
        return static_cast<std::size_t>(std::count_if(p.equilibria.begin(), p.equilibria.end(), [&](const auto& e) {
            return (e.verdict != "unstable") == stable;
        }));
    };
    if (format == "json") {
        std::string out = fmt::format("{{\"scene\": {}, \"points\": [", json_string(s.scene_name));
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            const auto& p = s.points[i];
            out += fmt::format("{}{{\"inputs\": {{", i ? ", " : "");
            for (std::size_t k = 0; k < p.inputs.size(); ++k)
                out += fmt::format("{}{}: {}", k ? ", " : "", json_string(s.input_names[k]), json_number(p.inputs[k]));
            out += "}, \"equilibria\": [";
            for (std::size_t j = 0; j < p.equilibria.size(); ++j) {
                const auto& e = p.equilibria[j];
                out += fmt::format("{}{{\"q\": [", j ? ", " : "");
                for (std::size_t k = 0; k < e.q.size(); ++k) out += fmt::format("{}{}", k ? ", " : "", json_number(e.q[k]));
                out += fmt::format("], \"verdict\": {}, \"growth\": {}}}", json_string(e.verdict),
                                   json_number(largest_growth(e)));
            }
            out += "], \"rotations\": [";
            for (std::size_t j = 0; j < p.rotations.size(); ++j) {
                const auto& r = p.rotations[j];
                out += fmt::format("{}{{\"rotation\": {}, \"gamma\": [{}, {}, {}], \"spin\": {}, \"verdict\": {}, "
                                   "\"growth\": {}}}",
                                   j ? ", " : "", json_string(r.label), json_number(r.gamma[0]), json_number(r.gamma[1]),
                                   json_number(r.gamma[2]), json_number(r.spin), json_string(r.verdict),
                                   json_number(largest_growth(r)));
            }
            out += fmt::format("], \"error\": {}}}", p.error.empty() ? "null" : json_string(p.error));
        }
        return out + "]}\n";
    }
    if (format != "text")
        throw InputError(SourcePos{"--format"}, fmt::format("unknown summary format '{}' (expected text or json)", format));
    std::string out = fmt::format("{}: {} at {} grid points\n", s.scene_name,
                                  s.rigid ? "permanent rotations about the principal axes" : "relative equilibria",
                                  s.points.size());
    for (const auto& p : s.points) {
        std::string at;
        for (std::size_t k = 0; k < p.inputs.size(); ++k)
            at += fmt::format("{}{} = {:.6g}", k ? ", " : "", s.input_names[k], p.inputs[k]);
        if (s.rigid && p.error.empty()) {
            std::string verdicts;
            for (const auto& r : p.rotations) verdicts += fmt::format("{}{} {}", verdicts.empty() ? "" : "; ", r.label, r.verdict);
            out += fmt::format("  {}: {}\n", at, verdicts.empty() ? "none" : verdicts);
            continue;
        }
        out += p.error.empty() ? fmt::format("  {}: {} equilibria, {} stable, {} unstable\n", at, p.equilibria.size(),
                                             count(p, true), count(p, false))
                               : fmt::format("  {}: none found ({})\n", at, p.error);
    }
    return out;
}

std::string equilibria_plot_script(const EquilibriumSweep& s, const EnsembleSpec& spec, const std::string& terminal,
                                   const std::filesystem::path& output) {
    std::vector<std::size_t> varied;
    for (std::size_t k = 0; k < spec.grid.size(); ++k)
        if (spec.grid[k].count > 1) varied.push_back(k);
    if (varied.empty() || varied.size() > 2)
        throw InputError(SourcePos{"--plot"}, fmt::format("a picture of an equilibrium sweep needs a grid that varies one "
                                                          "axis (a bifurcation diagram) or two (a stability map); this "
                                                          "one varies {}",
                                                          varied.size()));
    const auto label = [](const std::string& text) { return gnuplot_quoted(gnuplot_text(text)); };
    std::string out = fmt::format("set terminal {} size 1000,700 font ',10'\nset output {}\nset grid\n", terminal,
                                  gnuplot_quoted(output.string()));
    const std::string& x = s.input_names[varied[0]];
    if (varied.size() == 1 && s.rigid) {
        // Each permanent rotation's growth rate (the largest Re λ on its leaf) against the axis: the
        // boundary is where a branch leaves zero.
        for (const char* kind : {"stable", "unstable"}) {
            out += fmt::format("${} << EOD\n", kind);
            for (const auto& p : s.points)
                for (const auto& r : p.rotations)
                    if ((r.verdict == "unstable") == (std::string(kind) == "unstable"))
                        out += fmt::format("{} {}\n", number(p.inputs[varied[0]]), number(largest_growth(r)));
            out += "EOD\n";
        }
        return out + fmt::format("set title {}\nset xlabel {}\nset ylabel 'largest Re(lambda) on the leaf'\n"
                                 "set key outside\n"
                                 "plot $stable using 1:2 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'spectrally stable', "
                                 "$unstable using 1:2 with points pt 6 ps 0.8 lc rgb '#d62728' title 'unstable'\n",
                                 label(fmt::format("{}: permanent rotations", s.scene_name)), label(x));
    }
    if (varied.size() == 1) {
        if (s.coordinate_names.empty()) throw InputError(SourcePos{"--plot"}, "the scene has no coordinates to draw");
        // Stable equilibria as filled points, unstable as open ones: the branches of the diagram.
        for (const char* kind : {"stable", "unstable"}) {
            out += fmt::format("${} << EOD\n", kind);
            for (const auto& p : s.points)
                for (const auto& e : p.equilibria)
                    if ((e.verdict == "unstable") == (std::string(kind) == "unstable"))
                        out += fmt::format("{} {}\n", number(p.inputs[varied[0]]), number(e.q[0]));
            out += "EOD\n";
        }
        return out + fmt::format("set title {}\nset xlabel {}\nset ylabel {}\nset key outside\n"
                                 "plot $stable using 1:2 with points pt 7 ps 0.8 lc rgb '#1f77b4' title 'stable', "
                                 "$unstable using 1:2 with points pt 6 ps 0.8 lc rgb '#d62728' title 'unstable'\n",
                                 label(fmt::format("{}: relative equilibria", s.scene_name)), label(x),
                                 label(s.coordinate_names[0]));
    }
    const std::string& y = s.input_names[varied[1]];
    out += "$d << EOD\n";
    for (const auto& p : s.points) {
        const auto stable = std::count_if(p.equilibria.begin(), p.equilibria.end(),
                                          [](const auto& e) { return e.verdict != "unstable"; }) +
                            std::count_if(p.rotations.begin(), p.rotations.end(),
                                          [](const auto& r) { return r.verdict != "unstable"; });
        out += fmt::format("{} {} {}\n", number(p.inputs[varied[0]]), number(p.inputs[varied[1]]),
                           p.error.empty() ? std::to_string(stable) : std::string("NaN"));
    }
    out += "EOD\n";
    return out + fmt::format("set title {}\nset xlabel {}\nset ylabel {}\nset cblabel {}\n"
                             "set palette rgb 33,13,10\nplot $d using 1:2:3 with image notitle\n",
                             label(fmt::format("{}: stability map", s.scene_name)), label(x), label(y),
                             label(s.rigid ? "spectrally stable rotations" : "stable equilibria"));
}

}  // namespace eomc::host
