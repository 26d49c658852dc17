// Materials on the CPU side: every type reads, writes and reads back the same; per-type defaults;
// the conversion to GPU materials (presets, smooth vs rough, flags); texture loading errors name
// the file and the material; the GGX albedo table's known values.
#include "renderer/gpu_scene.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace caustic;

namespace {

Scene mustParse(const std::string& text) {
    SceneLoadResult r = parseScene(text, "scenes/x.json");
    INFO(r.error);
    REQUIRE(r.scene);
    return *r.scene;
}

const char* kAllTypes = R"({"version": 1, "materials": [
  {"name": "d", "type": "diffuse", "albedo": [0.5, 0.5, 0.5], "albedo_texture": "a.png"},
  {"name": "on", "type": "oren_nayar", "sigma": 0.3, "energy_compensation": true},
  {"name": "eon", "type": "eon", "albedo": [0.9, 0.8, 0.7]},
  {"name": "m", "type": "mirror", "tint": [0.9, 0.9, 0.9]},
  {"name": "t", "type": "transmission"},
  {"name": "g", "type": "dielectric", "ior": 1.33, "roughness": 0.2, "normal_texture": "n.png"},
  {"name": "au", "type": "conductor", "metal": "gold", "roughness": 0.3, "energy_compensation": true},
  {"name": "c", "type": "conductor", "metal": "custom", "eta": [0.2, 0.3, 0.4], "k": [3, 2, 1],
   "roughness_texture": "r.png", "emission": [1, 0, 0]}
]})";

}  // namespace

TEST_CASE("materials: every type round-trips, with per-type defaults", "[scene_io][materials]") {
    const Scene s = mustParse(kAllTypes);
    REQUIRE(s.materials.size() == 8);
    CHECK(s.materials[1].type == MaterialType::OrenNayar);
    CHECK(s.materials[1].sigma == 0.3f);
    CHECK(s.materials[2].roughness == 0.5f);  // eon's default roughness
    CHECK(s.materials[4].ior == 1.0f);        // transmission's default ior
    CHECK(s.materials[5].ior == 1.33f);
    CHECK(s.materials[6].metal == Metal::Gold);
    CHECK(s.materials[7].k == glm::vec3(3, 2, 1));
    CHECK(s.materials[0].albedoTexture == "a.png");
    const Scene again = mustParse(sceneToJson(s));
    CHECK(again.materials == s.materials);
    // eta and k are written for custom metals only.
    const std::string json = sceneToJson(s);
    CHECK(json.find("\"eta\": [0.2, 0.3, 0.4]") != std::string::npos);
    CHECK(json.find("\"eta\"") == json.rfind("\"eta\""));
}

TEST_CASE("materials: conversion to the GPU", "[materials]") {
    Scene s = mustParse(kAllTypes);
    for (Material& m : s.materials) m.albedoTexture = m.normalTexture = m.roughnessTexture = "";
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, &c, &error));
    REQUIRE(c.materials.size() == 8);
    CHECK(c.materials[0].info.x == MAT_DIFFUSE);
    CHECK(c.materials[1].info.x == MAT_OREN_NAYAR);
    CHECK(c.materials[1].info.y == MAT_FLAG_ENERGY_COMPENSATION);
    CHECK(c.materials[1].params.x == 0.3f);
    CHECK(c.materials[2].info.x == MAT_EON);
    CHECK(c.materials[3].info.x == MAT_MIRROR);
    CHECK(c.materials[4].info.x == MAT_TRANSMISSION);
    CHECK(c.materials[5].info.x == MAT_ROUGH_DIELECTRIC);
    CHECK(c.materials[5].params.y == 1.33f);
    CHECK(c.materials[6].info.x == MAT_ROUGH_CONDUCTOR);
    CHECK(c.materials[6].eta == glm::vec4(0.183f, 0.421f, 1.373f, 0));
    CHECK(c.materials[6].k == glm::vec4(3.424f, 2.346f, 1.770f, 0));
    CHECK(c.materials[7].info.x == MAT_CONDUCTOR);  // roughness 0: the smooth model
    CHECK(c.materials[7].emission.x == 1.0f);
    s.materials[5].roughness = 0.0f;
    REQUIRE(compileScene(s, &c, &error));
    CHECK(c.materials[5].info.x == MAT_DIELECTRIC);
    // Rough transmission: the GGX BTDF without the reflection lobe; at IOR 1 nothing bends, so it
    // stays the delta pass-through.
    s.materials[4].roughness = 0.3f;
    REQUIRE(compileScene(s, &c, &error));
    CHECK(c.materials[4].info.x == MAT_TRANSMISSION);
    s.materials[4].ior = 1.33f;
    REQUIRE(compileScene(s, &c, &error));
    CHECK(c.materials[4].info.x == MAT_ROUGH_DIELECTRIC);
    CHECK(c.materials[4].info.y == MAT_FLAG_NO_REFLECTION);
    CHECK(c.materials[4].params == glm::vec4(0.3f, 1.33f, 0, 0));
}

