// Builds GL compute programs on a worker thread whose context shares objects with the renderer's,
// so that a build taking seconds (llvmpipe compiles inside glLinkProgram even where it offers
// GL_KHR_parallel_shader_compile; a driver compiling a megakernel takes seconds too) never blocks
// the thread that draws the editor's window. The renderer asks (Renderer::setProgramBuilder) and
// polls; meanwhile it renders with a program that is right for the scene, or renders nothing and
// keeps its image (renderer_programs.cpp, selectProgram).
//
// The worker compiles with compileComputeProgram (the program-binary cache included), then waits
// for the driver to finish (glFinish) before it marks the build done: a program object is shared,
// and the GL makes a change made in one context visible in another once it is complete and the
// object is bound there again (OpenGL 4.6, section 5.3).
#pragma once

#include "renderer/shader_loader.h"

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace caustic {

class ProgramBuilder {
public:
    // The worker's context: makeCurrent makes it current on the calling thread (the worker's),
    // release makes none current there; both are called on the worker thread only. The context
    // must share objects with the renderer's (a GLFW window created with the editor's window as
    // its share, HeadlessGlContext::createShared).
    struct WorkerContext {
        std::function<bool()> makeCurrent;
        std::function<void()> release;
    };

    // One requested build. done() turns true once, with program (0 on failure) and error set; they
    // are read only after that.
    class Build {
    public:
        bool done() const;
        unsigned program() const { return m_program; }
        const std::string& error() const { return m_error; }
        // The requester no longer wants the program: a build still to finish has it deleted by
        // the worker; a finished one's program is returned (non-zero) for the caller to delete.
        unsigned abandon();

    private:
        friend class ProgramBuilder;
        mutable std::mutex m_mutex;
        bool m_done = false, m_abandoned = false;
        unsigned m_program = 0;
        std::string m_error;
        ShaderSource m_source;
        std::string m_name;
        bool m_printTimes = false;
    };

    // Starts the worker, which makes the context current; null with a message when it cannot.
    static std::shared_ptr<ProgramBuilder> start(WorkerContext context, std::string* error);
    // Finishes the build in progress, drops those queued (their programs are never made), and
    // releases the context on the worker before joining it.
    ~ProgramBuilder();
    ProgramBuilder(const ProgramBuilder&) = delete;
    ProgramBuilder& operator=(const ProgramBuilder&) = delete;

    // Queues a build (first in, first out) and returns at once.
    std::shared_ptr<Build> request(ShaderSource source, std::string name, bool printTimes = false);

    // Tests and editor scripts: while held, the worker starts no build, so a caller can observe the
    // renderer with a build outstanding whatever the machine's speed.
    void hold(bool on);
    // Builds requested and not yet done (queued or in progress).
    int outstanding() const;
    // Builds finished since start, and of them those that compiled (not abandoned before they started).
    int completed() const;
    int compiled() const;

private:
    explicit ProgramBuilder(WorkerContext context) : m_context(std::move(context)) {}
    void run(std::promise<std::string>* started);

    WorkerContext m_context;
    std::thread m_thread;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::deque<std::shared_ptr<Build>> m_queue;
    bool m_stop = false, m_held = false, m_busy = false;
    int m_completed = 0, m_compiled = 0;
};

}  // namespace caustic
