// Model files' materials (glTF metallic-roughness terms) mapped to caustic's.
#include "renderer/gpu_scene.h"
#include "renderer/mesh.h"
#include "renderer/mesh_import.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace caustic;

TEST_CASE("imported glTF materials become layered surfaces with their factors", "[cpu][materials]") {
    ImportedMaterial gold;
    gold.name = "gold";
    gold.baseColor = glm::vec3(1.0f, 0.766f, 0.336f);
    gold.metallic = 1.0f;
    gold.roughness = 0.4f;
    gold.ior = 1.45f;
    gold.specular = 0.7f;
    gold.specularColor = glm::vec3(1.0f, 0.9f, 0.8f);
    gold.clearcoat = 0.5f;
    gold.clearcoatRoughness = 0.3f;
    gold.sheenColor = glm::vec3(0.2f, 0.1f, 0.0f);
    gold.sheenRoughness = 0.6f;
    gold.normalTexture = "/models/n.png";
    gold.normalScale = 0.25f;
    std::vector<std::string> unmapped;
    const Material m = mapImportedMaterial(gold, &unmapped);
    CHECK(m.type == MaterialType::Surface);
    CHECK(m.albedo == gold.baseColor);
    CHECK(m.metalness == 1.0f);
    CHECK(m.specularRoughness == 0.4f);  // perceptual in both
    CHECK(m.specularIor == 1.45f);
    CHECK(m.specularWeight == 0.7f);
    CHECK(m.specularColor == gold.specularColor);
    CHECK(m.coatWeight == 0.5f);
    CHECK(m.coatRoughness == 0.3f);
    CHECK(m.coatIor == 1.5f);           // KHR_materials_clearcoat's fixed IOR
    CHECK(m.sheenWeight == 1.0f);
    CHECK(m.sheenColor == gold.sheenColor);
    CHECK(m.sheenRoughness == 0.6f);
    CHECK(m.normalTexture == "/models/n.png");
    CHECK(m.normalScale == 0.25f);
    INFO(unmapped.size());
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
    // The surface's transmission (docs/materials.md, "glTF transmission and volume"): without
    // KHR_materials_volume a thin-walled sheet, tinted by the base colour.
    CHECK(g.type == MaterialType::Surface);
    CHECK(g.transmissionWeight == 1.0f);
    CHECK(g.thinWalled);
    CHECK(g.transmissionColor == glass.baseColor);
    CHECK(g.specularIor == Approx(1.45f));
    CHECK(g.specularRoughness == Approx(0.1f));  // perceptual in both
    // A partial factor is kept as it is, and a closed object (KHR_materials_volume) is not thin.
    glass.transmission = 0.3f;
    glass.volume = true;
    g = mapImportedMaterial(glass, &unmapped);
    CHECK(g.transmissionWeight == 0.3f);
    CHECK_FALSE(g.thinWalled);
    // KHR_materials_diffuse_transmission: a thin-walled surface's subsurface, all of it transmitted;
    // on a closed object, reported.
    ImportedMaterial leaf;
    leaf.name = "leaf";
    leaf.diffuseTransmission = 0.6f;
    leaf.diffuseTransmissionColor = glm::vec3(0.3f, 0.8f, 0.1f);
    unmapped.clear();
    g = mapImportedMaterial(leaf, &unmapped);
    CHECK(g.thinWalled);
    CHECK(g.subsurfaceWeight == 0.6f);
    CHECK(g.subsurfaceColor == leaf.diffuseTransmissionColor);
    CHECK(g.subsurfaceAnisotropy > 0.99f);
    CHECK(unmapped.empty());
    leaf.volume = true;
    g = mapImportedMaterial(leaf, &unmapped);
    CHECK(g.subsurfaceWeight == 0.0f);
    bool reported = false;
    for (const std::string& line : unmapped) reported |= line.find("material 'leaf': KHR_materials_diffuse_transmission") == 0;
    CHECK(reported);
    unmapped.clear();

    ImportedMaterial paint;
    paint.name = "paint";
    paint.baseColor = glm::vec3(0.2f, 0.5f, 0.1f);
    paint.emission = glm::vec3(3.0f);
    paint.metallicRoughnessTexture = "/models/paint_mr.png";
    paint.emissionTexture = "/models/paint_emission.png";
    paint.opacity = 0.5f;
    paint.baseColorTexture = "/tmp/base.png";
    unmapped.clear();
    Material p = mapImportedMaterial(paint, &unmapped);
    CHECK(p.type == MaterialType::Surface);
    CHECK(p.albedo == glm::vec3(0.2f, 0.5f, 0.1f));
    CHECK(p.metalness == 0.0f);
    CHECK(p.emission == glm::vec3(3.0f));
    CHECK(p.albedoTexture == "/tmp/base.png");
    CHECK(p.roughnessTexture == "/models/paint_mr.png");
    CHECK(p.emissionTexture == "/models/paint_emission.png");  // per texel, times the factor
    CHECK(p.alphaMode == AlphaMode::Opaque);  // glTF OPAQUE ignores the alpha (reported below)
    std::string all;
    for (const std::string& u : unmapped) all += u + "\n";
    INFO(all);
    CHECK(all.find("emission texture") == std::string::npos);
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

TEST_CASE("glTF metallic-roughness textures: roughness from G, metalness from B, per texel", "[cpu][materials]") {
    // glTF 2.0, section 3.9.2: G = perceptual roughness, B = metalness, each times its factor;
    // R (occlusion in packed ORM textures) must not matter. The baked texture holds roughness in
    // R and metalness in G for the surface material's roughness slot.
    const ImageData mr = image(4, 2, [](int x, int) { return glm::vec3(0.9f, x < 2 ? 0.2f : 1.0f, x % 2 ? 1.0f : 0.25f); });
    MetallicRoughnessMap baked;
    std::string error;
    REQUIRE(bakeMetallicRoughness(mr, 0.5f, 0.8f, &baked, &error));
    REQUIRE(baked.texture.channels == 3);
    REQUIRE(baked.texture.pixels.size() == 24);
    for (int i = 0; i < 8; ++i) {
        const int x = i % 4;
        INFO("texel " << i);
        CHECK(baked.texture.pixels[3 * i] == Approx(0.5f * (x < 2 ? 0.2f : 1.0f)));
        CHECK(baked.texture.pixels[3 * i + 1] == Approx(0.8f * (x % 2 ? 1.0f : 0.25f)));
    }
    CHECK(baked.metalMin == Approx(0.2f));
    CHECK(baked.metalMax == Approx(0.8f));
    CHECK(baked.metalFraction == Approx(0.5f));

    ImportedMaterial steel;
    steel.name = "steel";
    steel.baseColor = glm::vec3(0.8f);
    steel.metallic = 0.8f;
    steel.roughness = 0.5f;
    steel.metallicRoughnessTexture = "/models/steel_mr.png";
    std::vector<std::string> unmapped;
    const Material m = mapImportedMaterial(steel, &unmapped, &baked);
    CHECK(m.type == MaterialType::Surface);
    CHECK(m.roughnessTexture == "/models/steel_mr.png");
    INFO(joined(unmapped));
    CHECK(unmapped.empty());  // a per-texel mix is what the surface material does: nothing to report

    // Glass keeps its roughness map; a broken image is refused.
    ImportedMaterial glass = steel;
    glass.transmission = 1.0f;
    const Material g = mapImportedMaterial(glass, &unmapped, &baked);
    CHECK(g.type == MaterialType::Surface);
    CHECK(g.roughnessTexture == "/models/steel_mr.png");
    CHECK(g.transmissionWeight == 1.0f);
    ImageData broken = mr;
    broken.pixels[4] = std::nanf("");
    CHECK_FALSE(bakeMetallicRoughness(broken, 1.0f, 1.0f, &baked, &error));
    CHECK(error.find("non-finite") != std::string::npos);
}

TEST_CASE("KHR_materials_volume's attenuation becomes the surface's transmission absorption", "[cpu][materials][gltf]") {
    // A glass whose light keeps [0.8, 0.5, 0.2] over 0.25 world units: OpenPBR's transmission_color at
    // transmission_depth, which the glTF extension's attenuation colour and distance are.
    std::vector<std::string> unmapped;
    ImportedMaterial glass;
    glass.name = "bottle";
    glass.transmission = 1.0f;
    glass.attenuationColor = glm::vec3(0.8f, 0.5f, 0.2f);
    glass.attenuationDistance = 0.25f;
    glass.volume = true;
    glass.baseColor = glm::vec3(1.0f);  // glTF's default: no tint of its own
    Material g = mapImportedMaterial(glass, &unmapped);
    CHECK(g.type == MaterialType::Surface);
    CHECK_FALSE(g.thinWalled);
    CHECK(g.transmissionColor == glm::vec3(0.8f, 0.5f, 0.2f));
    CHECK(g.transmissionDepth == 0.25f);
    CHECK(joined(unmapped).find("volume") == std::string::npos);
    // A black channel: clamped to 1e-4 (a finite coefficient), as the loader would require.
    glass.attenuationColor = glm::vec3(0.0f, 0.5f, 1.0f);
    g = mapImportedMaterial(glass, &unmapped);
    CHECK(g.transmissionColor == glm::vec3(1e-4f, 0.5f, 1.0f));
    // No extension (distance 0: infinite) or a white colour: clear glass, as before.
    glass.attenuationDistance = 0.0f;
    CHECK(mapImportedMaterial(glass, &unmapped).transmissionDepth == 0.0f);
    glass.attenuationDistance = 2.0f;
    glass.attenuationColor = glm::vec3(1.0f);
    CHECK(mapImportedMaterial(glass, &unmapped).transmissionDepth == 0.0f);
    // Without transmission the surface material has no interior: reported.
    ImportedMaterial opaque;
    opaque.name = "opaque";
    opaque.attenuationColor = glm::vec3(0.5f);
    opaque.attenuationDistance = 1.0f;
    unmapped.clear();
    CHECK(mapImportedMaterial(opaque, &unmapped).type == MaterialType::Surface);
    CHECK(joined(unmapped).find("material 'opaque': KHR_materials_volume") != std::string::npos);
}

TEST_CASE("a glTF file's KHR_materials_volume reaches the imported material through the import process",
          "[cpu][materials][gltf]") {
    test::TempDir dir;
    const std::string file = dir.file("volume.gltf");
    std::ofstream(file) << R"({"asset": {"version": "2.0"},
      "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume"],
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "materials": [{"name": "amber", "extensions": {
        "KHR_materials_transmission": {"transmissionFactor": 1},
        "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationDistance": 0.5,
                                 "attenuationColor": [0.9, 0.5, 0.1]}}}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
      "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})";
    const MeshImportResult r = importMeshFile(file);
    INFO(r.error);
    REQUIRE(r.ok());
    const ImportedMaterial* amber = nullptr;  // (Assimp may add its default material beside it)
    for (const ImportedMaterial& im : r.materials)
        if (im.name == "amber") amber = &im;
    REQUIRE(amber != nullptr);
    CHECK(amber->attenuationDistance == 0.5f);
    CHECK(amber->attenuationColor == glm::vec3(0.9f, 0.5f, 0.1f));
    CHECK(amber->volume);  // thicknessFactor 0.1
    for (const std::string& w : r.warnings) CHECK(w.find("KHR_materials_volume") == std::string::npos);
    std::vector<std::string> unmapped;
    const Material m = mapImportedMaterial(*amber, &unmapped);
    CHECK(m.type == MaterialType::Surface);
    CHECK(m.transmissionWeight == 1.0f);
    CHECK(m.transmissionColor == glm::vec3(0.9f, 0.5f, 0.1f));
    CHECK(m.transmissionDepth == 0.5f);
}
