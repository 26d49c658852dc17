// Model files' materials (glTF metallic-roughness terms) mapped to caustic's.
#include "renderer/gpu_scene.h"
#include "renderer/mesh.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

TEST_CASE("imported metals get a complex IOR whose normal-incidence Fresnel is the base colour", "[cpu][materials]") {
    ImportedMaterial gold;
    gold.name = "gold";
    gold.baseColor = glm::vec3(1.0f, 0.766f, 0.336f);
    gold.metallic = 1.0f;
    gold.roughness = 0.4f;
    std::vector<std::string> unmapped;
    Material m = mapImportedMaterial(gold, &unmapped);
    CHECK(m.type == MaterialType::Conductor);
    CHECK(m.metal == Metal::Custom);
    CHECK(m.roughness == Approx(0.16f));  // alpha = perceptual roughness squared
    for (int c = 0; c < 3; ++c) {
        // F0 = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2), the conductor Fresnel at normal incidence.
        const double n = m.eta[c], k = m.k[c];
        const double f0 = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
        INFO("channel " << c << " eta " << n << " k " << k);
        CHECK(f0 == Approx(std::min(double(gold.baseColor[c]), 0.99)).epsilon(1e-3));
    }
    CHECK(unmapped.empty());
}

TEST_CASE("imported dielectrics, diffuse bases and what cannot be mapped", "[cpu][materials]") {
    std::vector<std::string> unmapped;
    ImportedMaterial glass;
    glass.name = "glass";
    glass.transmission = 1.0f;
    glass.ior = 1.45f;
    glass.roughness = 0.1f;
    Material g = mapImportedMaterial(glass, &unmapped);
    CHECK(g.type == MaterialType::Dielectric);
    CHECK(g.ior == Approx(1.45f));
    CHECK(g.roughness == Approx(0.01f));

    ImportedMaterial paint;
    paint.name = "paint";
    paint.baseColor = glm::vec3(0.2f, 0.5f, 0.1f);
    paint.emission = glm::vec3(3.0f);
    paint.metallicRoughnessTexture = "*0 (an embedded texture)";  // never read: the factors are used
    paint.opacity = 0.5f;
    paint.baseColorTexture = "/tmp/base.png";
    unmapped.clear();
    Material p = mapImportedMaterial(paint, &unmapped);
    CHECK(p.type == MaterialType::Diffuse);
    CHECK(p.albedo == glm::vec3(0.2f, 0.5f, 0.1f));
    CHECK(p.emission == glm::vec3(3.0f));
    CHECK(p.albedoTexture == "/tmp/base.png");
    std::string all;
    for (const std::string& u : unmapped) all += u + "\n";
    INFO(all);
    CHECK(all.find("metallic-roughness texture") != std::string::npos);
    CHECK(all.find("opacity") != std::string::npos);
    CHECK(all.find("material 'paint'") != std::string::npos);
}

namespace {

// A w x h RGB image whose texel (x, y) is rgb(x, y).
template <class F>
ImageData image(int w, int h, F rgb) {
    ImageData img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const glm::vec3 c = rgb(x, y);
            img.pixels.insert(img.pixels.end(), {c.r, c.g, c.b});
        }
    return img;
}

std::string joined(const std::vector<std::string>& lines) {
    std::string all;
    for (const std::string& l : lines) all += l + "\n";
    return all;
}

}  // namespace

