// Running a command line from a test: its exit status and what it printed, each test case in a
// scratch directory of its own under the build tree.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace test_support {

namespace fs = std::filesystem;

struct Result {
    int status = -1;  // the exit status; −1 if the command did not exit normally
    std::string out, err;
};

inline std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Writes text to path (binary: the bytes as given) and returns the path.
inline fs::path write_file(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

// A scene file dir/scene.toml holding text.
inline fs::path write_scene(const fs::path& dir, const std::string& text) { return write_file(dir / "scene.toml", text); }

// <build>/<area>/<name>, emptied first.
inline fs::path scratch(const std::string& area, const std::string& name) {
    const fs::path dir = fs::path(EOMC_BINARY_DIR) / area / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// `env command`, its output captured through files in dir (removed afterwards).
inline Result run_command(const std::string& command, const fs::path& dir, const std::string& env = "") {
    const std::string line =
        env + " " + command + " > '" + (dir / "stdout").string() + "' 2> '" + (dir / "stderr").string() + "'";
    const int raw = std::system(line.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(dir / "stdout");
    r.err = slurp(dir / "stderr");
    fs::remove(dir / "stdout");
    fs::remove(dir / "stderr");
    return r;
}

// eomc with these arguments.
inline Result run_eomc(const std::string& arguments, const fs::path& dir) {
    return run_command(std::string(EOMC_EXECUTABLE) + " " + arguments, dir);
}

}  // namespace test_support
