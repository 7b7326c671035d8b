// The run's summary, for people (text) or other tools (one JSON object: NaN and infinities as
// null), one function per section with its text and JSON forms side by side.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "host/simulate.hpp"
#include "host/simulate/output.hpp"
#include "host/simulate/runs.hpp"
#include "support/json.hpp"

namespace eomc::host {

namespace {

std::string json_number(double v) { return std::isfinite(v) ? number(v) : "null"; }

// A JSON object of name: value pairs, in order.
std::string json_values(const std::vector<std::pair<std::string, double>>& values) {
    std::string s = "{";
    for (std::size_t i = 0; i < values.size(); ++i)
        s += fmt::format("{}{}: {}", i ? ", " : "", json_string(values[i].first), json_number(values[i].second));
    return s + "}";
}

// ---- the state, the outputs and the invariants ----------------------------------------------

std::string json_invariants(const SimulationResult& r) {
    std::string s = "{";
    for (std::size_t i = 0; i < r.invariants.size(); ++i) {
        const auto& v = r.invariants[i];
        s += fmt::format("{}{}: {{\"initial\": {}, \"max_abs_drift\": {}", i ? ", " : "", json_string(v.name),
                         json_number(v.initial), json_number(v.max_abs_drift));
        if (v.jumps > 0)  // max_abs_drift is then between the jumps
            s += fmt::format(", \"final\": {}, \"jumps\": {}, \"change_at_jumps\": {}", json_number(v.final), v.jumps,
                             json_number(v.jump_change));
        s += "}";
    }
    return s + "}";
}

std::string text_values(const SimulationResult& r, std::size_t width) {
    std::string s = "final state\n";
    for (const auto& [n, v] : r.state) s += fmt::format("  {:<{}}  {:>24}\n", n, width, number(v));
    if (!r.outputs.empty()) s += "outputs\n";
    for (const auto& [n, v] : r.outputs) s += fmt::format("  {:<{}}  {:>24}\n", n, width, number(v));
    if (!r.invariants.empty()) {
        s += fmt::format("invariants\n  {:<{}}  {:>24}  {:>12}  {:>12}\n", "", width, "initial", "max |drift|", "relative");
        for (const auto& v : r.invariants) {
            const double rel = v.relative_drift();
            s += fmt::format("  {:<{}}  {:>24}  {:>12.3g}  {:>12}\n", v.name, width, number(v.initial), v.max_abs_drift,
                             std::isnan(rel) && !std::isnan(v.max_abs_drift) ? "-" : fmt::format("{:.3g}", rel));
            if (v.jumps > 0)
                s += fmt::format("  {:<{}}  drift between the {} jumps (impacts, Zeno points); at them it changed by {}, "
                                 "to {}\n",
                                 "", width, v.jumps, number(v.jump_change), number(v.final));
        }
    }
    return s;
}

// ---- the scene's events ------------------------------------------------------------------------

std::string json_events(const SimulationResult& r) {
    std::string s = "[";
    for (std::size_t i = 0; i < r.events.size(); ++i) {
        const auto& e = r.events[i];
        s += fmt::format("{}{{\"name\": {}, \"t\": {}, \"direction\": \"{}\", \"terminal\": {}, \"state\": {{",
                         i ? ", " : "", json_string(e.name), json_number(e.t), e.direction > 0 ? "up" : "down",
                         e.terminal ? "true" : "false");
        for (std::size_t k = 0; k < e.state.size() && k < r.state.size(); ++k)
            s += fmt::format("{}{}: {}", k ? ", " : "", json_string(r.state[k].first), json_number(e.state[k]));
        s += "}}";
    }
    return s + "]";
}

std::string text_events(const SimulationResult& r, std::size_t width) {
    if (r.events.empty()) return "";
    // Each event once per crossing; a long run lists the first ones (all are in the CSV and the JSON).
    constexpr std::size_t shown = 20;
    std::string s = fmt::format("events      {} located\n", r.events.size());
    for (std::size_t i = 0; i < r.events.size() && i < shown; ++i) {
        const auto& e = r.events[i];
        s += fmt::format("  {:<{}}  t = {:>24}  {}{}\n", e.name, width, number(e.t), e.direction > 0 ? "up" : "down",
                         e.terminal ? ", terminal" : "");
    }
    if (r.events.size() > shown) s += fmt::format("  ... {} more\n", r.events.size() - shown);
    return s;
}

// ---- constraint rows and programs (only kernels with them: other summaries keep their shape) ----

std::string json_rows_and_programs(const SimulationResult& r) {
    std::string s;
    if (!r.constraints.empty()) {
        s += ", \"constraints\": {";
        for (std::size_t i = 0; i < r.constraints.size(); ++i)
            s += fmt::format("{}{}: {{\"max_abs_residual\": {}}}", i ? ", " : "", json_string(r.constraints[i].name),
                             json_number(r.constraints[i].max_abs_residual));
        s += "}";
    }
    if (!r.programs.empty()) {
        s += ", \"programs\": {";
        for (std::size_t i = 0; i < r.programs.size(); ++i) {
            const auto& g = r.programs[i];
            s += fmt::format("{}{}: {{\"law\": {}, \"initial\": {}, \"initial_rate\": {}, \"final\": {}, "
                             "\"max_abs_residual\": {}, \"max_departure\": {}}}",
                             i ? ", " : "", json_string(g.name), json_string(g.law), json_number(g.initial),
                             json_number(g.initial_rate), json_number(g.final), json_number(g.max_abs_residual),
                             json_number(g.max_departure));
        }
        s += "}";
    }
    return s;
}

std::string text_rows_and_programs(const SimulationResult& r, std::size_t width) {
    std::string s;
    if (!r.constraints.empty()) {
        s += fmt::format("constraints\n  {:<{}}  {:>24}\n", "", width, "max |residual|");
        for (const auto& c : r.constraints) s += fmt::format("  {:<{}}  {:>24.3g}\n", c.name, width, c.max_abs_residual);
    }
    if (!r.programs.empty()) {
        s += fmt::format("programs\n  {:<{}}  {:>12}  {:>12}  {:>14}  {}\n", "", width, "initial", "final",
                         "max departure", "law");
        for (const auto& g : r.programs)
            s += fmt::format("  {:<{}}  {:>12.4g}  {:>12.4g}  {:>14.3g}  {}\n", g.name, width, g.initial, g.final,
                             g.max_departure, g.law);
    }
    return s;
}

// ---- unilateral rows (only kernels with them) ----------------------------------------------------

// The contact events of one kind, as JSON objects by `fields`.
template <class Fields>
std::string json_contact_events(const SimulationResult& r, std::string_view kind, Fields&& fields) {
    std::string s = "[";
    bool any = false;
    for (const auto& e : r.contact_events) {
        if (e.kind != kind) continue;
        s += fmt::format("{}{{{}}}", any ? ", " : "", fields(e));
        any = true;
    }
    return s + "]";
}

// Carnot's theorem over the impacts: the kinetic energy they changed (measured) against what the
// theorem predicts, summed, and the largest difference at one impact (one row per impact even when
// several contacts share it).
struct CarnotBalance {
    double energy_change = 0.0, carnot = 0.0, worst = 0.0;
};
CarnotBalance carnot_balance(const SimulationResult& r) {
    CarnotBalance b;
    double last_t = std::numeric_limits<double>::quiet_NaN();
    for (const auto& e : r.contact_events) {
        if (e.kind != "impact" || e.t == last_t) continue;  // one impact's rows carry its whole ΔT
        last_t = e.t;
        b.energy_change += e.energy_change;
        b.carnot += e.carnot;
        b.worst = std::max(b.worst, std::abs(e.energy_change - e.carnot));
    }
    return b;
}

std::string json_contacts(const SimulationResult& r) {
    if (r.contacts.empty()) return "";
    std::string s = fmt::format(", \"contacts\": {{\"method\": {}, \"impact_law\": {}, \"rows\": {{",
                                json_string(r.contact_method), json_string(r.impact_law));
    for (std::size_t i = 0; i < r.contacts.size(); ++i) {
        const auto& c = r.contacts[i];
        s += fmt::format("{}{}: {{\"kinematic\": {}, \"restitution\": {}, \"lambda\": {}, \"active\": {}, "
                         "\"impacts\": {}}}",
                         i ? ", " : "", json_string(c.name), c.kinematic ? "true" : "false", json_number(c.restitution),
                         json_number(c.lambda), c.active ? "true" : "false", c.impacts);
    }
    s += "}, \"impacts\": " + json_contact_events(r, "impact", [](const ContactEventReport& e) {
             return fmt::format("\"row\": {}, \"t\": {}, \"rate_before\": {}, \"rate_after\": {}, \"impulse\": {}, "
                                "\"energy_change\": {}, \"carnot\": {}",
                                json_string(e.name), json_number(e.t), json_number(e.rate_before),
                                json_number(e.rate_after), json_number(e.impulse), json_number(e.energy_change),
                                json_number(e.carnot));
         });
    const CarnotBalance b = carnot_balance(r);
    s += fmt::format(", \"carnot_balance\": {{\"sum_energy_change\": {}, \"sum_carnot\": {}, \"max_abs_difference\": {}}}",
                     json_number(b.energy_change), json_number(b.carnot), json_number(b.worst));
    s += ", \"zeno\": " + json_contact_events(r, "zeno", [](const ContactEventReport& e) {
             return fmt::format("\"row\": {}, \"t\": {}, \"ratio\": {}, \"extrapolation_error\": {}", json_string(e.name),
                                json_number(e.t), json_number(e.ratio), json_number(e.extrapolation_error));
         });
    s += ", \"events\": [";
    for (std::size_t i = 0; i < r.contact_events.size(); ++i) {
        const auto& e = r.contact_events[i];
        s += fmt::format("{}{{\"kind\": {}, \"row\": {}, \"t\": {}{}}}", i ? ", " : "", json_string(e.kind),
                         json_string(e.name), json_number(e.t),
                         e.kind == "contact" ? fmt::format(", \"lambda\": {}", json_number(e.lambda)) : "");
    }
    return s + "]}";
}

// Every impact (the JSON and the CSV have them too): the rates f-dot before and after, the
// percussion P, the kinetic energy change and Carnot's prediction of it.
std::string text_impacts(const SimulationResult& r, std::size_t width) {
    const std::size_t impacts = std::size_t(
        std::count_if(r.contact_events.begin(), r.contact_events.end(), [](const auto& e) { return e.kind == "impact"; }));
    if (impacts == 0) return "";
    std::string s = fmt::format("impacts     {}\n  {:<{}}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}\n", impacts,
                                "", width, "t", "rate before", "rate after", "P", "delta T", "Carnot");
    for (const auto& e : r.contact_events)
        if (e.kind == "impact")
            s += fmt::format("  {:<{}}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}  {:>24}\n", e.name, width, number(e.t),
                             number(e.rate_before), number(e.rate_after), number(e.impulse), number(e.energy_change),
                             number(e.carnot));
    const CarnotBalance b = carnot_balance(r);
    s += fmt::format("  {:<{}}  sum of delta T {}, of Carnot {}; largest |delta T - Carnot| {:.3g}\n", "Carnot", width,
                     number(b.energy_change), number(b.carnot), b.worst);
    return s;
}

std::string text_contacts(const SimulationResult& r, std::size_t width) {
    if (r.contacts.empty()) return "";
    std::string s = fmt::format("contacts    {}, {} impacts\n  {:<{}}  {:>5}  {:>24}  {:>6}  {:>7}\n", r.contact_method,
                                r.impact_law, "", width, "e", "lambda", "active", "impacts");
    for (const auto& c : r.contacts)
        s += fmt::format("  {:<{}}  {:>5}  {:>24}  {:>6}  {:>7}{}\n", c.name, width, number(c.restitution),
                         number(c.lambda), c.active ? "yes" : "no", c.impacts, c.kinematic ? "  (kinematic)" : "");
    s += text_impacts(r, width);
    for (const auto& e : r.contact_events)
        if (e.kind == "zeno")
            s += fmt::format("zeno        {} at t = {} (interval ratio {}, extrapolation error {:.3g})\n", e.name,
                             number(e.t), number(e.ratio), e.extrapolation_error);
    std::size_t listed = 0, phases = 0;  // the first 20 contact phases and separations (all in the JSON)
    for (const auto& e : r.contact_events)
        if (e.kind == "contact" || e.kind == "separation") {
            if (++phases > 20) continue;
            ++listed;
            s += fmt::format("{:<12}{} at t = {}{}\n", e.kind, e.name, number(e.t),
                             e.kind == "contact" ? fmt::format(" (lambda {})", number(e.lambda)) : "");
        }
    if (phases > listed) s += fmt::format("            ... {} more contact and separation events\n", phases - listed);
    return s;
}

// ---- the whole summary ----------------------------------------------------------------------------

std::string json_summary(const SimulationResult& r) {
    std::string s = fmt::format("{{\"t\": {}, \"state\": {}, \"outputs\": {}, \"invariants\": {}, \"events\": {}",
                                json_number(r.t), json_values(r.state), json_values(r.outputs), json_invariants(r),
                                json_events(r));
    s += json_rows_and_programs(r) + json_contacts(r);
    if (!r.hint.empty()) s += fmt::format(", \"hint\": {}", json_string(r.hint));  // only stability-limited runs
    if (!r.warnings.empty()) {
        s += ", \"warnings\": [";
        for (std::size_t i = 0; i < r.warnings.size(); ++i) s += (i ? ", " : "") + json_string(r.warnings[i]);
        s += "]";
    }
    s += fmt::format(", \"stopped_by\": {}, \"compensated\": {}",
                     r.stopped_by.empty() ? "null" : json_string(r.stopped_by), r.compensated ? "true" : "false");
    s += fmt::format(", \"steps\": {}, \"rejected\": {}, \"rhs_evals\": {}, \"wall_s\": {}, \"compile_s\": {}, "
                     "\"cache_hit\": {}}}\n",
                     r.steps, r.rejected, r.rhs_evals, json_number(r.wall_s), json_number(r.compile_s),
                     r.cache_hit ? "true" : "false");
    return s;
}

std::string text_summary(const SimulationResult& r) {
    std::size_t width = 6;  // aligns the values of the longest name
    for (const auto& [n, v] : r.state) width = std::max(width, n.size());
    for (const auto& [n, v] : r.outputs) width = std::max(width, n.size());
    for (const auto& v : r.invariants) width = std::max(width, v.name.size());
    for (const auto& e : r.events) width = std::max(width, e.name.size());
    for (const auto& c : r.constraints) width = std::max(width, c.name.size());
    for (const auto& c : r.contacts) width = std::max(width, c.name.size());

    std::string s = fmt::format("{}: {} to t = {}{}\n", r.scene_name, r.integrator, number(r.t),
                                r.stopped_by.empty() ? "" : fmt::format(", stopped by the terminal event '{}'", r.stopped_by));
    if (!r.hint.empty()) s += fmt::format("hint: {}\n", r.hint);
    for (const auto& w : r.warnings) s += fmt::format("warning: {}\n", w);
    s += text_values(r, width) + text_events(r, width) + text_rows_and_programs(r, width) + text_contacts(r, width);
    s += fmt::format("steps       {} accepted, {} rejected, {} rhs evaluations\n", r.steps, r.rejected, r.rhs_evals);
    s += fmt::format("time        integration {:.3g} s; kernel {:.3g} s ({})\n", r.wall_s, r.compile_s,
                     r.cache_hit ? "cached: " + r.library_path : "compiled into " + r.library_path);
    if (!r.csv_path.empty()) s += fmt::format("csv         {} ({} rows)\n", r.csv_path, r.csv_rows);
    return s;
}

}  // namespace

std::string unresolved_events_warning(std::size_t pieces, double t_first) {
    if (pieces == 0) return "";
    return fmt::format("an event or contact function did not resolve on {} piece{} of steps, the first at t = {} (it "
                       "jumps or is not smooth there): a crossing and its return inside such a piece may be unseen",
                       pieces, pieces == 1 ? "" : "s", number(t_first));
}

double InvariantReport::relative_drift() const {
    return initial != 0.0 ? max_abs_drift / std::abs(initial) : std::numeric_limits<double>::quiet_NaN();
}

double SimulationResult::value(const std::string& name) const {
    for (const auto& [n, v] : state)
        if (n == name) return v;
    for (const auto& [n, v] : outputs)
        if (n == name) return v;
    for (const auto& c : contacts)
        if ("lambda_" + c.name == name) return c.lambda;
    throw std::out_of_range("no state variable or output '" + name + "'");
}

void print_summary(const SimulationResult& r, const std::string& format, std::ostream& out) {
    if (format == "json") out << json_summary(r);
    else if (format == "text") out << text_summary(r);
    else
        throw InputError(SourcePos{"--summary"}, fmt::format("unknown summary format '{}' (expected text or json)", format));
}

}  // namespace eomc::host
