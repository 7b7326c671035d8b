// Files are written whole or not at all: to a temporary name beside the target, synced, then
// renamed over it (atomic on POSIX), so a failure never leaves a half-written output behind.
//
// Only a missing target or an existing regular file is replaced. rename() replaces whatever
// has the name: run as root, `--output /dev/full` would replace the device node, and a
// symbolic link would be replaced by a file rather than written through. So a device, FIFO,
// socket, directory or symbolic link at the target is refused (eomc::InputError naming the path,
// exit 2), except exactly /dev/null, which is written to directly and never replaced. A symbolic link is refused rather than resolved: resolving it would write wherever the
// link points when it is followed, which in a shared directory is someone else's choice; a user
// who means the file behind it can name that file.
//
// The temporary is created with O_CREAT | O_EXCL | O_NOFOLLOW (never an existing file, never
// through a link planted under its name), mode 0666 less the umask like any new file, registered
// for removal on SIGINT/SIGTERM/SIGHUP (cli/cleanup.hpp) and removed on every failure path.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

#include "support/cleanup.hpp"

namespace eomc {

// Exactly "/dev/null", the null character device there: output that is asked for and thrown away
// (a run timed without its CSV). It is written to directly, never replaced.
bool discarded_output(const std::filesystem::path& path);

// Throws eomc::InputError (at the path) when `path` exists and is not a regular file (or /dev/null).
void check_output_target(const std::filesystem::path& path);

// One output being written. The parent directory is created if missing.
class AtomicOutput {
public:
    explicit AtomicOutput(const std::filesystem::path& target);
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;
    ~AtomicOutput();  // not committed: closed and removed

    const std::filesystem::path& target() const { return target_; }
    const std::filesystem::path& temporary() const { return temporary_.path(); }

    // Writes through the file descriptor (retrying short writes); throws on error.
    void write(const std::string& bytes);
    // A buffered stream over the same file, owned by this object (for many small writes).
    std::FILE* stream();

    // Flushes, fsyncs and closes the temporary, checks the target again and renames the
    // temporary over it. Throws std::runtime_error (temporary removed) on any I/O error.
    void commit();

private:
    void close_quietly();

    std::filesystem::path target_;
    TemporaryFile temporary_;
    int fd_ = -1;
    std::FILE* stream_ = nullptr;
    bool discard_ = false;  // the target is /dev/null
};

void write_file_atomically(const std::filesystem::path& path, const std::string& content);

}  // namespace eomc
