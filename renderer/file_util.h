// Small file helpers: whole-file reads and crash-safe writes (write a temporary file beside the
// target, flush it to disk, then rename it over the target, so a reader never sees a partial file).
// Every error message names the file and the OS reason.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace caustic {

// A unique temporary name in the same directory as finalPath (so the final rename stays on one
// file system), hidden, and ending with finalPath's extension so writers that choose the format
// from the extension still work: "dir/name.png" -> "dir/.name.png.tmp-<pid>-<counter>.png".
// The name part is kept short (at most kTempNameKeep bytes of the original name, cut at a UTF-8
// boundary; an extension longer than 16 bytes is dropped), so the temporary's name stays far
// below the 255-byte limit of common file systems even when finalPath's own name is close to it.
inline constexpr std::size_t kTempNameKeep = 64;
std::string tempPathBeside(const std::string& finalPath);

// Renames tmp over finalPath (atomic on POSIX). On failure removes tmp, sets *error (if non-null)
// and returns false.
bool commitTempFile(const std::string& tmp, const std::string& finalPath, std::string* error);

// Writes size bytes to a temporary file beside path, checking every write, fsync and close,
// then renames it over path. On any failure the temporary is removed, path keeps its old
// contents and *error is set ("<path>: cannot write: writing the temporary file '...' failed: No
// space left on device"). While the temporary exists it is registered with the signal cleanup
// below, so SIGINT/SIGTERM/SIGHUP/SIGQUIT do not leave it behind.
bool writeFileAtomically(const std::string& path, const char* data, std::size_t size, std::string* error);
inline bool writeFileAtomically(const std::string& path, const std::string& contents, std::string* error) {
    return writeFileAtomically(path, contents.data(), contents.size(), error);
}

// Temporary files removed if the process is ended by SIGINT, SIGTERM, SIGHUP or SIGQUIT. The handler
// (installed when a name is registered, unless the signal is ignored; chaining to the handler it
// replaced) only calls unlink() on the registered names, then calls that handler or lets the
// signal take its default effect (async-signal-safe). At most
// kMaxTempFiles names of at most kMaxTempPath bytes are held at once; a name that does not fit
// is simply not registered (its file is still removed on every ordinary failure).
inline constexpr int kMaxTempFiles = 32;
inline constexpr std::size_t kMaxTempPath = 4096;
class TempFileRegistration {
public:
    explicit TempFileRegistration(const std::string& path);
    ~TempFileRegistration();
    TempFileRegistration(const TempFileRegistration&) = delete;
    TempFileRegistration& operator=(const TempFileRegistration&) = delete;
    bool registered() const { return m_slot >= 0; }

private:
    int m_slot = -1;
};

// Opens path for reading only if it is a regular file (not a FIFO, device, socket or folder:
// reading /dev/zero or a FIFO would never end). Opened without blocking, so a FIFO with no writer
// is refused instead of waiting. Returns the descriptor, or -1 with *error = "<path>: <reason>".
int openRegularFile(const std::string& path, std::string* error);
// The same check without keeping the file open.
bool checkRegularFile(const std::string& path, std::string* error);

// The whole file, or nullopt with *error = "<path>: cannot read: <reason>".
std::optional<std::string> readTextFile(const std::string& path, std::string* error);

}  // namespace caustic
