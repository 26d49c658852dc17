// Scene model and scene files: Transform::toMatrix, the default Cornell box, JSON round trips,
// the exact path and wording of every kind of load error, and crash-safe saving.
#include "renderer/file_util.h"
#include "renderer/scene.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

#ifndef CAUSTIC_SOURCE_DIR
#error "CAUSTIC_SOURCE_DIR must be defined as the repository root"
#endif

using namespace caustic;
namespace fs = std::filesystem;

namespace {

const std::string kCornellBox = std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json";

glm::vec3 transformPoint(const glm::mat4& m, glm::vec3 p) { return glm::vec3(m * glm::vec4(p, 1.0f)); }

// Normals transform with the inverse transpose.
glm::vec3 transformNormal(const glm::mat4& m, glm::vec3 n) {
    return glm::normalize(glm::vec3(glm::transpose(glm::inverse(m)) * glm::vec4(n, 0.0f)));
}

bool near(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) {
    return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(eps)));
}

std::string str(glm::vec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

#define CHECK_NEAR_VEC(a, b)                                   \
    do {                                                       \
        INFO(#a " = " << str(a) << ", expected " << str(b));   \
        CHECK(near((a), (b)));                                 \
    } while (false)

Scene mustParse(const std::string& json) {
    SceneLoadResult result = parseScene(json, "test.json");
    INFO(result.error);
    REQUIRE(result);
    return *result.scene;
}

// A fresh empty directory, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        static int counter = 0;
        path = fs::temp_directory_path() /
               ("caustic-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(path)) names.push_back(entry.path().filename());
        return names;
    }
};

// A scene that uses every feature: every shape, light type and environment field, a matrix
// transform, a scalar and a vector scale, and floats that are awkward to print.
const char* kEverything = R"({
  "version": 1,
  "camera": { "position": [1.5, 2.25, -7.125], "look_at": [0.1, 0.2, 0.3], "up": [0, 0, 1],
              "fov": 61.7, "fov_axis": "x" },
  "render": { "width": 17, "height": 3000, "samples": 16777216, "max_depth": 0,
              "seed": 4294967295, "light_selection": "uniform" },
  "materials": [
    { "name": "a", "type": "diffuse", "albedo": [0.1, 0.2, 0.3], "emission": [0, 1e-7, 1e12] },
    { "name": "b", "albedo": [1, 0, 0.333333343] },
    { "name": "leaf", "albedo_texture": "leaf.png", "alpha_mode": "mask", "alpha_cutoff": 0.25,
      "emission": [1, 1, 1], "emission_texture": "glow.png" }
  ],
  "objects": [
    { "name": "ball", "shape": "sphere", "material": "a",
      "transform": { "translate": [1, 2, 3], "rotate": [10, 20, 30], "scale": 0.5 } },
    { "shape": "quad", "material": "b", "transform": { "scale": [2, -3, 1e-3] } },
    { "name": "crate", "shape": "box", "material": "a",
      "transform": { "matrix": [1, 0, 0, 5,  0, 0, -2, 6,  0, 3, 0, 7,  0, 0, 0, 1] } },
    { "name": "lamp", "shape": "quad", "material": "b", "emission": [1.5, 0, 2], "two_sided": true },
    { "name": "bulb", "shape": "sphere", "material": "b", "emission": [4, 4, 4] }
  ],
  "lights": [
    { "name": "panel", "type": "rect", "color": [5, 6, 7], "two_sided": true,
      "transform": { "translate": [0, 3, 0], "rotate": [90, 0, 0] } },
    { "type": "sphere", "color": [1, 1, 1], "position": [0, 1, 0], "radius": 0.25 },
    { "name": "bulb", "type": "point", "color": [100, 90, 80], "position": [-1, 2, -3] },
    { "name": "spot", "type": "spot", "color": [10, 10, 10], "position": [0, 5, 0],
      "direction": [0, -1, 0.5], "inner_angle": 0, "outer_angle": 180, "falloff": "linear_angle" },
    { "type": "spot", "inner_angle": 12.5, "outer_angle": 12.5 }
  ],
  "environment": { "type": "sky", "horizon": [0.9, 0.8, 0.7], "zenith": [0.1, 0.2, 0.9],
                   "intensity": 2.5 }
})";

}  // namespace

// ---------------------------------------------------------------------------------------------

TEST_CASE("Transform::toMatrix rotations are right-handed, in degrees", "[scene]") {
    Transform t;
    t.rotate = {90, 0, 0};
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {0, 0, 1}), glm::vec3(0, -1, 0));
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {0, 1, 0}), glm::vec3(0, 0, 1));
    t.rotate = {0, 90, 0};
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {0, 0, 1}), glm::vec3(1, 0, 0));
    t.rotate = {0, 0, 90};
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {1, 0, 0}), glm::vec3(0, 1, 0));
    t.rotate = {-90, 0, 0};
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {0, 0, 1}), glm::vec3(0, 1, 0));
}

