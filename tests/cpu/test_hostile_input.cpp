// Hostile input and hard limits (issue 12, docs/reliability.md): writes that cannot lie (a
// failed write keeps the old file and leaves no temporary, also when a signal arrives mid-write),
// short temporary names, bounded JSON nesting, regular files only, image sizes checked from the
// header, strict strings, and textures of unused model materials not loaded.
//
// Failures are made real where it is cheap: a file size limit (RLIMIT_FSIZE) makes write() fail
// with EFBIG like a full disk fails it with ENOSPC; each such case runs in a forked child so the
// limit and the signals stay out of the test process.
#include "renderer/file_util.h"
#include "renderer/gpu_limits.h"
#include "renderer/gpu_scene.h"
#include "renderer/hdr_file.h"
#include "renderer/scene_io.h"
#include "tests/support/meshes.h"

#include <catch2/catch.hpp>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace caustic;
namespace fs = std::filesystem;

namespace {

const std::string kCornellBox = std::string(CAUSTIC_SOURCE_DIR) + "/scenes/cornell-box.json";

std::vector<std::string> entries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    return names;
}

std::string slurp(const std::string& path) {
    std::string error;
    return readTextFile(path, &error).value_or("<unreadable: " + error + ">");
}

// Runs body in a forked child under a file size limit of `limit` bytes, with SIGXFSZ ignored so
// that an oversized write() fails with EFBIG instead of killing the process. Returns the child's
// wait status; body's return value is the exit code.
template <class Body>
int inChildWithFileLimit(rlim_t limit, Body body) {
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit r{limit, limit};
        ::setrlimit(RLIMIT_FSIZE, &r);
        ::_exit(body());
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
}

// 100,000 nested arrays as the camera: the shape of the file that crashed the loader.
std::string deeplyNestedScene(std::size_t depth) {
    return R"({"version": 1, "camera": )" + std::string(depth, '[') + std::string(depth, ']') + "}";
}

}  // namespace

// ---- 1. Writes that cannot lie ------------------------------------------------------------------

TEST_CASE("hostile: a write that fails (file size limit) reports it and keeps the previous file", "[hostile][file_util]") {
    test::TempDir dir;
    const std::string file = dir.file("out.bin");
    std::string error;
    REQUIRE(writeFileAtomically(file, std::string(100, 'a'), &error));
    const int status = inChildWithFileLimit(1000, [&] {
        std::string why;
        const bool ok = writeFileAtomically(file, std::string(5000, 'b'), &why);
        // Exit codes say what the child saw: 0 the expected failure with the file named.
        if (ok) return 10;
        if (why.find(file + ": cannot write:") != 0) return 11;
        if (why.find("File too large") == std::string::npos) return 12;
        return 0;
    });
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(slurp(file) == std::string(100, 'a'));
    CHECK(entries(dir.path) == std::vector<std::string>{"out.bin"});
}

TEST_CASE("hostile: a scene save that fails (file size limit) keeps the previous scene file", "[hostile][scene_io]") {
    test::TempDir dir;
    const std::string file = dir.file("scene.json");
    const SceneLoadResult cornell = loadScene(kCornellBox);
    REQUIRE(cornell);
    Scene small = *cornell.scene;
    small.objects.resize(1);
    std::string error;
    REQUIRE(saveScene(small, file, &error));
    const std::string before = slurp(file);
    REQUIRE(before.size() < 2000);
    const int status = inChildWithFileLimit(2000, [&] {
        std::string why;
        if (saveScene(*cornell.scene, file, &why)) return 10;  // the full box is larger than the limit
        return why.find(file + ": cannot write:") == 0 ? 0 : 11;
    });
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    CHECK(slurp(file) == before);
    CHECK(entries(dir.path) == std::vector<std::string>{"scene.json"});
}

