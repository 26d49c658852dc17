// The surface material's transmission and subsurface (shaders/integrator/surface_parts.glsl), by
// whole renders against what they must equal:
//   - transmission_weight 1 is the dielectric with the same interface and interior;
//   - a partial weight w is exactly the mix w I(1) + (1 - w) I(0) of the two renders (one convex
//     object under a sky: each path meets it once from outside, so the image is linear in the
//     surface's BSDF), with a coat, a sheen and some metalness on, which the part choice rescales;
//   - the subsurface's random walk is the dielectric with the same (dense) interior walked by the
//     ordinary medium code, and is outside the depth budget (max_depth 3 resolves it whole);
//   - a thick index-matched slab shows subsurface_color within the accuracy of van de Hulst's
//     relation the colour is mapped by;
//   - thin-walled: a smooth clear sheet and a white diffuse transmitter lose nothing (a furnace).
// The models' chi-square tests are in test_bsdf.cpp.
#include "renderer/gpu_materials.h"
#include "renderer/scene_schema.h"
#include "tests/gpu/gl_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

using namespace caustic;

namespace {

// A camera on +z at distance 5 looking at the origin under a sky of two coloured emitters and a
// dim constant environment (as test_media.cpp's refraction stage), with a unit sphere of
// material m at the origin, or (sheet) a unit square turned 30 degrees about y.
Scene stage(const Material& m, int size, int maxDepth, bool sheet = false) {
    Scene s;
    s.render.width = s.render.height = size;
    s.render.maxDepth = maxDepth;
    s.render.seed = 11;
    s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    for (int side = 0; side < 2; ++side) {
        Object e;
        e.name = side == 0 ? "left" : "right";
        e.shape = Shape::Quad;
        e.material = "black";
        e.emission = side == 0 ? glm::vec3(2.0f, 0.4f, 0.1f) : glm::vec3(0.1f, 0.5f, 2.0f);
        e.transform.translate = glm::vec3(side == 0 ? -1.5f : 1.5f, 0.3f, -3.0f);
        e.transform.scale = glm::vec3(1.5f, 3.0f, 1.0f);
        s.objects.push_back(e);
    }
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(0.3f);
    s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = 28.0f;
    s.materials.push_back(m);
    if (sheet) {
        Object q;
        q.name = "sheet";
        q.shape = Shape::Quad;
        q.material = m.name;
        q.transform.rotate = glm::vec3(0.0f, 30.0f, 0.0f);
        s.objects.push_back(q);
    } else {
        s.objects.push_back(test::sphereAt(m.name, glm::vec3(0.0f), 1.0f));
    }
    return s;
}

Material surfaceMaterial(const std::string& name) {
    Material m = materialDefaults(MaterialType::Surface);
    m.name = name;
    return m;
}

// The number of pixel channels where a and b differ by more than 6 combined standard errors.
int pixelChannelsApart(const Film& a, const Film& b) {
    int n = 0;
    for (size_t i = 0; i < a.mean.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (std::abs(a.mean[i][c] - b.mean[i][c]) > 6.0 * std::sqrt(a.varianceOfMean[i][c] + b.varianceOfMean[i][c])) ++n;
    return n;
}

}  // namespace

TEST_CASE("surface parts: transmission weight 1 is the dielectric with the same interior", "[gpu][parts]") {
    auto renderer = test::makeRenderer();
    struct Case { const char* name; float roughness; glm::vec3 colour; float depth; glm::vec3 scatter; };
    for (const Case& k : {Case{"smooth, absorbing", 0.0f, {0.9f, 0.5f, 0.2f}, 1.0f, glm::vec3(0.0f)},
                          Case{"rough, scattering", 0.3f, {0.5f, 0.7f, 0.9f}, 0.8f, {0.6f, 0.4f, 0.3f}}}) {
        INFO(k.name);
        Material s = surfaceMaterial("m");
        s.specularRoughness = k.roughness;
        s.specularIor = 1.45f;
        s.transmissionWeight = 1.0f;
        s.transmissionColor = k.colour;
        s.transmissionDepth = k.depth;
        s.transmissionScatter = k.scatter;
        s.scatterAnisotropy = 0.3f;
        Material d = s;
        d.type = MaterialType::Dielectric;
        d.roughness = k.roughness * k.roughness;  // the surface's roughness is perceptual
        d.ior = 1.45f;
        const Film a = test::renderFilm(*renderer, stage(s, 32, 64), 256);
        const Film b = test::renderFilm(*renderer, stage(d, 32, 64), 256);
        test::checkSameMean(a, b);
        test::checkBlocksAgree(a, b, "surface transmission vs dielectric");
        // Power: the clear dielectric is another image.
        Material clear = d;
        clear.transmissionDepth = 0.0f;
        clear.transmissionColor = glm::vec3(1.0f);
        clear.transmissionScatter = glm::vec3(0.0f);
        const Film c = test::renderFilm(*renderer, stage(clear, 32, 64), 256);
        CHECK(pixelChannelsApart(a, c) > int(a.mean.size()) / 10);
    }
}

TEST_CASE("surface parts: a partial weight is the mix of the whole part and the rest", "[gpu][parts]") {
    // f is linear in the part's share w: f(w) = w f(1) + (1 - w) f(0) for every (wo, wi), coat,
    // sheen and metal included; with one convex object each path meets the surface once from
    // outside (a thin-walled one: a single sheet, met once), so the images mix the same way.
    auto renderer = test::makeRenderer();
    Material m = surfaceMaterial("m");
    m.albedo = glm::vec3(0.7f, 0.3f, 0.2f);
    m.metalness = 0.3f;
    m.specularRoughness = 0.4f;
    m.coatWeight = 0.7f;
    m.coatColor = glm::vec3(0.9f, 0.8f, 0.6f);
    m.coatRoughness = 0.2f;
    m.sheenWeight = 0.5f;
    m.sheenColor = glm::vec3(0.6f, 0.7f, 1.0f);
    m.transmissionColor = glm::vec3(0.4f, 0.8f, 0.5f);
    m.transmissionDepth = 1.0f;
    m.subsurfaceColor = glm::vec3(0.2f, 0.8f, 0.9f);
    m.subsurfaceRadius = 0.3f;
    struct Case { const char* name; float transmission, subsurface; bool thin; };
    for (const Case& k : {Case{"transmission 0.4", 0.4f, 0.0f, false}, Case{"subsurface 0.6", 0.0f, 0.6f, false},
                          Case{"transmission 0.3 + subsurface 0.5", 0.3f, 0.5f, false},
                          Case{"thin-walled transmission 0.5 + subsurface 0.5", 0.5f, 0.5f, true}}) {
        INFO(k.name);
        Material part = m, rest = m, mixed = m;
        part.thinWalled = rest.thinWalled = mixed.thinWalled = k.thin;
        mixed.transmissionWeight = k.transmission;
        mixed.subsurfaceWeight = k.subsurface;
        // The whole part: the same shares among the parts, all of the base.
        const float w = k.transmission + (1.0f - k.transmission) * k.subsurface;
        part.transmissionWeight = k.transmission / w;
        part.subsurfaceWeight = part.transmissionWeight < 1.0f ? 1.0f : 0.0f;
        const Film fMixed = test::renderFilm(*renderer, stage(mixed, 32, 64, k.thin), 512);
        const Film fPart = test::renderFilm(*renderer, stage(part, 32, 64, k.thin), 512);
        const Film fRest = test::renderFilm(*renderer, stage(rest, 32, 64, k.thin), 512);
        // The metal is outside the dielectric base: the weight of the parts in f is (1 - M) w, the
        // rest of the dielectric base's share goes to the rest.
        Film expected = fMixed;
        for (size_t i = 0; i < expected.mean.size(); ++i) {
            expected.mean[i] = w * fPart.mean[i] + (1.0f - w) * fRest.mean[i];
            expected.varianceOfMean[i] = w * w * fPart.varianceOfMean[i] + (1.0f - w) * (1.0f - w) * fRest.varianceOfMean[i];
        }
        test::checkSameMean(fMixed, expected);
        test::checkBlocksAgree(fMixed, expected, "mixed vs the mix of the renders");
        CHECK(pixelChannelsApart(fPart, fRest) > int(fPart.mean.size()) / 10);
    }
}

TEST_CASE("surface parts: the subsurface walk is the dense interior, outside the depth budget", "[gpu][parts]") {
    // The same medium as a dielectric's interior (transmission_scatter and colour chosen to give
    // the walk's sigma_s and sigma_t), rendered with depth to spare, against the walk at max_depth 3
    // (camera ray, entry, exit: a walk of any length counts as none of them).
    auto renderer = test::makeRenderer();
    Material s = surfaceMaterial("m");
    s.specularRoughness = 0.0f;
    s.specularIor = 1.4f;
    s.subsurfaceWeight = 1.0f;
    s.subsurfaceColor = glm::vec3(0.8f, 0.5f, 0.25f);
    s.subsurfaceRadius = 0.25f;
    s.subsurfaceRadiusScale = glm::vec3(1.0f, 0.6f, 0.3f);
    s.subsurfaceAnisotropy = 0.2f;
    Material d;
    d.name = "m";
    d.type = MaterialType::Dielectric;
    d.ior = 1.4f;
    d.transmissionDepth = 1.0f;
    glm::vec3 sigmaT = 1.0f / (s.subsurfaceRadius * s.subsurfaceRadiusScale), albedo;
    for (int c = 0; c < 3; ++c) albedo[c] = subsurfaceSingleScatteringAlbedo(s.subsurfaceColor[c], s.subsurfaceAnisotropy);
    d.transmissionColor = glm::exp(-sigmaT);  // at depth 1: sigma_t
    d.transmissionScatter = albedo * sigmaT;  // at depth 1: sigma_s
    d.scatterAnisotropy = s.subsurfaceAnisotropy;
    const Film walk = test::renderFilm(*renderer, stage(s, 16, 3), 512);
    const Film medium = test::renderFilm(*renderer, stage(d, 16, 2000), 512);
    test::checkSameMean(walk, medium);
    test::checkBlocksAgree(walk, medium, "subsurface walk vs dielectric interior");
    // Power: the ordinary medium truncated at the same depth is darker.
    const Film truncated = test::renderFilm(*renderer, stage(d, 16, 3), 512);
    CHECK(pixelChannelsApart(walk, truncated) > int(walk.mean.size()) / 10);
}

TEST_CASE("surface parts: a thick index-matched slab shows subsurface_color", "[gpu][parts]") {
    // A slab 40 mean free paths thick and 400 wide under a uniform white sky: a pixel seen at
    // cos theta = mu is the slab's directional albedo R(mu), and its albedo under diffuse light is
    // 2 int R(mu) mu dmu (Gauss-Legendre, 6 views). The colour maps to the interior by van de
    // Hulst's relation, which is this albedo up to its own accuracy: docs/materials.md
    // ("Subsurface") gives the measured table; the bound is 0.02.
    auto renderer = test::makeRenderer();
    Material m = surfaceMaterial("m");
    m.specularIor = 1.0f;  // index-matched: the relation's boundary
    m.specularRoughness = 0.0f;
    m.subsurfaceWeight = 1.0f;
    m.subsurfaceRadius = 0.01f;
    m.subsurfaceRadiusScale = glm::vec3(1.0f);
    m.subsurfaceColor = glm::vec3(0.2f, 0.5f, 0.8f);
    // Gauss-Legendre on [0, 1], 6 nodes.
    const double nodes[6] = {0.033765242898424, 0.169395306766868, 0.380690406958402,
                             0.619309593041598, 0.830604693233132, 0.966234757101576};
    const double weights[6] = {0.085662246189585, 0.180380786524069, 0.233956967286346,
                               0.233956967286346, 0.180380786524069, 0.085662246189585};
    for (const float g : {0.0f, 0.5f}) {
        m.subsurfaceAnisotropy = g;
        glm::dvec3 albedo(0.0), variance(0.0);
        for (int k = 0; k < 6; ++k) {
            const double mu = nodes[k], sinTheta = std::sqrt(1.0 - mu * mu);
            Scene s;
            s.render.width = s.render.height = 8;
            s.render.maxDepth = 8;
            s.render.seed = 3 + k;
            s.materials.push_back(m);
            Object slab;
            slab.name = "slab";
            slab.shape = Shape::Box;
            slab.material = "m";
            slab.transform.scale = glm::vec3(2.0f, 0.2f, 2.0f);
            slab.transform.translate = glm::vec3(0.0f, -0.2f, 0.0f);  // the top face at y = 0
            s.objects.push_back(slab);
            s.environment.type = EnvironmentType::Constant;
            s.environment.radiance = glm::vec3(1.0f);
            s.camera.position = glm::vec3(float(3.0 * sinTheta), float(3.0 * mu), 0.0f);
            s.camera.lookAt = glm::vec3(0.0f);
            s.camera.up = glm::vec3(0.0f, 0.0f, -1.0f);
            s.camera.fovDegrees = 0.5f;
            const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 512));
            albedo += 2.0 * weights[k] * mu * st.mean;
            variance += glm::pow(2.0 * weights[k] * mu * st.standardError, glm::dvec3(2.0));
            std::printf("subsurface slab g %.1f mu %.3f: R = %.4f %.4f %.4f\n", g, mu, st.mean.x, st.mean.y, st.mean.z);
        }
        for (int c = 0; c < 3; ++c) {
            const double se = std::sqrt(variance[c]);
            std::printf("subsurface slab g %.1f: colour %.2f -> albedo %.4f +- %.4f\n", g, m.subsurfaceColor[c], albedo[c], se);
            INFO("g " << g << " channel " << c << ": colour " << m.subsurfaceColor[c] << " albedo " << albedo[c] << " se " << se);
            CHECK(std::abs(albedo[c] - m.subsurfaceColor[c]) < 0.02);
            CHECK(se < 0.004);
        }
    }
}

