// Alpha cut-outs and emission textures through import, compile and the real integrator, with the
// files tests/gltf/make_test_gltf.py writes (tests/data/gltf/leaf.* and glow.*; the script's
// comments say what they hold):
//   - camera rays: the leaf, black, filling the view in front of a white constant environment, is
//     black exactly where its mask keeps it and white exactly where it cuts it out (stripes whose
//     edges fall on pixel edges, so every pixel is one or the other), .glb and .gltf alike, bit for
//     bit; the same mesh with an opaque material is black everywhere; the mask is compiled out of
//     the scene-specialised program of a scene without one;
//   - shadow and bounce rays: a floor lit through the leaf gets half the light the leaf would stop
//     (the mask keeps half its area), and light sampling alone, BSDF sampling alone and MIS agree
//     per image block (shadow rays and bounce rays see the same holes);
//   - emission textures: the glow quad seen directly is emissiveFactor x strength x the texel
//     (decoded from sRGB), and a floor it lights gets the same light from light sampling alone,
//     BSDF sampling alone and MIS (next event estimation sees the texture a hit sees); likewise a
//     scene material's emission_texture on a quad and a sphere (rect and sphere lights).
#include "tests/gpu/gl_fixture.h"

#include "renderer/dirty.h"
#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <cstdlib>
#include <string>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

const fs::path kData = fs::path(CAUSTIC_SOURCE_DIR) / "tests" / "data" / "gltf";
constexpr int kViewSize = 64;

// The camera on +z looking at the quad [-1, 1]^2 (z = 0), which fills the view exactly.
Scene facingScene(const fs::path& file) {
    Scene s;
    s.render.width = s.render.height = kViewSize;
    s.render.maxDepth = 0;
    s.render.filter = PixelFilter::Box;
    s.render.seed = 3;
    s.camera.position = glm::vec3(0.0f, 0.0f, 4.0f);
    s.camera.lookAt = glm::vec3(0.0f);
    s.camera.fovDegrees = float(2.0 * std::atan(0.25) * 180.0 / 3.14159265358979323846);
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(1.0f);
    Object quad;
    quad.shape = Shape::Mesh;
    quad.file = file.string();  // the file's own materials
    s.objects.push_back(quad);
    return s;
}

std::string defineOf(const ShaderDefines& defines, const std::string& name) {
    for (const auto& [k, v] : defines)
        if (k == name) return v;
    return "(absent)";
}

float srgbToLinear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }

// A grey floor lit by a rect light (lightSize across) at height 3 facing down, seen by a camera
// low enough not to see anything at height 1 above the floor's middle, where the objects under
// test go.
Scene litFloorScene(float lightSize) {
    Scene s;
    s.render.width = s.render.height = 24;
    s.render.maxDepth = 3;
    s.render.seed = 11;
    s.materials.push_back({"grey", MaterialType::Diffuse, glm::vec3(0.6f, 0.5f, 0.4f), glm::vec3(0.0f)});
    s.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    s.objects.push_back(test::floorQuad("grey", 4.0f));
    Light l;
    l.type = LightType::Rect;
    l.color = glm::vec3(2.0f / (lightSize * lightSize));
    l.transform.translate = glm::vec3(0.0f, 3.0f, 0.0f);
    l.transform.rotate = glm::vec3(90.0f, 0.0f, 0.0f);  // front (+z) down
    l.transform.scale = glm::vec3(0.5f * lightSize, 0.5f * lightSize, 1.0f);
    s.lights.push_back(l);
    s.camera.position = glm::vec3(0.0f, 0.5f, 3.5f);
    s.camera.lookAt = glm::vec3(0.0f, 0.0f, 0.0f);
    s.camera.fovDegrees = 30.0f;
    return s;
}

Object horizontalQuadMesh(const fs::path& file, float height) {
    Object o;
    o.shape = Shape::Mesh;
    o.file = file.string();
    o.transform.translate = glm::vec3(0.0f, height, 0.0f);
    o.transform.rotate = glm::vec3(-90.0f, 0.0f, 0.0f);  // the quad's +z up
    return o;
}


}  // namespace