TEST_CASE("Transform::toMatrix composes T * Rz * Ry * Rx * S", "[scene]") {
    Transform t;
    CHECK(t.toMatrix() == glm::mat4(1.0f));

    // Scale first, then rotate, then translate: (1,0,0) -S-> (2,0,0) -Rz90-> (0,2,0) -T-> (1,4,3).
    t.translate = {1, 2, 3};
    t.rotate = {0, 0, 90};
    t.scale = {2, 1, 1};
    CHECK_NEAR_VEC(transformPoint(t.toMatrix(), {1, 0, 0}), glm::vec3(1, 4, 3));

    // x before y before z: +y -Rx90-> +z -Ry90-> +x -Rz90-> +y. (Rz*Ry*Rx applied to +y.)
    Transform r;
    r.rotate = {90, 90, 0};
    CHECK_NEAR_VEC(transformPoint(r.toMatrix(), {0, 1, 0}), glm::vec3(1, 0, 0));
    r.rotate = {90, 90, 90};
    CHECK_NEAR_VEC(transformPoint(r.toMatrix(), {0, 1, 0}), glm::vec3(0, 1, 0));
    CHECK_NEAR_VEC(transformPoint(r.toMatrix(), {1, 0, 0}), glm::vec3(0, 0, -1));

    // An explicit matrix replaces translate/rotate/scale.
    Transform m = t;
    m.matrix = glm::mat4(3.0f);
    CHECK(m.toMatrix() == glm::mat4(3.0f));
}

TEST_CASE("Scene::findMaterial", "[scene]") {
    Scene scene;
    scene.materials.push_back({"white", MaterialType::Diffuse, glm::vec3(0.8f), glm::vec3(0.0f)});
    scene.materials.push_back({"red", MaterialType::Diffuse, glm::vec3(0.8f, 0, 0), glm::vec3(0.0f)});
    REQUIRE(scene.findMaterial("red") != nullptr);
    CHECK(scene.findMaterial("red")->albedo == glm::vec3(0.8f, 0, 0));
    CHECK(scene.findMaterial("blue") == nullptr);
}

// ---------------------------------------------------------------------------------------------

TEST_CASE("The default Cornell box loads and matches Mitsuba 3's cornell_box()", "[scene_io]") {
    const SceneLoadResult result = loadScene(kCornellBox);
    INFO(result.error);
    REQUIRE(result);
    const Scene& scene = *result.scene;
    CHECK(scene.sourcePath == kCornellBox);
    CHECK(scene.camera.position == glm::vec3(0, 0, 3.9f));
    CHECK(scene.camera.lookAt == glm::vec3(0));
    CHECK(scene.camera.up == glm::vec3(0, 1, 0));
    CHECK(scene.camera.fovDegrees == 39.3077f);
    CHECK(scene.camera.fovAxis == FovAxis::Smaller);
    CHECK(scene.render.width == 256);
    CHECK(scene.render.height == 256);
    CHECK(scene.render.samples == 256);
    CHECK(scene.render.maxDepth == 10);
    CHECK(scene.render.seed == 0);
    CHECK(scene.environment.type == EnvironmentType::None);
    REQUIRE(scene.materials.size() == 3);
    REQUIRE(scene.objects.size() == 8);
    CHECK(scene.lights.empty());
    CHECK(scene.findMaterial("white")->albedo == glm::vec3(0.885809f, 0.698859f, 0.666422f));
    CHECK(scene.findMaterial("green")->albedo == glm::vec3(0.105421f, 0.37798f, 0.076425f));
    CHECK(scene.findMaterial("red")->albedo == glm::vec3(0.570068f, 0.0430135f, 0.0443706f));

    // The light, as in Mitsuba a white diffuse quad that also emits, from its front only: y = 0.99,
    // x in [-0.23, 0.23], z in [-0.18, 0.20], emitting (its +z) towards -y.
    const Object& light = scene.objects.back();
    CHECK(light.name == "ceiling light");
    CHECK(light.shape == Shape::Quad);
    CHECK(light.material == "white");
    CHECK_FALSE(light.twoSided);
    CHECK(light.emission == glm::vec3(18.387f, 13.9873f, 6.75357f));
    const glm::mat4 lm = light.transform.toMatrix();
    CHECK_NEAR_VEC(transformPoint(lm, {-1, -1, 0}), glm::vec3(-0.23f, 0.99f, -0.18f));
    CHECK_NEAR_VEC(transformPoint(lm, {1, -1, 0}), glm::vec3(0.23f, 0.99f, -0.18f));
    CHECK_NEAR_VEC(transformPoint(lm, {-1, 1, 0}), glm::vec3(-0.23f, 0.99f, 0.20f));
    CHECK_NEAR_VEC(transformPoint(lm, {1, 1, 0}), glm::vec3(0.23f, 0.99f, 0.20f));
    CHECK_NEAR_VEC(transformNormal(lm, {0, 0, 1}), glm::vec3(0, -1, 0));

    // The walls: 2x2 quads on the faces of [-1, 1]^3, facing inward.
    struct Wall {
        const char* name;
        const char* material;
        glm::vec3 center;
        glm::vec3 normal;
    };
    const Wall walls[] = {
        {"floor", "white", {0, -1, 0}, {0, 1, 0}},  {"ceiling", "white", {0, 1, 0}, {0, -1, 0}},
        {"back", "white", {0, 0, -1}, {0, 0, 1}},   {"left", "red", {-1, 0, 0}, {1, 0, 0}},
        {"right", "green", {1, 0, 0}, {-1, 0, 0}},
    };
    for (const Wall& wall : walls) {
        INFO("wall " << wall.name);
        const auto it = std::find_if(scene.objects.begin(), scene.objects.end(),
                                     [&](const Object& o) { return o.name == wall.name; });
        REQUIRE(it != scene.objects.end());
        CHECK(it->shape == Shape::Quad);
        CHECK(it->material == wall.material);
        const glm::mat4 m = it->transform.toMatrix();
        CHECK_NEAR_VEC(transformPoint(m, {0, 0, 0}), wall.center);
        CHECK_NEAR_VEC(transformNormal(m, {0, 0, 1}), wall.normal);
        // Every corner lies on the face of the unit cube: all coordinates are +-1.
        for (const glm::vec3 corner : {glm::vec3(-1, -1, 0), glm::vec3(1, -1, 0), glm::vec3(-1, 1, 0),
                                       glm::vec3(1, 1, 0)}) {
            const glm::vec3 p = transformPoint(m, corner);
            INFO("corner " << str(p));
            CHECK(near(glm::abs(p), glm::vec3(1)));
        }
    }

    // The boxes stand on (or just through) the floor.
    const Object& small = scene.objects[5];
    const Object& large = scene.objects[6];
    CHECK(small.shape == Shape::Box);
    CHECK(large.shape == Shape::Box);
    CHECK(small.transform.scale == glm::vec3(0.3f));
    CHECK(transformPoint(small.transform.toMatrix(), {0, -1, 0}).y == Approx(-1.0f).margin(1e-6));
    CHECK(transformPoint(large.transform.toMatrix(), {0, -1, 0}).y == Approx(-1.01f).margin(1e-6));
    CHECK(transformPoint(large.transform.toMatrix(), {0, 1, 0}).y == Approx(0.21f).margin(1e-6));
}

