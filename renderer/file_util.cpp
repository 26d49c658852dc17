#include "renderer/file_util.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <new>

#include <csignal>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace caustic {

namespace {

void setError(std::string* error, std::string message) {
    if (error) *error = std::move(message);
}

std::string osReason(int err) { return std::strerror(err); }

// Writes all of data to fd, retrying short writes and EINTR. Returns 0 or an errno value.
int writeAll(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        data += n;
        size -= static_cast<std::size_t>(n);
    }
    return 0;
}

// The directory part of path including the trailing slash ("" when there is none).
std::string directoryOf(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Makes a completed rename durable. Best effort: some file systems refuse fsync on directories.
void syncDirectoryOf(const std::string& path) {
    const std::string dir = directoryOf(path);
    const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

}  // namespace

std::string tempPathBeside(const std::string& finalPath) {
    static std::atomic<unsigned> counter{0};
    const std::string dir = directoryOf(finalPath);
    const std::string name = finalPath.substr(dir.size());
    // The extension is the part from the last dot, unless that dot starts the name (".bashrc").
    const std::size_t dot = name.find_last_of('.');
    std::string extension = dot == std::string::npos || dot == 0 ? std::string() : name.substr(dot);
    if (extension.size() > 16) extension.clear();
    // A short prefix of the name (whole UTF-8 sequences only), so "." + prefix + ".tmp-<pid>-<n>"
    // + extension stays near 110 bytes at most.
    std::size_t keep = std::min(name.size(), kTempNameKeep);
    while (keep > 0 && keep < name.size() && (static_cast<unsigned char>(name[keep]) & 0xC0) == 0x80) --keep;
    return dir + "." + name.substr(0, keep) + ".tmp-" + std::to_string(static_cast<long>(::getpid())) + "-" +
           std::to_string(counter.fetch_add(1)) + extension;
}

// ---- Removing temporary files on SIGINT / SIGTERM / SIGHUP / SIGQUIT ---------------------------
//
// A fixed table of names: the handler may only touch memory that is never reallocated, and only
// call async-signal-safe functions (unlink, sigaction, raise). A slot is claimed with a
// compare-exchange (0 -> 1 "filling"), its name written, then published (2 "live"); the handler
// unlinks live slots only.

namespace {

struct TempSlot {
    std::atomic<int> state{0};  // 0 free, 1 being filled or emptied, 2 live
    char path[kMaxTempPath];
};
TempSlot g_tempSlots[kMaxTempFiles];

constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
constexpr int kCleanupSignalCount = sizeof(kCleanupSignals) / sizeof(kCleanupSignals[0]);
struct sigaction g_previous[kCleanupSignalCount];

void removeTempFilesOnSignal(int sig) {
    const int savedErrno = errno;
    for (TempSlot& slot : g_tempSlots)
        if (slot.state.load(std::memory_order_acquire) == 2) ::unlink(slot.path);
    for (int i = 0; i < kCleanupSignalCount; ++i) {
        if (kCleanupSignals[i] != sig) continue;
        const struct sigaction& prev = g_previous[i];
        if (prev.sa_flags & SA_SIGINFO) break;  // a three-argument handler is not chained: default action
        if (prev.sa_handler == SIG_IGN) { errno = savedErrno; return; }
        if (prev.sa_handler != SIG_DFL) { prev.sa_handler(sig); errno = savedErrno; return; }
        break;
    }
    // The signal's default action (terminate; SIGQUIT also dumps core), as if no handler had been installed.
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    ::sigaction(sig, &dfl, nullptr);
    ::raise(sig);
    errno = savedErrno;
}

// Installs the handler for each signal unless it is already there or the signal is ignored (nohup,
// a background job: it stays ignored). Checked at every registration, so a handler that the
// program (or a test framework) installed later is chained to rather than lost.
void installTempFileCleanup() {
    static std::mutex mutex;
    const std::lock_guard<std::mutex> lock(mutex);
    for (int i = 0; i < kCleanupSignalCount; ++i) {
        struct sigaction current {};
        if (::sigaction(kCleanupSignals[i], nullptr, &current) != 0) continue;
        const bool simple = !(current.sa_flags & SA_SIGINFO);
        if (simple && (current.sa_handler == removeTempFilesOnSignal || current.sa_handler == SIG_IGN)) continue;
        g_previous[i] = current;
        struct sigaction action {};
        action.sa_handler = removeTempFilesOnSignal;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESTART;
        ::sigaction(kCleanupSignals[i], &action, nullptr);
    }
}

}  // namespace

TempFileRegistration::TempFileRegistration(const std::string& path) {
    installTempFileCleanup();
    if (path.size() + 1 > kMaxTempPath || path.find('\0') != std::string::npos) return;
    for (int i = 0; i < kMaxTempFiles; ++i) {
        int expected = 0;
        if (!g_tempSlots[i].state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) continue;
        std::memcpy(g_tempSlots[i].path, path.c_str(), path.size() + 1);
        g_tempSlots[i].state.store(2, std::memory_order_release);
        m_slot = i;
        return;
    }
}

TempFileRegistration::~TempFileRegistration() {
    if (m_slot < 0) return;
    g_tempSlots[m_slot].state.store(1, std::memory_order_release);
    g_tempSlots[m_slot].path[0] = '\0';
    g_tempSlots[m_slot].state.store(0, std::memory_order_release);
}

bool commitTempFile(const std::string& tmp, const std::string& finalPath, std::string* error) {
    if (std::rename(tmp.c_str(), finalPath.c_str()) != 0) {
        const int err = errno;
        std::remove(tmp.c_str());
        setError(error, finalPath + ": cannot write: renaming the temporary file '" + tmp +
                            "' failed: " + osReason(err));
        return false;
    }
    syncDirectoryOf(finalPath);
    return true;
}

bool writeFileAtomically(const std::string& path, const char* data, std::size_t size, std::string* error) {
    const std::string tmp = tempPathBeside(path);
    const TempFileRegistration registration(tmp);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        setError(error, path + ": cannot write: cannot create the temporary file '" + tmp +
                            "': " + osReason(errno));
        return false;
    }
    int err = writeAll(fd, data, size);
    const char* step = "writing";
    if (err == 0 && ::fsync(fd) != 0) {
        err = errno;
        step = "flushing";
    }
    if (::close(fd) != 0 && err == 0) {
        err = errno;
        step = "closing";
    }
    if (err != 0) {
        std::remove(tmp.c_str());
        setError(error, path + ": cannot write: " + step + " the temporary file '" + tmp +
                            "' failed: " + osReason(err));
        return false;
    }
    return commitTempFile(tmp, path, error);
}

