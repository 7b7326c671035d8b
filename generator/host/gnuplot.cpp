#include "host/gnuplot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "host/toolchain.hpp"
#include "support/input_file.hpp"

namespace eomc::host {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> path_entries(const std::string& path) {
    std::vector<std::string> out;
    std::stringstream in(path);
    for (std::string dir; std::getline(in, dir, ':');) out.push_back(dir);
    return out;
}

}  // namespace

bool has_control_character(std::string_view s) {
    return std::any_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7F; });
}

std::string find_gnuplot() {
    const char* configured = std::getenv("EOMC_GNUPLOT");
    const std::string name = configured && *configured ? configured : "gnuplot";
    if (name.find('/') != std::string::npos) return ::access(name.c_str(), X_OK) == 0 ? name : "";
    const char* path = std::getenv("PATH");
    for (const std::string& dir : path_entries(path ? path : "")) {
        const fs::path candidate = fs::path(dir.empty() ? "." : dir) / name;
        if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) return candidate.string();
    }
    return "";
}

// A single-quoted gnuplot string: no backslash, backquote or macro processing happens inside
// one (gnuplot's "quote marks" and "substitution"), so only a line break could end it and
// start a command; validate() refuses those in the paths, and this refuses them anyway.
std::string gnuplot_quoted(const std::string& s) {
    if (has_control_character(s)) throw std::logic_error("a control character in a gnuplot string: " + codegen::comment_text(s));
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

std::string gnuplot_text(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '_' || c == '^' || c == '@' || c == '&' || c == '~' || c == '{' || c == '}') out += '\\';
        out += c;
    }
    return out;
}

std::string write_plot(const std::function<std::string(const std::string&, const fs::path&)>& script_for,
                       const fs::path& png) {
    const std::string gnuplot = find_gnuplot();
    if (gnuplot.empty())
        return "gnuplot was not found (install gnuplot-nox); " + png.string() + " was not written";
    TempDir dir("eomc-plot-");
    const fs::path partial = png.parent_path() / fmt::format(".{}.{}.tmp", png.filename().string(), ::getpid());
    std::string log;
    for (const char* terminal : {"pngcairo", "png"}) {
        const fs::path script = dir.path() / "plot.gp";
        std::ofstream(script) << script_for(terminal, partial);
        const int status = run_process({gnuplot, script.string()}, dir.path() / "gnuplot.log", true);
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(partial)) {
            std::error_code ec;
            fs::rename(partial, png, ec);
            if (!ec) return "";
            log = ec.message();
            break;
        }
        log = read_whole_file(dir.path() / "gnuplot.log");
    }
    std::error_code ignored;
    fs::remove(partial, ignored);
    return fmt::format("gnuplot failed, {} was not written:\n{}", png.string(), log);
}

}  // namespace eomc::host
