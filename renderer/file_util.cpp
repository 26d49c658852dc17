#include "renderer/file_util.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

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
    const std::string extension =
        dot == std::string::npos || dot == 0 ? std::string() : name.substr(dot);
    return dir + "." + name + ".tmp-" + std::to_string(static_cast<long>(::getpid())) + "-" +
           std::to_string(counter.fetch_add(1)) + extension;
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

bool writeFileAtomically(const std::string& path, const std::string& contents, std::string* error) {
    const std::string tmp = tempPathBeside(path);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
        setError(error, path + ": cannot write: cannot create the temporary file '" + tmp +
                            "': " + osReason(errno));
        return false;
    }
    int err = writeAll(fd, contents.data(), contents.size());
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
