// Shared by the fuzz harnesses (tests/fuzz/fuzz_*.cpp): a scratch file for readers that take a
// path, and the check that turns a broken property into a crash the fuzzer (or the smoke test)
// reports. Each harness defines LLVMFuzzerTestOneInput; it is linked either with libFuzzer
// (-fsanitize=fuzzer, tests/fuzz/run.sh) or with smoke_main.cpp (the fixed-run-count smoke in
// ctest). docs/reliability.md describes the harnesses and their findings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace caustic::fuzz {

// A broken property: print it and abort (libFuzzer saves the input as a crash).
[[noreturn]] inline void failed(const char* what, const std::string& detail) {
    std::fprintf(stderr, "fuzz property broken: %s\n  %s\n", what, detail.c_str());
    std::fflush(stderr);
    std::abort();
}
#define FUZZ_CHECK(cond, detail) \
    do {                                                   \
        if (!(cond)) ::caustic::fuzz::failed(#cond, (detail)); \
    } while (0)

// The folder for this process's scratch files: $TMPDIR (else /tmp)/caustic-fuzz-<pid>, removed
// at exit with the files in it.
class ScratchDir {
public:
    static ScratchDir& get() {
        static ScratchDir dir;
        return dir;
    }
    const std::string& path() const { return m_path; }
    // Writes data to <dir>/input<ext> (replacing the previous input) and returns its path. One
    // name per extension, so a run leaves at most a handful of files.
    std::string write(const std::uint8_t* data, std::size_t size, std::string_view ext) {
        std::string file = m_path + "/input" + std::string(ext);
        const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
        if (fd < 0) failed("scratch file opens", file);
        std::size_t done = 0;
        while (done < size) {
            const ssize_t n = ::write(fd, data + done, size - done);
            if (n <= 0) failed("scratch file writes", file);
            done += static_cast<std::size_t>(n);
        }
        ::close(fd);
        m_written[slot(ext)] = file;
        return file;
    }
    ~ScratchDir() {
        for (const std::string& f : m_written)
            if (!f.empty()) ::unlink(f.c_str());
        ::rmdir(m_path.c_str());
    }

private:
    ScratchDir() {
        const char* tmp = std::getenv("TMPDIR");
        m_path = std::string(tmp && *tmp ? tmp : "/tmp") + "/caustic-fuzz-" + std::to_string(::getpid());
        ::mkdir(m_path.c_str(), 0700);
    }
    std::size_t slot(std::string_view ext) {
        for (std::size_t i = 0; i < kSlots; ++i)
            if (m_ext[i] == ext || m_ext[i].empty()) {
                m_ext[i] = std::string(ext);
                return i;
            }
        // Full (the fuzzer invents extensions: "p3", "pm3", ...): the last slot's file is removed
        // and the slot reused, so a run still leaves at most kSlots files.
        if (!m_written[kSlots - 1].empty()) ::unlink(m_written[kSlots - 1].c_str());
        m_ext[kSlots - 1] = std::string(ext);
        return kSlots - 1;
    }
    static constexpr std::size_t kSlots = 64;
    std::string m_path;
    std::string m_ext[kSlots];
    std::string m_written[kSlots];
};

// ".<ext>", appended piece by piece: GCC 12 warns (-Wrestrict, a false positive, GCC bug 105329)
// about "." + std::string(ext) once it is inlined.
inline std::string dotted(std::string_view ext) {
    std::string s(1, '.');
    s.append(ext);
    return s;
}

// Splits "<first line>\n<rest>" (the harnesses whose input starts with a file extension or
// option lines). No newline: the whole input is the first line and the rest is empty.
inline std::pair<std::string_view, std::string_view> splitFirstLine(std::string_view in) {
    const std::size_t nl = in.find('\n');
    if (nl == std::string_view::npos) return {in, {}};
    return {in.substr(0, nl), in.substr(nl + 1)};
}

}  // namespace caustic::fuzz
