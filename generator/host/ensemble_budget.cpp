#include "host/ensemble_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "host/ensemble.hpp"

namespace eomc::host {

namespace {

// A heap block of n doubles as glibc's malloc hands it out: 16-byte chunks, 8 bytes of header.
std::size_t heap_doubles(std::size_t n) { return n == 0 ? 0 : std::max<std::size_t>(32, (8 * n + 8 + 15) / 16 * 16); }

// Three significant digits, never an exponent: 1.5, 42.3, 1000.
std::string short_number(double v) { return v < 100 ? fmt::format("{:.3g}", v) : fmt::format("{:.0f}", v); }

}  // namespace

std::size_t ensemble_bytes_per_member(std::size_t inputs, std::size_t state, std::size_t invariants,
                                      std::size_t observed, std::size_t ranks) {
    const std::size_t cells = inputs + 1 + state + invariants + observed;  // and t
    std::size_t bytes = sizeof(MemberResult) + heap_doubles(inputs) + heap_doubles(state) + heap_doubles(invariants) +
                        heap_doubles(observed);
    bytes += 24 * cells + 16;              // its CSV line: 17 significant digits a number, and the index, status
    bytes += 8 * (1 + state + invariants + observed);  // a column's values, sorted for the quantiles
    if (ranks > 1) bytes += 120 + 8 * cells;          // packed for the gather, and the gathered copy
    return bytes;
}

std::size_t default_memory_limit() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages <= 0 || page <= 0) return std::size_t{4} << 30;  // unknown: 4 GiB
    return static_cast<std::size_t>(pages) / 2 * static_cast<std::size_t>(page);
}

void check_ensemble_memory(std::size_t members, std::size_t per_member, std::size_t limit, const SourcePos& where) {
    const double bytes = static_cast<double>(members) * static_cast<double>(per_member);
    if (bytes <= static_cast<double>(limit)) return;
    throw InputError(where, fmt::format("{} members would hold about {} in memory ({} B each: the row, its CSV line, "
                                        "the statistics), more than the limit of {} (--max-memory-mib, default half "
                                        "the physical memory); run fewer members, or several ensembles with "
                                        "different --seed",
                                        members, bytes_text(bytes), per_member, bytes_text(static_cast<double>(limit))));
}

void check_work_budget(std::size_t count, double seconds_each, std::size_t parallel, double budget_s,
                       const SourcePos& where, const std::string& what) {
    const double estimate = static_cast<double>(count) * seconds_each / static_cast<double>(std::max<std::size_t>(1, parallel));
    if (estimate <= budget_s) return;
    throw InputError(where, fmt::format("{} {}s would take about {} ({} a {}, measured on the first{}), more than "
                                        "--budget-s {}; ask for fewer, or give --budget-s {:.0f} to run them",
                                        count, what, duration_text(estimate), duration_text(seconds_each), what,
                                        parallel > 1 ? fmt::format(", on {} threads", parallel) : "", budget_s,
                                        std::ceil(estimate * 1.1)));
}

std::string duration_text(double s) {
    if (s < 1e-3) return short_number(s * 1e6) + " µs";
    if (s < 1) return short_number(s * 1e3) + " ms";
    if (s < 120) return short_number(s) + " s";
    if (s < 7200) return short_number(s / 60) + " min";
    if (s < 172800) return short_number(s / 3600) + " h";
    return short_number(s / 86400) + " days";
}

std::string bytes_text(double b) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
    std::size_t u = 0;
    for (; b >= 1024 && u + 1 < std::size(units); ++u) b /= 1024;
    return u == 0 ? fmt::format("{:.0f} B", b) : short_number(b) + " " + units[u];
}

}  // namespace eomc::host
