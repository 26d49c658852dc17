#include "renderer/program_builder.h"

#include <glad/gl.h>

namespace caustic {

bool ProgramBuilder::Build::done() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_done;
}

unsigned ProgramBuilder::Build::abandon() {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_abandoned = true;
    const unsigned program = m_done ? m_program : 0u;
    m_program = 0;
    return program;
}

std::shared_ptr<ProgramBuilder> ProgramBuilder::start(WorkerContext context, std::string* error) {
    std::shared_ptr<ProgramBuilder> builder(new ProgramBuilder(std::move(context)));
    std::promise<std::string> started;
    std::future<std::string> result = started.get_future();
    builder->m_thread = std::thread([b = builder.get(), &started] { b->run(&started); });
    const std::string why = result.get();
    if (!why.empty()) {
        builder->m_thread.join();
        *error = why;
        return nullptr;
    }
    return builder;
}

ProgramBuilder::~ProgramBuilder() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
        m_held = false;
    }
    m_wake.notify_all();
    if (m_thread.joinable()) m_thread.join();
}

std::shared_ptr<ProgramBuilder::Build> ProgramBuilder::request(ShaderSource source, std::string name, bool printTimes) {
    auto build = std::make_shared<Build>();
    build->m_source = std::move(source);
    build->m_name = std::move(name);
    build->m_printTimes = printTimes;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_queue.push_back(build);
    }
    m_wake.notify_all();
    return build;
}

void ProgramBuilder::hold(bool on) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_held = on;
    }
    m_wake.notify_all();
}

int ProgramBuilder::outstanding() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return static_cast<int>(m_queue.size()) + (m_busy ? 1 : 0);
}

int ProgramBuilder::completed() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_completed;
}

int ProgramBuilder::compiled() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_compiled;
}

void ProgramBuilder::run(std::promise<std::string>* started) {
    if (!m_context.makeCurrent()) {
        started->set_value("the shader-building thread could not make its OpenGL context current");
        return;
    }
    started->set_value("");
    for (;;) {
        std::shared_ptr<Build> build;
        {
            std::unique_lock<std::mutex> lock(m_mutex);
            m_wake.wait(lock, [&] { return m_stop || (!m_held && !m_queue.empty()); });
            if (m_stop) break;
            build = std::move(m_queue.front());
            m_queue.pop_front();
            m_busy = true;
        }
        bool wanted;
        {
            std::lock_guard<std::mutex> lock(build->m_mutex);
            wanted = !build->m_abandoned;
        }
        std::string error;
        unsigned program = 0;
        if (wanted) {
            program = compileComputeProgram(build->m_source, build->m_name, &error, build->m_printTimes);
            glFinish();   // complete before another context binds it
        }
        {
            std::lock_guard<std::mutex> lock(build->m_mutex);
            if (build->m_abandoned) {
                if (program) glDeleteProgram(program);
                program = 0;
            }
            build->m_program = program;
            build->m_error = std::move(error);
            build->m_done = true;
            build->m_source = {};
        }
        std::lock_guard<std::mutex> lock(m_mutex);
        m_busy = false;
        ++m_completed;
        if (wanted) ++m_compiled;
    }
    m_queue.clear();
    m_context.release();
}

}  // namespace caustic
