// The Cornell box (scenes/cornell-box.json at 128x128, max depth 10) against its converged image
// mean, and that converged mean against an independent estimate.
//
// tests/data/cornell-box-128-reference.json holds the converged mean: caustic itself at many
// samples per pixel (the hidden case at the end of this file regenerates it), with its standard
// error from the per-pixel sample variances.
//
// Why the CPU tracer (tests/support/reference_tracer.h) is an independent estimate of the same
// number: it solves the same integral (camera, box filter, max depth, one-sided light) with a
// different estimator and different code. It samples only the BSDF and counts emission wherever a
// path hits it; caustic adds next event estimation with light selection by power and combines
// both with the power heuristic. Light sampling pdfs, MIS weights, the shadow-ray test, the ray
// offsets and the light-selection CDF therefore do not enter the CPU estimate at all, so an error
// in any of them moves caustic's mean but not the CPU's. The CPU tracer also has its own
// intersection routines, random numbers and hemisphere sampling, and runs in double precision, so
// float round-off or a shared sampling bug cannot cancel out. What the two share is the scene
// compilation (renderer/gpu_scene.cpp) and the definitions of the image (makeFrame's camera,
// depth semantics, emitter sidedness), which are what the comparison takes as given.
//
// What the tests prove:
//   1. "agrees with its converged mean": a quick caustic render (64 spp) has the converged mean
//      within 4 combined standard errors, per channel, with a combined error below 1% of the
//      mean: the integrator as it is today still converges to the stored value (a regression in
//      transport, sampling or the light set-up moves it by many standard errors).
//   2. "agrees with an independent CPU path tracer": the stored converged value is right, i.e.
//      unbiased up to ~4 standard errors of a sub-percent estimate, as judged by an estimator
//      that shares none of caustic's variance-reduction machinery (4M paths, about 0.4%
//      standard error). Without 2, test 1 could only show that caustic agrees with an earlier
//      caustic. It has already earned its place: the first converged mean, made before the
//      shadow-ray fix of commit a8f6f40, was 7% low in red, 13 CPU standard errors away.
//   3. "reproduces closed forms": the CPU tracer itself is right where the answer is known (a
//      closed emitting sphere, L = Le / (1 - a); the directly visible one-sided light), so that a
//      disagreement in 2 points at caustic rather than at the tracer.
// The three take about 3 + 2.5 + 0.2 s on 2 cores (llvmpipe for the first).
#include "renderer/scene_io.h"
#include "tests/gpu/gl_fixture.h"
#include "tests/support/reference_tracer.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

using namespace caustic;

namespace {

constexpr const char* kReferenceFile = CAUSTIC_SOURCE_DIR "/tests/data/cornell-box-128-reference.json";

Scene cornell128(std::uint32_t seed) {
    SceneLoadResult loaded = loadScene(CAUSTIC_SOURCE_DIR "/scenes/cornell-box.json");
    INFO(loaded.error);
    REQUIRE(loaded);
    Scene s = *loaded.scene;
    s.render.width = s.render.height = 128;
    s.render.seed = seed;
    return s;
}

struct Reference {
    glm::dvec3 mean{0.0}, standardError{0.0};
    int width = 0, height = 0, maxDepth = 0;
};

Reference loadReference() {
    std::ifstream in(kReferenceFile);
    INFO(kReferenceFile);
    REQUIRE(in.good());
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    REQUIRE(!j.is_discarded());
    Reference r;
    for (int c = 0; c < 3; ++c) {
        r.mean[c] = j.at("mean").at(c).get<double>();
        r.standardError[c] = j.at("standard_error").at(c).get<double>();
    }
    r.width = j.at("width").get<int>();
    r.height = j.at("height").get<int>();
    r.maxDepth = j.at("max_depth").get<int>();
    return r;
}

// |a - b| <= k sqrt(se_a^2 + se_b^2) per channel, and the combined error below maxRelative of the
// mean, so that the comparison can fail.
void checkAgree(const char* what, glm::dvec3 mean, glm::dvec3 se, const Reference& ref, double k, double maxRelative) {
    for (int c = 0; c < 3; ++c) {
        const double combined = std::sqrt(se[c] * se[c] + ref.standardError[c] * ref.standardError[c]);
        INFO(what << " channel " << c << ": mean " << mean[c] << " +- " << se[c] << ", reference " << ref.mean[c]
                  << " +- " << ref.standardError[c] << ", difference " << (mean[c] - ref.mean[c]) / combined
                  << " combined standard errors");
        CHECK(std::abs(mean[c] - ref.mean[c]) <= k * combined);
        CHECK(combined <= maxRelative * ref.mean[c]);
    }
}

}  // namespace

