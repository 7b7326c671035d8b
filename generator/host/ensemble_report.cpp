// The ensembles' results as CSV, statistics, a summary and a picture (ensemble.hpp).
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "host/ensemble.hpp"
#include "host/gnuplot.hpp"
#include "host/simulate/output.hpp"
#include "support/json.hpp"

namespace eomc::host {

namespace {

std::string json_number(double v) { return std::isfinite(v) ? number(v) : "null"; }

// A CSV cell holding free text: quoted, quotes doubled, line breaks as spaces (RFC 4180).
std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += "\"\"";
        else if (c == '\n' || c == '\r') out += ' ';
        else out += c;
    }
    return out + "\"";
}

// The numeric columns summarised and drawn: t, the state, the drifts, the --observe columns.
std::vector<std::string> column_names(const EnsembleResult& r) {
    std::vector<std::string> names{"t"};
    names.insert(names.end(), r.state_names.begin(), r.state_names.end());
    for (const auto& n : r.invariant_names) names.push_back(n + "_max_drift");
    names.insert(names.end(), r.observed_names.begin(), r.observed_names.end());
    return names;
}
double column_value(const MemberResult& m, std::size_t c) {
    if (c == 0) return m.t;
    if (c <= m.state.size()) return m.state[c - 1];
    c -= 1 + m.state.size();
    return c < m.drifts.size() ? m.drifts[c] : m.observed[c - m.drifts.size()];
}