TEST_CASE("Round trip: load(save(load(x))) == load(x)", "[scene_io]") {
    const SceneLoadResult original = GENERATE(loadScene(kCornellBox), parseScene(kEverything, "everything.json"));
    INFO(original.error);
    REQUIRE(original);

    const std::string json = sceneToJson(*original.scene);
    INFO(json);
    const Scene reloaded = mustParse(json);
    CHECK(reloaded == *original.scene);
    CHECK(sceneToJson(reloaded) == json);  // the writer is deterministic

    TempDir dir;
    const std::string file = (dir.path / "saved.json").string();
    std::string error;
    REQUIRE(saveScene(*original.scene, file, &error));
    CHECK(error.empty());
    const SceneLoadResult fromDisk = loadScene(file);
    INFO(fromDisk.error);
    REQUIRE(fromDisk);
    CHECK(*fromDisk.scene == *original.scene);
    CHECK(fromDisk.scene->sourcePath == file);
    CHECK(dir.entries() == std::vector<std::string>{"saved.json"});  // no temporary left behind
}

TEST_CASE("The every-feature scene reads as written", "[scene_io]") {
    const Scene s = mustParse(kEverything);
    CHECK(s.camera.fovAxis == FovAxis::X);
    CHECK(s.render.seed == 4294967295u);
    CHECK(s.render.samples == (1 << 24));
    CHECK(s.render.maxDepth == 0);
    CHECK(s.render.lightSelection == LightSelection::Uniform);
    CHECK(s.materials[1].type == MaterialType::Diffuse);
    CHECK(s.materials[0].emission.z == 1e12f);
    CHECK(s.materials[0].alphaMode == AlphaMode::Opaque);
    CHECK(s.materials[2].alphaMode == AlphaMode::Mask);
    CHECK(s.materials[2].alphaCutoff == 0.25f);
    CHECK(s.materials[2].emissionTexture == "glow.png");
    CHECK(s.objects[0].transform.scale == glm::vec3(0.5f));
    CHECK(s.objects[1].name.empty());
    CHECK(s.objects[1].transform.scale == glm::vec3(2, -3, 1e-3f));
    REQUIRE(s.objects[2].transform.matrix.has_value());
    // Row-major in the file: the translation (5, 6, 7) is the last column.
    CHECK_NEAR_VEC(transformPoint(s.objects[2].transform.toMatrix(), {0, 0, 0}), glm::vec3(5, 6, 7));
    CHECK_NEAR_VEC(transformPoint(s.objects[2].transform.toMatrix(), {0, 0, 1}), glm::vec3(5, 4, 7));
    CHECK_FALSE(s.objects[0].emits());
    CHECK(s.objects[3].emission == glm::vec3(1.5f, 0.0f, 2.0f));
    CHECK(s.objects[3].twoSided);
    CHECK(s.objects[4].emits());
    CHECK_FALSE(s.objects[4].twoSided);  // one-sided unless said otherwise
    CHECK(s.lights[0].twoSided);
    CHECK(s.lights[1].type == LightType::Sphere);
    CHECK(s.lights[1].radius == 0.25f);
    CHECK(s.lights[2].type == LightType::Point);
    CHECK(s.lights[3].outerAngle == 180.0f);
    CHECK(s.lights[3].falloff == SpotFalloff::LinearAngle);
    CHECK(s.lights[4].falloff == SpotFalloff::Smoothstep);  // the default
    CHECK(s.lights[4].direction == Light{}.direction);  // absent keys keep scene.h's defaults
    CHECK(s.environment.type == EnvironmentType::Sky);
    CHECK(s.environment.intensity == 2.5f);
}

TEST_CASE("Absent keys take the defaults of scene.h", "[scene_io]") {
    CHECK(mustParse(R"({"version": 1})") == Scene{});
    const Scene partial = mustParse(R"({"version": 1, "camera": {"fov": 50}, "render": {"samples": 4},
                                        "environment": {"type": "constant"}})");
    Scene expected;
    expected.camera.fovDegrees = 50;
    expected.render.samples = 4;
    expected.environment.type = EnvironmentType::Constant;
    CHECK(partial == expected);
    // Integral floats are integers; 1e3 too.
    CHECK(mustParse(R"({"version": 1, "render": {"width": 1e3, "height": 20.0}})").render.width == 1000);
}

