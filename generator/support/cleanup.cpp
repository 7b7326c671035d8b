#include "support/cleanup.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace eomc {

namespace {

// Slot states. Only a thread that moved a slot from `free` to `writing` writes its path; the
// handler reads only `active` slots, after claiming them (`active` → `cleaning`), so a slot being
// reused can never hand it a half-written path.
enum SlotState : int { free_slot = 0, writing = 1, active = 2, cleaning = 3 };

struct PathSlot {
    std::atomic<int> state{free_slot};
    CleanupEntry::Kind kind = CleanupEntry::Kind::file;
    char path[PATH_MAX] = {};
};

constexpr std::size_t max_paths = 64, max_groups = 16;
std::array<PathSlot, max_paths> paths;
std::array<std::atomic<pid_t>, max_groups> groups{};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<pid_t>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

constexpr std::array<int, 3> handled_signals{SIGINT, SIGTERM, SIGHUP};

// Removes the files directly inside `dir`, then `dir`. getdents64 is a plain system call (no
// allocation, no libc state), unlike readdir(); entries are re-read after each pass because
// unlinking while reading may skip some.
void remove_flat_directory(const char* dir) {
    const int fd = ::open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd >= 0) {
        alignas(8) static char buffer[8192];
        for (int pass = 0; pass < 8; ++pass) {
            bool removed = false;
            ::lseek(fd, 0, SEEK_SET);
            for (;;) {
                const long n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
                if (n <= 0) break;
                for (long at = 0; at < n;) {
                    // struct linux_dirent64: u64 ino, s64 off, u16 reclen, u8 type, char name[].
                    unsigned short reclen = 0;
                    std::memcpy(&reclen, buffer + at + 16, sizeof reclen);
                    const char* name = buffer + at + 19;
                    if (!(name[0] == '.' && (name[1] == '\0' || (name[1] == '.' && name[2] == '\0'))))
                        removed = ::unlinkat(fd, name, 0) == 0 || removed;
                    at += reclen;
                }
            }
            if (!removed) break;
        }
        ::close(fd);
    }
    ::rmdir(dir);
}

void on_fatal_signal(int sig) {
    const int saved_errno = errno;
    // The compiler first, so that it writes nothing more: SIGTERM lets GCC's driver delete its own
    // temporaries; what still runs after ~2 s is killed.
    bool any = false;
    for (auto& g : groups)
        if (const pid_t pgid = g.load(); pgid > 0) any = ::kill(-pgid, SIGTERM) == 0 || any;
    for (int i = 0; any && i < 40; ++i) {
        any = false;
        for (auto& g : groups) {
            const pid_t pgid = g.load();
            if (pgid <= 0) continue;
            ::waitpid(pgid, nullptr, WNOHANG);  // the leader is our child: reap it
            if (::kill(-pgid, 0) == 0) any = true;
        }
        if (any) ::poll(nullptr, 0, 50);
    }
    for (auto& g : groups)
        if (const pid_t pgid = g.load(); pgid > 0) ::kill(-pgid, SIGKILL);

    for (const auto kind : {CleanupEntry::Kind::file, CleanupEntry::Kind::directory})
        for (auto& slot : paths) {
            int expected = active;
            if (slot.kind != kind || !slot.state.compare_exchange_strong(expected, cleaning)) continue;
            if (kind == CleanupEntry::Kind::file) ::unlink(slot.path);
            else remove_flat_directory(slot.path);
        }

    // Die of the same signal, so that the parent sees "killed by signal N" (the signal stays
    // blocked until this handler returns, then its default action ends the process).
    ::signal(sig, SIG_DFL);
    ::raise(sig);
    errno = saved_errno;
}

}  // namespace

void install_signal_cleanup() {
    static std::atomic<bool> installed{false};
    if (installed.exchange(true)) return;
    struct sigaction action {};
    action.sa_handler = on_fatal_signal;
    sigemptyset(&action.sa_mask);
    for (int s : handled_signals) sigaddset(&action.sa_mask, s);  // one cleanup at a time
    for (int s : handled_signals) {
        struct sigaction old {};
        if (::sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        ::sigaction(s, &action, nullptr);
    }
}

CleanupEntry::CleanupEntry(const std::filesystem::path& path, Kind kind) {
    const std::string& text = path.native();
    if (text.size() >= PATH_MAX) throw std::runtime_error("path too long to register for cleanup: " + text);
    for (std::size_t i = 0; i < paths.size(); ++i) {
        int expected = free_slot;
        if (!paths[i].state.compare_exchange_strong(expected, writing)) continue;
        paths[i].kind = kind;
        std::memcpy(paths[i].path, text.c_str(), text.size() + 1);
        paths[i].state.store(active);
        slot_ = static_cast<int>(i);
        return;
    }
    throw std::runtime_error("too many temporaries at once (cleanup registry full)");
}

CleanupEntry::CleanupEntry(CleanupEntry&& other) noexcept : slot_(std::exchange(other.slot_, -1)) {}

CleanupEntry& CleanupEntry::operator=(CleanupEntry&& other) noexcept {
    if (this != &other) {
        release();
        slot_ = std::exchange(other.slot_, -1);
    }
    return *this;
}

CleanupEntry::~CleanupEntry() { release(); }

void CleanupEntry::release() {
    if (slot_ < 0) return;
    int expected = active;
    // If the handler holds the slot (cleaning), the process is about to die: leave it.
    paths[static_cast<std::size_t>(slot_)].state.compare_exchange_strong(expected, free_slot);
    slot_ = -1;
}

CleanupProcessGroup::CleanupProcessGroup(pid_t pgid) {
    for (std::size_t i = 0; i < groups.size(); ++i) {
        pid_t expected = 0;
        if (groups[i].compare_exchange_strong(expected, pgid)) {
            slot_ = static_cast<int>(i);
            return;
        }
    }
    // No slot: the group still runs and is waited for; only a signal would orphan it.
}

CleanupProcessGroup::~CleanupProcessGroup() {
    if (slot_ >= 0) groups[static_cast<std::size_t>(slot_)].store(0);
}

TemporaryFile::TemporaryFile(std::filesystem::path path)
    : path_(std::move(path)), entry_(path_, CleanupEntry::Kind::file) {}

TemporaryFile::TemporaryFile(TemporaryFile&& other) noexcept
    : path_(std::exchange(other.path_, {})), entry_(std::move(other.entry_)) {}

TemporaryFile& TemporaryFile::operator=(TemporaryFile&& other) noexcept {
    if (this != &other) {
        remove();
        path_ = std::exchange(other.path_, {});
        entry_ = std::move(other.entry_);
    }
    return *this;
}

TemporaryFile::~TemporaryFile() { remove(); }

void TemporaryFile::release() {
    entry_.release();
    path_.clear();
}

void TemporaryFile::remove() {
    if (!path_.empty()) ::unlink(path_.c_str());
    release();
}

}  // namespace eomc