TEST_CASE("alpha cut-outs: camera rays pass where a glTF MASK leaf's alpha is below its cutoff",
          "[gpu][gltf][alpha]") {
    auto renderer = test::makeRenderer();
    const Film glb = test::renderFilm(*renderer, facingScene(kData / "leaf.glb"), 4);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_ALPHA_MASK") == "1u");
    const Film gltf = test::renderFilm(*renderer, facingScene(kData / "leaf.gltf"), 4);
    REQUIRE(glb.mean.size() == gltf.mean.size());
    size_t different = 0;
    for (size_t i = 0; i < glb.mean.size(); ++i) different += glb.mean[i] != gltf.mean[i] ? 1 : 0;
    CHECK(different == 0);

    // glTF u = (x + 1) / 2 runs with the image's x; the mask keeps u mod 1/4 in [0, 1/8) (the
    // base colour texture's alpha, scaled by KHR_texture_transform, against cutoff 0.4 / factor
    // 0.8): columns x mod 16 < 8 of 64. A kept point is the black quad (max depth 0: no
    // reflection), a cut-out one the white environment behind.
    double worst = 0.0, sum = 0.0;
    int worstX = -1;
    for (int y = 0; y < glb.height; ++y)
        for (int x = 0; x < glb.width; ++x) {
            const float expected = x % 16 < 8 ? 0.0f : 1.0f;
            const double d = std::abs(double(glb.mean[glb.index(x, y)].g) - expected);
            sum += d;
            if (d > worst) {
                worst = d;
                worstX = x;
            }
        }
    INFO("largest difference " << worst << " (column " << worstX << "), mean " << sum / double(glb.mean.size()));
    CHECK(worst <= 0.25);  // at most one of a pixel's 4 samples on the wrong side of an edge
    CHECK(sum / double(glb.mean.size()) < 1e-3);

    // Unspecialised (as on NVIDIA by default), the program for a scene with masks has them too,
    // and gives the same image.
    IntegratorConfig unspecialisedConfig = test::testConfig();
    unspecialisedConfig.specialize = false;
    std::unique_ptr<Renderer> general = test::makeRenderer(unspecialisedConfig);
    const Film unspecialised = test::renderFilm(*general, facingScene(kData / "leaf.glb"), 4);
    double generalSum = 0.0;
    for (size_t i = 0; i < glb.mean.size(); ++i) generalSum += std::abs(double(unspecialised.mean[i].g - glb.mean[i].g));
    CHECK(generalSum / double(glb.mean.size()) < 1e-3);

    // The same mesh with an opaque material: no holes, and no mask in the specialised program.
    Scene opaque = facingScene(kData / "leaf.glb");
    opaque.materials.push_back({"black", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)});
    opaque.objects[0].material = "black";
    const Film solid = test::renderFilm(*renderer, opaque, 2);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_ALPHA_MASK") == "0u");
    for (const glm::vec3& m : solid.mean) REQUIRE(m == glm::vec3(0.0f));
}

