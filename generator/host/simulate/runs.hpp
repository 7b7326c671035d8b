// The two kinds of run simulate() chooses between, and what they share: the kernel and its
// parameters with the resolved settings, and the recorder that watches the invariants, writes
// the CSV rows and keeps the last accepted state for a post-mortem.
#pragma once

#include <chrono>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "eomc/runtime/errors.hpp"
#include "eomc/runtime/state.hpp"
#include "host/kernel_loader.hpp"
#include "host/simulate.hpp"
#include "host/simulate/output.hpp"
#include "host/simulate/watches.hpp"

namespace eomc::host {

// One run: what was asked, as resolved, on which kernel.
struct Run {
    const SimulationRequest& request;
    const RunSettings& settings;
    const KernelLibrary& lib;
    const KernelLibrary::Parameters& parameters;
};

// A kernel without unilateral rows, by the request's integrator, with the kernel's events.
SimulationResult simulate_smooth(const Run& run, runtime::State<double>& x, SimulationResult result);
// A kernel with unilateral rows (Mei ch. 6), by the request's contact method.
SimulationResult simulate_contacts(const Run& run, runtime::State<double>& x, SimulationResult result);

// Whether a method that uses a Jacobian gets the kernel's symbolic one (else forward differences,
// n calls each): not for the variational state, nor for the contact phases (their rates carry the
// multipliers); and which one it runs on, for the summary.
bool symbolic_jacobian(const Run& run);
// The warning for pieces of steps on which an event function would not resolve (runtime::
// EventLocator::unresolved), "" when there were none.
std::string unresolved_events_warning(std::size_t pieces, double t_first);
std::string jacobian_source(const Run& run);

// The observed points of a run: the invariants' drift, one CSV row each (t, the state, the
// invariants, the outputs, then `extra` cells and, where the CSV has one, the event column), the
// progress bar, and the last recorded state.
class Recorder {
public:
    // x0: the start, the last accepted state until a point is recorded.
    Recorder(const Run& run, const std::vector<std::string>& state_names, const std::vector<std::string>& extra_columns,
             bool event_column, const runtime::State<double>& x0);

    void record(double t, const runtime::State<double>& xs, const std::string* event = nullptr,
                std::string_view extra = {});
    bool started() const { return invariants_.started(); }
    // The state jumps before the next record (an impact, a Zeno point): InvariantWatch::jump.
    void jump() { invariants_.jump(); }
    double t_last() const { return t_last_; }
    const runtime::State<double>& x_last() const { return x_last_; }

    // The end of a run that reached t at x: the CSV committed, the final state, the outputs there,
    // the invariants' report and the CSV's rows into the result.
    void finish(double t, const runtime::State<double>& x, SimulationResult& result);

    // A run that failed at an integration error: the rows up to the last accepted state are kept
    // (a valid trajectory, for the post-mortem) and the message says which variable failed and
    // where the solution was last seen. `method` names what was integrating.
    runtime::IntegrationError failed(const runtime::IntegrationError& e, std::string_view method);
    // A run that reached the CSV's row limit: not a failure of the integration but a refusal of
    // its size, so nothing is kept.
    std::runtime_error row_limit(const CsvOutput::RowLimit& limit, std::string_view method) const;

private:
    // Stops the run (InputError at --budget-s) once its pace projects it past request.budget_s.
    void check_budget(double t);

    const Run& run_;
    std::vector<std::string> state_names_;
    bool event_column_;
    CsvOutput csv_;
    ProgressBar progress_;
    InvariantWatch invariants_;
    std::vector<double> outputs_;
    double t_last_ = 0.0;
    runtime::State<double> x_last_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    unsigned budget_calls_ = 0;
};

}  // namespace eomc::host
