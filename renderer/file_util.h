// Small file helpers: whole-file reads and crash-safe writes (write a temporary file beside the
// target, flush it to disk, then rename it over the target, so a reader never sees a partial file).
// Every error message names the file and the OS reason.
#pragma once

#include <optional>
#include <string>

namespace caustic {

// A unique temporary name in the same directory as finalPath (so the final rename stays on one
// file system), hidden, and ending with finalPath's extension so writers that choose the format
// from the extension still work: "dir/name.png" -> "dir/.name.png.tmp-<pid>-<counter>.png".
std::string tempPathBeside(const std::string& finalPath);

// Renames tmp over finalPath (atomic on POSIX). On failure removes tmp, sets *error (if non-null)
// and returns false.
bool commitTempFile(const std::string& tmp, const std::string& finalPath, std::string* error);

// Writes contents to a temporary file beside path, flushes and fsyncs it, then renames it over
// path. On failure nothing is left behind, path keeps its old contents, *error is set.
bool writeFileAtomically(const std::string& path, const std::string& contents, std::string* error);

// The whole file, or nullopt with *error = "<path>: cannot read: <reason>".
std::optional<std::string> readTextFile(const std::string& path, std::string* error);

}  // namespace caustic
