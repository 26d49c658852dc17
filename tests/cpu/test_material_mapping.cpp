// Model files' materials (glTF metallic-roughness terms) mapped to caustic's.
#include "renderer/gpu_scene.h"
#include "renderer/mesh.h"

#include <catch2/catch.hpp>

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
    paint.metallicRoughnessTexture = "/tmp/mr.png";
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