TEST_CASE("materials: an unreadable texture is an error naming the file and the material", "[materials]") {
    Scene s = mustParse(R"({"version": 1, "materials": [{"name": "brick", "albedo_texture": "tex/missing.png"}]})");
    s.sourcePath = "scenes/x.json";
    CompiledScene c;
    std::string error;
    ImageReader failing = [](const std::string& path, ImageData*, std::string* why) {
        *why = path + ": No such file or directory";
        return false;
    };
    CHECK_FALSE(compileScene(s, failing, &c, &error));
    CHECK(error.find("scenes/tex/missing.png") != std::string::npos);
    CHECK(error.find("'brick'") != std::string::npos);
    CHECK(error.find("materials[0].albedo_texture") != std::string::npos);
    // No reader at all (a lean build) also names both.
    CHECK_FALSE(compileScene(s, &c, &error));
    CHECK(error.find("missing.png") != std::string::npos);
    CHECK(error.find("'brick'") != std::string::npos);
    // A reader that succeeds with an empty image.
    ImageReader empty = [](const std::string&, ImageData* out, std::string*) {
        *out = ImageData{};
        return true;
    };
    CHECK_FALSE(compileScene(s, empty, &c, &error));
    CHECK(error.find("empty") != std::string::npos);
}

TEST_CASE("materials: textures are shared between materials and keep their size", "[materials]") {
    Scene s = mustParse(R"({"version": 1, "materials": [
        {"name": "a", "albedo_texture": "t.png"}, {"name": "b", "albedo_texture": "t.png"},
        {"name": "c", "type": "eon", "roughness_texture": "t.png"}]})");
    int reads = 0;
    ImageReader reader = [&](const std::string&, ImageData* out, std::string*) {
        ++reads;
        out->width = 7;
        out->height = 3;
        out->channels = 4;
        out->pixels.assign(7 * 3 * 4, 0.5f);
        return true;
    };
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, reader, &c, &error));
    CHECK(reads == 2);  // once as sRGB (albedo), once linear (roughness)
    REQUIRE(c.textures.size() == 2);
    CHECK(c.materials[0].textures.x == c.materials[1].textures.x);
    CHECK(c.textures[0].info == glm::uvec4(0, 7, 3, 3));  // 7x3, 3x1, 1x1
    CHECK(c.texels.size() == size_t(2 * (21 + 3 + 1)));
}


TEST_CASE("materials: dielectric absorption (OpenPBR transmission_color and transmission_depth)", "[materials][scene_io]") {
    const Scene s = mustParse(R"({"version": 1, "materials": [
      {"name": "amber", "type": "dielectric", "transmission_color": [0.8, 0.4, 0.1], "transmission_depth": 0.5},
      {"name": "rough", "type": "dielectric", "roughness": 0.2, "transmission_color": [0.5, 1, 1], "transmission_depth": 2},
      {"name": "clear", "type": "dielectric"},
      {"name": "white at depth", "type": "dielectric", "transmission_depth": 3}
    ]})");
    CHECK(s.materials[0].transmissionColor == glm::vec3(0.8f, 0.4f, 0.1f));
    CHECK(s.materials[0].transmissionDepth == 0.5f);
    CHECK(s.materials[2].transmissionColor == glm::vec3(1.0f));  // the defaults: no absorption
    CHECK(s.materials[2].transmissionDepth == 0.0f);
    // Round trip; the keys are written only where they differ from the defaults, so files without
    // absorption (and their hashes) are as before.
    const std::string json = sceneToJson(s);
    CHECK(mustParse(json).materials == s.materials);
    CHECK(json.find("\"transmission_color\": [0.8, 0.4, 0.1]") != std::string::npos);
    CHECK(json.find("\"transmission_depth\": 0.5") != std::string::npos);
    const size_t clear = json.find("\"clear\"");
    REQUIRE(clear != std::string::npos);
    CHECK(json.find("transmission_", clear) > json.find("\"white at depth\""));

    // sigma_a = -ln(colour) / depth per channel, in k.rgb, flagged; none for the others.
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, &c, &error));
    CHECK(c.materials[0].info.x == MAT_DIELECTRIC);
    CHECK(c.materials[0].info.y == MAT_FLAG_MEDIUM);
    for (int i = 0; i < 3; ++i) {
        const float expected = -std::log(glm::vec3(0.8f, 0.4f, 0.1f)[i]) / 0.5f;
        CHECK(c.materials[0].k[i] == Approx(expected).epsilon(1e-6));
    }
    CHECK(c.materials[1].info.x == MAT_ROUGH_DIELECTRIC);
    CHECK(c.materials[1].info.y == MAT_FLAG_MEDIUM);
    CHECK(c.materials[1].k.x == Approx(std::log(2.0f) / 2.0f).epsilon(1e-6));
    CHECK(c.materials[1].k.y == 0.0f);
    CHECK(c.materials[2].info.y == 0u);  // clear glass: the GPU material of before, byte for byte
    CHECK(c.materials[2].k == glm::vec4(0.0f));
    CHECK(c.materials[3].info.y == 0u);  // white at any depth absorbs nothing
    CHECK(c.materials[3].k == glm::vec4(0.0f));
}