TEST_CASE("hostile: SIGTERM, SIGINT, SIGHUP or SIGQUIT during a write leaves no temporary file", "[hostile][file_util]") {
    // The signal arrives while write() is under way: the file size limit raises SIGXFSZ inside
    // the write, and its handler sends the process the signal under test.
    for (const int sig : {SIGTERM, SIGINT, SIGHUP, SIGQUIT}) {
        INFO("signal " << sig);
        test::TempDir dir;
        const std::string file = dir.file("image.exr");
        std::fflush(nullptr);
        const pid_t pid = ::fork();
        if (pid == 0) {
            for (const int s : {SIGTERM, SIGINT, SIGHUP, SIGQUIT}) std::signal(s, SIG_DFL);  // as in a plain program
            const rlimit noCore{0, 0};  // SIGQUIT's default action dumps core: not into the test's folder
            ::setrlimit(RLIMIT_CORE, &noCore);
            static int s_signal = 0;
            s_signal = sig;
            std::signal(SIGXFSZ, [](int) { ::raise(s_signal); });
            const rlimit r{1000, 1000};
            ::setrlimit(RLIMIT_FSIZE, &r);
            std::string why;
            writeFileAtomically(file, std::string(5000, 'x'), &why);
            ::_exit(3);  // not reached: the signal ends the process
        }
        int status = 0;
        ::waitpid(pid, &status, 0);
        REQUIRE(WIFSIGNALED(status));  // the signal still has its usual effect
        CHECK(WTERMSIG(status) == sig);
        CHECK(entries(dir.path).empty());
    }
}

TEST_CASE("hostile: a registered temporary file is removed on SIGTERM, an unregistered one is not", "[hostile][file_util]") {
    test::TempDir dir;
    const std::string registered = dir.file(".a.tmp-1");
    const std::string other = dir.file(".b.tmp-1");
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::signal(SIGTERM, SIG_DFL);  // the test framework's handler, as in a plain program
        TempFileRegistration reg(registered);
        std::ofstream(registered) << "x";
        std::ofstream(other) << "y";
        ::raise(SIGTERM);
        ::_exit(3);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGTERM);
    CHECK(entries(dir.path) == std::vector<std::string>{".b.tmp-1"});
}

TEST_CASE("hostile: temporary names stay short, so a 250-byte file name can be written", "[hostile][file_util]") {
    test::TempDir dir;
    // 249 bytes of name with two-byte characters around the cut, plus ".png": 253 bytes in all.
    std::string name(61, 'n');
    for (int i = 0; i < 60; ++i) name += "\xc3\xa9";  // é
    name += std::string(249 - name.size(), 'x');
    name += ".png";
    REQUIRE(name.size() == 253);
    const std::string path = dir.file(name);
    const std::string tmp = tempPathBeside(path);
    const std::string tmpName = fs::path(tmp).filename().string();
    INFO(tmpName);
    CHECK(tmpName.size() <= 120);
    CHECK(tmpName.substr(tmpName.size() - 4) == ".png");
    // Cut on a character boundary: no lone continuation byte right before ".tmp-".
    const std::size_t at = tmpName.find(".tmp-");
    REQUIRE(at != std::string::npos);
    CHECK((static_cast<unsigned char>(tmpName[at - 1]) & 0xC0) != 0xC0);
    std::string error;
    CHECK(writeFileAtomically(path, "hello", &error));
    INFO(error);
    CHECK(slurp(path) == "hello");
    CHECK(entries(dir.path) == std::vector<std::string>{name});
}

// ---- 2. Bounded JSON nesting ---------------------------------------------------------------------

TEST_CASE("hostile: a scene nested 100,000 deep is refused with a position, not a crash", "[hostile][scene_io]") {
    const std::string deep = deeplyNestedScene(100000);
    const SceneLoadResult parsed = parseScene(deep, "deep.json");
    REQUIRE_FALSE(parsed);
    CHECK(parsed.error == "deep.json:1:89: arrays and objects nested deeper than 64 levels");

    test::TempDir dir;
    const std::string file = dir.file("deep.json");
    std::ofstream(file) << deep;
    const SceneLoadResult loaded = loadScene(file);
    REQUIRE_FALSE(loaded);
    CHECK(loaded.error.find(file + ":1:89: arrays and objects nested deeper than 64 levels") == 0);
    // Through the --set path (which parses the file itself first).
    const SceneLoadResult overridden = loadScene(file, {{"camera.fov", "30"}});
    REQUIRE_FALSE(overridden);
    CHECK(overridden.error.find("nested deeper than 64 levels") != std::string::npos);
    // A deep --set value.
    const SceneLoadResult deepValue = loadScene(kCornellBox, {{"camera.fov", std::string(100000, '[') + std::string(100000, ']')}});
    REQUIRE_FALSE(deepValue);
    CHECK(deepValue.error.find("--set camera.fov=[[[[") == 0);
    CHECK(deepValue.error.find("the value has arrays and objects nested deeper than 64 levels") != std::string::npos);
    CHECK(deepValue.error.size() < 200);
    // Strings may hold any number of brackets.
    CHECK(parseScene(R"({"version": 1, "materials": [{"name": ")" + std::string(1000, '[') + R"("}]})", "s.json"));
}

