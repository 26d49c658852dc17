// The scene schema (renderer/scene_schema.h) against the loader: for every parameter of every
// struct and type, a value just outside its range (and NaN for every float) is refused by
// validateScene (no JSON) and by the file reader (the scene written and read back, as saveScene
// does), both naming the same place; the rules across fields agree; every scene of scenes/ is
// valid. And the camera's photographic terms (focal length, f-number).
#include "renderer/camera.h"
#include "renderer/scene_io.h"
#include "renderer/scene_schema.h"
#include "tests/support/scenes.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

using namespace caustic;

namespace {

// The loader's verdict on the scene (written and read back), "" when it loads.
std::string loaderError(const Scene& s) {
    const std::string text = sceneToJson(s);
    const SceneLoadResult r = parseScene(text, "x.json");
    return r ? "" : r.error;
}

// Values just outside the range (below, above) where the range has those ends.
std::vector<double> outsideValues(const Range& r, bool integer) {
    std::vector<double> out;
    if (std::isfinite(r.min))
        out.push_back(r.minExclusive ? r.min : integer ? r.min - 1 : std::nextafter(float(r.min), -1e30f));
    if (std::isfinite(r.max))
        out.push_back(r.maxExclusive ? r.max : integer ? r.max + 1 : std::nextafter(float(r.max), 1e30f));
    return out;
}

// Sets the parameter's value (component 0 of a vector) in `value`; false if it cannot hold x.
template <class T>
bool setNumber(const Param<T>& p, T& value, double x) {
    bool set = false;
    std::visit(
        [&](auto m) {
            using M = decltype(m);
            if constexpr (std::is_same_v<M, float T::*>) {
                value.*m = float(x);
                set = true;
            } else if constexpr (std::is_same_v<M, int T::*>) {
                if (x >= INT_MIN && x <= INT_MAX) value.*m = int(x), set = true;
            } else if constexpr (std::is_same_v<M, std::uint32_t T::*>) {
                if (x >= 0 && x <= 4294967295.0) value.*m = std::uint32_t(x), set = true;
            } else if constexpr (std::is_same_v<M, glm::vec3 T::*>) {
                (value.*m).x = float(x);
                set = true;
            } else if constexpr (std::is_same_v<M, std::optional<glm::vec3> T::*>) {
                if (value.*m) (*(value.*m)).x = float(x), set = true;
            }
        },
        p.member);
    return set;
}

int checked = 0;

// For each entity `pick(scene)[i]` of type T in the scene, every numeric parameter that applies.
// Every numeric parameter of the value that `value(scene)` picks, at `path` ("materials[2]",
// "camera"): values just outside its range, and NaN, refused by both at the same place.
template <class T>
void checkValue(const Scene& base, const std::function<T&(Scene&)>& value, const std::string& path) {
    Scene probe = base;
    for (const Param<T>& p : schemaOf<T>()) {
        const bool integer = p.kind == ParamKind::Int || p.kind == ParamKind::UInt;
        const bool numeric = integer || p.kind == ParamKind::Float || p.kind == ParamKind::Vector ||
                             p.kind == ParamKind::Colour || p.kind == ParamKind::Radiance ||
                             p.kind == ParamKind::OptionalPoint;
        if (!numeric || !appliesTo(p, value(probe))) continue;
        std::vector<double> bad = outsideValues(p.range, integer);
        if (!integer) bad.push_back(std::numeric_limits<double>::quiet_NaN());
        const bool vector = p.kind != ParamKind::Float && !integer;
        const std::string where = path + "." + std::string(p.key) + (vector ? "[0]" : "");
        for (const double x : bad) {
            Scene s = base;
            if (!setNumber(p, value(s), x)) continue;
            INFO(where << " = " << x);
            const auto v = validateScene(s);
            REQUIRE(v.has_value());
            CHECK(v->key == where);
            CHECK(loaderError(s).find(": " + where + ":") != std::string::npos);
            ++checked;
        }
    }
}

template <class T>
void checkEntities(const Scene& base, std::vector<T> Scene::*list, const std::string& name) {
    for (std::size_t i = 0; i < (base.*list).size(); ++i)
        checkValue<T>(base, [&](Scene& s) -> T& { return (s.*list)[i]; }, name + "[" + std::to_string(i) + "]");
}

template <class T>
void checkOne(const Scene& base, T Scene::*member, const std::string& name) {
    checkValue<T>(base, [&](Scene& s) -> T& { return s.*member; }, name);
}

}  // namespace

