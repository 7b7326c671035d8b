#include "host/toolchain.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "eomc/runtime/version.hpp"
#include "support/cleanup.hpp"
#include "support/diagnostic.hpp"
#include "support/sha256.hpp"
#include "support/input_file.hpp"

extern char** environ;

namespace eomc::host {

namespace fs = std::filesystem;

namespace {

// No -ffast-math and no FMA contraction: a simulation gives the same numbers wherever the
// code is compiled (DESIGN, habit 11).
std::vector<std::string> common_flags() {
    return {"-std=c++20", "-O2", "-ffp-contract=off", "-I", EOMC_KERNEL_RUNTIME_INCLUDE, "-I", EOMC_KERNEL_EIGEN_INCLUDE};
}

// The SHA-256 of every file under eomc/ in the runtime's include directory (relative path and
// bytes, in path order; eomc/ alone, should that directory ever be a shared one), once per
// process: a kernel's object depends on those headers, and a runtime changed without a version
// bump (a fix while developing) must not reuse the objects built against the old one. Unreadable
// files are hashed as such: the key still changes with them.
const std::string& runtime_headers_digest() {
    static const std::string digest = [] {
        std::vector<fs::path> files;
        std::error_code ec;
        const fs::path root(EOMC_KERNEL_RUNTIME_INCLUDE);
        for (fs::recursive_directory_iterator it(root / "eomc", ec), end; !ec && it != end; it.increment(ec))
            if (it->is_regular_file(ec)) files.push_back(it->path());
        std::sort(files.begin(), files.end());
        std::string all = ec ? "unlisted: " + ec.message() + '\0' : std::string();
        for (const auto& file : files) {
            all += file.lexically_relative(root).generic_string() + '\0';
            std::ifstream in(file, std::ios::binary);
            std::ostringstream bytes;
            bytes << in.rdbuf();
            all += (in ? sha256_hex(bytes.str()) : std::string("unreadable")) + '\0';
        }
        return sha256_hex(all);
    }();
    return digest;
}

void write_file(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Every cached object carries a record of itself, appended after its last byte (ELF loaders and
// execve read only what the headers point at, so the trailing bytes change nothing):
//   "\neomc-cache-record 1 key=<cache key> size=<bytes before the record> sha256=<of those bytes>\n"
// The object and its record are published by one rename, so no reader ever sees one without
// the other (a sidecar file would need two renames, and a window between them). Before an
// object is loaded or run its record must match: the key (this scene and build, not another's
// object under our name), the size (a truncated file would SIGBUS when its pages are touched)
// and the SHA-256. The cache directory is private (ensure_private_directory), so the threat is
// a damaged or misplaced file, not an adversary; SHA-256 is nevertheless collision-resistant,
// which FNV-1a (the key's hash until cache version 2) is not.
constexpr std::string_view record_magic = "\neomc-cache-record 1 key=";
constexpr std::size_t key_hex = 32, size_digits = 20;
constexpr std::size_t record_size = record_magic.size() + key_hex + 6 + size_digits + 8 + 64 + 1;

std::string record_for(const std::string& key, std::string_view object) {
    return fmt::format("{}{} size={:0{}} sha256={}\n", record_magic, key, object.size(), size_digits, sha256_hex(object));
}

std::string octal_mode(mode_t mode) { return fmt::format("{:04o}", mode & 07777); }

// Signals that the cleanup handler takes are held back while a child is started and registered,
// so that no signal can fall between the two and orphan it.
class BlockedSignals {
public:
    BlockedSignals() {
        sigset_t set;
        sigemptyset(&set);
        for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, s);
        ::pthread_sigmask(SIG_BLOCK, &set, &old_);
    }
    ~BlockedSignals() { ::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
    const sigset_t& old() const { return old_; }

private:
    sigset_t old_;
};

}  // namespace

fs::path ensure_private_directory(const fs::path& dir) {
    const uid_t me = ::geteuid();
    const SourcePos where{dir.string()};
    struct stat st {};
    if (::lstat(dir.c_str(), &st) != 0) {
        if (errno != ENOENT)
            throw std::runtime_error(fmt::format("cannot use the cache directory {}: {}", dir.string(), std::strerror(errno)));
        std::error_code ec;
        if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
        // 0700: the objects in it are code this process will run.
        if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST)
            throw std::runtime_error(fmt::format("cannot create the cache directory {}: {}", dir.string(), std::strerror(errno)));
        if (::lstat(dir.c_str(), &st) != 0)
            throw std::runtime_error(fmt::format("cannot use the cache directory {}: {}", dir.string(), std::strerror(errno)));
    }
    fs::path resolved = dir;
    if (S_ISLNK(st.st_mode)) {
        // Whoever owns a link decides where it points, at any time: only ours (or root's) count.
        if (st.st_uid != me && st.st_uid != 0)
            throw InputError(where, fmt::format("the kernel cache directory is a symbolic link owned by uid {}, not by "
                                                "you (uid {}); eomc would load code from wherever it points. Remove it, "
                                                "or give a directory of your own with --cache-dir",
                                                st.st_uid, me));
        std::error_code ec;
        resolved = fs::canonical(dir, ec);
        if (ec || ::stat(resolved.c_str(), &st) != 0)
            throw std::runtime_error(fmt::format("cannot use the cache directory {}: {}", dir.string(),
                                                 ec ? ec.message() : std::strerror(errno)));
    }
    if (!S_ISDIR(st.st_mode))
        throw InputError(where, "the kernel cache directory is not a directory; remove it or give another with --cache-dir");
    if (st.st_uid != me)
        throw InputError(where, fmt::format("the kernel cache directory is owned by uid {}, not by you (uid {}); eomc "
                                            "would load code that another user can replace. Give a directory of your "
                                            "own with --cache-dir, or remove this one",
                                            st.st_uid, me));
    if (st.st_mode & (S_IWGRP | S_IWOTH))
        throw InputError(where, fmt::format("the kernel cache directory has mode {}: other users can write to it, and "
                                            "eomc would load code they put there. Fix it with `chmod go-w {}` (or "
                                            "`chmod 700`), or give another with --cache-dir",
                                            octal_mode(st.st_mode), resolved.string()));
    return resolved;
}

std::string verify_cache_entry(const fs::path& path, const std::string& key) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) return errno == ENOENT ? "missing" : std::strerror(errno);
    if (!S_ISREG(st.st_mode)) return "it is not a regular file";
    if (st.st_uid != ::geteuid()) return fmt::format("it is owned by uid {}, not by this user", st.st_uid);
    const std::string bytes = read_whole_file(path);
    if (bytes.size() < record_size || bytes.compare(bytes.size() - record_size, record_magic.size(), record_magic) != 0)
        return "it has no eomc record (truncated, damaged, or not written by this eomc)";
    const std::string_view object(bytes.data(), bytes.size() - record_size);
    const std::string record = bytes.substr(bytes.size() - record_size);
    if (record.compare(record_magic.size(), key_hex, key) != 0) return "its record is for another kernel or build";
    if (record != record_for(key, object)) {
        const std::string size_field = fmt::format(" size={:0{}} ", object.size(), size_digits);
        return record.find(size_field) == std::string::npos ? "its size differs from its record (truncated or extended)"
                                                            : "its SHA-256 differs from its record (damaged or replaced)";
    }
    return "";
}