TEST_CASE("the Cornell box at 128x128 agrees with its converged mean", "[gpu][cornell]") {
    const Reference ref = loadReference();
    auto renderer = test::makeRenderer();
    Scene s = cornell128(1);  // the reference used another seed: the two estimates are independent
    REQUIRE(ref.width == s.render.width);
    REQUIRE(ref.height == s.render.height);
    REQUIRE(ref.maxDepth == s.render.maxDepth);
    Film film = test::renderFilm(*renderer, s, 64);
    const test::ImageStats st = test::imageStats(film);
    checkAgree("caustic, 64 spp", st.mean, st.standardError, ref, 4.0, 0.01);
    CHECK(renderer->droppedSamples() == 0);
}

TEST_CASE("the converged Cornell mean agrees with an independent CPU path tracer", "[gpu][cornell][cpu]") {
    const Reference ref = loadReference();
    Scene s = cornell128(0);
    REQUIRE(ref.maxDepth == s.render.maxDepth);
    CompiledScene compiled;
    std::string error;
    REQUIRE(compileScene(s, &compiled, &error));
    test::reference::TracerSettings settings;
    settings.paths = 4'000'000;  // about 0.4% standard error, 2-3 s on 2 cores
    settings.seed = 12345;
    const test::reference::MeanEstimate cpu = test::reference::estimateImageMean(s, compiled, settings);
    INFO(cpu.error);
    REQUIRE(cpu.error.empty());
    INFO("CPU tracer: " << cpu.paths << " paths in " << cpu.seconds << " s");
    checkAgree("CPU BSDF-only tracer", cpu.mean, cpu.standardError, ref, 4.0, 0.01);
}