TEST_CASE("surface parts: thin-walled sheets lose nothing where nothing absorbs (furnace)", "[gpu][parts][furnace]") {
    // A smooth clear sheet reflects 2F / (1 + F) and transmits the rest; a white diffuse
    // transmitter reflects and transmits all it receives: under radiance 1 everywhere, a closed
    // sphere of either (thin-walled: the light passes in and out, never refracted) returns 1. Under
    // a specular layer the transmitter returns w E(wo) + (1 - w E(wo)) = 1 up to the accuracy of
    // the tabulated E (the surface's furnace: within 0.005), seen once, on a flat sheet.
    auto renderer = test::makeRenderer();
    Material bubble = surfaceMaterial("m");
    bubble.specularRoughness = 0.0f;
    bubble.specularIor = 1.6f;
    bubble.transmissionWeight = 1.0f;
    bubble.thinWalled = true;
    Material translucent = surfaceMaterial("m");
    translucent.subsurfaceWeight = 1.0f;
    translucent.subsurfaceColor = glm::vec3(1.0f);
    translucent.specularWeight = 0.0f;
    translucent.subsurfaceAnisotropy = 0.4f;
    translucent.thinWalled = true;
    Material glossy = translucent;
    glossy.specularWeight = 1.0f;
    glossy.specularRoughness = 0.4f;
    struct Case { const char* name; Material m; bool sheet; double tolerance; };
    for (const Case& k : {Case{"bubble", bubble, false, 1e-4}, Case{"translucent", translucent, false, 1e-4},
                          Case{"translucent under a specular layer", glossy, true, 0.005}}) {
        Scene s;
        s.render.width = s.render.height = 16;
        s.render.maxDepth = 256;
        s.render.seed = 5;
        s.materials.push_back(k.m);
        if (k.sheet) {
            Object q;
            q.name = "sheet";
            q.shape = Shape::Quad;
            q.material = "m";
            q.transform.rotate = glm::vec3(0.0f, 40.0f, 0.0f);
            q.transform.scale = glm::vec3(3.0f);  // fills the view
            s.objects.push_back(q);
        } else {
            s.objects.push_back(test::sphereAt("m", glm::vec3(0.0f), 1.0f));
        }
        s.environment.type = EnvironmentType::Constant;
        s.environment.radiance = glm::vec3(1.0f);
        s.camera.position = glm::vec3(0.0f, 0.0f, 5.0f);
        s.camera.lookAt = glm::vec3(0.0f);
        s.camera.fovDegrees = 30.0f;
        s.render.russianRoulette = RussianRoulette::Mitsuba;
        const test::ImageStats st = test::imageStats(test::renderFilm(*renderer, s, 256));
        for (int c = 0; c < 3; ++c) {
            INFO(k.name << " channel " << c << ": mean " << st.mean[c] << " se " << st.standardError[c]);
            CHECK(std::abs(st.mean[c] - 1.0) <= 4.0 * st.standardError[c] + k.tolerance);
        }
    }
}