TEST_CASE("hostile: a message about a large or nested value shows a bounded prefix of it", "[hostile][scene_io]") {
    // 60 levels (inside the limit) in a place that wants an object.
    const SceneLoadResult nested = parseScene(deeplyNestedScene(60), "n.json");
    REQUIRE_FALSE(nested);
    CHECK(nested.error == "n.json: camera: must be an object, got array [[[[[...]]]]]");
    // A million-element array is not serialised whole for a 40-character message.
    std::string big = R"({"version": 1, "camera": [)";
    for (int i = 0; i < 1000000; ++i) big += i ? ",1" : "1";
    big += "]}";
    const SceneLoadResult large = parseScene(big, "big.json");
    REQUIRE_FALSE(large);
    CHECK(large.error == "big.json: camera: must be an object, got array [1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,...");
}

// ---- 3 and 4. Regular files only; sizes from the header -------------------------------------------

TEST_CASE("hostile: the HDR reader refuses a FIFO, /dev/zero and a folder, naming the file", "[hostile][image]") {
    test::TempDir dir;
    const std::string fifo = dir.file("sky.hdr");
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    ImageData img;
    std::string error;
    // Hang guard: an unguarded read of a FIFO with no writer never returns; the alarm then ends the
    // test program saying so.
    std::signal(SIGALRM, [](int) {
        static const char kMessage[] = "hostile: the HDR reader hung on a FIFO or /dev/zero (no answer in 60 s)\n";
        [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
        ::_exit(1);
    });
    ::alarm(60);
    CHECK_FALSE(readRadianceHdr(fifo, &img, &error));
    CHECK(error == fifo + ": cannot read: a FIFO (named pipe), not a regular file");
    CHECK_FALSE(readRadianceHdr("/dev/zero", &img, &error));
    CHECK(error == "/dev/zero: cannot read: a character device, not a regular file");
    ::alarm(0);
    std::signal(SIGALRM, SIG_DFL);
    CHECK_FALSE(readRadianceHdr(dir.path.string(), &img, &error));
    CHECK(error == dir.path.string() + ": cannot read: a folder, not a regular file");
    CHECK_FALSE(readRadianceHdr(std::string("sky.hdr\0.png", 12), &img, &error));
    CHECK(error == "sky.hdr?.png: cannot read: the file name contains a NUL byte");
}

TEST_CASE("hostile: an HDR header declaring a huge image is refused before any allocation", "[hostile][image]") {
    test::TempDir dir;
    for (const int side : {60000, 100000}) {
        INFO(side);
        const std::string file = dir.file("huge-" + std::to_string(side) + ".hdr");
        std::ofstream(file, std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << side << " +X " << side
                                              << "\n" << std::string(64, '\x01');
        ImageData img;
        std::string error;
        CHECK_FALSE(readRadianceHdr(file, &img, &error));
        const std::string size = std::to_string(side) + "x" + std::to_string(side);
        CHECK(error == file + ": declares " + size + " pixels, more than the limit of 134217728 pixels (16384x8192) and 65536 per side");
        CHECK(img.pixels.capacity() == 0);
    }
}

// ---- 5. Needless refusals --------------------------------------------------------------------------

TEST_CASE("hostile: a model whose own material names a missing texture imports when the scene gives it a material", "[hostile][materials]") {
    test::TempDir dir;
    {
        std::ofstream(dir.file("model.mtl")) << "newmtl painted\nKd 0.8 0.8 0.8\nmap_Kd missing-texture.png\n";
        std::ofstream obj(dir.file("model.obj"));
        obj << "mtllib model.mtl\nusemtl painted\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
    }
    const std::string file = dir.file("model.obj");
    std::vector<std::string> reads;
    ImageReader reader = [&](const std::string& path, ImageData*, std::string* why) {
        reads.push_back(path);
        *why = path + ": cannot read: No such file or directory";
        return false;
    };
    auto sceneWith = [&](const std::string& material) {
        Scene s = *parseScene(R"({"version": 1, "materials": [{"name": "white"}], "objects": [
            {"shape": "mesh", "file": ")" + file + R"(")" + material + "}]}", "s.json").scene;
        return s;
    };
    CompiledScene c;
    std::string error;
    // The object has the scene's material: the file's texture is never read.
    CHECK(compileScene(sceneWith(R"(, "material": "white")"), reader, &c, &error));
    CHECK(error == "");
    CHECK(reads.empty());
    // The object uses the file's materials: the missing texture is an error naming it and the object.
    CHECK_FALSE(compileScene(sceneWith(""), reader, &c, &error));
    INFO(error);
    CHECK(error.find("objects[0].file (" + file + ") material ") == 0);  // Assimp adds a default material first
    CHECK(error.find("(material 'painted')") != std::string::npos);
    CHECK(error.find(dir.file("missing-texture.png")) != std::string::npos);
    CHECK(reads == std::vector<std::string>{dir.file("missing-texture.png")});
}