namespace {

void note_rebuild(const CompileRequest& request, const fs::path& path, const std::string& reason) {
    std::cerr << fmt::format("eomc: note: rebuilding {} cached as {}: {}\n", request.what, path.string(), reason);
}

}  // namespace

std::string default_cache_dir() {
    // XDG Base Directory: $XDG_CACHE_HOME counts only when set to an absolute path.
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return (fs::path(xdg) / "eomc").string();
    if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "eomc").string();
    // One per user: a shared /tmp/eomc-cache would run whatever another user left in it (and
    // ensure_private_directory refuses this one too if it is not ours and private).
    return (fs::temp_directory_path() / fmt::format("eomc-cache-{}", ::geteuid())).string();
}

std::string compiler() {
    if (const char* cxx = std::getenv("EOMC_CXX"); cxx && *cxx) return cxx;
    return EOMC_KERNEL_CXX;
}

TempDir::TempDir(const std::string& prefix) {
    std::string tmpl = (fs::temp_directory_path() / (prefix + "XXXXXX")).string();
    BlockedSignals blocked;  // created and registered, or neither
    if (!::mkdtemp(tmpl.data()))
        throw std::runtime_error(fmt::format("cannot create a temporary directory {}: {}", tmpl, std::strerror(errno)));
    path_ = tmpl;
    try {
        cleanup_ = CleanupEntry(path_, CleanupEntry::Kind::directory);
    } catch (...) {
        ::rmdir(path_.c_str());
        throw;
    }
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
    cleanup_.release();
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
    // The child leads a process group of its own, registered for the signal handler, which kills
    // the whole group (a compiler driver and the cc1plus, as, ld it starts) rather than orphan it.
    // It starts with this thread's signal mask as it was and the default actions.
    BlockedSignals blocked;
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    posix_spawnattr_setpgroup(&attributes, 0);
    posix_spawnattr_setsigmask(&attributes, &blocked.old());
    sigset_t defaults;
    sigemptyset(&defaults);
    for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&defaults, s);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    pid_t pid = 0;
    const int rc = ::posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (rc != 0) throw std::runtime_error(fmt::format("cannot run '{}': {}", argv[0], std::strerror(rc)));
    const CleanupProcessGroup group(pid);
    ::pthread_sigmask(SIG_SETMASK, &blocked.old(), nullptr);  // registered: signals may come
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
    std::string key = "eomc build cache 4";
    key += '\0';
    key += compiler();
    key += '\0';
    for (const auto& f : common_flags()) key += f + '\0';
    for (const auto& f : request.flags) key += f + '\0';
    for (const auto& f : request.optional_flags) key += "optional " + f + '\0';
    key += "libraries";
    key += '\0';
    for (const auto& l : request.libraries) key += l + '\0';
    for (const auto& note : request.key_notes) key += "note " + note + '\0';
    key += "runtime " + std::to_string(EOMC_RUNTIME_VERSION) + ' ' + runtime_headers_digest() + '\0';
    for (const auto& file : request.files) {
        key += file.name + '\0';
        key += file.text + '\0';
    }
    return sha256_hex(key).substr(0, key_hex);  // 128 bits name an entry; its record holds the full check
}

