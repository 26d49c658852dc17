#include "renderer/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <glad/gl.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <dlfcn.h>
#include <link.h>
#endif

namespace caustic {
namespace {

#if defined(__SANITIZE_ADDRESS__)
// AddressSanitizer builds only (tests/sanitize.sh). LeakSanitizer looks for leaks at exit, after
// eglTerminate or glfwTerminate has unloaded Mesa's DRI driver (swrast_dri.so and the libraries
// only it needed). What the driver keeps for the life of the process then lies in no module, its
// stack frames are "<unknown module>", and the GL stack's suppressions (tests/sanitize/lsan.supp)
// cannot match them: every editor session and batch render reported a 128-byte leak that no one
// could attribute. So these builds take one more reference to each loaded DRI driver, with
// RTLD_NODELETE, which keeps it mapped until the process ends (docs/reliability.md).
void pinGlDriversForLeakChecks() {
    std::vector<std::string> drivers;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* out) -> int {
            if (info->dlpi_name && std::strstr(info->dlpi_name, "_dri.so"))
                static_cast<std::vector<std::string>*>(out)->push_back(info->dlpi_name);
            return 0;
        },
        &drivers);
    for (const std::string& d : drivers) dlopen(d.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
}
#endif

std::atomic<int> g_debugErrors{0};

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                              const GLchar* message, const void*) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    // A shader that fails to build reaches the caller through its info log, with the file and
    // line named (shader_loader.cpp); some drivers also send the compiler's messages here as
    // errors (Mesa 26 does, Mesa 25.0 did not). They are no misuse of the API: neither counted
    // (the tests' glDebugErrorCount() == 0) nor printed a second time.
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    if (type == GL_DEBUG_TYPE_ERROR) g_debugErrors.fetch_add(1);
    // Performance and portability notes are useful while developing, errors always.
    if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        std::fprintf(stderr, "caustic: GL debug [id %u]: %s\n", id, message);
}

const char* eglErrorName(EGLint e) {
    switch (e) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        default: return "EGL error";
    }
}

std::string eglFailure(const char* what) {
    char buf[160];
    EGLint e = eglGetError();
    std::snprintf(buf, sizeof buf, "%s failed (%s, 0x%04x)", what, eglErrorName(e), e);
    return buf;
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

// Initialises the display, binds desktop GL and creates a core context of the highest version
// the driver accepts (Mesa refuses 4.6; 4.5 is what we need).
bool initAndCreate(EGLDisplay display, EGLContext* ctxOut, EGLConfig* configOut, int* minorOut, std::string* why) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) { *why = eglFailure("eglInitialize"); return false; }
    if (!eglBindAPI(EGL_OPENGL_API)) { *why = eglFailure("eglBindAPI(EGL_OPENGL_API)"); eglTerminate(display); return false; }
    const char* ext = eglQueryString(display, EGL_EXTENSIONS);
    if (!hasExtension(ext, "EGL_KHR_surfaceless_context")) {
        *why = "the display lacks EGL_KHR_surfaceless_context";
        eglTerminate(display);
        return false;
    }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(ext, "EGL_KHR_no_config_context")) {
        const EGLint attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(display, attrs, &config, 1, &count) || count == 0) {
            *why = "no config with EGL_OPENGL_BIT and no EGL_KHR_no_config_context";
            eglTerminate(display);
            return false;
        }
    }
    for (int minorWanted : {6, 5}) {
        std::vector<EGLint> attrs = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, minorWanted,
                                     EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                     EGL_NONE};
        EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, attrs.data());
        if (ctx != EGL_NO_CONTEXT) {
            *ctxOut = ctx;
            *configOut = config;
            *minorOut = minorWanted;
            return true;
        }
    }
    *why = eglFailure("eglCreateContext (OpenGL 4.6 and 4.5 core)");
    eglTerminate(display);
    return false;
}

}  // namespace

int glDebugErrorCount() { return g_debugErrors.load(); }
int takeGlDebugErrors() { return g_debugErrors.exchange(0); }

void enableGlDebugOutput() {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
}

bool loadGlFunctions(void* (*getProc)(const char*), bool debugOutput, std::string* error) {
    const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(getProc));
    if (version == 0) { *error = "could not load OpenGL functions"; return false; }
    if (GLAD_VERSION_MAJOR(version) < 4 || (GLAD_VERSION_MAJOR(version) == 4 && GLAD_VERSION_MINOR(version) < 5)) {
        *error = "OpenGL 4.5 is required, the context offers " + std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                 std::to_string(GLAD_VERSION_MINOR(version));
        return false;
    }
#if defined(__SANITIZE_ADDRESS__)
    pinGlDriversForLeakChecks();
#endif
    if (debugOutput) enableGlDebugOutput();
    return true;
}