// ---- 6. Small lies -----------------------------------------------------------------------------------

TEST_CASE("hostile: strings with a NUL byte and empty texture names are errors naming the JSON path", "[hostile][scene_io]") {
    auto error = [](const std::string& material) {
        const SceneLoadResult r = parseScene(R"({"version": 1, "materials": [{"name": "m", )" + material + "}]}", "s.json");
        return r ? std::string("loaded") : r.error;
    };
    CHECK(error(R"("albedo_texture": "brick.png\u0000.jpg")") ==
          "s.json: materials[0].albedo_texture: must not contain a NUL character (\\u0000)");
    CHECK(error(R"("albedo_texture": "")") ==
          "s.json: materials[0].albedo_texture: must not be empty (leave the key out for no texture)");
    CHECK(error(R"("normal_texture": "")") ==
          "s.json: materials[0].normal_texture: must not be empty (leave the key out for no texture)");
    CHECK(error(R"("roughness_texture": "")") ==
          "s.json: materials[0].roughness_texture: must not be empty (leave the key out for no texture)");
    const SceneLoadResult mesh = parseScene(
        R"({"version": 1, "materials": [{"name": "m"}], "objects": [{"shape": "mesh", "file": "a.obj\u0000", "material": "m"}]})", "s.json");
    REQUIRE_FALSE(mesh);
    CHECK(mesh.error == "s.json: objects[0].file: must not contain a NUL character (\\u0000)");
}

TEST_CASE("hostile: non-finite numbers are refused from the file and from --set, naming the path", "[hostile][scene_io]") {
    const SceneLoadResult fromFile = parseScene(
        R"({"version": 1, "materials": [{"name": "m"}], "objects": [{"shape": "sphere", "material": "m", "transform": {"translate": [1e39, 0, 0]}}]})",
        "s.json");
    REQUIRE_FALSE(fromFile);
    CHECK(fromFile.error == "s.json: objects[0].transform.translate[0]: must be a finite 32-bit float, got 1e+39");
    for (const char* value : {"[1e39, 0, 0]", "[NaN, 0, 0]", "[1e999, 0, 0]"}) {
        INFO(value);
        const SceneLoadResult r = loadScene(kCornellBox, {{"objects[0].transform.translate", value}});
        REQUIRE_FALSE(r);
        CHECK(r.error.find("objects[0].transform.translate") != std::string::npos);
    }
}

TEST_CASE("hostile: --set with an index past any array says so", "[hostile][scene_io]") {
    for (const char* index : {"99", "4294967296", "99999999999999999999999999"}) {
        INFO(index);
        const std::string path = std::string("objects[") + index + "].shape";
        const SceneLoadResult r = loadScene(kCornellBox, {{path, "\"sphere\""}});
        REQUIRE_FALSE(r);
        CHECK(r.error == "--set " + path + "=\"sphere\": objects[" + index + "]: no such element (the array has " +
                             std::to_string(loadScene(kCornellBox).scene->objects.size()) + ")");
    }
}

// ---- 7. Valid numbers that 32-bit floats cannot carry -----------------------------------------------
// Each of these rendered a black or NaN image with exit 0 (issue 12, item 5); each is now either
// refused naming the JSON path or computed in double so that it renders correctly.

namespace {

std::string parseError(const std::string& body) {
    const SceneLoadResult r = parseScene(R"({"version": 1, )" + body + "}", "s.json");
    return r ? std::string("loaded") : r.error;
}

std::string compileError(const Scene& scene) {
    CompiledScene compiled;
    std::string error;
    if (compileScene(scene, nullptr, &compiled, &error)) return "compiled";
    return error;
}

Scene withLight(const Light& light) {
    Scene s = *loadScene(kCornellBox).scene;
    s.lights.push_back(light);
    return s;
}

}  // namespace

