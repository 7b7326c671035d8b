// Pictures through gnuplot, as the bench and the ensembles draw them: the program found, strings
// quoted so that no text of the user's can become a command, and a PNG written whole or not at all.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace eomc::host {

// A byte below 0x20, or DEL: such text must not reach a plot script (a line break ends a string).
bool has_control_character(std::string_view s);

// $EOMC_GNUPLOT (a path or a name on PATH; tests point it at nothing) or gnuplot on PATH; "" if none.
std::string find_gnuplot();

// A single-quoted gnuplot string (throws std::logic_error on a control character).
std::string gnuplot_quoted(const std::string& s);

// Text for an enhanced-mode label: '_' and '^' would start sub- and superscripts.
std::string gnuplot_text(const std::string& s);

// Writes `png` through gnuplot (pngcairo, else png) with the script script_for(terminal, output).
// Returns "" on success, else the reason there is no plot (no gnuplot, or its log).
std::string write_plot(const std::function<std::string(const std::string&, const std::filesystem::path&)>& script_for,
                       const std::filesystem::path& png);

}  // namespace eomc::host
