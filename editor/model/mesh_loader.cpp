#include "editor/model/mesh_loader.h"

#include "renderer/mesh_cache.h"

#include <algorithm>
#include <chrono>

namespace caustic::editor {

MeshLoader::~MeshLoader() {
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
        m_queue.clear();
        m_discardCurrent = true;
    }
    m_wake.notify_all();
    if (m_thread.joinable()) m_thread.join();
}

std::uint64_t MeshLoader::request(const std::string& file) {
    std::uint64_t id = 0;
    {
        std::lock_guard lock(m_mutex);
        id = m_nextId++;
        m_queue.push_back({id, file});
        if (!m_thread.joinable()) m_thread = std::thread([this] { work(); });
    }
    m_wake.notify_one();
    return id;
}

std::vector<MeshLoadResult> MeshLoader::poll() {
    std::lock_guard lock(m_mutex);
    std::vector<MeshLoadResult> out = std::move(m_done);
    m_done.clear();
    return out;
}

bool MeshLoader::busy() const {
    std::lock_guard lock(m_mutex);
    return !m_queue.empty() || !m_current.empty() || !m_done.empty();
}

std::vector<std::string> MeshLoader::pending() const {
    std::lock_guard lock(m_mutex);
    std::vector<std::string> files;
    if (!m_current.empty() && !m_discardCurrent) files.push_back(m_current);
    for (const Job& j : m_queue) files.push_back(j.file);
    return files;
}

bool MeshLoader::waitIdle(double timeoutSeconds) const {
    std::unique_lock lock(m_mutex);
    return m_idle.wait_for(lock, std::chrono::duration<double>(timeoutSeconds),
                           [this] { return m_queue.empty() && m_current.empty(); });
}

void MeshLoader::cancel() {
    {
        std::lock_guard lock(m_mutex);
        m_queue.clear();
        if (!m_current.empty()) m_discardCurrent = true;
    }
    m_idle.notify_all();
}

void MeshLoader::cancel(const std::vector<std::uint64_t>& ids) {
    auto listed = [&ids](std::uint64_t id) { return std::find(ids.begin(), ids.end(), id) != ids.end(); };
    {
        std::lock_guard lock(m_mutex);
        m_queue.erase(std::remove_if(m_queue.begin(), m_queue.end(), [&](const Job& j) { return listed(j.id); }), m_queue.end());
        if (!m_current.empty() && listed(m_currentId)) m_discardCurrent = true;
    }
    m_idle.notify_all();
}

void MeshLoader::work() {
    std::unique_lock lock(m_mutex);
    for (;;) {
        m_wake.wait(lock, [this] { return m_stop || !m_queue.empty(); });
        if (m_stop) break;
        Job job = std::move(m_queue.front());
        m_queue.pop_front();
        m_current = job.file;
        m_currentId = job.id;
        m_discardCurrent = false;
        lock.unlock();

        MeshLoadResult result;
        result.id = job.id;
        result.file = job.file;
        result.thread = std::this_thread::get_id();
        const auto t0 = std::chrono::steady_clock::now();
        auto entry = std::make_shared<MeshCacheEntry>();
        std::string error;
        if (prepareMesh(job.file, entry.get(), &error)) result.mesh = std::move(entry);
        else result.error = error.empty() ? job.file + ": could not be imported" : error;
        result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

        lock.lock();
        const bool keep = !m_discardCurrent && !m_stop;
        if (keep) m_done.push_back(std::move(result));
        m_current.clear();
        m_discardCurrent = false;
        if (m_queue.empty()) m_idle.notify_all();
        if (keep && m_onFinished) {
            lock.unlock();
            m_onFinished();
            lock.lock();
        }
    }
    m_current.clear();
    m_idle.notify_all();
}

}  // namespace caustic::editor