TEST_CASE("materials: absorption parameters are checked", "[materials][scene_io]") {
    auto errorOf = [](const std::string& material) {
        SceneLoadResult r = parseScene(R"({"version": 1, "materials": [)" + material + "]}", "scenes/x.json");
        return r.scene ? std::string() : r.error;
    };
    // The colour is in (0, 1]: 0 would be an infinite coefficient.
    CHECK(errorOf(R"({"name": "g", "type": "dielectric", "transmission_color": [0, 0.5, 0.5], "transmission_depth": 1})")
              .find("transmission_color") != std::string::npos);
    CHECK(errorOf(R"({"name": "g", "type": "dielectric", "transmission_color": [1.2, 0.5, 0.5], "transmission_depth": 1})")
              .find("transmission_color") != std::string::npos);
    CHECK(errorOf(R"({"name": "g", "type": "dielectric", "transmission_depth": -1})").find("transmission_depth") !=
          std::string::npos);
    // A colour at depth 0 would be ignored: refused, naming the depth.
    const std::string e = errorOf(R"({"name": "g", "type": "dielectric", "transmission_color": [0.5, 0.5, 0.5]})");
    CHECK(e.find("transmission_color") != std::string::npos);
    CHECK(e.find("transmission_depth") != std::string::npos);
    // Only dielectrics take them.
    CHECK(!errorOf(R"({"name": "g", "type": "diffuse", "transmission_depth": 1})").empty());
    CHECK(errorOf(R"({"name": "g", "type": "dielectric", "transmission_color": [0.5, 0.5, 0.5], "transmission_depth": 1})")
              .empty());
}