TEST_CASE("A sky preset sets horizon, zenith and intensity, the file's own keys override it", "[scene_io]") {
    const Scene original = mustParse(R"({"version": 1, "environment": {"type": "sky", "preset": "original"}})");
    CHECK(original.environment.type == EnvironmentType::Sky);
    // The values docs/scene-format.md gives for "original".
    CHECK(original.environment.horizon == glm::vec3(0.1f, 0.3f, 0.35f));
    CHECK(original.environment.zenith == glm::vec3(1.0f));
    CHECK(original.environment.intensity == 0.3f);
    // "default" is the sky's defaults of scene.h.
    const Scene byDefault = mustParse(R"({"version": 1, "environment": {"type": "sky", "preset": "default"}})");
    const Scene plain = mustParse(R"({"version": 1, "environment": {"type": "sky"}})");
    CHECK(byDefault == plain);
    // An explicit key wins wherever it stands, before or after "preset".
    for (const char* json : {R"({"version": 1, "environment": {"intensity": 2, "type": "sky", "preset": "original"}})",
                             R"({"version": 1, "environment": {"type": "sky", "preset": "original", "intensity": 2}})"}) {
        INFO(json);
        const Scene s = mustParse(json);
        CHECK(s.environment.intensity == 2.0f);
        CHECK(s.environment.horizon == original.environment.horizon);
    }
    // Saved as the values (the preset is a shorthand, not stored) and read back the same.
    const std::string saved = sceneToJson(original);
    CHECK(saved.find("preset") == std::string::npos);
    CHECK(mustParse(saved) == original);
}

TEST_CASE("Floats survive the round trip bit for bit", "[scene_io]") {
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_real_distribution<float> exponent(-30.0f, 30.0f);
    Scene scene;
    for (int i = 0; i < 300; ++i) {
        Material m;
        m.name = "m" + std::to_string(i);
        m.albedo = {unit(rng), unit(rng), std::nextafter(1.0f, 0.0f)};
        // Emission stays within its limit (1e12); the largest float goes through a translation.
        m.emission = {std::pow(10.0f, 0.4f * exponent(rng)), std::numeric_limits<float>::denorm_min(),
                      std::nextafter(1e12f, 0.0f)};
        scene.materials.push_back(m);
        Object o;
        o.material = m.name;
        o.transform.translate = {-std::pow(10.0f, exponent(rng)), unit(rng) * 1000.0f,
                                 i == 0 ? std::numeric_limits<float>::max() : 0.1f};
        o.transform.rotate = {unit(rng) * 360.0f - 180.0f, -0.0f, 1e-30f};
        scene.objects.push_back(o);
    }
    const Scene reloaded = mustParse(sceneToJson(scene));
    REQUIRE(reloaded.materials.size() == scene.materials.size());
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        INFO("material " << i);
        CHECK(reloaded.materials[i] == scene.materials[i]);
        CHECK(reloaded.objects[i] == scene.objects[i]);
    }
    // Short decimals stay short in the file.
    Scene simple;
    simple.camera.fovDegrees = 39.3077f;
    CHECK(sceneToJson(simple).find("\"fov\": 39.3077,") != std::string::npos);
    CHECK(sceneToJson(simple).find("\"up\": [0, 1, 0]") != std::string::npos);
}

// ---------------------------------------------------------------------------------------------

namespace {

struct BadInput {
    const char* what;
    std::string json;
    std::string path;     // expected JSON path ("" for file-level errors)
    std::string phrase;   // must appear in the message
};

std::string scene(const std::string& body) { return "{\"version\": 1, " + body + "}"; }

const std::string kMaterials = R"("materials": [{"name": "white"}, {"name": "red"}])";

std::string withObject(const std::string& object) {
    return scene(kMaterials + R"(, "objects": [{"material": "white"}, )" + object + "]");
}

std::string withLight(const std::string& light) { return scene(R"("lights": [)" + light + "]"); }

std::string withTransform(const std::string& transform) {
    return withObject(R"({"material": "red", "transform": )" + transform + "}");
}

}  // namespace

