#include "support/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "support/diagnostic.hpp"

namespace eomc {

namespace fs = std::filesystem;

namespace {

const char* kind_of(mode_t mode) {
    if (S_ISLNK(mode)) return "a symbolic link";
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

// Makes the rename itself durable (POSIX leaves it to the directory's own fsync); best effort.
void sync_directory(const fs::path& dir) {
    const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

}  // namespace

bool discarded_output(const fs::path& path) {
    struct stat st {};
    return path.native() == "/dev/null" && ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode) &&
           st.st_rdev == makedev(1, 3);
}

void check_output_target(const fs::path& path) {
    if (discarded_output(path)) return;
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) return;
        throw InputError(SourcePos{path.string()}, fmt::format("cannot use this output: {}", std::strerror(errno)));
    }
    if (S_ISREG(st.st_mode)) return;
    throw InputError(SourcePos{path.string()},
                     fmt::format("the output exists and is {}; eomc replaces only regular files{}", kind_of(st.st_mode),
                                 S_ISLNK(st.st_mode) ? " (name the file the link points to, or remove the link)"
                                                     : ": choose another path"));
}

AtomicOutput::AtomicOutput(const fs::path& target) : target_(target) {
    if (discarded_output(target)) {  // written through, nothing to rename
        discard_ = true;
        fd_ = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (fd_ < 0) throw std::runtime_error(fmt::format("cannot write /dev/null: {}", std::strerror(errno)));
        return;
    }
    check_output_target(target);
    if (target.has_parent_path()) fs::create_directories(target.parent_path());
    static std::atomic<unsigned> serial{0};
    for (int attempt = 0;; ++attempt) {
        const fs::path candidate = fmt::format("{}.tmp.{}.{}", target.string(), ::getpid(), serial++);
        // Registered before it exists: a signal between open() and the registration would
        // otherwise leave it behind (unlinking a name not yet created is harmless).
        TemporaryFile registered(candidate);
        fd_ = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (fd_ >= 0) {
            temporary_ = std::move(registered);
            return;
        }
        const int err = errno;
        registered.release();  // not ours: someone else's file, or nothing
        if (err == EEXIST && attempt < 100) continue;
        throw std::runtime_error(fmt::format("cannot write {}: cannot create {}: {}", target.string(),
                                             candidate.string(), std::strerror(err)));
    }
}

AtomicOutput::~AtomicOutput() { close_quietly(); }  // temporary_ removes the file

void AtomicOutput::close_quietly() {
    if (stream_) std::fclose(stream_);
    else if (fd_ >= 0) ::close(fd_);
    stream_ = nullptr;
    fd_ = -1;
}

void AtomicOutput::write(const std::string& bytes) {
    if (stream_) {
        if (std::fwrite(bytes.data(), 1, bytes.size(), stream_) != bytes.size())
            throw std::runtime_error(fmt::format("cannot write {}: {}", target_.string(), std::strerror(errno)));
        return;
    }
    for (std::size_t done = 0; done < bytes.size();) {
        const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw std::runtime_error(fmt::format("cannot write {}: {}", target_.string(), std::strerror(errno)));
        done += static_cast<std::size_t>(n);
    }
}

std::FILE* AtomicOutput::stream() {
    if (!stream_) {
        stream_ = ::fdopen(fd_, "w");
        if (!stream_) throw std::runtime_error(fmt::format("cannot write {}: {}", target_.string(), std::strerror(errno)));
    }
    return stream_;
}

void AtomicOutput::commit() {
    if (discard_) {  // no fsync: /dev/null refuses it (EINVAL)
        close_quietly();
        return;
    }
    int err = 0;
    if (stream_ && (std::fflush(stream_) != 0 || std::ferror(stream_))) err = errno ? errno : EIO;
    const int fd = stream_ ? ::fileno(stream_) : fd_;
    // Durable before it takes the name: after a crash the name holds the old file or the new one.
    if (!err && ::fsync(fd) != 0) err = errno;
    const int closed = stream_ ? std::fclose(stream_) : ::close(fd_);
    if (!err && closed != 0) err = errno;
    stream_ = nullptr;
    fd_ = -1;
    if (err) {
        temporary_.remove();
        throw std::runtime_error(fmt::format("cannot write {}: {}", target_.string(), std::strerror(err)));
    }
    try {
        check_output_target(target_);  // again: it may have changed during a long run
    } catch (...) {
        temporary_.remove();
        throw;
    }
    if (::rename(temporary_.path().c_str(), target_.c_str()) != 0) {
        err = errno;
        temporary_.remove();
        throw std::runtime_error(fmt::format("cannot write {}: {}", target_.string(), std::strerror(err)));
    }
    temporary_.release();
    sync_directory(target_.parent_path());
}

void write_file_atomically(const fs::path& path, const std::string& content) {
    if (discarded_output(path)) return;
    AtomicOutput out(path);
    out.write(content);
    out.commit();
}

}  // namespace eomc
