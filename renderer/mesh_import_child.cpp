// importMeshFile: Assimp in a child process (issue 12). Assimp 5.2.5's importers crash on corrupt
// files (SEGV and heap overflows in its MDL, ASE, COLLADA, MD5 and 3DS readers, an uncaught
// DeadlyImportError in its COB reader: docs/reliability.md), and nothing in caustic's code can
// catch that. So the import runs in a forked child: it parses, converts and validates as
// importMeshFileInProcess does, writes the result through a pipe and exits; the parent reads it
// back. A crash then costs one import ("the importer crashed (signal 11, ...)"), not the CLI or
// the editor with its unsaved edits.
//
// fork() without exec: the child starts from a copy of the parent (copy-on-write, so the cost is
// the page tables, a few milliseconds for the editor) and only runs the import, Assimp's own code
// and the conversion, then _exit()s (no atexit handlers, no flushing of the parent's stdio
// buffers). glibc makes malloc usable in the child of a multithreaded parent; the import takes no
// other lock the parent's other threads could hold. If fork fails (no memory, process limit), the
// import runs in this process instead, as before.
//
// A child that runs longer than the time-out (kImportTimeoutSeconds; Assimp loops for ever on some
// corrupt SMD, COLLADA and OpenGEX files) is killed and the import fails saying so.
//
// The result is serialised field by field (below); the static_asserts on the sizes of Mesh and
// ImportedMaterial fail the build when a field is added, so that it is not silently dropped here.
#include "renderer/mesh_import.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace caustic {
namespace {

// Update writeMesh/readMesh, writeMaterial/readMaterial and the embedded images' fields when these
// change.
static_assert(sizeof(Mesh) == 160, "a Mesh field was added: serialise it in mesh_import_child.cpp");
static_assert(sizeof(ImportedMaterial) == 304,
              "an ImportedMaterial field was added: serialise it in mesh_import_child.cpp");
static_assert(sizeof(EmbeddedImage) == 2 * sizeof(std::string) + 2 * sizeof(int),
              "an EmbeddedImage field was added: serialise it in serializeImport/deserializeImport");

constexpr std::uint32_t kMagic = 0x31494d43;  // "CMI1"

struct Writer {
    std::string out;
    template <class T>
    void pod(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        out.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void str(const std::string& s) {
        pod(std::uint64_t(s.size()));
        out.append(s);
    }
    template <class T>
    void vec(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        pod(std::uint64_t(v.size()));
        out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};

struct Reader {
    const std::string& in;
    std::size_t at = 0;
    bool ok = true;
    bool take(void* dst, std::size_t n) {
        if (!ok || n > in.size() - at) return ok = false;
        if (n == 0) return true;  // an empty vector's data() may be null: memcpy(null, ..., 0) is undefined
        std::memcpy(dst, in.data() + at, n);
        at += n;
        return true;
    }
    template <class T>
    bool pod(T& v) { return take(&v, sizeof v); }
    bool count(std::uint64_t& n, std::size_t elementSize) {
        // A count the remaining bytes cannot hold is a broken stream, not an allocation to try.
        return pod(n) && (elementSize == 0 || n <= (in.size() - at) / elementSize) ? true : (ok = false);
    }
    bool str(std::string& s) {
        std::uint64_t n = 0;
        if (!count(n, 1)) return false;
        s.assign(in.data() + at, n);
        at += n;
        return true;
    }
    template <class T>
    bool vec(std::vector<T>& v) {
        std::uint64_t n = 0;
        if (!count(n, sizeof(T))) return false;
        v.resize(n);
        return take(v.data(), n * sizeof(T));
    }
};

void writeMaterial(Writer& w, const ImportedMaterial& m) {
    w.str(m.name);
    w.pod(m.baseColor);
    w.pod(m.opacity);
    w.str(m.baseColorTexture);
    w.pod(m.roughness);
    w.pod(m.metallic);
    w.str(m.metallicRoughnessTexture);
    w.str(m.normalTexture);
    w.pod(m.normalScale);
    w.pod(m.emission);
    w.str(m.emissionTexture);
    w.pod(m.transmission);
    w.pod(m.ior);
    w.pod(m.doubleSided);
    w.pod(m.specular);
    w.pod(m.specularColor);
    w.pod(m.clearcoat);
    w.pod(m.clearcoatRoughness);
    w.pod(m.sheenColor);
    w.pod(m.sheenRoughness);
    w.pod(m.alphaMode);
    w.pod(m.alphaCutoff);
    w.pod(m.wrap);
    w.pod(m.attenuationColor);
    w.pod(m.attenuationDistance);
    w.pod(m.volume);
    w.pod(m.diffuseTransmission);
    w.pod(m.diffuseTransmissionColor);
}

bool readMaterial(Reader& r, ImportedMaterial& m) {
    return r.str(m.name) && r.pod(m.baseColor) && r.pod(m.opacity) && r.str(m.baseColorTexture) && r.pod(m.roughness) &&
           r.pod(m.metallic) && r.str(m.metallicRoughnessTexture) && r.str(m.normalTexture) && r.pod(m.normalScale) &&
           r.pod(m.emission) && r.str(m.emissionTexture) && r.pod(m.transmission) && r.pod(m.ior) && r.pod(m.doubleSided) &&
           r.pod(m.specular) && r.pod(m.specularColor) && r.pod(m.clearcoat) && r.pod(m.clearcoatRoughness) &&
           r.pod(m.sheenColor) && r.pod(m.sheenRoughness) && r.pod(m.alphaMode) && r.pod(m.alphaCutoff) &&
           r.pod(m.wrap) && r.pod(m.attenuationColor) && r.pod(m.attenuationDistance) && r.pod(m.volume) &&
           r.pod(m.diffuseTransmission) && r.pod(m.diffuseTransmissionColor);
}

void writeMesh(Writer& w, const Mesh& m) {
    w.str(m.name);
    w.vec(m.positions);
    w.vec(m.normals);
    w.vec(m.uvs);
    w.vec(m.tangents);
    w.vec(m.triangles);
    w.pod(m.material);
}

bool readMesh(Reader& r, Mesh& m) {
    return r.str(m.name) && r.vec(m.positions) && r.vec(m.normals) && r.vec(m.uvs) && r.vec(m.tangents) &&
           r.vec(m.triangles) && r.pod(m.material);
}

bool writeAll(int fd, const std::string& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += std::size_t(n);
    }
    return true;
}

}  // namespace

std::string serializeImport(const MeshImportResult& r) {
    Writer w;
    w.pod(kMagic);
    w.str(r.error);
    w.pod(std::uint64_t(r.warnings.size()));
    for (const std::string& s : r.warnings) w.str(s);
    w.pod(std::uint64_t(r.meshes.size()));
    for (const Mesh& m : r.meshes) writeMesh(w, m);
    w.pod(std::uint64_t(r.materials.size()));
    for (const ImportedMaterial& m : r.materials) writeMaterial(w, m);
    w.pod(std::uint64_t(r.embedded.size()));
    for (const EmbeddedImage& e : r.embedded) {
        w.str(e.name);
        w.str(e.bytes);
        w.pod(std::int32_t(e.width));
        w.pod(std::int32_t(e.height));
    }
    w.pod(kMagic);
    return std::move(w.out);
}

bool deserializeImport(const std::string& bytes, MeshImportResult* out) {
    Reader r{bytes};
    std::uint32_t magic = 0, end = 0;
    std::uint64_t n = 0;
    MeshImportResult result;
    if (!r.pod(magic) || magic != kMagic || !r.str(result.error)) return false;
    if (!r.count(n, sizeof(std::uint64_t))) return false;
    result.warnings.resize(n);
    for (std::string& s : result.warnings)
        if (!r.str(s)) return false;
    if (!r.count(n, sizeof(std::uint64_t))) return false;
    result.meshes.resize(n);
    for (Mesh& m : result.meshes)
        if (!readMesh(r, m)) return false;
    if (!r.count(n, sizeof(std::uint64_t))) return false;
    result.materials.resize(n);
    for (ImportedMaterial& m : result.materials)
        if (!readMaterial(r, m)) return false;
    if (!r.count(n, 2 * sizeof(std::uint64_t) + 2 * sizeof(std::int32_t))) return false;
    result.embedded.resize(n);
    for (EmbeddedImage& e : result.embedded) {
        std::int32_t width = 0, height = 0;
        if (!r.str(e.name) || !r.str(e.bytes) || !r.pod(width) || !r.pod(height)) return false;
        e.width = width;
        e.height = height;
    }
    if (!r.pod(end) || end != kMagic || r.at != bytes.size()) return false;
    *out = std::move(result);
    return true;
}

MeshImportResult importMeshFile(const std::string& path, double timeoutSeconds) {
    // CAUSTIC_IMPORT_IN_PROCESS=1 imports in this process instead: for the sanitizer runs of the
    // editor's sessions (tests/sanitize.sh sets it there: GCC 12's AddressSanitizer does not lock
    // its allocator around fork, so a child forked while another thread allocates waits for ever
    // at its first allocation) and for debugging Assimp under a debugger. Normal builds fork:
    // glibc makes its own malloc safe across fork.
    if (const char* env = std::getenv("CAUSTIC_IMPORT_IN_PROCESS"); env && std::strcmp(env, "1") == 0)
        return importMeshFileInProcess(path);
    const auto t0 = std::chrono::steady_clock::now();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return importMeshFileInProcess(path);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return importMeshFileInProcess(path);
    }
    if (pid == 0) {  // the child: import, write, leave without running the parent's exit code
        ::close(fds[0]);
        // A parent that dies (killed by a test's alarm, or by the user) takes a child that hangs
        // in Assimp with it, instead of leaving it spinning.
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(4);
        std::signal(SIGPIPE, SIG_IGN);   // a parent that went away makes write fail, not kill
        // A crash must end the child plainly: the parent's handlers (a test framework's report,
        // a program's crash handler, the temporary-file cleanup) are not the child's business.
        for (const int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGTERM, SIGINT, SIGHUP, SIGQUIT})
            std::signal(sig, SIG_DFL);
        bool written = false;
        try {
            written = writeAll(fds[1], serializeImport(importMeshFileInProcess(path)));
        } catch (...) {   // out of memory while serialising: the parent reports a failed import
        }
        ::_exit(written ? 0 : 3);
    }
    ::close(fds[1]);
    std::string bytes;
    char buf[1 << 16];
    bool timedOut = false;
    for (;;) {
        const double left = timeoutSeconds - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (left <= 0.0) {
            timedOut = true;
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int ready = ::poll(&p, 1, int(std::min(left * 1000.0 + 1.0, 60000.0)));
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) continue;   // the time left is checked again above
        const ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        bytes.append(buf, std::size_t(n));
    }
    ::close(fds[0]);
    if (timedOut) ::kill(pid, SIGKILL);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    MeshImportResult r;
    if (timedOut) {
        char secs[32];
        std::snprintf(secs, sizeof secs, "%g", timeoutSeconds);
        r.error = path + ": the importer did not finish within " + secs +
                  " s (Assimp hangs on some corrupt files); the import was stopped";
    } else if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* name = ::sigabbrev_np(sig);
        r.error = path + ": the importer crashed (signal " + std::to_string(sig) + (name ? std::string(", SIG") + name : "") +
                  ") inside Assimp; the file is probably corrupt";
    } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !deserializeImport(bytes, &r)) {
        r = MeshImportResult{};
        r.error = path + ": the import process failed (exit status " +
                  std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace caustic