std::unique_ptr<HeadlessGlContext> HeadlessGlContext::create(bool debugOutput, std::string* error, int gpu) {
    std::string tried;
    auto note = [&](const std::string& platform, const std::string& why) {
        tried += "\n  " + platform + ": " + why;
    };
    const char* clientExt = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto getPlatformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));

    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLConfig config = EGL_NO_CONFIG_KHR;
    int minor = 5;
    std::string platform;

    // 1. EGL device platform: a real GPU without any window system.
    if (!getPlatformDisplay || !hasExtension(clientExt, "EGL_EXT_platform_device")) {
        note("EGL device platform", "EGL_EXT_platform_device is not offered by this libEGL");
    } else {
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
        auto queryDeviceAttrib = reinterpret_cast<PFNEGLQUERYDEVICEATTRIBEXTPROC>(eglGetProcAddress("eglQueryDeviceAttribEXT"));
        constexpr EGLint kEglCudaDeviceNv = 0x323A;   // EGL_NV_device_cuda's EGL_CUDA_DEVICE_NV
        int hardware = 0;   // hardware devices seen so far
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (!queryDevices || !queryDevices(16, devices, &count)) {
            note("EGL device platform", "eglQueryDevicesEXT failed");
        } else if (count == 0) {
            note("EGL device platform", "no EGL devices");
        }
        for (EGLint i = 0; i < count && context == EGL_NO_CONTEXT; ++i) {
            // Mesa lists a software device too; leave software rendering to the surfaceless
            // platform below so that a real GPU is always preferred.
            const char* devExt = queryDeviceString ? queryDeviceString(devices[i], EGL_EXTENSIONS) : nullptr;
            if (hasExtension(devExt, "EGL_MESA_device_software")) {
                note("EGL device " + std::to_string(i), "software device, skipped");
                continue;
            }
            if (gpu >= 0) {   // only the device asked for (see the header)
                EGLAttrib cuda = -1;
                const bool numbered = hasExtension(devExt, "EGL_NV_device_cuda") && queryDeviceAttrib &&
                                      queryDeviceAttrib(devices[i], kEglCudaDeviceNv, &cuda);
                const long number = numbered ? long(cuda) : long(hardware);
                ++hardware;
                if (number != gpu) {
                    note("EGL device " + std::to_string(i), (numbered ? "CUDA device " : "hardware device ") +
                                                                std::to_string(number) + ", not --gpu " + std::to_string(gpu));
                    continue;
                }
            }
            EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
            std::string why;
            if (d == EGL_NO_DISPLAY) { note("EGL device " + std::to_string(i), eglFailure("eglGetPlatformDisplayEXT")); continue; }
            if (initAndCreate(d, &context, &config, &minor, &why)) { display = d; platform = "EGL device"; }
            else note("EGL device " + std::to_string(i), why);
        }
    }

    if (context == EGL_NO_CONTEXT && gpu >= 0) {
        *error = "--gpu " + std::to_string(gpu) + ": no such GPU could be used; tried:" + tried;
        return nullptr;
    }
    // 2. Mesa's surfaceless platform (llvmpipe, or a Mesa GPU driver).
    if (context == EGL_NO_CONTEXT) {
        if (!getPlatformDisplay || !hasExtension(clientExt, "EGL_MESA_platform_surfaceless")) {
            note("EGL surfaceless platform (Mesa)", "EGL_MESA_platform_surfaceless is not offered (is libegl-mesa0 installed?)");
        } else {
            EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
            std::string why;
            if (d == EGL_NO_DISPLAY) note("EGL surfaceless platform (Mesa)", eglFailure("eglGetPlatformDisplayEXT"));
            else if (initAndCreate(d, &context, &config, &minor, &why)) { display = d; platform = "EGL surfaceless (Mesa)"; }
            else note("EGL surfaceless platform (Mesa)", why);
        }
    }

    if (context == EGL_NO_CONTEXT) {
        *error = "no headless OpenGL 4.5 context could be created; tried:" + tried;
        return nullptr;
    }
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
        *error = eglFailure("eglMakeCurrent") + " on the " + platform + " platform";
        eglDestroyContext(display, context);
        eglTerminate(display);
        return nullptr;
    }
    std::unique_ptr<HeadlessGlContext> ctx(new HeadlessGlContext());
    ctx->m_display = display;
    ctx->m_context = context;
    ctx->m_config = config;
    ctx->m_minor = minor;
    ctx->m_debugOutput = debugOutput;
    if (!loadGlFunctions(reinterpret_cast<void* (*)(const char*)>(eglGetProcAddress), debugOutput, error)) {
        *error = platform + ": " + *error;
        return nullptr;
    }
    ctx->m_info.platform = platform;
    ctx->m_info.vendor = reinterpret_cast<const char*>(glGetString(GL_VENDOR));
    ctx->m_info.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    ctx->m_info.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return ctx;
}

ProgramBuilder::WorkerContext HeadlessGlContext::sharedWorkerContext(std::string* error) {
    const EGLint attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, m_minor,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    eglBindAPI(EGL_OPENGL_API);
    EGLContext shared = eglCreateContext(m_display, m_config, m_context, attrs);
    if (shared == EGL_NO_CONTEXT) {
        *error = eglFailure("eglCreateContext (a context sharing the renderer's objects)");
        return {};
    }
    EGLDisplay display = m_display;
    const bool debug = m_debugOutput;
    // Made current on the worker thread (with this context's debug output: errors there count
    // too), and destroyed there when the worker lets it go.
    return {[display, shared, debug] {
                eglBindAPI(EGL_OPENGL_API);
                if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, shared)) {
                    if (debug) enableGlDebugOutput();
                    return true;
                }
                eglDestroyContext(display, shared);
                return false;
            },
            [display, shared] {
                eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
                eglDestroyContext(display, shared);
            }};
}

void HeadlessGlContext::makeCurrent() {
    eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context);
}

HeadlessGlContext::~HeadlessGlContext() {
    if (m_display) {
        eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (m_context) eglDestroyContext(m_display, m_context);
        eglTerminate(m_display);
    }
}

}  // namespace caustic
