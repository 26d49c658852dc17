// A headless OpenGL 4.5+ core context through EGL, with no display server: the EGL device
// platform first (NVIDIA's driver exposes GPUs as EGL devices), then Mesa's surfaceless platform
// (llvmpipe on machines without a GPU). The editor makes its context with GLFW instead; the
// renderer does not care which one is current.
#pragma once

#include "renderer/program_builder.h"

#include <memory>
#include <string>

namespace caustic {

struct GlContextInfo {
    std::string platform;   // "EGL device" or "EGL surfaceless (Mesa)"
    std::string vendor, renderer, version;
};

class HeadlessGlContext {
public:
    // Creates the context and makes it current on the calling thread. On failure returns null and
    // sets *error to a message naming every platform tried and why it failed.
    // debugOutput turns on GL_KHR_debug messages (errors are printed to stderr).
    // gpu >= 0 asks for one GPU (caustic --gpu, the farm's GPU assignment): the EGL device whose
    // CUDA device number is gpu where the driver tells it (EGL_NV_device_cuda: the numbering
    // CUDA_VISIBLE_DEVICES and Ray use), else the gpu-th hardware device; no fallback to another
    // device or to software rendering.
    static std::unique_ptr<HeadlessGlContext> create(bool debugOutput, std::string* error, int gpu = -1);
    ~HeadlessGlContext();
    HeadlessGlContext(const HeadlessGlContext&) = delete;
    HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

    const GlContextInfo& info() const { return m_info; }
    void makeCurrent();
    // A second context sharing this one's objects, for a ProgramBuilder's worker thread (made
    // current there, destroyed when the worker releases it). The builder must be gone before this
    // context is. Empty functions with a message when the driver refuses.
    ProgramBuilder::WorkerContext sharedWorkerContext(std::string* error);

private:
    HeadlessGlContext() = default;
    void* m_display = nullptr;
    void* m_context = nullptr;
    void* m_config = nullptr;   // EGL_NO_CONFIG_KHR where the display has EGL_KHR_no_config_context
    int m_minor = 5;            // the context's OpenGL 4.x minor version
    bool m_debugOutput = false; // create's debugOutput, for the shared contexts too
    GlContextInfo m_info;
};

// Loads GL entry points with glad through the given loader and, if asked, installs the debug
// callback. Shared by the headless context and the editor's window context.
bool loadGlFunctions(void* (*getProc)(const char*), bool debugOutput, std::string* error);

// Installs the debug callback on the current context (loadGlFunctions does for the first; a second,
// sharing context, such as a ProgramBuilder's, needs its own: the callback is per context).
void enableGlDebugOutput();

// Number of GL errors reported through the debug callback so far (tests assert it stays zero).
int glDebugErrorCount();
// Returns that number and sets it to zero (for a test that provokes GL errors on purpose).
int takeGlDebugErrors();

}  // namespace caustic