TEST_CASE("glTF metallic-roughness textures: roughness from G as alpha, metalness from B", "[cpu][materials]") {
    // glTF 2.0, section 3.9.2: G = perceptual roughness, B = metalness, each times its factor;
    // R (occlusion in packed ORM textures) must not matter.
    const ImageData mr = image(4, 2, [](int x, int) { return glm::vec3(0.9f, x < 2 ? 0.2f : 1.0f, 1.0f); });
    MetallicRoughnessMap baked;
    std::string error;
    REQUIRE(bakeMetallicRoughness(mr, 0.5f, 1.0f, &baked, &error));
    REQUIRE(baked.alpha.channels == 1);
    REQUIRE(baked.alpha.pixels.size() == 8);
    CHECK(baked.alpha.pixels[0] == Approx(0.01f));   // (0.5 x 0.2)^2
    CHECK(baked.alpha.pixels[3] == Approx(0.25f));   // (0.5 x 1)^2
    CHECK(baked.alpha.pixels[5] == Approx(0.01f));
    CHECK(baked.metalMin == 1.0f);
    CHECK(baked.metalFraction == 1.0f);

    ImportedMaterial steel;
    steel.name = "steel";
    steel.baseColor = glm::vec3(0.8f);
    steel.metallic = 1.0f;
    steel.roughness = 0.5f;
    steel.metallicRoughnessTexture = "/models/steel_mr.png";
    std::vector<std::string> unmapped;
    // Before the texture is read: the factors, and nothing reported yet.
    const Material provisional = mapImportedMaterial(steel, &unmapped);
    CHECK(provisional.type == MaterialType::Conductor);
    CHECK(provisional.roughnessTexture.empty());
    CHECK(unmapped.empty());
    // Read: a conductor whose roughness slot takes the texture (the path marks it rough).
    const Material m = mapImportedMaterial(steel, &unmapped, &baked);
    CHECK(m.type == MaterialType::Conductor);
    CHECK(m.roughnessTexture == "/models/steel_mr.png");
    INFO(joined(unmapped));
    CHECK(unmapped.empty());

    // Metalness uniform below 0.5 (factor 0.4 x B = 1): a non-metal, reported as rounded; a
    // diffuse base has no roughness, so no roughness map.
    REQUIRE(bakeMetallicRoughness(mr, 1.0f, 0.4f, &baked, &error));
    unmapped.clear();
    const Material dull = mapImportedMaterial(steel, &unmapped, &baked);
    CHECK(dull.type == MaterialType::Diffuse);
    CHECK(dull.roughnessTexture.empty());
    CHECK(joined(unmapped).find("metallic 0.4") != std::string::npos);

    // Metalness varying over the texture: the majority of texels decides, and it is reported.
    const ImageData mixed = image(4, 1, [](int x, int) { return glm::vec3(0.0f, 0.5f, x == 0 ? 0.0f : 1.0f); });
    REQUIRE(bakeMetallicRoughness(mixed, 1.0f, 1.0f, &baked, &error));
    CHECK(baked.metalFraction == Approx(0.75f));
    unmapped.clear();
    const Material mostlyMetal = mapImportedMaterial(steel, &unmapped, &baked);
    CHECK(mostlyMetal.type == MaterialType::Conductor);
    CHECK(joined(unmapped).find("metalness varies") != std::string::npos);
    CHECK(joined(unmapped).find("75.0%") != std::string::npos);
    const ImageData mostlyNot = image(4, 1, [](int x, int) { return glm::vec3(0.0f, 0.5f, x == 0 ? 1.0f : 0.0f); });
    REQUIRE(bakeMetallicRoughness(mostlyNot, 1.0f, 1.0f, &baked, &error));
    unmapped.clear();
    CHECK(mapImportedMaterial(steel, &unmapped, &baked).type == MaterialType::Diffuse);
    CHECK(joined(unmapped).find("a non-metal throughout") != std::string::npos);

    // Glass keeps its roughness map too; a broken image is refused.
    ImportedMaterial glass = steel;
    glass.transmission = 1.0f;
    REQUIRE(bakeMetallicRoughness(mr, 1.0f, 0.0f, &baked, &error));
    const Material g = mapImportedMaterial(glass, &unmapped, &baked);
    CHECK(g.type == MaterialType::Dielectric);
    CHECK(g.roughnessTexture == "/models/steel_mr.png");
    ImageData broken = mr;
    broken.pixels[4] = std::nanf("");
    CHECK_FALSE(bakeMetallicRoughness(broken, 1.0f, 1.0f, &baked, &error));
    CHECK(error.find("non-finite") != std::string::npos);
}