int openRegularFile(const std::string& path, std::string* error) {
    if (path.empty()) {
        setError(error, "(empty file name): cannot read: no file given");
        return -1;
    }
    if (path.find('\0') != std::string::npos) {
        std::string shown = path;
        for (char& c : shown)
            if (c == '\0') c = '?';
        setError(error, shown + ": cannot read: the file name contains a NUL byte");
        return -1;
    }
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        setError(error, path + ": cannot read: " + osReason(errno));
        return -1;
    }
    struct stat info {};
    if (::fstat(fd, &info) != 0) {
        const int err = errno;
        ::close(fd);
        setError(error, path + ": cannot read: " + osReason(err));
        return -1;
    }
    if (!S_ISREG(info.st_mode)) {
        ::close(fd);
        const char* kind = S_ISDIR(info.st_mode)    ? "a folder"
                           : S_ISFIFO(info.st_mode) ? "a FIFO (named pipe)"
                           : S_ISCHR(info.st_mode)  ? "a character device"
                           : S_ISBLK(info.st_mode)  ? "a block device"
                           : S_ISSOCK(info.st_mode) ? "a socket"
                                                    : "not a regular file";
        setError(error, path + ": cannot read: " + kind + ", not a regular file");
        return -1;
    }
    // Back to blocking reads for the caller.
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    return fd;
}

bool checkRegularFile(const std::string& path, std::string* error) {
    const int fd = openRegularFile(path, error);
    if (fd < 0) return false;
    ::close(fd);
    return true;
}

std::optional<std::string> readTextFile(const std::string& path, std::string* error) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        setError(error, path + ": cannot read: " + osReason(errno));
        return std::nullopt;
    }
    std::string contents;
    struct stat info {};
    if (::fstat(fd, &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0) {
        contents.reserve(static_cast<std::size_t>(info.st_size));
    }
    char buffer[1 << 16];
    int err = 0;
    try {
        for (;;) {
            const ssize_t n = ::read(fd, buffer, sizeof buffer);
            if (n == 0) break;
            if (n < 0) {
                if (errno == EINTR) continue;
                err = errno;
                break;
            }
            contents.append(buffer, static_cast<std::size_t>(n));
        }
    } catch (const std::bad_alloc&) {
        err = ENOMEM;
    }
    ::close(fd);
    if (err != 0) {
        contents = std::string();
        setError(error, path + ": cannot read: " + osReason(err));
        return std::nullopt;
    }
    return contents;
}

}  // namespace caustic
