// Absorption inside dielectrics (OpenPBR's transmission_color / transmission_depth: an interior
// medium that only absorbs, whose segments' transmittance exp(-sigma_a t) goes into the path's
// throughput; shaders/integrator/medium.glsl). Against closed forms: an index-matched slab and sphere, where
// every path is deterministic, and a glass slab with its Fresnel multiple reflections.
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

const glm::vec3 kColour(0.8f, 0.4f, 0.1f);  // transmission_color: sigma_a = -ln(c) / depth
constexpr float kDepth = 0.5f;              // transmission_depth

Material absorbingGlass(float ior, float roughness, bool absorbs) {
    Material m;
    m.name = "glass";
    m.type = MaterialType::Dielectric;
    m.ior = ior;
    m.roughness = roughness;
    if (absorbs) {
        m.transmissionColor = kColour;
        m.transmissionDepth = kDepth;
    }
    return m;
}

// A camera with a 1 degree field of view on the z axis looking at `glass` (a slab: the box scaled
// to thickness 2 halfThickness across the view, or a unit sphere) in front of a uniform emitting
// quad (radiance 1, both faces), with no environment: every ray through the glass sees the
// emitter's radiance times the glass's transmittance; reflections towards the camera see black.
Scene throughGlass(const Material& glass, Shape shape, float halfThickness) {
    Scene s;
    s.render.width = 16;
    s.render.height = 16;
    s.render.maxDepth = 64;  // internal reflections: a truncation of R^64, nothing
    s.render.seed = 11;
    s.materials.push_back(glass);
    s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    Object g;
    g.name = "glass";
    g.shape = shape;
    g.material = "glass";
    if (shape == Shape::Box) g.transform.scale = glm::vec3(4.0f, 4.0f, halfThickness);
    s.objects.push_back(g);
    Object emitter;
    emitter.name = "emitter";
    emitter.shape = Shape::Quad;
    emitter.material = "black";
    emitter.emission = glm::vec3(1.0f);
    emitter.transform.translate = glm::vec3(0.0f, 0.0f, -3.0f);
    emitter.transform.scale = glm::vec3(20.0f);
    s.objects.push_back(emitter);
    s.environment.type = EnvironmentType::None;
    s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 1.0f;
    return s;
}

glm::dvec3 sigmaA() { return -glm::log(glm::dvec3(kColour)) / double(kDepth); }

std::string defineOf(const ShaderDefines& defines, const std::string& name) {
    for (const auto& [k, v] : defines)
        if (k == name) return v;
    return "(absent)";
}

}  // namespace

TEST_CASE("absorption: an index-matched slab transmits exp(-sigma_a d) exactly, per channel", "[gpu][absorption]") {
    // ior 1: no Fresnel, no bending; each camera ray crosses the slab once, so every sample is
    // exp(-sigma_a d / cos) with cos > cos(0.71 deg) (the corner of a 1 degree view): no noise.
    // The tolerance, 1e-3 relative, is for that obliquity (-7.7e-5 sigma_a d) and for the ray
    // origins' offsets off each face (geometry/intersect.glsl, offsetRayOrigin: relative to the
    // scene's scale), which shorten the segment inside by about 1e-4 of d here (measured: +3.1e-4
    // relative in blue, sigma_a d = 2.3). A missing or doubled factor is off by tens of percent.
    auto renderer = test::makeRenderer();
    for (float halfThickness : {0.25f, 0.5f}) {  // d = transmission_depth (the colour), 2 depths (its square)
        const double d = 2.0 * halfThickness;
        const glm::dvec3 expected = glm::exp(-sigmaA() * d);
        Film film = test::renderFilm(*renderer, throughGlass(absorbingGlass(1.0f, 0.0f, true), Shape::Box, halfThickness), 4);
        CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "1u");  // MEDIA_ABSORBING
        INFO("d " << d << " expected " << expected.x << " " << expected.y << " " << expected.z);
        for (const glm::vec3& p : film.mean)
            for (int c = 0; c < 3; ++c) {
                INFO("channel " << c << " pixel " << p[c]);
                REQUIRE(std::abs(p[c] - expected[c]) <= 1e-3 * expected[c]);
            }
    }
    // The same slab without absorption: 1, and the feature compiled out.
    Film clear = test::renderFilm(*renderer, throughGlass(absorbingGlass(1.0f, 0.0f, false), Shape::Box, 0.25f), 4);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_MEDIA") == "0u");
    for (const glm::vec3& p : clear.mean) REQUIRE(std::abs(p.g - 1.0f) < 1e-5f);
}