TEST_CASE("alpha cut-outs: a scene material's alpha_mode on a mesh, switched on by a material edit",
          "[gpu][gltf][alpha]") {
    // The leaf's mesh (its UVs carry the file's texture transform) with a scene material whose
    // albedo texture is generated: the file's stripes of alpha 1 and 0, black. Opaque first; then
    // Renderer::update with the material edit alone (what the editor sends) must cut the holes.
    auto renderer = test::makeRenderer();
    renderer->setImageReader([](const std::string& path, ImageData* out, std::string* error) {
        if (fs::path(path).filename() != "stripes.png") {
            *error = path + ": no such generated image";
            return false;
        }
        out->width = out->height = 8;
        out->channels = 4;
        out->pixels.clear();
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) out->pixels.insert(out->pixels.end(), {0.0f, 0.0f, 0.0f, x % 4 < 2 ? 1.0f : 0.0f});
        return true;
    });
    Scene s = facingScene(kData / "leaf.glb");
    Material cut{"cut", MaterialType::Diffuse, glm::vec3(0.0f), glm::vec3(0.0f)};
    cut.albedoTexture = "stripes.png";
    s.materials.push_back(cut);
    s.objects[0].material = "cut";
    const Film opaque = test::renderFilm(*renderer, s, 2);
    for (const glm::vec3& m : opaque.mean) REQUIRE(m == glm::vec3(0.0f));
    s.materials[0].alphaMode = AlphaMode::Mask;
    std::string error;
    REQUIRE(renderer->update(s, kDirtyMaterials, &error));
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_ALPHA_MASK") == "1u");
    renderer->render(4);
    const Film masked = renderer->readFilm();
    double sum = 0.0;
    for (int y = 0; y < masked.height; ++y)
        for (int x = 0; x < masked.width; ++x)
            sum += std::abs(double(masked.mean[masked.index(x, y)].g) - (x % 16 < 8 ? 0.0 : 1.0));
    INFO("mean difference from the expected stripes " << sum / double(masked.mean.size()));
    CHECK(sum / double(masked.mean.size()) < 1e-3);
}

TEST_CASE("alpha cut-outs: shadow rays and bounce rays pass the holes too", "[gpu][gltf][alpha][mis]") {
    auto renderer = test::makeRenderer();
    // Direct light only (max depth 1), so the floor's radiance is the light that reaches it.
    Scene none = litFloorScene(0.6f);
    none.render.maxDepth = 1;
    Scene masked = none, opaque = none;
    masked.objects.push_back(horizontalQuadMesh(kData / "leaf.glb", 1.0f));
    opaque.objects.push_back(horizontalQuadMesh(kData / "leaf.glb", 1.0f));
    opaque.objects.back().material = "black";
    const test::ImageStats a = test::imageStats(test::renderFilm(*renderer, none, 64));
    const test::ImageStats b = test::imageStats(test::renderFilm(*renderer, masked, 64));
    const test::ImageStats c = test::imageStats(test::renderFilm(*renderer, opaque, 64));
    // What reaches the floor through the mask, as a fraction of what the opaque leaf stops: the
    // mask keeps half the leaf's area in stripes finer than its shadow, so about one half (not
    // exactly: the camera weighs the floor unevenly across the stripes' shadows).
    const double stopped = a.mean.r - c.mean.r, passed = b.mean.r - c.mean.r;
    INFO("no leaf " << a.mean.r << ", masked " << b.mean.r << ", opaque " << c.mean.r);
    REQUIRE(stopped > 0.2 * a.mean.r);  // the leaf's shadow is a good part of the image
    CHECK(passed / stopped == Approx(0.5).margin(0.05));

    // Shadow rays (light sampling) and bounce rays (BSDF sampling) see the same holes, with the
    // leaf reflecting and casting light (max depth 3).
    Scene s = litFloorScene(2.0f);
    s.objects.push_back(horizontalQuadMesh(kData / "leaf.glb", 1.0f));
    test::checkStrategiesAgree(*renderer, s, 64);
}

