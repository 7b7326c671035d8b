// The recorder of a run's observed points (runs.hpp).
#include <chrono>
#include <limits>

#include <fmt/format.h>

#include "host/ensemble_budget.hpp"

#include "host/simulate/runs.hpp"

namespace eomc::host {

namespace {

std::vector<std::string> columns(const KernelLibrary& lib, const std::vector<std::string>& state_names,
                                 const std::vector<std::string>& extra, bool event_column) {
    std::vector<std::string> out{"t"};
    out.insert(out.end(), state_names.begin(), state_names.end());
    out.insert(out.end(), lib.invariant_names().begin(), lib.invariant_names().end());
    out.insert(out.end(), lib.output_names().begin(), lib.output_names().end());
    out.insert(out.end(), extra.begin(), extra.end());
    if (event_column) out.push_back("event");
    return out;
}

}  // namespace

Recorder::Recorder(const Run& run, const std::vector<std::string>& state_names,
                   const std::vector<std::string>& extra_columns, bool event_column, const runtime::State<double>& x0)
    : run_(run), state_names_(state_names), event_column_(event_column),
      csv_(run.request.csv_path, columns(run.lib, state_names, extra_columns, event_column), run.request.max_rows),
      progress_(run.request.progress, run.request.t_end,
                [](double t, double end) { return fmt::format("t = {:.6g} / {:.6g}", t, end); }, 64,
                run.request.progress_always),
      invariants_(run.lib, run.parameters),
      outputs_(run.lib.output_names().size()), x_last_(x0) {}

void Recorder::record(double t, const runtime::State<double>& xs, const std::string* event, std::string_view extra) {
    invariants_.observe(t, xs);
    if (!outputs_.empty() && !run_.request.csv_path.empty())
        run_.lib.outputs(t, xs.data(), outputs_.data(), run_.parameters);
    csv_.row(t, xs, invariants_.values(), outputs_, event_column_ ? event : nullptr, event_column_, extra);
    t_last_ = t;
    x_last_ = xs;
    progress_.update(t);
    check_budget(t);
}

void Recorder::check_budget(double t) {
    const double budget = run_.request.budget_s, t_end = run_.request.t_end;
    if (!(budget > 0) || ++budget_calls_ % 64 != 0) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (elapsed < SimulationRequest::budget_probe_s || !(t_end > 0)) return;
    const double projected = t > 0 ? elapsed * t_end / t : std::numeric_limits<double>::infinity();
    if (projected <= budget) return;
    throw InputError(SourcePos{"--budget-s"},
                     fmt::format("{}: at its pace over the first {} (to t = {} of t_end = {}) the run would take about "
                                 "{}, more than the budget of {}; raise --budget-s, shorten --t-end, or loosen the "
                                 "step or tolerances (nothing was written)",
                                 run_.lib.scene_name(), duration_text(elapsed), number(t), number(t_end),
                                 duration_text(projected), duration_text(budget)));
}

void Recorder::finish(double t, const runtime::State<double>& x, SimulationResult& result) {
    csv_.commit();
    result.t = t;
    for (std::size_t i = 0; i < x.size(); ++i) result.state.emplace_back(state_names_[i], x[i]);
    if (!outputs_.empty()) {
        run_.lib.outputs(t, x.data(), outputs_.data(), run_.parameters);
        for (std::size_t i = 0; i < outputs_.size(); ++i)
            result.outputs.emplace_back(run_.lib.output_names()[i], outputs_[i]);
    }
    result.invariants = invariants_.reports();
    if (!run_.request.csv_path.empty()) {
        result.csv_path = run_.request.csv_path;
        result.csv_rows = csv_.rows();
    }
}

runtime::IntegrationError Recorder::failed(const runtime::IntegrationError& e, std::string_view method) {
    std::string message = fmt::format("simulating {} with {}: {}", run_.lib.scene_name(), method, e.what());
    if (e.kind() == runtime::IntegrationError::Kind::contact) {
        if (e.component() < run_.lib.contact_names().size())
            message += fmt::format("; contact {} is {}", e.component(), run_.lib.contact_names()[e.component()]);
    } else if (e.component() < state_names_.size()) {
        message += fmt::format("; component {} is {}", e.component(), state_names_[e.component()]);
    }
    message += fmt::format("; last accepted state at t = {}:", number(t_last_));
    for (std::size_t i = 0; i < x_last_.size(); ++i)
        message += fmt::format(" {} = {}", state_names_[i], number(x_last_[i]));
    if (!run_.request.csv_path.empty()) {
        csv_.commit();
        message += fmt::format("; {} holds the {} rows up to t = {}", run_.request.csv_path, csv_.rows(), number(t_last_));
    }
    return runtime::IntegrationError(e.kind(), e.t(), message, e.component());
}

std::runtime_error Recorder::row_limit(const CsvOutput::RowLimit& limit, std::string_view method) const {
    return std::runtime_error(fmt::format("simulating {} with {}: the CSV {} reached its limit of {} rows at t = {} "
                                          "(of t_end = {}) and was not written; raise --max-rows, shorten --t-end, "
                                          "or run without --output",
                                          run_.lib.scene_name(), method, run_.request.csv_path, run_.request.max_rows,
                                          number(limit.t), number(run_.request.t_end)));
}

}  // namespace eomc::host