TEST_CASE("Bad scenes fail with the JSON path and a clear reason", "[scene_io]") {
    const std::vector<BadInput> cases = {
        // Document level.
        {"top level not an object", "[1, 2]", "", "the top level must be a JSON object, got array"},
        {"missing version", R"({"camera": {}})", "version", "missing"},
        {"wrong version", R"({"version": 2})", "version", "unsupported scene version 2 (this build reads version 1)"},
        {"version as string", R"({"version": "1"})", "version", "must be an integer, got string \"1\""},
        {"unknown top-level key", scene(R"("materail": [])"), "materail",
         "unknown key (allowed: version, camera, render, materials, objects, lights, environment)"},
        {"duplicate key", scene(R"("camera": {"fov": 30, "up": [0, 1, 0], "fov": 40})"), "camera.fov", "duplicate key"},
        // Camera.
        {"unknown nested key", scene(R"("camera": {"fvo": 30})"), "camera.fvo",
         "unknown key (allowed: position, look_at, up, fov, fov_axis, roll, aperture_radius, focal_distance, focus_point, squeeze, blades, blade_rotation, aperture_image, lens, lens_f_stop, sensor_width, lens_dispersion)"},
        {"string for a number", scene(R"("camera": {"fov": "wide"})"), "camera.fov", "must be a number, got string \"wide\""},
        {"lens key without a lens", scene(R"("camera": {"lens_f_stop": 4})"), "camera.lens_f_stop",
         "only a camera with a `lens` takes lens_f_stop"},
        {"empty lens file", scene(R"("camera": {"lens": ""})"), "camera.lens",
         "must not be empty (leave the key out for the thin lens)"},
        {"fov 180", scene(R"("camera": {"fov": 180})"), "camera.fov", "must be < 180, got 180"},
        {"fov 0", scene(R"("camera": {"fov": 0})"), "camera.fov", "must be > 0, got 0"},
        {"1e999 overflows", scene(R"("camera": {"fov": 1e999})"), "camera.fov", "number out of range"},
        {"1e999 in an array", withLight(R"({"position": [0, 0, -1e999]})"), "lights[0].position[2]", "number out of range"},
        {"beyond float range", scene(R"("camera": {"fov": 1e39})"), "camera.fov", "must be a finite 32-bit float"},
        {"2-element vector", scene(R"("camera": {"position": [1, 2]})"), "camera.position",
         "must be an array of 3 numbers, got array [1,2]"},
        {"vector of strings", scene(R"("camera": {"up": [0, "1", 0]})"), "camera.up[1]", "must be a number"},
        {"null for a vector", scene(R"("camera": {"up": null})"), "camera.up", "must be an array of 3 numbers, got null"},
        {"look_at == position", scene(R"("camera": {"position": [1, 2, 3], "look_at": [1, 2, 3]})"),
         "camera.look_at", "must differ from position"},
        {"up parallel to view", scene(R"("camera": {"position": [0, 5, 0], "look_at": [0, 0, 0]})"),
         "camera.up", "parallel to the view direction"},
        {"zero up", scene(R"("camera": {"up": [0, 0, 0]})"), "camera.up", "must be non-zero"},
        {"unknown fov_axis", scene(R"("camera": {"fov_axis": "diagonal"})"), "camera.fov_axis",
         "unknown value 'diagonal' (allowed: smaller, larger, x, y)"},
        // Render settings.
        {"section not an object", scene(R"("render": 5)"), "render", "must be an object, got number 5"},
        {"negative samples", scene(R"("render": {"samples": -4})"), "render.samples", "must be >= 1, got -4"},
        {"too many samples", scene(R"("render": {"samples": 16777217})"), "render.samples", "must be <= 16777216, got 16777217"},
        {"bool as number", scene(R"("render": {"samples": true})"), "render.samples", "must be an integer, got boolean true"},
        {"non-integer width", scene(R"("render": {"width": 10.5})"), "render.width", "must be an integer, got 10.5"},
        {"zero height", scene(R"("render": {"height": 0})"), "render.height", "must be >= 1, got 0"},
        {"huge width", scene(R"("render": {"width": 16385})"), "render.width", "must be <= 16384"},
        {"negative max_depth", scene(R"("render": {"max_depth": -1})"), "render.max_depth", "must be >= 0"},
        {"negative seed", scene(R"("render": {"seed": -1})"), "render.seed", "must be >= 0, got -1"},
        {"seed over 32 bits", scene(R"("render": {"seed": 4294967296})"), "render.seed", "must be <= 4294967295"},
        {"unknown light_selection", scene(R"("render": {"light_selection": "random"})"),
         "render.light_selection", "unknown value 'random' (allowed: power, uniform, tree)"},
        // Materials.
        {"materials not an array", scene(R"("materials": {"name": "white"})"), "materials", "must be an array"},
        {"material without name", scene(R"("materials": [{"albedo": [1, 1, 1]}])"), "materials[0]", "missing key 'name'"},
        {"empty material name", scene(R"("materials": [{"name": ""}])"), "materials[0].name", "must not be empty"},
        {"duplicate material", scene(R"("materials": [{"name": "white"}, {"name": "red"}, {"name": "white"}])"),
         "materials[2].name", "duplicate material name 'white' (also materials[0])"},
        {"albedo above 1", scene(R"("materials": [{"name": "w", "albedo": [1.5, 0, 0]}])"),
         "materials[0].albedo[0]", "must be <= 1, got 1.5"},
        {"negative emission", scene(R"("materials": [{"name": "w", "emission": [0, -1, 0]}])"),
         "materials[0].emission[1]", "must be >= 0, got -1"},
        {"unknown material type", scene(R"("materials": [{"name": "w", "type": "glass"}])"),
         "materials[0].type", "unknown value 'glass' (allowed: diffuse, oren_nayar, eon, mirror, transmission, dielectric, conductor, surface, volume)"},
        {"unknown material key", scene(R"("materials": [{"name": "w", "roughness": 0.5}])"),
         "materials[0].roughness", "unknown key for a 'diffuse' material (allowed: name, type, albedo, emission, albedo_texture, normal_texture, "
         "normal_scale, roughness_texture, emission_texture, alpha_mode, alpha_cutoff)"},
        {"eta on a preset metal", scene(R"("materials": [{"name": "g", "type": "conductor", "metal": "gold", "eta": [1, 1, 1]}])"),
         "materials[0].eta", "only a 'custom' metal takes eta and k (this one is 'gold')"},
        {"unknown metal", scene(R"("materials": [{"name": "g", "type": "conductor", "metal": "brass"}])"),
         "materials[0].metal", "unknown value 'brass' (allowed: aluminium, gold, copper, silver, chromium, platinum, perfect, custom)"},
        {"roughness above 1", scene(R"("materials": [{"name": "g", "type": "dielectric", "roughness": 1.5}])"),
         "materials[0].roughness", "must be <= 1, got 1.5"},
        {"zero ior", scene(R"("materials": [{"name": "g", "type": "dielectric", "ior": 0}])"),
         "materials[0].ior", "must be > 0, got 0"},
        {"negative alpha_cutoff", scene(R"("materials": [{"name": "g", "alpha_mode": "mask", "alpha_cutoff": -0.5}])"),
         "materials[0].alpha_cutoff", "must be >= 0, got -0.5"},
        {"unknown alpha_mode", scene(R"("materials": [{"name": "g", "alpha_mode": "blend"}])"),
         "materials[0].alpha_mode", "unknown value 'blend' (allowed: opaque, mask)"},
        {"texture not a string", scene(R"("materials": [{"name": "g", "albedo_texture": 3}])"),
         "materials[0].albedo_texture", "must be a string, got number 3"},
        // Objects.
        {"missing material ref", withObject(R"({"material": "blue"})"), "objects[1].material",
         "unknown material 'blue' (known: white, red)"},
        {"object without material", withObject(R"({"shape": "box"})"), "objects[1].material", "every object needs a material"},
        {"no materials at all", scene(R"("objects": [{"material": "white"}])"), "objects[0].material",
         "unknown material 'white' (no materials are defined)"},
        {"object not an object", withObject("42"), "objects[1]", "must be an object, got number 42"},
        {"unknown shape", withObject(R"({"material": "red", "shape": "cone"})"), "objects[1].shape",
         "unknown value 'cone' (allowed: sphere, quad, box, mesh)"},
        {"unknown object key", withObject(R"({"material": "red", "colour": [1, 0, 0]})"), "objects[1].colour",
         "unknown key for a 'sphere' object (allowed: name, shape, material, transform, emission, two_sided)"},
        {"negative object emission", withObject(R"({"material": "red", "emission": [1, -1, 0]})"), "objects[1].emission[1]",
         "must be >= 0, got -1"},
        {"two_sided as a number", withObject(R"({"material": "red", "emission": [1, 1, 1], "two_sided": 0})"),
         "objects[1].two_sided", "must be true or false, got number 0"},
        {"emission on a mesh with its file's materials", withObject(R"({"shape": "mesh", "file": "a.obj", "emission": [1, 1, 1]})"),
         "objects[1].emission", "cannot take an object emission"},
        {"mesh without a file", withObject(R"({"material": "red", "shape": "mesh"})"), "objects[1].file",
         "a mesh object needs a model file"},
        {"file on a sphere", withObject(R"({"material": "red", "file": "a.obj"})"), "objects[1].file",
         "unknown key for a 'sphere' object"},
        // Transforms.
        {"unknown transform key", withTransform(R"({"skew": 1})"), "objects[1].transform.skew",
         "unknown key (allowed: translate, rotate, scale, matrix)"},
        {"zero scale", withTransform(R"({"scale": 0})"), "objects[1].transform.scale", "must be non-zero"},
        {"zero scale component", withLight(R"({"type": "rect", "transform": {"scale": [1, 0, 1]}})"),
         "lights[0].transform.scale[1]", "must be non-zero"},
        {"scale of 2", withTransform(R"({"scale": [1, 2]})"), "objects[1].transform.scale",
         "must be a number or an array of 3 numbers"},
        {"singular matrix", withTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,0,0, 0,0,0,1]})"),
         "objects[1].transform.matrix", "must be invertible"},
        {"projective matrix", withTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]})"),
         "objects[1].transform.matrix", "the last row must be [0, 0, 0, 1]"},
        {"15-number matrix", withTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0]})"),
         "objects[1].transform.matrix", "must be an array of 16 numbers (row-major)"},
        {"matrix with translate", withTransform(R"({"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "translate": [1, 2, 3]})"),
         "objects[1].transform.translate", "cannot be combined with 'matrix'"},
        // Lights.
        {"unknown light type", withLight(R"({"type": "area"})"), "lights[0].type",
         "unknown value 'area' (allowed: rect, sphere, point, spot)"},
        {"key of another light type", withLight(R"({"type": "point", "radius": 1})"), "lights[0].radius",
         "unknown key for a 'point' light (allowed: name, type, color, position)"},
        {"number as bool", withLight(R"({"type": "rect", "two_sided": 1})"), "lights[0].two_sided",
         "must be true or false, got number 1"},
        {"negative color", withLight(R"({"color": [1, 1, -0.5]})"), "lights[0].color[2]", "must be >= 0, got -0.5"},
        {"zero radius", withLight(R"({"type": "sphere", "radius": 0})"), "lights[0].radius", "must be > 0, got 0"},
        {"spot inner > outer", withLight(R"({"type": "spot", "inner_angle": 40, "outer_angle": 30})"),
         "lights[0].inner_angle", "must be <= outer_angle (30), got 40"},
        {"spot outer 0", withLight(R"({"type": "spot", "inner_angle": 0, "outer_angle": 0})"),
         "lights[0].outer_angle", "must be > 0, got 0"},
        {"spot outer above 180", withLight(R"({"type": "spot", "outer_angle": 181})"),
         "lights[0].outer_angle", "must be <= 180, got 181"},
        {"unknown spot falloff", withLight(R"({"type": "spot", "falloff": "linear"})"), "lights[0].falloff",
         "unknown value 'linear' (allowed: smoothstep, linear_angle)"},
        {"falloff on a point light", withLight(R"({"type": "point", "falloff": "smoothstep"})"), "lights[0].falloff",
         "unknown key for a 'point' light"},
        {"spot zero direction", withLight(R"({"type": "spot", "direction": [0, 0, 0]})"),
         "lights[0].direction", "must be non-zero"},
        {"name as number", withLight(R"({"name": 7})"), "lights[0].name", "must be a string, got number 7"},
        // Environment.
        {"unknown environment type", scene(R"("environment": {"type": "hdri"})"), "environment.type",
         "unknown value 'hdri' (allowed: none, constant, sky, map)"},
        {"key of another environment type", scene(R"("environment": {"type": "sky", "radiance": [1, 1, 1]})"),
         "environment.radiance", "unknown key for a 'sky' environment (allowed: type, preset, horizon, zenith, intensity, medium_sigma_a, medium_sigma_s, medium_anisotropy)"},
        {"unknown sky preset", scene(R"("environment": {"type": "sky", "preset": "dusk"})"), "environment.preset",
         "unknown value 'dusk' (allowed: default, original)"},
        {"sky preset as number", scene(R"("environment": {"type": "sky", "preset": 1})"), "environment.preset",
         "must be a string, got number 1"},
        {"preset on a constant environment", scene(R"("environment": {"type": "constant", "preset": "original"})"),
         "environment.preset", "unknown key for a 'constant' environment"},
        {"negative intensity", scene(R"("environment": {"type": "constant", "intensity": -1})"),
         "environment.intensity", "must be >= 0, got -1"},
    };
    for (const BadInput& bad : cases) {
        INFO("case: " << bad.what << "\njson: " << bad.json);
        const SceneLoadResult result = parseScene(bad.json, "scenes/x.json");
        CHECK_FALSE(result);
        CHECK_FALSE(result.scene.has_value());
        INFO("message: " << result.error);
        const std::string prefix = "scenes/x.json: " + (bad.path.empty() ? "" : bad.path + ": ");
        CHECK(result.error.rfind(prefix, 0) == 0);
        CHECK(result.error.find(bad.phrase) != std::string::npos);
        CHECK(result.error.find('\n') == std::string::npos);
    }
}

