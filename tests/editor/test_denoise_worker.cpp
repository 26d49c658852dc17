// The viewport denoiser's worker thread (editor/model/denoise_worker.h) with a stand-in denoiser:
// requests never wait for a running job, a waiting job is replaced by a newer one, results carry
// their job's generation and sample count, failures come back as errors, and the destructor
// joins a thread that is still busy.
#include "editor/model/denoise_worker.h"
#include "tests/editor/hang_guard.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <future>
#include <mutex>
#include <stdexcept>
#include <thread>

using namespace caustic;
using namespace caustic::editor;
using namespace std::chrono_literals;

namespace {

Film smallFilm(float value) {
    Film f;
    f.width = 2;
    f.height = 1;
    f.mean.assign(2, glm::vec3(value));
    f.albedo.assign(2, glm::vec3(0.5f));
    f.normal.assign(2, glm::vec3(0.0f, 0.0f, 1.0f));
    f.count.assign(2, 1.0f);
    return f;
}

DenoiseJob job(std::uint64_t generation, int samples, float value) {
    DenoiseJob j;
    j.generation = generation;
    j.samples = samples;
    j.film = smallFilm(value);
    return j;
}

// A denoiser that blocks until released, so tests control when a job finishes.
struct Gate {
    std::mutex m;
    std::condition_variable cv;
    bool open = false;
    std::atomic<int> entered{0};
    void release() {
        { std::lock_guard<std::mutex> l(m); open = true; }
        cv.notify_all();
    }
    DenoiseWorker::Function fn() {
        return [this](const Film& film, const DenoiseOptions&, DenoiseResult* out, std::string*) {
            ++entered;
            std::unique_lock<std::mutex> l(m);
            cv.wait(l, [this] { return open; });
            out->image.assign(film.mean.size(), film.mean[0] * 2.0f);
            out->device = "test";
            return true;
        };
    }
};

}  // namespace

TEST_CASE("denoise worker: a result carries its generation and samples", "[denoise]") {
    Gate gate;
    gate.release();
    DenoiseWorker w(gate.fn());
    w.request(job(7, 16, 1.5f));
    std::optional<DenoiseOutput> out;
    test::waitUntil("a result", [&] { out = w.take(); return out.has_value(); });
    CHECK(out->ok);
    CHECK(out->generation == 7);
    CHECK(out->samples == 16);
    CHECK(out->width == 2);
    CHECK(out->height == 1);
    REQUIRE(out->image.size() == 2);
    CHECK(out->image[1].x == 3.0f);
    CHECK(out->device == "test");
    CHECK_FALSE(w.take().has_value());   // taken once
    test::waitUntil("the worker going idle", [&] { return !w.busy(); });
}

TEST_CASE("denoise worker: requests never wait, and a waiting job is replaced", "[denoise]") {
    Gate gate;
    DenoiseWorker w(gate.fn());
    w.request(job(1, 4, 1.0f));
    test::waitUntil("the first job starting", [&] { return gate.entered.load() == 1; });   // job 1 is running, blocked
    // Two requests while job 1 is held in the denoiser (the gate opens only after both return):
    // a request that waited for the running job would never return.
    auto requests = std::async(std::launch::async, [&w] {
        w.request(job(1, 8, 2.0f));     // waits
        w.request(job(2, 12, 3.0f));    // replaces it
    });
    if (requests.wait_for(std::chrono::duration<double>(test::kHangGuardSeconds)) != std::future_status::ready) {
        gate.release();
        FAIL("request() waited for the running job");
    }
    CHECK(w.busy());
    CHECK_FALSE(w.take().has_value());
    gate.release();
    test::waitUntil("the worker finishing both jobs", [&] { return !w.busy() && w.jobsStarted() == 2; });
    std::optional<DenoiseOutput> out = w.take();   // the newest result only
    REQUIRE(out.has_value());
    CHECK(out->generation == 2);
    CHECK(out->samples == 12);
    CHECK(w.jobsStarted() == 2);   // the replaced job never ran
}

TEST_CASE("denoise worker: an edit drops a waiting job of the old generation", "[denoise]") {
    Gate gate;
    DenoiseWorker w(gate.fn());
    w.request(job(3, 4, 1.0f));
    test::waitUntil("the first job starting", [&] { return gate.entered.load() == 1; });
    w.request(job(3, 8, 1.0f));
    w.dropOlderThan(4);
    gate.release();
    test::waitUntil("the worker going idle", [&] { return !w.busy(); });
    CHECK(w.jobsStarted() == 1);
    std::optional<DenoiseOutput> out = w.take();
    REQUIRE(out.has_value());
    CHECK(out->generation == 3);   // finished; the UI compares it with its generation and drops it
}

TEST_CASE("denoise worker: failures and exceptions come back as errors", "[denoise]") {
    int calls = 0;
    DenoiseWorker w([&calls](const Film&, const DenoiseOptions&, DenoiseResult*, std::string* error) -> bool {
        if (++calls == 1) {
            *error = "no device";
            return false;
        }
        throw std::runtime_error("boom");
    });
    w.request(job(1, 1, 1.0f));
    std::optional<DenoiseOutput> out;
    test::waitUntil("a result", [&] { out = w.take(); return out.has_value(); });
    CHECK_FALSE(out->ok);
    CHECK(out->error == "no device");
    w.request(job(1, 1, 1.0f));
    test::waitUntil("a result", [&] { out = w.take(); return out.has_value(); });
    CHECK_FALSE(out->ok);
    CHECK(out->error == "boom");
}

TEST_CASE("denoise worker: a wrong-sized result is an error", "[denoise]") {
    DenoiseWorker w([](const Film&, const DenoiseOptions&, DenoiseResult* out, std::string*) {
        out->image.assign(1, glm::vec3(0.0f));
        return true;
    });
    w.request(job(1, 1, 1.0f));
    std::optional<DenoiseOutput> out;
    test::waitUntil("a result", [&] { out = w.take(); return out.has_value(); });
    CHECK_FALSE(out->ok);
    CHECK(out->image.empty());
}

TEST_CASE("denoise worker: the destructor joins while a job runs and drops the waiting one", "[denoise]") {
    Gate gate;
    std::thread releaser;
    {
        DenoiseWorker w(gate.fn());
        w.request(job(1, 1, 1.0f));
        test::waitUntil("the first job starting", [&] { return gate.entered.load() == 1; });
        w.request(job(1, 2, 1.0f));
        releaser = std::thread([&gate] {
            std::this_thread::sleep_for(50ms);
            gate.release();
        });
    }   // joins after the running job; the waiting one never starts
    releaser.join();
    CHECK(gate.entered.load() == 1);
}
