// What `sweep` and `ensemble` may ask of the machine, refused before the work starts: the memory
// an ensemble's rows, CSV and statistics hold (estimated before the kernel compiles), and the time
// a sweep or ensemble takes (its points × the time of the first one, against --budget-s).
#pragma once

#include <cstddef>
#include <string>

#include "support/diagnostic.hpp"

namespace eomc::host {

// The default of --budget-s: an hour of work, estimated.
inline constexpr double default_budget_s = 3600.0;

// The bytes one member costs the process that holds the rows (rank 0 under MPI): its MemberResult
// and vectors, its CSV line, its share of the statistics, and under MPI (ranks > 1) its packed
// copy. A member that succeeds; a failed one adds its message's length.
std::size_t ensemble_bytes_per_member(std::size_t inputs, std::size_t state, std::size_t invariants,
                                      std::size_t observed, std::size_t ranks);

// Half the physical memory (the default limit when --max-memory-mib is not given).
std::size_t default_memory_limit();

// Throws InputError at `where` (--samples or --grid) when `members` × `per_member` bytes pass
// `limit` bytes, with the estimate and the way to raise the limit.
void check_ensemble_memory(std::size_t members, std::size_t per_member, std::size_t limit, const SourcePos& where);

// Throws InputError at `where` when `count` units of work at `seconds_each` (the first one's,
// measured), run `parallel` at a time, would take longer than `budget_s`; `what` names a unit
// ("grid point", "member").
void check_work_budget(std::size_t count, double seconds_each, std::size_t parallel, double budget_s,
                       const SourcePos& where, const std::string& what);

// "3.2 h", "12 s"; "1.5 GiB", "420 B".
std::string duration_text(double seconds);
std::string bytes_text(double bytes);

}  // namespace eomc::host
