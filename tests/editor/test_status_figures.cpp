// The status bar's figures and pacing: the sample rate and ETA, when a shown error clears, and
// when idle pacing starts (editor/model/status.h, render_session.h).
#include "editor/model/render_session.h"
#include "editor/model/status.h"

#include <catch2/catch.hpp>

#include <string>

using namespace caustic;
using namespace caustic::editor;

TEST_CASE("The sample rate is per second of elapsed time since the restart", "[editor][status]") {
    SampleRateMeter m;
    m.restart(10.0);
    CHECK_FALSE(m.known());
    // Each frame renders 0.01 s of samples in a 0.25 s frame: the wall-clock rate is what counts.
    m.observe(10.25, 0.04, true);
    m.observe(14.0, 0.64, true);
    CHECK(m.samplesPerSecond() == Approx(0.16));
    // Target reached: frames without rendering do not dilute it.
    m.observe(30.0, 0.64, false);
    CHECK(m.samplesPerSecond() == Approx(0.16));
    m.restart(30.0);
    CHECK_FALSE(m.known());
    CHECK(m.samplesPerSecond() == 0.0);
}

TEST_CASE("The ETA is the samples left at the wall-clock rate, durations read as s, min, h", "[editor][status]") {
    SampleRateMeter m;
    m.restart(0.0);
    CHECK(m.etaSeconds(0.0, 16.0) < 0.0);  // no rate yet: unknown
    m.observe(10.0, 4.0, true);             // 0.4 spp/s
    CHECK(m.etaSeconds(4.0, 16.0) == Approx(30.0));
    CHECK(m.etaSeconds(16.0, 16.0) == 0.0);
    CHECK(durationText(-1.0) == "-");
    CHECK(durationText(42.4) == "42 s");
    CHECK(durationText(185.0) == "3 min 05 s");
    CHECK(durationText(7800.0) == "2 h 10 min");
}

TEST_CASE("A shown error clears once its cause is gone", "[editor][status]") {
    const ShownError render{true, 7};
    CHECK(errorResolved(render, true, 7));          // the scene compiles again
    CHECK_FALSE(errorResolved(render, false, 8));   // still failing
    const ShownError refused{false, 7};
    CHECK_FALSE(errorResolved(refused, true, 7));   // nothing edited yet: a preview recompile is no fix
    CHECK(errorResolved(refused, true, 8));         // the next edit went through
}

TEST_CASE("Idle pacing starts a second after the last input, never while dragging or in scripts", "[editor][status]") {
    RenderSession session;
    session.noteInput(10.0);
    CHECK_FALSE(session.idle(10.5));
    CHECK(session.idle(10.0 + kIdleAfter + 0.01));
    session.interacting = true;
    CHECK_FALSE(session.idle(20.0));
    session.interacting = false;
    session.idlePacing = false;  // a script drives the frames
    CHECK_FALSE(session.idle(20.0));
    session.idlePacing = true;
    session.noteInput(19.9);
    CHECK_FALSE(session.idle(20.0));
}
