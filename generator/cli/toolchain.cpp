#include "cli/toolchain.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "eomc/runtime/version.hpp"

extern char** environ;

namespace eomc::cli {

namespace fs = std::filesystem;

namespace {

// No -ffast-math and no FMA contraction: a simulation gives the same numbers wherever the
// code is compiled (DESIGN, habit 11).
std::vector<std::string> common_flags() {
    return {"-std=c++20", "-O2", "-ffp-contract=off", "-I", EOMC_KERNEL_RUNTIME_INCLUDE, "-I", EOMC_KERNEL_EIGEN_INCLUDE};
}

// FNV-1a, 64 bits: a fixed function (std::hash may differ between runs and builds), good
// enough for a cache whose entries are all produced by this program.
std::uint64_t fnv1a(const std::string& bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

std::string default_cache_dir() {
    // XDG Base Directory: $XDG_CACHE_HOME counts only when set to an absolute path.
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return (fs::path(xdg) / "eomc").string();
    if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "eomc").string();
    return (fs::temp_directory_path() / "eomc-cache").string();
}

std::string compiler() {
    if (const char* cxx = std::getenv("EOMC_CXX"); cxx && *cxx) return cxx;
    return EOMC_KERNEL_CXX;
}

TempDir::TempDir(const std::string& prefix) {
    std::string tmpl = (fs::temp_directory_path() / (prefix + "XXXXXX")).string();
    if (!::mkdtemp(tmpl.data()))
        throw std::runtime_error(fmt::format("cannot create a temporary directory {}: {}", tmpl, std::strerror(errno)));
    path_ = tmpl;
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

int run_process(const std::vector<std::string>& argv, const fs::path& stdout_path, bool stderr_to_stdout) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (!stdout_path.empty()) {
        posix_spawn_file_actions_addopen(&actions, 1, stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (stderr_to_stdout) posix_spawn_file_actions_adddup2(&actions, 1, 2);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int rc = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw std::runtime_error(fmt::format("cannot run '{}': {}", argv[0], std::strerror(rc)));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error(fmt::format("waiting for '{}': {}", argv[0], std::strerror(errno)));
    return status;
}

std::string describe_status(int status) {
    if (WIFEXITED(status)) return fmt::format("exited with status {}", WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return fmt::format("was killed by signal {}", WTERMSIG(status));
    return fmt::format("failed (wait status {})", status);
}

std::string cache_key(const CompileRequest& request) {
    // Everything that determines the bytes of the output, each part NUL-terminated so that
    // moving text from one part to the next changes the key.
    std::string key = "eomc build cache 2";
    key += '\0';
    key += compiler();
    key += '\0';
    for (const auto& f : common_flags()) key += f + '\0';
    for (const auto& f : request.flags) key += f + '\0';
    key += "libraries";
    key += '\0';
    for (const auto& l : request.libraries) key += l + '\0';
    key += "runtime " + std::to_string(EOMC_RUNTIME_VERSION) + '\0';
    for (const auto& file : request.files) {
        key += file.name + '\0';
        key += file.text + '\0';
    }
    return fmt::format("{:016x}", fnv1a(key));
}

fs::path cached_path(const CompileRequest& request, const std::string& cache_dir) {
    const fs::path dir = cache_dir.empty() ? default_cache_dir() : cache_dir;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(fmt::format("cannot create the cache directory {}: {}", dir.string(), ec.message()));
    return dir / (cache_key(request) + request.suffix);
}

// Two runs racing on the same key both compile and the last rename wins; the contents are the
// same. A crash leaves at most a stray hidden temporary, never a truncated file under the key.
void compile(const CompileRequest& request, const fs::path& target) {
    if (request.files.empty()) throw std::invalid_argument("compile: no source file");
    TempDir dir("eomc-build-");
    for (const auto& file : request.files) write_file(dir.path() / file.name, file.text);

    std::string tmpl = (target.parent_path() / fmt::format(".{}.XXXXXX", target.filename().string())).string();
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw std::runtime_error(fmt::format("cannot create {}: {}", tmpl, std::strerror(errno)));
    ::close(fd);
    const fs::path partial = tmpl;

    std::vector<std::string> argv{compiler()};
    for (auto& f : common_flags()) argv.push_back(std::move(f));
    argv.insert(argv.end(), request.flags.begin(), request.flags.end());
    argv.insert(argv.end(), {"-o", partial.string(), (dir.path() / request.files.front().name).string()});
    argv.insert(argv.end(), request.libraries.begin(), request.libraries.end());
    const fs::path log = dir.path() / "compiler.log";
    int status = 0;
    try {
        status = run_process(argv, log, true);
    } catch (const std::exception& e) {
        std::error_code ignored;
        fs::remove(partial, ignored);
        throw std::runtime_error(fmt::format("cannot run the C++ compiler: {}", e.what()));
    }
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        std::error_code ec;
        fs::remove(partial, ec);
        std::string output = read_file(log);
        constexpr std::size_t max_output = 64 * 1024;  // template errors can run to megabytes
        if (output.size() > max_output) output = output.substr(0, max_output) + "\n[... compiler output truncated]\n";
        throw std::runtime_error(fmt::format("compiling {} failed: {} {}:\n{}", request.what, argv[0],
                                             describe_status(status), output));
    }
    std::error_code ec;
    fs::rename(partial, target, ec);
    if (ec) {
        fs::remove(partial, ec);
        throw std::runtime_error(fmt::format("cannot move {} to {}: {}", request.what, target.string(), ec.message()));
    }
}

Artifact find_or_compile(const CompileRequest& request, const std::string& cache_dir) {
    const fs::path path = cached_path(request, cache_dir);
    Artifact a{path.string(), fs::exists(path)};
    if (!a.cache_hit) compile(request, path);
    return a;
}

}  // namespace eomc::cli
