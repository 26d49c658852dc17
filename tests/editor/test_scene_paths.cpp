// Save As into another folder keeps the files a scene names (environment map, mesh files,
// textures) the same files (issue 15): saved into a sibling and into a parent folder, the scene
// is loaded back from there and compiled, reading exactly the files of the original.
#include "editor/model/editor_state.h"
#include "editor/model/scene_paths.h"
#include "renderer/gpu_scene.h"
#include "renderer/scene_io.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <set>

#include <unistd.h>

using namespace caustic;
using namespace caustic::editor;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("caustic-scene-paths-" + std::to_string(::getpid()));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

void writeFile(const fs::path& p, const std::string& text) {
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
}

// Reads nothing but proves the file is there: a 2x2 grey image for each path that exists,
// recording the normalised paths it was asked for.
struct RecordingReader {
    std::set<std::string> read;
    ImageReader reader() {
        return [this](const std::string& path, ImageData* out, std::string* error) {
            if (!fs::is_regular_file(path)) {
                *error = path + ": cannot read image";
                return false;
            }
            read.insert(fs::absolute(path).lexically_normal().string());
            *out = ImageData{2, 2, 3, std::vector<float>(12, 0.5f)};
            return true;
        };
    }
};

}  // namespace

TEST_CASE("rebasePath keeps a relative path relative and the same file", "[editor][paths]") {
    CHECK(rebasePath("../assets/sky.hdr", "/p/scenes", "/p/scenes/sub") == "../../assets/sky.hdr");
    CHECK(rebasePath("../assets/sky.hdr", "/p/scenes", "/p") == "assets/sky.hdr");
    CHECK(rebasePath("../assets/sky.hdr", "/p/scenes", "/p/other") == "../assets/sky.hdr");
    CHECK(rebasePath("tex/a.png", "/p/scenes", "/q") == "../p/scenes/tex/a.png");
    CHECK(rebasePath("/abs/sky.hdr", "/p/scenes", "/p") == "/abs/sky.hdr");   // absolute stays absolute
    CHECK(rebasePath("", "/p/scenes", "/p") == "");
    CHECK(rebasePath("./a/../b.obj", "/p", "/p") == "./a/../b.obj");        // same folder: untouched
}

TEST_CASE("Save As into a sibling and a parent folder rebases every path, the copies load and compile", "[editor][paths]") {
    TempDir tmp;
    const fs::path root = tmp.path;
    writeFile(root / "assets" / "sky.hdr", "not decoded by the test reader");
    writeFile(root / "assets" / "albedo.png", "x");
    writeFile(root / "assets" / "normal.png", "x");
    writeFile(root / "assets" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    writeFile(root / "assets" / "tri2.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n");
    const std::string absoluteNormal = (root / "assets" / "normal.png").string();

    Scene s = EditorState().scene;
    s.environment.type = EnvironmentType::Map;
    s.environment.file = "../assets/sky.hdr";
    REQUIRE_FALSE(s.materials.empty());
    s.materials[0].albedoTexture = "../assets/albedo.png";
    s.materials[0].normalTexture = absoluteNormal;
    Object mesh;
    mesh.name = "tri";
    mesh.shape = Shape::Mesh;
    mesh.material = s.materials[0].name;
    mesh.file = "../assets/tri.obj";
    s.objects.push_back(mesh);
    const fs::path original = root / "scenes" / "a.json";
    fs::create_directories(original.parent_path());
    std::string error;
    REQUIRE(saveScene(s, original.string(), &error));

    EditorState st;
    REQUIRE(st.open(original.string(), &error));
    const int meshIndex = static_cast<int>(st.scene.objects.size()) - 1;
    // An edit before the save: its undo must put back a path that works from the new folder.
    REQUIRE(st.apply(makeSetMeshFile(st, meshIndex, (root / "assets" / "tri2.obj").string())));
    REQUIRE(st.scene.objects.back().file == "../assets/tri2.obj");

    auto compileFrom = [&](const fs::path& file) {
        SceneLoadResult loaded = loadScene(file.string());
        REQUIRE(loaded.scene);
        RecordingReader reader;
        CompiledScene compiled;
        std::string why;
        INFO(file.string());
        const bool ok = compileScene(*loaded.scene, reader.reader(), &compiled, &why);
        INFO(why);
        CHECK(ok);   // a missing mesh or image fails it
        CHECK(reader.read.count((root / "assets" / "sky.hdr").lexically_normal().string()) == 1);
        CHECK(reader.read.count((root / "assets" / "albedo.png").lexically_normal().string()) == 1);
        CHECK(reader.read.count(fs::path(absoluteNormal).lexically_normal().string()) == 1);
        return *loaded.scene;
    };

    SECTION("a sibling folder (scenes/sub)") {
        const fs::path copy = root / "scenes" / "sub" / "b.json";
        fs::create_directories(copy.parent_path());
        REQUIRE(st.saveAs(copy.string(), &error));
        const Scene loaded = compileFrom(copy);
        CHECK(loaded.environment.file == "../../assets/sky.hdr");
        CHECK(loaded.materials[0].albedoTexture == "../../assets/albedo.png");
        CHECK(loaded.materials[0].normalTexture == absoluteNormal);
        CHECK(loaded.objects.back().file == "../../assets/tri2.obj");
        // The scene in memory belongs to the new file: its paths resolve from there too.
        CHECK(st.scene.environment.file == "../../assets/sky.hdr");
        CHECK(st.scene.sourcePath == copy.string());
        // Undo puts back the first mesh, named from the new folder.
        REQUIRE(st.undo());
        CHECK(st.scene.objects.back().file == "../../assets/tri.obj");
        CHECK(fs::is_regular_file(copy.parent_path() / st.scene.objects.back().file));
        REQUIRE(st.redo());
        CHECK(st.scene.objects.back().file == "../../assets/tri2.obj");
    }
    SECTION("the parent folder") {
        const fs::path copy = root / "b.json";
        REQUIRE(st.saveAs(copy.string(), &error));
        const Scene loaded = compileFrom(copy);
        CHECK(loaded.environment.file == "assets/sky.hdr");
        CHECK(loaded.objects.back().file == "assets/tri2.obj");
        REQUIRE(st.undo());
        CHECK(st.scene.objects.back().file == "assets/tri.obj");
    }
    SECTION("the same folder changes nothing") {
        REQUIRE(st.saveAs((root / "scenes" / "c.json").string(), &error));
        CHECK(st.scene.environment.file == "../assets/sky.hdr");
        compileFrom(root / "scenes" / "c.json");
    }
}

TEST_CASE("Save As proposes a name that overwrites nothing", "[editor][paths]") {
    TempDir tmp;
    CHECK(suggestSaveAsName(tmp.path.string(), "") == "scene.json");
    writeFile(tmp.path / "scene.json", "{}");
    CHECK(suggestSaveAsName(tmp.path.string(), "") == "scene-2.json");
    CHECK(suggestSaveAsName(tmp.path.string(), "/elsewhere/box.json") == "box-2.json");
    writeFile(tmp.path / "box-2.json", "{}");
    CHECK(suggestSaveAsName(tmp.path.string(), "/elsewhere/box.json") == "box-3.json");
}
