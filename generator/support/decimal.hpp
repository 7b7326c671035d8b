// One decimal grammar for every number given on the command line (--set, --grid, the numeric
// options), and for the ensemble specifications built from them.
#pragma once

#include <string_view>

#include "support/diagnostic.hpp"

namespace eomc {

// [+|-] digits [. digits] [e|E [+|-] digits], the whole text, a finite normal double (or 0).
// Throws InputError at `where` with the reason.
double parse_decimal(std::string_view text, const SourcePos& where);

}  // namespace eomc
