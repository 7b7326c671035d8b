// The system C++ compiler as eomc uses it at run time, and the cache of what it builds.
//
// Generated code (a kernel with its adapter for `simulate`, a kernel with the benchmark driver
// for `bench`) is compiled with the compiler that built eomc, against this source tree's runtime
// headers, and kept in a cache directory under a name derived from everything that decides its
// bytes: compiler, flags, runtime version, the text of every source file. A second run with the
// same inputs finds it there.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace eomc::cli {

// $XDG_CACHE_HOME/eomc, else ~/.cache/eomc, else <tmp>/eomc-cache.
std::string default_cache_dir();

// $EOMC_CXX when set (an installed eomc on a machine whose compiler lives elsewhere), else the
// compiler that built eomc.
std::string compiler();

struct SourceFile {
    std::string name;  // file name in the build directory, e.g. "kernel.hpp"
    std::string text;
};

struct CompileRequest {
    // Written into a private temporary directory; the first one is the translation unit.
    std::vector<SourceFile> files;
    // After the common flags (C++20, -O2, no FMA contraction, the runtime and Eigen include
    // directories): e.g. -fPIC -shared for a library.
    std::vector<std::string> flags;
    // After the source file: e.g. -lquadmath.
    std::vector<std::string> libraries;
    std::string suffix;  // of the cached file: ".so", or "" for an executable
    std::string what;    // for messages: "the generated kernel"
};

// FNV-1a 64 (hex) of compiler, flags, libraries, runtime version and every file's name and text.
std::string cache_key(const CompileRequest& request);

// <cache_dir>/<cache_key><suffix>, creating cache_dir ("" = default_cache_dir()) if needed.
std::filesystem::path cached_path(const CompileRequest& request, const std::string& cache_dir);

// Compiles into `target` (normally cached_path(...)). The output goes to a temporary name beside
// it and is renamed into place when complete, so a concurrent run sees no file or a whole one.
// Throws std::runtime_error with the compiler's output (truncated) when compilation fails.
void compile(const CompileRequest& request, const std::filesystem::path& target);

struct Artifact {
    std::string path;
    bool cache_hit = false;
};

// cached_path(), compiled first unless it exists.
Artifact find_or_compile(const CompileRequest& request, const std::string& cache_dir);

// Runs argv (searched on PATH when argv[0] has no slash) and waits for it. Its standard output
// goes to `stdout_path` ("" = inherited); its standard error to the same file when
// `stderr_to_stdout`, else inherited. Returns the wait status; throws std::runtime_error when it
// cannot be started.
int run_process(const std::vector<std::string>& argv, const std::filesystem::path& stdout_path, bool stderr_to_stdout);

// "exited with status 3", "was killed by signal 9".
std::string describe_status(int status);

// A fresh private directory, removed with everything in it when the object goes away.
class TempDir {
public:
    explicit TempDir(const std::string& prefix = "eomc-");
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

}  // namespace eomc::cli