TEST_CASE("hostile: parameters beyond what the renderer's floats carry are refused, naming the JSON path", "[hostile][scene_io]") {
    CHECK(parseError(R"("materials": [{"name": "m", "type": "conductor", "metal": "custom", "k": [1e38, 1, 1]}])") ==
          "s.json: materials[0].k[0]: must be <= 1000, got 1e+38");
    CHECK(parseError(R"("materials": [{"name": "m", "type": "conductor", "metal": "custom", "eta": [1e-9, 1, 1]}])") ==
          "s.json: materials[0].eta[0]: must be >= 0.001, got 1e-09");
    CHECK(parseError(R"("environment": {"type": "constant", "radiance": [3e38, 1, 1]})") ==
          "s.json: environment.radiance[0]: must be <= 1e+12, got 3e+38");
    CHECK(parseError(R"("environment": {"type": "constant", "radiance": [1e10, 1, 1], "intensity": 1e10})").find(
              "s.json: environment.intensity: times the radiance gives 1e+20, more than 1e+12") == 0);
    CHECK(parseError(R"("materials": [{"name": "m", "emission": [0, 3e38, 0]}])") ==
          "s.json: materials[0].emission[1]: must be <= 1e+12, got 3e+38");
    CHECK(parseError(R"("camera": {"position": [0, 0, 3e38]})") == "s.json: camera.position[2]: must be <= 1e+18, got 3e+38");
    CHECK(parseError(R"("camera": {"position": [0, 0, 1], "look_at": [-3e38, 0, 0]})") ==
          "s.json: camera.look_at[0]: must be >= -1e+18, got -3e+38");
    CHECK(parseError(R"("lights": [{"type": "point", "position": [2e19, 0, 0]}])") ==
          "s.json: lights[0].position[0]: must be <= 1e+18, got 2e+19");
    CHECK(parseError(R"("lights": [{"type": "sphere", "color": [1e13, 1, 1]}])") ==
          "s.json: lights[0].color[0]: must be <= 1e+12, got 1e+13");
    // The limits themselves are accepted.
    CHECK(parseError(R"("camera": {"position": [0, 0, 1e18]}, "environment": {"type": "constant", "radiance": [1e12, 0, 0]})") ==
          "loaded");
}

TEST_CASE("hostile: an emitter whose area underflows or overflows a float is refused, naming the JSON path", "[hostile][gpu_scene]") {
    Light rect;
    rect.type = LightType::Rect;
    for (float scale : {1e-25f, 1e20f}) {
        INFO(scale);
        rect.transform.scale = glm::vec3(scale);
        CHECK(compileError(withLight(rect)).find("lights[0].transform: the emitter's area (") == 0);
    }
    rect.transform.scale = glm::vec3(1e-6f);  // area 4e-12: fine
    CHECK(compileError(withLight(rect)) == "compiled");
    Light sphere;
    sphere.type = LightType::Sphere;
    sphere.radius = 9e18f;
    CHECK(compileError(withLight(sphere)).find("lights[0].radius: the emitter's area (1.02e+39)") == 0);
    // An emitting object: the Cornell box's own light scaled down 1e-20 (area 1.7e-41).
    Scene s = *loadScene(kCornellBox).scene;
    s.objects.back().transform.scale *= 1e-20f;
    CHECK(compileError(s).find("objects[7]: the emitter's area (") == 0);
}

TEST_CASE("hostile: an object far away (1e30) with an environment keeps every light's pmf finite", "[hostile][gpu_scene]") {
    Scene s = *loadScene(kCornellBox).scene;
    Object far = s.objects[0];
    far.transform.translate = glm::vec3(1e30f, 0.0f, 0.0f);
    s.objects.push_back(far);
    s.environment.type = EnvironmentType::Constant;
    s.environment.radiance = glm::vec3(0.2f);
    s.render.lightSelection = LightSelection::Power;
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, nullptr, &c, &error));
    double sum = 0.0;
    for (const auto& l : c.lights) {
        CHECK(std::isfinite(l.color.w));
        sum += l.color.w;
    }
    CHECK(sum == Approx(1.0));
    for (float v : c.lightCdf) CHECK(std::isfinite(v));
    // The environment's radius (5e29) squared saturates at the largest float: it takes almost all
    // the probability, the ceiling light keeps a positive share.
    REQUIRE(c.envLightIndex >= 0);
    CHECK(c.lights[size_t(c.envLightIndex)].color.w > 0.99f);
    for (size_t i = 0; i < c.lights.size(); ++i)
        if (int(i) != c.envLightIndex) CHECK(c.lights[i].color.w > 0.0f);
}