TEST_CASE("JSON syntax errors give line and column", "[scene_io]") {
    const SceneLoadResult result = parseScene("{\n  \"version\": 1,\n  \"camera\": ]\n}", "x.json");
    REQUIRE_FALSE(result);
    INFO(result.error);
    CHECK(result.error.rfind("x.json:3:13: JSON syntax error: ", 0) == 0);
    CHECK(result.error.find("unexpected ']'") != std::string::npos);
    CHECK(result.error.find("[json.exception") == std::string::npos);

    // Columns count characters, not bytes: "é" is two bytes.
    const SceneLoadResult utf8 = parseScene("{\"version\": 1, \"lights\": [{\"name\": \"é\", x}]}", "u.json");
    INFO(utf8.error);
    CHECK(utf8.error.rfind("u.json:1:41: JSON syntax error: ", 0) == 0);

    const SceneLoadResult empty = parseScene("", "e.json");
    CHECK(empty.error.rfind("e.json:1:1: JSON syntax error: ", 0) == 0);
    const SceneLoadResult trailing = parseScene("{\"version\": 1}\n,", "t.json");
    INFO(trailing.error);
    CHECK(trailing.error.rfind("t.json:2:1: JSON syntax error: ", 0) == 0);
}

// ---------------------------------------------------------------------------------------------

