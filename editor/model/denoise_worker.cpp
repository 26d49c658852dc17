#include "editor/model/denoise_worker.h"

#include <chrono>
#include <exception>
#include <utility>

namespace caustic::editor {

DenoiseWorker::DenoiseWorker(Function denoiser) : m_denoise(std::move(denoiser)), m_thread([this] { loop(); }) {}

DenoiseWorker::~DenoiseWorker() {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stop = true;
        m_pending.reset();
    }
    m_wake.notify_all();
    if (m_thread.joinable()) m_thread.join();
}

void DenoiseWorker::request(DenoiseJob job) {
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_pending = std::move(job);
    }
    m_wake.notify_one();
}

void DenoiseWorker::dropOlderThan(std::uint64_t generation) {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_pending && m_pending->generation < generation) m_pending.reset();
}

std::optional<DenoiseOutput> DenoiseWorker::take() {
    std::lock_guard<std::mutex> lock(m_mutex);
    std::optional<DenoiseOutput> out = std::move(m_done);
    m_done.reset();
    return out;
}

bool DenoiseWorker::busy() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_running || m_pending.has_value();
}

std::uint64_t DenoiseWorker::jobsStarted() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_started;
}

void DenoiseWorker::loop() {
    for (;;) {
        DenoiseJob job;
        {
            std::unique_lock<std::mutex> lock(m_mutex);
            m_wake.wait(lock, [this] { return m_stop || m_pending.has_value(); });
            if (m_stop) return;
            job = std::move(*m_pending);
            m_pending.reset();
            m_running = true;
            ++m_started;
        }
        // The denoiser runs without the lock: the UI thread can queue, poll and drop meanwhile.
        DenoiseOutput out;
        out.generation = job.generation;
        out.samples = job.samples;
        out.progressive = job.progressive;
        out.width = job.film.width;
        out.height = job.film.height;
        DenoiseResult result;
        const auto t0 = std::chrono::steady_clock::now();
        try {
            out.ok = m_denoise(job.film, job.options, &result, &out.error);
        } catch (const std::exception& e) {
            out.ok = false;
            out.error = e.what();
        }
        out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (out.ok) {
            out.image = std::move(result.image);
            out.device = std::move(result.device);
            if (out.image.size() != static_cast<size_t>(out.width) * static_cast<size_t>(out.height)) {
                out.ok = false;
                out.error = "the denoiser returned an image of the wrong size";
                out.image.clear();
            }
        }
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_done = std::move(out);
            m_running = false;
        }
    }
}

}  // namespace caustic::editor
