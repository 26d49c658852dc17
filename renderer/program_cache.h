// An on-disk cache of linked GL programs (GL 4.1's glGetProgramBinary / glProgramBinary,
// ARB_get_program_binary), so a program built once is not compiled again by a later run: the
// editor reopening a scene, batch renders of the same kind of scene.
//
// Each program is a file named by a 128-bit hash of its whole source (defines and includes
// expanded) and of the driver (GL_VENDOR, GL_RENDERER, GL_VERSION): another driver or another
// source never finds it. A file that is damaged, or that the driver refuses (it may refuse a
// binary after an update), is a miss: the program is compiled and the file written again. Files
// are written atomically; the folder keeps the 256 most recently written (older ones are removed).
//
// The folder is one per process, chosen by the program from its configuration
// (IntegratorConfig::programCache, $CAUSTIC_PROGRAM_CACHE) before it builds anything: a folder,
// or "off" (or empty) for no cache; without a choice, $XDG_CACHE_HOME/caustic/programs, else
// ~/.cache/caustic/programs.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace caustic {

// Sets the folder (nullopt: the default one). Safe to call while builds run on other threads.
void useProgramCache(const std::optional<std::string>& setting);
std::string programCacheDir();   // "" when the cache is off

// A program linked from the cached binary for this source, or 0 (a miss).
unsigned loadCachedProgram(const std::string& source);
// Writes the linked program's binary for this source (the program must have been linked with
// GL_PROGRAM_BINARY_RETRIEVABLE_HINT). Failures are silent: the cache is an optimisation.
void storeCachedProgram(unsigned program, const std::string& source);

// Loads from the cache that linked a program, since the start of the process (for tests and
// CAUSTIC_COMPILE_TIMES).
std::uint64_t programCacheHits();

}  // namespace caustic
