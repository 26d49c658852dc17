// The viewport denoiser's background thread (no GL, no ImGui; unit-tested in tests/editor/).
// The UI thread reads the film (GL: it must stay on that thread) and hands it over with
// request(); one worker thread runs the denoiser on it; the UI thread polls take() once a frame
// and uploads the result. The UI thread never waits for the denoiser: request() and take() only
// hold the mutex to move a job or a result. At most one job runs and one waits: a request while
// one is waiting replaces it. Every job carries the accumulation generation it was read from
// (any edit restarts accumulation and starts a new generation) and its sample count, so the UI
// can discard a result whose image has since changed; dropOlderThan() also drops a waiting job
// that an edit made pointless. The destructor stops the thread and joins it (after the running
// job, if any, finishes).
#pragma once

#include "renderer/denoise.h"
#include "renderer/film.h"

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace caustic::editor {

struct DenoiseJob {
    std::uint64_t generation = 0;   // the accumulation the film was read from
    int samples = 0;                // samples per pixel in the film
    bool progressive = false;       // an idle denoise: shown while its accumulation goes on
    Film film;
    DenoiseOptions options;
};

struct DenoiseOutput {
    std::uint64_t generation = 0;
    int samples = 0;
    bool progressive = false;        // the job's
    int width = 0, height = 0;
    bool ok = false;
    std::string error;               // when !ok
    std::vector<glm::vec3> image;    // linear radiance, the film's layout (row 0 at the top)
    std::string device;              // the OIDN device that ran
    double seconds = 0.0;            // the denoiser's wall time
};

class DenoiseWorker {
public:
    // The denoiser; renderer/denoise.h's denoise() in the editor, a stand-in in tests.
    using Function = std::function<bool(const Film&, const DenoiseOptions&, DenoiseResult*, std::string*)>;

    explicit DenoiseWorker(Function denoiser);
    ~DenoiseWorker();   // stops and joins the thread
    DenoiseWorker(const DenoiseWorker&) = delete;
    DenoiseWorker& operator=(const DenoiseWorker&) = delete;

    // Queues a job; replaces the waiting one, if any. Never blocks on a running job.
    void request(DenoiseJob job);
    // Drops the waiting job if it belongs to an older generation.
    void dropOlderThan(std::uint64_t generation);
    // The newest finished result since the last call (older unclaimed ones are dropped).
    std::optional<DenoiseOutput> take();
    bool busy() const;                 // a job is running or waiting
    std::uint64_t jobsStarted() const;   // for tests: how many jobs the thread ran

private:
    void loop();

    Function m_denoise;
    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<DenoiseJob> m_pending;
    std::optional<DenoiseOutput> m_done;
    bool m_running = false;
    bool m_stop = false;
    std::uint64_t m_started = 0;
    std::thread m_thread;   // last: starts after the members above exist
};

}  // namespace caustic::editor
