// What a run writes while it goes: the trajectory CSV (written to a temporary file and renamed into
// place when the run ends) and the progress bar on a terminal.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "eomc/runtime/state.hpp"
#include "support/output_file.hpp"

namespace eomc::host {

// A number as the summaries and messages print it: every digit of a double.
inline std::string number(double v) { return fmt::format("{:.17g}", v); }

// The CSV goes to a temporary file next to the target and is renamed over it when the run ends:
// after a successful integration, or after one that failed mid-run (a collision, a step-size
// collapse), when it holds every row up to the last accepted state. A run that fails in any other
// way (bad input, an I/O error, the row limit, a signal) leaves neither a half-written file nor a
// clobbered old one (support/output_file.hpp: what may be replaced, and how).
class CsvOutput {
public:
    CsvOutput(const std::string& path, const std::vector<std::string>& columns, std::size_t max_rows);
    CsvOutput(const CsvOutput&) = delete;
    CsvOutput& operator=(const CsvOutput&) = delete;

    // `event`: the name of the event located at t, or null; with_event_column: the CSV has one.
    // `extra`: cells after the outputs, each behind its comma (a contact run's λ and active set).
    // Throws RowLimit before writing row max_rows + 1.
    void row(double t, const runtime::State<double>& x, const std::vector<double>& invariants,
             const std::vector<double>& outputs, const std::string* event = nullptr, bool with_event_column = false,
             std::string_view extra = {});

    // Flushes, syncs, closes and renames into place; throws (and removes the temporary) on any I/O error.
    void commit();

    std::size_t rows() const { return rows_; }

    struct RowLimit {
        double t;
    };

private:
    std::optional<AtomicOutput> out_;
    std::FILE* file_ = nullptr;
    fmt::memory_buffer buffer_;
    std::size_t rows_ = 0, max_rows_;
};

// A one-line bar on stderr, for people watching a terminal: silent for runs under ~1 s,
// redrawn at most 10 times a second, erased when done (also when the run fails). `label(done,
// total)` is the text after the bar; the clock is read every `check_every` calls (reading it every
// step would cost more than a small kernel's step).
class ProgressBar {
public:
    using Label = std::function<std::string(double done, double total)>;
    // Drawn on stderr when `wanted` and stderr is a terminal, once the run passes a second; with
    // `always` (--progress) from the start and wherever stderr goes, a line each update when it is
    // not a terminal, the last update (done ≥ total) always drawn.
    ProgressBar(bool wanted, double total, Label label, unsigned check_every, bool always = false);
    // A run's time: "t = 1.5 / 10".
    ProgressBar(bool wanted, double t_end);
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;
    ~ProgressBar();

    void update(double done);

private:
    using Clock = std::chrono::steady_clock;
    bool enabled_, terminal_, always_;
    double total_;
    Label label_;
    unsigned check_every_;
    Clock::time_point start_ = Clock::now(), last_{};
    unsigned calls_ = 0;
    bool drawn_ = false, finished_ = false;  // finished_: the last update drawn (`always`)
};

}  // namespace eomc::host