TEST_CASE("materials: media convert as OpenPBR and the schema say, and round-trip", "[materials][media][scene_io]") {
    const Scene s = mustParse(R"({"version": 1, "materials": [
      {"name": "milky", "type": "dielectric", "transmission_color": [0.5, 0.6, 0.7], "transmission_depth": 0.5,
       "transmission_scatter": [0.4, 0.9, 0.1], "transmission_scatter_anisotropy": 0.3},
      {"name": "smoke", "type": "volume", "sigma_a": [0.1, 0.2, 0.3], "sigma_s": [1, 2, 3], "anisotropy": -0.5},
      {"name": "vacuum", "type": "volume"}],
      "environment": {"type": "none", "medium_sigma_a": [0.01, 0.02, 0.03], "medium_sigma_s": [0.1, 0.1, 0.1],
                      "medium_anisotropy": 0.7}})");
    CHECK(s.materials[1].type == MaterialType::Volume);
    CHECK(s.environment.mediumSigmaS == glm::vec3(0.1f));
    const std::string json = sceneToJson(s);
    const Scene back = mustParse(json);
    CHECK(back.materials == s.materials);
    CHECK(back.environment == s.environment);
    // Nothing written for the defaults: a scene without media is the file of before.
    CHECK(sceneToJson(mustParse(R"({"version": 1})")).find("medium") == std::string::npos);

    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, &c, &error));
    // OpenPBR: sigma_t = -ln(T) / d, sigma_s = S / d, sigma_a = sigma_t - sigma_s raised by the most
    // negative channel: (0.693, 0.511, 0.357) - (0.4, 0.9, 0.1) = (0.293, -0.389, 0.257), + 0.389.
    const glm::dvec3 st = -glm::log(glm::dvec3(0.5, 0.6, 0.7)), S(0.4, 0.9, 0.1);
    glm::dvec3 sa = st - S;
    sa -= std::min({sa.x, sa.y, sa.z});
    CHECK(c.materials[0].info.y == MAT_FLAG_MEDIUM);
    for (int i = 0; i < 3; ++i) {
        CHECK(c.materials[0].k[i] == Approx(sa[i] / 0.5).margin(1e-5));
        CHECK(c.materials[0].eta[i] == Approx(S[i] / 0.5).epsilon(1e-6));
    }
    CHECK(c.materials[0].k.y == Approx(0.0).margin(1e-6));  // the shifted channel
    CHECK(c.materials[0].eta.w == 0.3f);
    CHECK(c.materials[1].info.x == MAT_VOLUME);
    CHECK(c.materials[1].info.y == MAT_FLAG_MEDIUM);
    CHECK(glm::vec3(c.materials[1].k) == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(c.materials[1].eta == glm::vec4(1.0f, 2.0f, 3.0f, -0.5f));
    CHECK(c.materials[2].info == glm::uvec4(MAT_VOLUME, 0u, 0u, 0u));  // vacuum: no medium flag
    // The scene's fog in the frame, and glass splitting off with it.
    Scene split = s;
    split.render.glassSplit = true;
    const gpu::GpuFrame f = makeFrame(split, c, STRATEGY_MIS);
    CHECK(f.mediumA == glm::vec4(0.01f, 0.02f, 0.03f, 0.7f));
    CHECK(glm::vec3(f.mediumS) == glm::vec3(0.1f));
    CHECK((f.options.x & OPTION_GLASS_SPLIT) == 0u);
    Scene clear;
    CompiledScene cc;
    REQUIRE(compileScene(clear, &cc, &error));
    CHECK((makeFrame(clear, cc, STRATEGY_MIS).options.x & OPTION_GLASS_SPLIT) != 0u);
}

TEST_CASE("materials: media parameters are checked", "[materials][media][scene_io]") {
    auto errorOf = [](const std::string& text) {
        SceneLoadResult r = parseScene(text, "scenes/x.json");
        return r.scene ? std::string() : r.error;
    };
    auto material = [&](const std::string& m) { return errorOf(R"({"version": 1, "materials": [)" + m + "]}"); };
    // Scatter is a coefficient times the depth: refused at depth 0, naming both.
    std::string e = material(R"({"name": "g", "type": "dielectric", "transmission_scatter": [0.5, 0.5, 0.5]})");
    CHECK(e.find("materials[0].transmission_scatter") != std::string::npos);
    CHECK(e.find("transmission_depth") != std::string::npos);
    // A volume has no surface to emit from.
    e = material(R"({"name": "v", "type": "volume", "emission": [1, 1, 1]})");
    CHECK(e.find("materials[0].emission") != std::string::npos);
    CHECK(e.find("volume") != std::string::npos);
    // Ranges: coefficients >= 0 and at most 1e9, anisotropy in (-1, 1).
    CHECK(material(R"({"name": "v", "type": "volume", "sigma_s": [-1, 0, 0]})").find("sigma_s") != std::string::npos);
    CHECK(material(R"({"name": "v", "type": "volume", "sigma_a": [1e10, 0, 0]})").find("sigma_a") != std::string::npos);
    CHECK(material(R"({"name": "v", "type": "volume", "anisotropy": 1})").find("anisotropy") != std::string::npos);
    CHECK(material(R"({"name": "g", "type": "dielectric", "transmission_depth": 1, "transmission_scatter_anisotropy": -1})")
              .find("transmission_scatter_anisotropy") != std::string::npos);
    CHECK(errorOf(R"({"version": 1, "environment": {"medium_sigma_s": [0, -0.1, 0]}})").find("environment.medium_sigma_s") !=
          std::string::npos);
    // Only the types that hold a medium take its keys.
    CHECK(material(R"({"name": "d", "type": "diffuse", "sigma_s": [1, 1, 1]})").find("sigma_s") != std::string::npos);
    CHECK(material(R"({"name": "v", "type": "volume", "sigma_a": [0.1, 0.1, 0.1], "sigma_s": [1, 1, 1], "anisotropy": 0.5})")
              .empty());
}