TEST_CASE("hostile: a camera up or view vector of length 1e-30 and a spot direction of 1e-44 give a finite unit basis", "[hostile][gpu_scene]") {
    Scene s = *loadScene(kCornellBox).scene;
    s.camera.up = glm::vec3(0.0f, 1e-30f, 0.0f);
    s.camera.position = glm::vec3(0.0f);
    s.camera.lookAt = glm::vec3(0.0f, 0.0f, -1e-30f);
    Light spot;
    spot.type = LightType::Spot;
    spot.direction = glm::vec3(0.0f, -1e-44f, 0.0f);
    s.lights.push_back(spot);
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, nullptr, &c, &error));
    const gpu::GpuFrame f = makeFrame(s, c, 0);
    auto unit = [](glm::vec4 v) { return std::abs(glm::length(glm::vec3(v)) - 1.0f) < 1e-5f; };
    CHECK(unit(f.camForward));
    CHECK(f.camForward.z == Approx(-1.0f));
    CHECK(glm::normalize(glm::vec3(f.camUp)).y == Approx(1.0f));
    CHECK(glm::normalize(glm::vec3(f.camRight)).x == Approx(1.0f));
    CHECK(std::isfinite(f.camLens.y));
    const gpu::GpuLight& l = c.lights.back();
    CHECK(unit(glm::vec4(glm::vec3(l.p1), 0.0f)));
    CHECK(l.p1.y == Approx(-1.0f));
}

// ---- 8. GL limits ---------------------------------------------------------------------------------

TEST_CASE("hostile: a compiled scene is checked against injected GL limits before upload", "[hostile][gpu_limits]") {
    Scene s = *loadScene(kCornellBox).scene;
    CompiledScene c;
    std::string error;
    REQUIRE(compileScene(s, nullptr, &c, &error));
    GpuLimits limits;
    limits.maxTextureSize = 16384;
    limits.maxStorageBlockSize = std::int64_t(1) << 27;
    CHECK(gpuLimitProblem(s, c, limits).empty());
    CHECK(gpuLimitProblem(s, c, GpuLimits{}).empty());   // unknown limits: nothing to check

    // An environment map one texel wider than the texture limit names the file and both sizes.
    s.environment.type = EnvironmentType::Map;
    s.environment.file = "sky.hdr";
    c.envMap.width = 16385;
    c.envMap.height = 100;
    CHECK(gpuLimitProblem(s, c, limits) ==
          "environment.file: sky.hdr: the map is 16385 x 100 pixels; this GPU's textures may be at most 16384 "
          "per side (GL_MAX_TEXTURE_SIZE); resample the map");
    c.envMap.width = 16384;
    CHECK(gpuLimitProblem(s, c, limits).empty());
    // The render size against the same limit (a GPU whose limit is below the scene format's).
    limits.maxTextureSize = 8192;
    c.envMap.width = 4096;
    s.render.width = 8193;
    CHECK(gpuLimitProblem(s, c, limits).find("render: 8193 x ") == 0);
    s.render.width = 256;
    // A storage buffer over the limit names the buffer and both sizes.
    limits.maxStorageBlockSize = 4096;
    c.triangles.resize(1000);
    CHECK(gpuLimitProblem(s, c, limits) ==
          "the scene's mesh triangles need 62.5 KiB of GPU storage; this GPU allows 4.0 KiB per buffer "
          "(GL_MAX_SHADER_STORAGE_BLOCK_SIZE)");
    // Where the scene is read through buffer textures (llvmpipe), their texel limit too: 1000
    // triangles are 4000 RGBA32UI texels.
    limits.maxStorageBlockSize = std::int64_t(1) << 27;
    limits.maxTextureBufferTexels = 4000;
    CHECK(gpuLimitProblem(s, c, limits).empty());
    limits.maxTextureBufferTexels = 3999;
    CHECK(gpuLimitProblem(s, c, limits) ==
          "the scene's mesh triangles need 4000 texels of a buffer texture; this GPU allows 3999 "
          "(GL_MAX_TEXTURE_BUFFER_SIZE)");
}