TEST_CASE("schema: validateScene and the file reader refuse the same out-of-range values at the same place",
          "[schema]") {
    const Scene base = test::everyTypeScene();
    REQUIRE(!validateScene(base).has_value());
    REQUIRE(loaderError(base).empty());
    checked = 0;
    checkEntities(base, &Scene::materials, "materials");
    checkEntities(base, &Scene::objects, "objects");
    checkEntities(base, &Scene::lights, "lights");
    checkOne(base, &Scene::camera, "camera");
    checkOne(base, &Scene::render, "render");
    for (const EnumChoice& c : enumChoices(EnvironmentType{})) {
        Scene s = base;
        s.environment.type = static_cast<EnvironmentType>(c.value);
        if (s.environment.type == EnvironmentType::Map) s.environment.file = "sky.hdr";
        checkOne(s, &Scene::environment, "environment");
    }
    INFO(checked << " values checked");
    CHECK(checked > 80);
}

TEST_CASE("schema: the rules across fields are the loader's", "[schema]") {
    Scene s = test::everyTypeScene();
    s.camera.focusPoint = s.camera.position + (s.camera.position - s.camera.lookAt);  // behind the camera
    auto v = validateScene(s);
    REQUIRE(v.has_value());
    CHECK(v->key == "camera.focus_point");
    CHECK(loaderError(s).find(": camera.focus_point: must lie in front of the camera") != std::string::npos);

    s = test::everyTypeScene();
    s.lights[3].innerAngle = 40.0f;  // the spot
    s.lights[3].outerAngle = 30.0f;
    v = validateScene(s);
    REQUIRE(v.has_value());
    CHECK(v->key == "lights[3].inner_angle");
    CHECK(loaderError(s).find(": lights[3].inner_angle: must be <= outer_angle") != std::string::npos);

    s = test::everyTypeScene();
    s.objects[0].material = "nothing";
    v = validateScene(s);
    REQUIRE(v.has_value());
    CHECK(v->key == "objects[0].material");
    CHECK(loaderError(s).find(": objects[0].material: unknown material 'nothing'") != std::string::npos);
}

TEST_CASE("schema: every scene of scenes/ is valid", "[schema]") {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(CAUSTIC_SOURCE_DIR) + "/scenes")) {
        if (entry.path().extension() != ".json") continue;
        const SceneLoadResult r = loadScene(entry.path().string());
        INFO(entry.path().string() << ": " << r.error);
        REQUIRE(r);
        const auto v = validateScene(*r.scene);
        CHECK(!v.has_value());
        ++scenes;
    }
    CHECK(scenes >= 5);
}

// ---------------------------------------------------------------------------------------------
// The camera's photographic terms (renderer/camera.h).

TEST_CASE("camera: focal length and f-number of a full-frame camera", "[camera]") {
    Camera c;
    c.fovAxis = FovAxis::X;
    // A 50 mm lens on a 36 mm wide sensor: 2 atan(18 / 50) across.
    c.fovDegrees = float(2.0 * std::atan(18.0 / 50.0) * 180.0 / 3.14159265358979323846);
    CHECK(focalLengthMm(cameraFrame(c, 1.5)) == Approx(50.0).epsilon(1e-6));
    // f/2 at 50 mm: an aperture of 25 mm diameter, a radius of 0.0125 scene units (metres).
    CameraFrame f = cameraFrame(c, 1.5);
    CHECK(apertureRadiusForFNumber(f, 2.0) == Approx(0.0125));
    c.apertureRadius = 0.0125f;
    CHECK(fNumber(cameraFrame(c, 1.5)) == Approx(2.0).epsilon(1e-6));
    c.apertureRadius = 0.0f;
    CHECK(std::isinf(fNumber(cameraFrame(c, 1.5))));
    // fovForFocalLength inverts focalLengthMm for every fov axis, landscape and portrait.
    for (const FovAxis axis : {FovAxis::Smaller, FovAxis::Larger, FovAxis::X, FovAxis::Y})
        for (const double aspect : {1.5, 0.6, 1.0})
            for (const double mm : {14.0, 35.0, 85.0, 400.0}) {
                Camera k;
                k.fovAxis = axis;
                k.fovDegrees = float(fovForFocalLength(k, aspect, mm));
                INFO("axis " << int(axis) << " aspect " << aspect << " mm " << mm << " fov " << k.fovDegrees);
                CHECK(k.fovDegrees > 0.0f);
                CHECK(k.fovDegrees < 180.0f);
                CHECK(focalLengthMm(cameraFrame(k, aspect)) == Approx(mm).epsilon(1e-5));
            }
}
