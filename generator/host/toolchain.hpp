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

#include "support/cleanup.hpp"

namespace eomc::host {

// $XDG_CACHE_HOME/eomc, else ~/.cache/eomc, else <tmp>/eomc-cache-<euid>.
std::string default_cache_dir();

// The cache holds code this process loads and runs, so it must be private. Creates `dir` with
// mode 0700 when missing (its parents as usual); an existing one must be a directory owned by the
// effective uid and writable by nobody else (a symbolic link counts only when it is ours or
// root's, and is resolved once). Throws eomc::InputError naming the directory and the fix
// otherwise. Returns the directory to use (the link's target when it was one). The parents are
// trusted, like a home directory's.
std::filesystem::path ensure_private_directory(const std::filesystem::path& dir);

// Checks a cached object against the record compile() appended to it (key, size, SHA-256;
// toolchain.cpp says why and how). Returns "" when it matches, "missing" when there is no file,
// else the reason it is refused.
std::string verify_cache_entry(const std::filesystem::path& path, const std::string& key);

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
    // After `flags`, where the compiler accepts them: a compile that fails with them is retried
    // once without (-march=native, which some compilers refuse). In the cache key either way.
    std::vector<std::string> optional_flags;
    // What decides the bytes beyond the command line, for the cache key: the CPU -march=native
    // describes.
    std::vector<std::string> key_notes;
    std::string suffix;  // of the cached file: ".so", or "" for an executable
    std::string what;    // for messages: "the generated kernel"
};

// SHA-256 (first 128 bits, hex) of compiler, flags, libraries, runtime version and every file's
// name and text.
std::string cache_key(const CompileRequest& request);

// <cache_dir>/<cache_key><suffix> in the private cache directory ("" = default_cache_dir(),
// checked and created by ensure_private_directory).
std::filesystem::path cache_entry_path(const CompileRequest& request, const std::string& cache_dir);

// cache_entry_path(), after removing an entry there that fails verify_cache_entry (with a note on
// stderr): what exists at the returned path afterwards may be used.
std::filesystem::path cached_path(const CompileRequest& request, const std::string& cache_dir);

// Compiles into `target` (normally cached_path(...)). The output goes to a temporary name beside
// it, gets its record (verify_cache_entry) and is synced and renamed into place when complete, so
// a concurrent run sees no file or a whole one. Throws std::runtime_error with the compiler's
// output (truncated) when compilation fails.
void compile(const CompileRequest& request, const std::filesystem::path& target);

struct Artifact {
    std::string path;
    bool cache_hit = false;
};

// The cached object when it passes verify_cache_entry, else compiled afresh (a bad entry is
// replaced, with a note on stderr).
Artifact find_or_compile(const CompileRequest& request, const std::string& cache_dir);

// Runs argv (searched on PATH when argv[0] has no slash) and waits for it. Its standard output
// goes to `stdout_path` ("" = inherited); its standard error to the same file when
// `stderr_to_stdout`, else inherited. Returns the wait status; throws std::runtime_error when it
// cannot be started.
int run_process(const std::vector<std::string>& argv, const std::filesystem::path& stdout_path, bool stderr_to_stdout);

// "exited with status 3", "was killed by signal 9".
std::string describe_status(int status);

// A fresh private directory, removed with everything in it when the object goes away (or on a
// signal, when it holds only files).
class TempDir {
public:
    explicit TempDir(const std::string& prefix = "eomc-");
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    CleanupEntry cleanup_;  // removed by the signal handler too (its files, then itself)
};

}  // namespace eomc::host
