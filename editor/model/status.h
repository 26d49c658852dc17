// What the status bar reports, decided without ImGui so it can be unit-tested (tests/editor/):
// the wall-clock sample rate, and when a shown error is stale.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace caustic::editor {

// Samples accumulated per second of elapsed (wall-clock) time since accumulation restarted. The
// render-time rate (samples per second of path-tracer time) flatters an editor whose UI, display
// and swap take most of each frame: it read 4.0 spp/s while the image gained 0.27 a second. The
// clock stops when rendering does (target reached, paused by Denoise now), so a finished render
// keeps the rate it had, instead of decaying while it sits there.
class SampleRateMeter {
public:
    void restart(double now) {
        m_start = m_end = now;
        m_samples = 0.0;
    }
    // `samples`: accumulated since the restart (a partly rendered sample counts its fraction);
    // `rendered`: this frame added some.
    void observe(double now, double samples, bool rendered) {
        if (!rendered) return;
        m_end = now;
        m_samples = samples;
    }
    bool known() const { return m_end > m_start && m_samples > 0.0; }
    double samplesPerSecond() const { return known() ? m_samples / (m_end - m_start) : 0.0; }
    double elapsedSeconds() const { return m_end - m_start; }
    // Seconds until `target` samples at the wall-clock rate so far, from `done`; negative when
    // unknown (no rate yet) and 0 once there.
    double etaSeconds(double done, double target) const {
        if (done >= target) return 0.0;
        return known() ? (target - done) / samplesPerSecond() : -1.0;
    }

private:
    double m_start = 0.0, m_end = 0.0, m_samples = 0.0;
};

// A duration for the status bar: "42 s", "3 min 05 s", "2 h 10 min"; "-" when negative (unknown).
inline std::string durationText(double seconds) {
    if (!(seconds >= 0.0)) return "-";
    char buffer[32];
    const long long s = static_cast<long long>(seconds + 0.5);
    if (s < 60) std::snprintf(buffer, sizeof buffer, "%lld s", s);
    else if (s < 3600) std::snprintf(buffer, sizeof buffer, "%lld min %02lld s", s / 60, s % 60);
    else std::snprintf(buffer, sizeof buffer, "%lld h %02lld min", s / 3600, (s % 3600) / 60);
    return buffer;
}

// Where the status bar's error came from, so it is cleared once its cause is gone: a scene the
// renderer could not compile, when a later compile succeeds; any other error (a refused edit, a
// failed save or import), when a later edit (the undo history moved) compiles.
struct ShownError {
    bool fromRender = false;
    std::uint64_t revision = 0;   // CommandStack::revision() when it was shown
};
inline bool errorResolved(const ShownError& e, bool compiled, std::uint64_t revisionNow) {
    return compiled && (e.fromRender || revisionNow != e.revision);
}

}  // namespace caustic::editor