TEST_CASE("absorption: an index-matched sphere transmits exp(-sigma_a chord)", "[gpu][absorption]") {
    // A unit sphere seen from 5 away in a 1 degree view: the chords through it lie between
    // 2 sqrt(1 - b^2) and 2, b <= 5 tan(0.5 deg) sqrt(2) < 0.062.
    auto renderer = test::makeRenderer();
    Film film = test::renderFilm(*renderer, throughGlass(absorbingGlass(1.0f, 0.0f, true), Shape::Sphere, 1.0f), 4);
    const double bMax = 0.062;
    const glm::dvec3 lo = glm::exp(-sigmaA() * 2.0), hi = glm::exp(-sigmaA() * 2.0 * std::sqrt(1.0 - bMax * bMax));
    for (const glm::vec3& p : film.mean)
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << " pixel " << p[c] << " expected in [" << lo[c] << ", " << hi[c] << "]");
            REQUIRE(p[c] >= lo[c] * (1.0 - 1e-3));  // the ray offsets, as for the slab
            REQUIRE(p[c] <= hi[c] * (1.0 + 1e-3));
        }
}

TEST_CASE("absorption: a glass slab (ior 1.5) matches the closed form with Fresnel multiple reflections",
          "[gpu][absorption][glass]") {
    // At normal incidence each face reflects R = ((n - 1) / (n + 1))^2; with tau = exp(-sigma_a d)
    // per crossing, the light that leaves the back after any number of internal reflections is
    //   T = (1 - R)^2 tau / (1 - R^2 tau^2)
    // (the geometric series of Born and Wolf's plane-parallel plate, intensities added: the slab
    // is thicker than the coherence length). Every path that gets out sees either the emitter
    // (behind) or black (in front), so the image is T. Checked with and without glass splitting
    // and by BSDF sampling alone, which each must weigh the absorbed segments alike.
    auto renderer = test::makeRenderer();
    const double n = 1.5, R = (n - 1.0) * (n - 1.0) / ((n + 1.0) * (n + 1.0));
    const glm::dvec3 tau = glm::exp(-sigmaA() * 0.5);
    const glm::dvec3 expected = (1.0 - R) * (1.0 - R) * tau / (1.0 - R * R * tau * tau);
    for (bool split : {true, false})
        for (std::uint32_t strategy : {STRATEGY_MIS, STRATEGY_BSDF_ONLY}) {
            INFO("glass split " << split << " strategy " << strategy);
            renderer->setStrategy(strategy);
            Scene s = throughGlass(absorbingGlass(1.5f, 0.0f, true), Shape::Box, 0.25f);
            s.render.glassSplit = split;
            test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 64));
            for (int c = 0; c < 3; ++c) {
                INFO("channel " << c << ": mean " << st.mean[c] << " expected " << expected[c] << " standard error "
                                << st.standardError[c]);
                CHECK(std::abs(st.mean[c] - expected[c]) <= 4.0 * st.standardError[c] + 1e-5 * expected[c]);
                CHECK(st.standardError[c] <= 0.01 * expected[c]);
            }
        }
    renderer->setStrategy(STRATEGY_MIS);
}

TEST_CASE("absorption: rough glass absorbs, in the order sigma_a says, and no more than the path allows",
          "[gpu][absorption][glass]") {
    // No closed form for a rough slab; the properties: 0 < L_absorbing < L_clear per channel,
    // the ratio ordered as the colour is (red passes most), and at most tau = exp(-sigma_a d)
    // (every path that gets through travels at least d inside, and tau is reached only at
    // normal incidence), with next event estimation at the rough vertices weighing the same factor.
    auto renderer = test::makeRenderer();
    Film clear = test::renderFilm(*renderer, throughGlass(absorbingGlass(1.5f, 0.2f, false), Shape::Box, 0.25f), 64);
    Film tinted = test::renderFilm(*renderer, throughGlass(absorbingGlass(1.5f, 0.2f, true), Shape::Box, 0.25f), 64);
    const test::ImageStats a = test::imageStats(tinted), b = test::imageStats(clear);
    const glm::dvec3 tau = glm::exp(-sigmaA() * 0.5);
    glm::dvec3 ratio;
    for (int c = 0; c < 3; ++c) {
        ratio[c] = a.mean[c] / b.mean[c];
        INFO("channel " << c << ": absorbing " << a.mean[c] << " +- " << a.standardError[c] << ", clear " << b.mean[c]
                        << " +- " << b.standardError[c] << ", tau " << tau[c]);
        CHECK(a.mean[c] > 0.0);
        CHECK(a.mean[c] < b.mean[c] - 4.0 * (a.standardError[c] + b.standardError[c]));
        CHECK(ratio[c] <= tau[c] * 1.02);
        CHECK(ratio[c] > 0.5 * tau[c]);  // not absorbed far beyond what the slab's thickness says
    }
    CHECK(ratio.x > ratio.y);
    CHECK(ratio.y > ratio.z);
}