TEST_CASE("emission textures: a glTF emissive texture seen directly is factor x strength x texel",
          "[gpu][gltf][emitters]") {
    auto renderer = test::makeRenderer();
    Scene s = facingScene(kData / "glow.glb");
    s.environment.type = EnvironmentType::None;
    const Film glb = test::renderFilm(*renderer, s, 2);
    CHECK(defineOf(renderer->featureDefines(), "CAUSTIC_EMISSION_TEXTURES") == "1u");
    s.objects[0].file = (kData / "glow.gltf").string();
    const Film gltf = test::renderFilm(*renderer, s, 2);
    size_t different = 0;
    for (size_t i = 0; i < glb.mean.size(); ++i) different += glb.mean[i] != gltf.mean[i] ? 1 : 0;
    CHECK(different == 0);
    // emissiveFactor (1, 0.5, 0.25) x emissive strength 3 x the sRGB texels (255, 128, 0) on the
    // left and (0, 64, 255) on the right, clamped to the edge: pure left texel for u < 1/4, right
    // for u > 3/4 (bilinear in between).
    const glm::vec3 factor = glm::vec3(1.0f, 0.5f, 0.25f) * 3.0f;
    const glm::vec3 left = factor * glm::vec3(1.0f, srgbToLinear(128.0f / 255.0f), 0.0f);
    const glm::vec3 right = factor * glm::vec3(0.0f, srgbToLinear(64.0f / 255.0f), 1.0f);
    double worst = 0.0;
    for (int y = 0; y < glb.height; ++y)
        for (int x = 0; x < glb.width; ++x) {
            if (x >= kViewSize / 4 - 1 && x <= 3 * kViewSize / 4) continue;
            const glm::vec3 expected = x < kViewSize / 2 ? left : right;
            const glm::vec3 got = glb.mean[glb.index(x, y)];
            for (int c = 0; c < 3; ++c)  // half-float texels: 2^-11 relative
                worst = std::max(worst, std::abs(double(got[c]) - expected[c]) / std::max(double(expected[c]), 1e-2));
        }
    INFO("largest relative difference " << worst);
    CHECK(worst < 2e-3);
    // In between, the green channel falls monotonically from the left texel's to the right's.
    const int row = kViewSize / 2;
    for (int x = kViewSize / 4; x < 3 * kViewSize / 4; ++x)
        CHECK(glb.mean[glb.index(x + 1, row)].g <= glb.mean[glb.index(x, row)].g + 1e-6f);
}

TEST_CASE("emission textures: light sampling, BSDF sampling and MIS agree", "[gpu][gltf][emitters][mis]") {
    auto renderer = test::makeRenderer();
    SECTION("a glTF mesh with an emissive texture (a mesh light)") {
        Scene s = litFloorScene(1.0f);
        s.lights.clear();
        Object glow = horizontalQuadMesh(kData / "glow.glb", 1.0f);
        glow.transform.scale = glm::vec3(0.6f);
        s.objects.push_back(glow);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
    SECTION("a scene material's emission_texture on a quad and on a sphere (rect and sphere lights)") {
        // A generated 4 x 2 texture: a different colour per texel, and one black texel.
        renderer->setImageReader([](const std::string& path, ImageData* out, std::string* error) {
            if (fs::path(path).filename() != "glow.png") {
                *error = path + ": no such generated image";
                return false;
            }
            out->width = 4;
            out->height = 2;
            out->channels = 3;
            out->pixels = {1, 0.2f, 0, 0, 1, 0.3f, 0.1f, 0.2f, 1, 1, 1, 1,
                           0, 0, 0, 0.5f, 0.5f, 0, 0, 0.6f, 0.6f, 0.9f, 0.1f, 0.7f};
            return true;
        });
        Scene s = litFloorScene(1.0f);
        s.lights.clear();
        Material m{"glowing", MaterialType::Diffuse, glm::vec3(0.5f), glm::vec3(4.0f)};
        m.emissionTexture = "glow.png";
        s.materials.push_back(m);
        Object panel;
        panel.shape = Shape::Quad;
        panel.material = "glowing";
        panel.transform.translate = glm::vec3(-0.5f, 1.0f, 0.0f);
        panel.transform.rotate = glm::vec3(70.0f, 20.0f, 0.0f);
        panel.transform.scale = glm::vec3(0.5f, 0.4f, 1.0f);
        s.objects.push_back(panel);
        s.objects.push_back(test::sphereAt("glowing", glm::vec3(0.7f, 0.5f, -0.3f), 0.35f));
        test::checkStrategiesAgree(*renderer, s, 64);
        // And the object's own emission in place of the material's is textured alike.
        s.objects[1].emission = glm::vec3(2.0f, 3.0f, 1.0f);
        test::checkStrategiesAgree(*renderer, s, 64);
    }
}
