// What a fatal signal must not leave behind: temporaries (a CSV being written, a kernel being
// compiled, its build directory) and the compiler's process group.
//
// Normal failures clean up through destructors; a signal's default action ends the process
// without running them. install_signal_cleanup() installs a handler for SIGINT, SIGTERM and
// SIGHUP that removes what is registered here and then re-raises the signal with its default
// disposition, so the exit status still says "killed by signal N". The handler only makes
// async-signal-safe calls (POSIX.1-2017 XSH 2.4.3: unlink, rmdir, kill, waitpid, signal, raise,
// plus the raw getdents64 system call) on entries prepared beforehand; registration is lock-free
// (slots claimed with atomics), so any thread may register while another takes the signal.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace eomc {

// Installs the handler (once; later calls do nothing). Signals ignored at start (e.g. SIGINT of a
// background job, SIGHUP under nohup) stay ignored.
void install_signal_cleanup();

// A path removed by the handler: a file (unlink), or a directory whose entries, files only, are
// unlinked before it is removed (a build directory holds sources, a log and nothing deeper).
// Paths longer than PATH_MAX are refused with std::runtime_error, as is a full registry.
class CleanupEntry {
public:
    enum class Kind { file, directory };
    CleanupEntry() = default;
    CleanupEntry(const std::filesystem::path& path, Kind kind);
    CleanupEntry(CleanupEntry&& other) noexcept;
    CleanupEntry& operator=(CleanupEntry&& other) noexcept;
    CleanupEntry(const CleanupEntry&) = delete;
    CleanupEntry& operator=(const CleanupEntry&) = delete;
    ~CleanupEntry();  // unregisters (does not remove: the owner decides)

    // Forget the path: it was renamed into place, or removed by its owner.
    void release();

private:
    int slot_ = -1;
};

// A child process group the handler kills (SIGTERM, then SIGKILL when it lingers) before it
// removes files: the compiler and whatever it started. Unregistered when destroyed.
class CleanupProcessGroup {
public:
    explicit CleanupProcessGroup(pid_t pgid);
    CleanupProcessGroup(const CleanupProcessGroup&) = delete;
    CleanupProcessGroup& operator=(const CleanupProcessGroup&) = delete;
    ~CleanupProcessGroup();

private:
    int slot_ = -1;
};

// A temporary file owned by this process: registered for the handler, unlinked when destroyed
// unless released (after it was renamed into place).
class TemporaryFile {
public:
    TemporaryFile() = default;
    explicit TemporaryFile(std::filesystem::path path);
    TemporaryFile(TemporaryFile&& other) noexcept;
    TemporaryFile& operator=(TemporaryFile&& other) noexcept;
    TemporaryFile(const TemporaryFile&) = delete;
    TemporaryFile& operator=(const TemporaryFile&) = delete;
    ~TemporaryFile();

    const std::filesystem::path& path() const { return path_; }
    void release();  // it is no longer ours to remove
    void remove();   // unlink now

private:
    std::filesystem::path path_;
    CleanupEntry entry_;
};

}  // namespace eomc