TEST_CASE("the CPU reference tracer reproduces closed forms", "[gpu][cornell][cpu]") {
    // Its own checks, so that a disagreement with caustic points at caustic: the emitting closed
    // sphere exercises spheres, emission from the inside, depth and Russian roulette; the Cornell
    // box at max depth 0 exercises the camera, the quads and the one-sided light, whose image mean
    // is Le times the light's projected area over the image's (exact for a box filter).
    test::reference::TracerSettings settings;
    settings.seed = 777;
    SECTION("inside a closed emitting sphere L = Le / (1 - a)") {
        const glm::vec3 albedo(0.5f, 0.25f, 0.75f), Le(1.0f, 2.0f, 0.5f);
        Scene s = test::closedEmittingSphere(albedo, Le);
        CompiledScene compiled;
        std::string error;
        REQUIRE(compileScene(s, &compiled, &error));
        settings.paths = 100'000;
        const auto est = test::reference::estimateImageMean(s, compiled, settings);
        REQUIRE(est.error.empty());
        const glm::dvec3 expected = glm::dvec3(Le) / (1.0 - glm::dvec3(albedo));
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": " << est.mean[c] << " +- " << est.standardError[c] << " expected " << expected[c]);
            CHECK(std::abs(est.mean[c] - expected[c]) <= 4.0 * est.standardError[c] + 1e-9);
            CHECK(est.standardError[c] <= 0.01 * expected[c]);
        }
    }
    SECTION("the Cornell box at max depth 0: Le times the light's share of the image") {
        Scene s = cornell128(0);
        s.render.maxDepth = 0;
        REQUIRE(s.lights.size() == 1);
        const Light& light = s.lights[0];
        // Project the light's corners with the pinhole of makeFrame (square image: tan(fov/2) on
        // both axes), then the shoelace formula; the image spans [-1, 1]^2 in these coordinates.
        const glm::dmat4 m(light.transform.toMatrix());
        const glm::dvec3 eye(s.camera.position);
        const glm::dvec3 forward = glm::normalize(glm::dvec3(s.camera.lookAt) - eye);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(s.camera.up)));
        const glm::dvec3 up = glm::cross(right, forward);
        const double tanHalf = std::tan(double(s.camera.fovDegrees) * 3.14159265358979323846 / 360.0);
        const glm::dvec2 canonical[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        glm::dvec2 projected[4];
        for (int i = 0; i < 4; ++i) {
            const glm::dvec3 v = glm::dvec3(m * glm::dvec4(canonical[i], 0.0, 1.0)) - eye;
            projected[i] = glm::dvec2(glm::dot(v, right), glm::dot(v, up)) / (glm::dot(v, forward) * tanHalf);
            REQUIRE(std::abs(projected[i].x) < 1.0);
            REQUIRE(std::abs(projected[i].y) < 1.0);
        }
        double area = 0.0;
        for (int i = 0; i < 4; ++i) {
            const glm::dvec2 a = projected[i], b = projected[(i + 1) % 4];
            area += 0.5 * (a.x * b.y - a.y * b.x);
        }
        const glm::dvec3 expected = glm::dvec3(light.color) * std::abs(area) / 4.0;
        CompiledScene compiled;
        std::string error;
        REQUIRE(compileScene(s, &compiled, &error));
        settings.paths = 1'000'000;
        const auto est = test::reference::estimateImageMean(s, compiled, settings);
        REQUIRE(est.error.empty());
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": " << est.mean[c] << " +- " << est.standardError[c] << " expected " << expected[c]);
            CHECK(std::abs(est.mean[c] - expected[c]) <= 4.0 * est.standardError[c]);
            CHECK(est.standardError[c] <= 0.02 * expected[c]);
        }
        // Seen from behind, the one-sided light is black; made two-sided, it is not.
        Scene behind = s;
        behind.camera.position = glm::vec3(0.0f, 3.0f, 0.0f);
        behind.camera.lookAt = glm::vec3(0.0f, 0.0f, 0.0f);
        behind.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
        behind.objects.clear();
        REQUIRE(compileScene(behind, &compiled, &error));
        settings.paths = 10'000;
        CHECK(test::reference::estimateImageMean(behind, compiled, settings).mean.x == 0.0);
        behind.lights[0].twoSided = true;
        REQUIRE(compileScene(behind, &compiled, &error));
        CHECK(test::reference::estimateImageMean(behind, compiled, settings).mean.x > 0.0);
    }
}

// Regenerates tests/data/cornell-box-128-reference.json's numbers (run by hand; minutes on
// llvmpipe): build/tests/caustic_gpu_tests "[cornell-regenerate]", CAUSTIC_REFERENCE_SPP to
// change the 4096 samples per pixel.
TEST_CASE("regenerate the converged Cornell box mean (hidden; prints tests/data JSON)", "[.][cornell-regenerate]") {
    const char* sppText = std::getenv("CAUSTIC_REFERENCE_SPP");
    const int spp = sppText ? std::atoi(sppText) : 4096;
    auto renderer = test::makeRenderer();
    Scene s = cornell128(20240601u);
    const auto t0 = std::chrono::steady_clock::now();
    Film film = test::renderFilm(*renderer, s, spp);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const test::ImageStats st = test::imageStats(film);
    std::printf("spp %d seed %u max_depth %d seconds %.1f dropped %llu\n", spp, s.render.seed, s.render.maxDepth,
                seconds, static_cast<unsigned long long>(renderer->droppedSamples()));
    std::printf("\"mean\": [%.9g, %.9g, %.9g],\n\"standard_error\": [%.9g, %.9g, %.9g],\n", st.mean.x, st.mean.y,
                st.mean.z, st.standardError.x, st.standardError.y, st.standardError.z);
    CHECK(renderer->droppedSamples() == 0);
}
