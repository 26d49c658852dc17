#include "renderer/program_cache.h"

#include "renderer/file_util.h"

#include <glad/gl.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <vector>

namespace fs = std::filesystem;

namespace caustic {
namespace {

constexpr char kMagic[8] = {'C', 'A', 'U', 'S', 'P', 'B', '0', '1'};
constexpr std::size_t kMaxFiles = 256;
std::atomic<std::uint64_t> g_hits{0};

// FNV-1a, 64 bits, from a given offset basis: two bases give the two halves of the file's hash.
std::uint64_t fnv1a(const std::string& s, std::uint64_t h) {
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ull;
    }
    return h;
}

std::string glString(GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return s ? s : "";
}

struct Key {
    std::uint64_t a = 0, b = 0;
};

Key keyFor(const std::string& source) {
    const std::string text = glString(GL_VENDOR) + '\n' + glString(GL_RENDERER) + '\n' + glString(GL_VERSION) + '\n' + source;
    return {fnv1a(text, 14695981039346656037ull), fnv1a(text, 0x9e3779b97f4a7c15ull)};
}

std::string fileFor(const std::string& dir, Key k) {
    char name[40];
    std::snprintf(name, sizeof name, "%016llx%016llx.bin", static_cast<unsigned long long>(k.a),
                  static_cast<unsigned long long>(k.b));
    return (fs::path(dir) / name).string();
}

struct Header {
    char magic[8];
    std::uint64_t keyB;      // the hash's second half again: a renamed or mixed-up file is a miss
    std::uint32_t format;    // the driver's binary format
    std::uint32_t reserved;
    std::uint64_t length;
};

void evictOldest(const std::string& dir) {
    std::error_code ec;
    std::vector<std::pair<fs::file_time_type, fs::path>> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().extension() == ".bin") files.emplace_back(e.last_write_time(ec), e.path());
    if (files.size() <= kMaxFiles) return;
    std::sort(files.begin(), files.end());
    for (std::size_t i = 0; i + kMaxFiles < files.size(); ++i) fs::remove(files[i].second, ec);
}

std::mutex g_settingMutex;
std::optional<std::string> g_setting;   // useProgramCache's; nullopt: the default folder

}  // namespace

void useProgramCache(const std::optional<std::string>& setting) {
    std::lock_guard<std::mutex> lock(g_settingMutex);
    g_setting = setting;
}

std::string programCacheDir() {
    {
        std::lock_guard<std::mutex> lock(g_settingMutex);
        if (g_setting) return *g_setting == "off" ? std::string() : *g_setting;
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (fs::path(xdg) / "caustic" / "programs").string();
    if (const char* home = std::getenv("HOME"); home && *home) return (fs::path(home) / ".cache" / "caustic" / "programs").string();
    return {};
}

unsigned loadCachedProgram(const std::string& source) {
    const std::string dir = programCacheDir();
    if (dir.empty()) return 0;
    const Key k = keyFor(source);
    std::ifstream in(fileFor(dir, k), std::ios::binary);
    if (!in) return 0;
    Header h{};
    if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.keyB != k.b ||
        h.length == 0 || h.length > (std::uint64_t(1) << 30))
        return 0;
    std::vector<char> data(static_cast<std::size_t>(h.length));
    if (!in.read(data.data(), static_cast<std::streamsize>(data.size()))) return 0;
    const GLuint program = glCreateProgram();
    glProgramBinary(program, h.format, data.data(), static_cast<GLsizei>(data.size()));
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {   // refused (another driver build): compiled again, and the file rewritten
        glDeleteProgram(program);
        while (glGetError() != GL_NO_ERROR) {
        }
        return 0;
    }
    ++g_hits;
    return program;
}

void storeCachedProgram(unsigned program, const std::string& source) {
    const std::string dir = programCacheDir();
    if (dir.empty()) return;
    GLint length = 0;
    glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &length);
    if (length <= 0) return;
    std::vector<char> data(static_cast<std::size_t>(length));
    GLenum format = 0;
    GLsizei written = 0;
    glGetProgramBinary(program, length, &written, &format, data.data());
    if (written <= 0) return;
    const Key k = keyFor(source);
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.keyB = k.b;
    h.format = format;
    h.length = static_cast<std::uint64_t>(written);
    std::string bytes(reinterpret_cast<const char*>(&h), sizeof h);
    bytes.append(data.data(), static_cast<std::size_t>(written));
    std::error_code ec;
    fs::create_directories(dir, ec);
    std::string error;
    if (writeFileAtomically(fileFor(dir, k), bytes, &error)) evictOldest(dir);
}

std::uint64_t programCacheHits() { return g_hits.load(); }

}  // namespace caustic
