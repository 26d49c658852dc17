// Background mesh preparation for the editor: a model file is imported (Assimp) and its BVH built
// on a worker thread (renderer/mesh_cache.h prepareMesh: pure CPU, no GL), so a large mesh never
// stalls the frame loop. The UI thread polls for finished meshes once per frame, inserts each into
// the renderer's MeshCache and only then applies the edit that uses it (docs/editor.md,
// "Importing meshes"); until then the viewport keeps rendering the scene as it was.
//
// One worker, requests served in order. Assimp cannot be interrupted, so cancel() drops what is
// queued and discards the result of the import in progress, and the destructor waits for that one
// import to finish (joins the thread).
#pragma once

#include "renderer/mesh_cache.h"

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace caustic::editor {

struct MeshLoadResult {
    std::uint64_t id = 0;                          // as returned by request()
    std::string file;                              // as requested
    std::shared_ptr<const MeshCacheEntry> mesh;    // null when the import failed
    std::string error;                             // "<file>: <reason>" when it failed
    double seconds = 0.0;                          // import + BVH build, on the worker
    std::thread::id thread;                        // the thread that prepared it (tests)
    bool ok() const { return mesh != nullptr; }
};

class MeshLoader {
public:
    MeshLoader() = default;
    ~MeshLoader();   // cancels and joins
    MeshLoader(const MeshLoader&) = delete;
    MeshLoader& operator=(const MeshLoader&) = delete;

    // Queues file (a path the process can open) and returns at once; ids start at 1.
    std::uint64_t request(const std::string& file);
    // The results finished since the last call, in request order. Never blocks.
    std::vector<MeshLoadResult> poll();
    // Something is queued, being prepared, or finished and not yet polled.
    bool busy() const;
    // The files queued or being prepared (for the status bar).
    std::vector<std::string> pending() const;
    // Blocks until nothing is queued or being prepared (results may wait for poll()), or until
    // timeoutSeconds pass; returns whether it became idle. For tests.
    bool waitIdle(double timeoutSeconds) const;
    // Drops the queued requests and the result of the one in progress (no result for either).
    void cancel();
    // Drops only the requests `ids` (queued or in progress); the others go on. Ids already
    // finished but not yet polled still come out of poll().
    void cancel(const std::vector<std::uint64_t>& ids);
    // Called on the worker after each result is ready (the editor wakes its frame loop with
    // glfwPostEmptyEvent). Set it before the first request.
    void setOnFinished(std::function<void()> onFinished) { m_onFinished = std::move(onFinished); }

private:
    struct Job { std::uint64_t id; std::string file; };
    void work();

    mutable std::mutex m_mutex;
    mutable std::condition_variable m_wake, m_idle;
    std::deque<Job> m_queue;
    std::vector<MeshLoadResult> m_done;
    std::string m_current;             // the file being prepared ("" when none)
    std::uint64_t m_currentId = 0;     // its request id
    bool m_discardCurrent = false;
    bool m_stop = false;
    std::uint64_t m_nextId = 1;
    std::function<void()> m_onFinished;
    std::thread m_thread;              // started by the first request
};

}  // namespace caustic::editor