TEST_CASE("Unreadable scene files", "[scene_io]") {
    const SceneLoadResult missing = loadScene("/nonexistent/dir/scene.json");
    REQUIRE_FALSE(missing);
    CHECK(missing.error == "/nonexistent/dir/scene.json: cannot read: No such file or directory");

    TempDir dir;
    const SceneLoadResult directory = loadScene(dir.path.string());
    REQUIRE_FALSE(directory);
    CHECK(directory.error == dir.path.string() + ": cannot read: Is a directory");
}

TEST_CASE("Saving is atomic and reports failures", "[scene_io][file_util]") {
    const SceneLoadResult cornell = loadScene(kCornellBox);
    REQUIRE(cornell);
    TempDir dir;

    SECTION("the parent is not a directory: nothing is created") {
        const fs::path parent = dir.path / "plain-file";
        std::ofstream(parent) << "x";
        const std::string file = (parent / "scene.json").string();
        std::string error;
        CHECK_FALSE(saveScene(*cornell.scene, file, &error));
        INFO(error);
        CHECK(error.rfind(file + ": cannot write: ", 0) == 0);
        CHECK(error.find("Not a directory") != std::string::npos);
        CHECK(dir.entries() == std::vector<std::string>{"plain-file"});
    }
    SECTION("the final rename fails: the temporary file is removed") {
        const fs::path target = dir.path / "scene.json";
        fs::create_directory(target);  // a directory where the file should go
        fs::create_directory(target / "keep");
        std::string error;
        CHECK_FALSE(saveScene(*cornell.scene, target.string(), &error));
        INFO(error);
        CHECK(error.rfind(target.string() + ": cannot write: ", 0) == 0);
        CHECK(error.find("Is a directory") != std::string::npos);
        CHECK(dir.entries() == std::vector<std::string>{"scene.json"});
        CHECK(fs::is_directory(target / "keep"));
    }
    SECTION("an existing file is replaced whole") {
        const fs::path target = dir.path / "scene.json";
        std::ofstream(target) << "old contents";
        std::string error;
        REQUIRE(saveScene(*cornell.scene, target.string(), &error));
        CHECK(readTextFile(target.string(), nullptr) == sceneToJson(*cornell.scene));
        CHECK(dir.entries() == std::vector<std::string>{"scene.json"});
    }
    SECTION("an invalid scene is not written") {
        Scene bad = *cornell.scene;
        bad.objects[0].material = "blue";
        bad.camera.fovDegrees = std::nanf("");
        const fs::path target = dir.path / "scene.json";
        std::string error;
        CHECK_FALSE(saveScene(bad, target.string(), &error));
        INFO(error);
        CHECK(error.rfind(target.string() + ": not saved, the scene is invalid: camera.fov: ", 0) == 0);
        CHECK(dir.entries().empty());
    }
}

