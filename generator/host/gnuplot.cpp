#include "host/gnuplot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "codegen/cpp_text.hpp"
#include "host/toolchain.hpp"
#include "support/input_file.hpp"
#include "support/output_file.hpp"

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

// gnuplot opens its output by name, following links and replacing what is there, and cannot be
// told otherwise. So it writes into this process's own mkdtemp directory (mode 0700, removed on
// SIGINT/SIGTERM/SIGHUP with the script and the log), and the PNG is published from there the way
// every CSV is: written whole to an O_EXCL|O_NOFOLLOW temporary beside the target and renamed.
std::string write_plot(const std::function<std::string(const std::string&, const fs::path&)>& script_for,
                       const fs::path& png) {
    const std::string gnuplot = find_gnuplot();
    if (gnuplot.empty())
        return "gnuplot was not found (install gnuplot-nox); " + png.string() + " was not written";
    check_output_target(png);  // before gnuplot runs: a refused target costs no drawing
    TempDir dir("eomc-plot-");
    const fs::path drawn = dir.path() / "plot.png";
    if (has_control_character(drawn.string()))  // $TMPDIR reaches the script: a line break would end its string
        return fmt::format("the temporary directory {} contains a control character; {} was not written",
                           codegen::comment_text(dir.path().string()), png.string());
    std::string log;
    for (const char* terminal : {"pngcairo", "png"}) {
        const fs::path script = dir.path() / "plot.gp";
        write_file_atomically(script, script_for(terminal, drawn));
        const int status = run_process({gnuplot, script.string()}, dir.path() / "gnuplot.log", true);
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::is_regular_file(fs::symlink_status(drawn))) {
            const std::string bytes = read_whole_file(drawn);
            if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) {
                log = fmt::format("gnuplot exited with status 0 but wrote {} bytes that are not a PNG", bytes.size());
                break;
            }
            write_file_atomically(png, bytes);
            return "";
        }
        log = read_whole_file(dir.path() / "gnuplot.log");
    }
    return fmt::format("gnuplot failed, {} was not written:\n{}", png.string(), log);
}

}  // namespace eomc::host