double quantile(const std::vector<double>& sorted, double p) {
    const double at = p * static_cast<double>(sorted.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(std::floor(at));
    const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
    return sorted[lo] + (at - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace

void refuse_if_all_refused(const EnsembleResult& result) {
    if (!result.members.empty() &&
        std::all_of(result.members.begin(), result.members.end(), [](const MemberResult& m) { return m.refused; }))
        throw InputError(result.members.front().refused_at,
                         fmt::format("every member was refused; member {}: {}", result.members.front().index,
                                     result.members.front().refusal));
}

std::string ensemble_csv(const EnsembleResult& r) {
    std::string out = "member";
    for (const auto& n : r.input_names) out += "," + n;
    out += ",status,t";
    for (const auto& n : r.state_names) out += "," + n;
    for (const auto& n : r.invariant_names) out += "," + n + "_max_drift";
    for (const auto& n : r.observed_names) out += "," + n;
    out += ",events,message\n";
    const auto cell = [&](double v) {
        out += ',';
        if (!std::isnan(v)) out += number(v);
    };
    for (const auto& m : r.members) {
        out += std::to_string(m.index);
        for (double v : m.inputs) cell(v);
        out += "," + m.status;
        cell(m.t);
        for (double v : m.state) cell(v);
        for (double v : m.drifts) cell(v);
        for (double v : m.observed) cell(v);
        out += fmt::format(",{},{}\n", m.events, quoted(m.message));
    }
    return out;
}

std::vector<ColumnStatistics> ensemble_statistics(const EnsembleResult& r) {
    const std::vector<std::string> names = column_names(r);
    std::vector<ColumnStatistics> out;
    for (std::size_t c = 0; c < names.size(); ++c) {
        std::vector<double> values;
        for (const auto& m : r.members) {
            if (m.status == "failed") continue;
            const double v = column_value(m, c);
            if (std::isfinite(v)) values.push_back(v);
        }
        ColumnStatistics s;
        s.name = names[c];
        s.count = values.size();
        if (!values.empty()) {
            double sum = 0.0;  // in index order: the same sum whatever ran where
            for (double v : values) sum += v;
            s.mean = sum / static_cast<double>(values.size());
            if (values.size() > 1) {
                double ss = 0.0;
                for (double v : values) ss += (v - s.mean) * (v - s.mean);
                s.std = std::sqrt(ss / static_cast<double>(values.size() - 1));
            }
            std::sort(values.begin(), values.end());
            s.min = values.front();
            s.max = values.back();
            s.q05 = quantile(values, 0.05);
            s.q50 = quantile(values, 0.50);
            s.q95 = quantile(values, 0.95);
        }
        out.push_back(s);
    }
    return out;
}

void print_ensemble_summary(const EnsembleResult& r, const std::string& format, std::ostream& out) {
    std::size_t ok = 0, stopped = 0, failed = 0;
    for (const auto& m : r.members) (m.status == "ok" ? ok : m.status == "stopped" ? stopped : failed) += 1;
    const auto stats = ensemble_statistics(r);
    const double rate = r.wall_s > 0 ? static_cast<double>(r.members.size()) / r.wall_s : MemberResult::nan;
    constexpr std::size_t listed = 10;  // failures named in the summary (all are in the CSV)
    if (format == "json") {
        std::string s = fmt::format("{{\"scene\": {}, \"method\": {}, \"members\": {}, \"ok\": {}, \"stopped\": {}, "
                                    "\"failed\": {}, \"ranks\": {}, \"threads\": {}, \"wall_s\": {}, \"runs_per_s\": {}, "
                                    "\"compile_s\": {}, \"statistics\": {{",
                                    json_string(r.scene_name), json_string(r.method), r.members.size(), ok, stopped,
                                    failed, r.ranks, r.threads, json_number(r.wall_s), json_number(rate),
                                    json_number(r.compile_s));
        for (std::size_t i = 0; i < stats.size(); ++i) {
            const auto& c = stats[i];
            s += fmt::format("{}{}: {{\"count\": {}, \"mean\": {}, \"std\": {}, \"min\": {}, \"q05\": {}, \"q50\": {}, "
                             "\"q95\": {}, \"max\": {}}}",
                             i ? ", " : "", json_string(c.name), c.count, json_number(c.mean), json_number(c.std),
                             json_number(c.min), json_number(c.q05), json_number(c.q50), json_number(c.q95),
                             json_number(c.max));
        }
        s += "}, \"failures\": [";
        std::size_t n = 0;
        for (const auto& m : r.members)
            if (m.status == "failed" && n < listed)
                s += fmt::format("{}{{\"member\": {}, \"message\": {}}}", n++ ? ", " : "", m.index, json_string(m.message));
        out << s << "]}\n";
        return;
    }
    if (format != "text")
        throw InputError(SourcePos{"--format"}, fmt::format("unknown summary format '{}' (expected text or json)", format));
    std::size_t width = 4;
    for (const auto& c : stats) width = std::max(width, c.name.size());
    std::string s = fmt::format("{}: {} runs with {}; {} ok, {} stopped by a terminal event, {} failed\n", r.scene_name,
                                r.members.size(), r.method, ok, stopped, failed);
    s += fmt::format("  {:<{}}  {:>6}  {:>13}  {:>10}  {:>13}  {:>13}  {:>13}  {:>13}  {:>13}\n", "", width, "count",
                     "mean", "std", "min", "5 %", "50 %", "95 %", "max");
    for (const auto& c : stats)
        s += fmt::format("  {:<{}}  {:>6}  {:>13.6g}  {:>10.3g}  {:>13.6g}  {:>13.6g}  {:>13.6g}  {:>13.6g}  {:>13.6g}\n",
                         c.name, width, c.count, c.mean, c.std, c.min, c.q05, c.q50, c.q95, c.max);
    std::size_t n = 0;
    for (const auto& m : r.members)
        if (m.status == "failed" && n++ < listed) s += fmt::format("failed      member {}: {}\n", m.index, m.message);
    if (failed > listed) s += fmt::format("            ... {} more (all in the CSV)\n", failed - listed);
    s += fmt::format("time        {:.3g} s on {}{} thread{} ({:.4g} runs/s); kernel {:.3g} s{}\n", r.wall_s,
                     r.ranks > 1 ? fmt::format("{} ranks × ", r.ranks) : "", r.threads, r.threads == 1 ? "" : "s", rate,
                     r.compile_s, r.cache_hit ? " (cached)" : "");
    out << s;
}

std::vector<double> ensemble_column(const EnsembleResult& r, const std::string& column) {
    const std::vector<std::string> names = column_names(r);
    const auto at = std::find(names.begin(), names.end(), column);
    if (at == names.end()) {
        const std::string near = nearest_name(column, names);
        throw InputError(SourcePos{"--plot-column"},
                         fmt::format("no column '{}'{} (expected one of {})", column,
                                     near.empty() ? "" : "; did you mean '" + near + "'?", fmt::join(names, ", ")));
    }
    const std::size_t c = static_cast<std::size_t>(at - names.begin());
    std::vector<double> out;
    for (const auto& m : r.members) {
        const double v = column_value(m, c);
        out.push_back(m.status == "failed" ? MemberResult::nan : v);
    }
    return out;
}

std::string ensemble_plot_script(const EnsembleResult& r, const EnsembleSpec& spec, const std::string& column,
                                 const std::string& terminal, const std::filesystem::path& output) {
    const std::vector<double> values = ensemble_column(r, column);
    const auto cell = [](double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string("NaN"); };
    const auto label = [](const std::string& text) { return gnuplot_quoted(gnuplot_text(text)); };
    std::string s = fmt::format("set terminal {} size 1000,700 font ',10'\nset output {}\nset grid\n", terminal,
                                gnuplot_quoted(output.string()));
    if (!spec.vary.empty()) {
        // The histogram: about √n bins (5 to 60) over the finite values' range.
        std::vector<double> finite;
        for (double v : values)
            if (std::isfinite(v)) finite.push_back(v);
        const std::size_t bins = std::clamp<std::size_t>(
            static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(finite.size())))), 5, 60);
        const double lo = finite.empty() ? 0.0 : *std::min_element(finite.begin(), finite.end());
        const double hi = finite.empty() ? 1.0 : *std::max_element(finite.begin(), finite.end());
        const double width = hi > lo ? (hi - lo) / static_cast<double>(bins) : 1.0;
        std::vector<std::size_t> count(bins, 0);
        for (double v : finite)
            ++count[std::min(bins - 1, static_cast<std::size_t>((v - lo) / width))];
        s += "$h << EOD\n";
        for (std::size_t b = 0; b < bins; ++b)
            s += fmt::format("{} {} {}\n", cell(lo + (static_cast<double>(b) + 0.5) * width), count[b], cell(width));
        s += "EOD\n";
        s += fmt::format("set title {}\nset xlabel {}\nset ylabel 'members'\nset yrange [0:*]\n"
                         "set style fill solid 0.5 border\nplot $h using 1:2:3 with boxes lc rgb '#1f77b4' notitle\n",
                         label(fmt::format("{}: {} over {} draws ({} failed, left out)", r.scene_name, column,
                                           r.members.size(), r.members.size() - finite.size())),
                         label(column));
        return s;
    }
    std::vector<std::size_t> varied;
    for (std::size_t k = 0; k < spec.grid.size(); ++k)
        if (spec.grid[k].count > 1) varied.push_back(k);
    if (varied.empty() || varied.size() > 2)
        throw InputError(SourcePos{"--plot"}, fmt::format("a picture of a sweep needs a grid that varies one axis (a "
                                                          "bifurcation diagram) or two (a map); this one varies {}",
                                                          varied.size()));
    s += "$d << EOD\n";
    for (std::size_t i = 0; i < r.members.size(); ++i) {
        const auto& in = r.members[i].inputs;
        s += varied.size() == 1 ? fmt::format("{} {}\n", cell(in[varied[0]]), cell(values[i]))
                                : fmt::format("{} {} {}\n", cell(in[varied[0]]), cell(in[varied[1]]), cell(values[i]));
    }
    s += "EOD\n";
    const std::string& x = spec.grid[varied[0]].name;
    if (varied.size() == 1)
        return s + fmt::format("set title {}\nset xlabel {}\nset ylabel {}\n"
                               "plot $d using 1:2 with linespoints pt 7 ps 0.6 lc rgb '#1f77b4' notitle\n",
                               label(fmt::format("{}: {} at the end of each run", r.scene_name, column)), label(x),
                               label(column));
    const std::string& y = spec.grid[varied[1]].name;
    return s + fmt::format("set title {}\nset xlabel {}\nset ylabel {}\nset cblabel {}\nset palette rgb 33,13,10\n"
                           "plot $d using 1:2:3 with image notitle\n",
                           label(fmt::format("{}: {} at the end of each run", r.scene_name, column)), label(x),
                           label(y), label(column));
}

}  // namespace eomc::host