TEST_CASE("File helpers", "[file_util]") {
    const std::string tmp = tempPathBeside("some/dir/image.png");
    INFO(tmp);
    CHECK(tmp.rfind("some/dir/.image.png.tmp-" + std::to_string(::getpid()) + "-", 0) == 0);
    CHECK(tmp.size() > 4);
    CHECK(tmp.substr(tmp.size() - 4) == ".png");
    CHECK(tempPathBeside("some/dir/image.png") != tmp);
    const std::string bare = tempPathBeside("Makefile");
    CHECK(bare.rfind(".Makefile.tmp-", 0) == 0);
    CHECK(bare.find('.', 1) == std::string("Makefile").size() + 1);  // no extension appended

    TempDir dir;
    const std::string file = (dir.path / "a.txt").string();
    std::string error;
    REQUIRE(writeFileAtomically(file, std::string("hello\0world", 11), &error));
    CHECK(readTextFile(file, &error) == std::string("hello\0world", 11));
    REQUIRE(writeFileAtomically(file, "", &error));
    CHECK(readTextFile(file, &error) == std::string());
    CHECK(dir.entries() == std::vector<std::string>{"a.txt"});

    const std::string missing = (dir.path / "nope.txt").string();
    CHECK_FALSE(readTextFile(missing, &error).has_value());
    CHECK(error == missing + ": cannot read: No such file or directory");

    // commitTempFile removes the temporary when the rename fails.
    const std::string tmpFile = tempPathBeside(file);
    std::ofstream(tmpFile) << "x";
    CHECK_FALSE(commitTempFile(tmpFile, (dir.path / "missing-dir" / "b.txt").string(), &error));
    CHECK(error.find("No such file or directory") != std::string::npos);
    CHECK_FALSE(fs::exists(tmpFile));
}

TEST_CASE("The example in docs/scene-format.md loads", "[scene_io]") {
    const std::string docPath = std::string(CAUSTIC_SOURCE_DIR) + "/docs/scene-format.md";
    std::string error;
    const std::optional<std::string> doc = readTextFile(docPath, &error);
    INFO(error);
    REQUIRE(doc.has_value());
    const std::size_t start = doc->find("```json\n");
    REQUIRE(start != std::string::npos);
    const std::size_t end = doc->find("```", start + 8);
    REQUIRE(end != std::string::npos);
    const Scene example = mustParse(doc->substr(start + 8, end - start - 8));
    CHECK(example.objects.size() == 2);
    CHECK(example.lights.size() == 1);
    CHECK(example.environment.type == EnvironmentType::Sky);
}

TEST_CASE("a lens-system camera reads and writes its keys, and the thin lens's aperture is read and ignored beside it",
          "[cpu][scene][lens]") {
    const SceneLoadResult r = parseScene(R"({"version": 1, "camera": {"position": [0, 1, 5], "aperture_radius": 0.2,
        "squeeze": 1.5, "lens": "../assets/lenses/dgauss-50mm.lens", "lens_f_stop": 2.8, "sensor_width": 24,
        "lens_dispersion": false, "aperture_image": "star.png"}})", "scenes/x.json");
    REQUIRE(r.error.empty());
    const Camera& c = r.scene->camera;
    CHECK(c.lens == "../assets/lenses/dgauss-50mm.lens");
    CHECK(c.lensFStop == 2.8f);
    CHECK(c.sensorWidthMm == 24.0f);
    CHECK_FALSE(c.lensDispersion);
    CHECK(c.apertureImage == "star.png");
    // Written back: the lens keys, not the thin lens's (they do nothing with a lens).
    const std::string text = sceneToJson(*r.scene);
    CHECK(text.find("\"lens_f_stop\"") != std::string::npos);
    CHECK(text.find("\"aperture_image\"") != std::string::npos);
    CHECK(text.find("\"aperture_radius\"") == std::string::npos);
    CHECK(text.find("\"squeeze\"") == std::string::npos);
    const SceneLoadResult again = parseScene(text, "scenes/x.json");
    REQUIRE(again.error.empty());
    CHECK(again.scene->camera.lens == c.lens);
    CHECK(again.scene->camera.lensFStop == c.lensFStop);
    // Without a lens the lens keys are refused, as every key of another mode is.
    CHECK(parseScene(R"({"version": 1, "camera": {"sensor_width": 24}})", "x.json").error.find("only a camera with a `lens`") !=
          std::string::npos);
}