fs::path cache_entry_path(const CompileRequest& request, const std::string& cache_dir) {
    const fs::path dir = ensure_private_directory(cache_dir.empty() ? default_cache_dir() : cache_dir);
    return dir / (cache_key(request) + request.suffix);
}

fs::path cached_path(const CompileRequest& request, const std::string& cache_dir) {
    const fs::path path = cache_entry_path(request, cache_dir);
    if (const std::string reason = verify_cache_entry(path, cache_key(request)); !reason.empty() && reason != "missing") {
        note_rebuild(request, path, reason);
        ::unlink(path.c_str());
    }
    return path;
}

// Two runs racing on the same key both compile and the last rename wins; each publishes a whole
// object with its record. A failure, or a signal, leaves neither a temporary in the cache nor the
// build directory (cleanup.hpp), never a truncated file under the key.
void compile(const CompileRequest& request, const fs::path& target) {
    if (request.files.empty()) throw std::invalid_argument("compile: no source file");
    TempDir dir("eomc-build-");
    for (const auto& file : request.files) write_file(dir.path() / file.name, file.text);

    // A name of our own beside the target (the linker replaces the file: only the name counts),
    // registered before it exists so that a signal cannot leave it behind.
    static std::atomic<unsigned> serial{0};
    TemporaryFile partial;
    for (int attempt = 0; partial.path().empty(); ++attempt) {
        TemporaryFile candidate(target.parent_path() /
                                fmt::format(".{}.{}.{}", target.filename().string(), ::getpid(), serial++));
        const int fd = ::open(candidate.path().c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
        if (fd >= 0) {
            ::close(fd);
            partial = std::move(candidate);
            break;
        }
        const int err = errno;
        candidate.release();
        if (err != EEXIST || attempt >= 100)
            throw std::runtime_error(fmt::format("cannot create {}: {}", candidate.path().string(), std::strerror(err)));
    }

    std::vector<std::string> argv;
    const fs::path log = dir.path() / "compiler.log";
    int status = 0;
    // With the optional flags first, then (when that fails) without them.
    for (const bool optional : {true, false}) {
        if (!optional && request.optional_flags.empty()) break;
        argv = {compiler()};
        for (auto& f : common_flags()) argv.push_back(std::move(f));
        argv.insert(argv.end(), request.flags.begin(), request.flags.end());
        if (optional) argv.insert(argv.end(), request.optional_flags.begin(), request.optional_flags.end());
        argv.insert(argv.end(), {"-o", partial.path().string(), (dir.path() / request.files.front().name).string()});
        argv.insert(argv.end(), request.libraries.begin(), request.libraries.end());
        try {
            status = run_process(argv, log, true);
        } catch (const std::exception& e) {
            throw std::runtime_error(fmt::format("cannot run the C++ compiler: {}", e.what()));
        }
        if (WIFEXITED(status) && WEXITSTATUS(status) == 0) break;
    }
    if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
        std::string output = read_whole_file(log);
        constexpr std::size_t max_output = 64 * 1024;  // template errors can run to megabytes
        if (output.size() > max_output) output = output.substr(0, max_output) + "\n[... compiler output truncated]\n";
        throw std::runtime_error(fmt::format("compiling {} failed: {} {}:\n{}", request.what, argv[0],
                                             describe_status(status), output));
    }

    // The record, then fsync: the rename must publish a complete object (a crash after the rename
    // must not find a short file under the key).
    // A compiler that says it succeeded must have written an ELF object (Linux loads nothing else):
    // a stand-in that wrote nothing must not become a cache entry.
    const std::string object = read_whole_file(partial.path());
    if (object.compare(0, 4, "\x7f" "ELF") != 0)
        throw std::runtime_error(fmt::format("compiling {}: {} exited with status 0 but wrote {} to {}", request.what,
                                             argv[0], object.empty() ? "nothing" : "no ELF object",
                                             partial.path().string()));
    const std::string record = record_for(cache_key(request), object);
    const int fd = ::open(partial.path().c_str(), O_WRONLY | O_APPEND | O_NOFOLLOW | O_CLOEXEC);
    bool written = fd >= 0 && ::write(fd, record.data(), record.size()) == static_cast<ssize_t>(record.size());
    written = fd >= 0 && ::fsync(fd) == 0 && written;
    const int err = errno;
    if (fd >= 0) ::close(fd);
    if (!written)
        throw std::runtime_error(fmt::format("cannot write {} to {}: {}", request.what, partial.path().string(),
                                             std::strerror(err)));
    if (::rename(partial.path().c_str(), target.c_str()) != 0)
        throw std::runtime_error(fmt::format("cannot move {} to {}: {}", request.what, target.string(), std::strerror(errno)));
    partial.release();
    if (const int d = ::open(target.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) {
        ::fsync(d);
        ::close(d);
    }
}

Artifact find_or_compile(const CompileRequest& request, const std::string& cache_dir) {
    const fs::path path = cache_entry_path(request, cache_dir);
    const std::string reason = verify_cache_entry(path, cache_key(request));
    Artifact a{path.string(), reason.empty()};
    if (!a.cache_hit) {
        if (reason != "missing") note_rebuild(request, path, reason);
        compile(request, path);  // replaces the bad entry in one rename
    }
    return a;
}

}  // namespace eomc::host
