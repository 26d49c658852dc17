// Tests wait for events (a worker becoming idle, a result arriving), never for a time budget: the
// limit here only turns a hang into a failure that says what never happened. It is generous
// because a loaded machine is slow, not wrong.
#pragma once

#include <catch2/catch.hpp>

#include <chrono>
#include <thread>

namespace caustic::test {

inline constexpr double kHangGuardSeconds = 600.0;

// Polls `done` until it holds; fails the test naming `what` if it never does (a hang).
template <class F>
void waitUntil(const char* what, F done) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(kHangGuardSeconds);
    while (!done()) {
        if (std::chrono::steady_clock::now() > end) FAIL("hung: " << what << " never happened (hang guard " << kHangGuardSeconds << " s)");
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

}  // namespace caustic::test
