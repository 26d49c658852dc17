// Fuzz harness: `--set` overrides (renderer/scene_io.h parseSceneOverride and
// loadScene(file, overrides)) on a scene file.
// Input: override lines ("path=value", one per line) up to the first empty line, then the scene
// text. Properties: a refusal (of the override's syntax or of the resulting scene) carries a
// one-line message; an accepted result passes the same save/read-back check as fuzz_scene.
// Seeds: scenes/*.json behind tests/fuzz/seeds/overrides.txt (tests/fuzz/run.sh builds them).
#include "renderer/scene_io.h"
#include "tests/fuzz/fuzz_common.h"

#include <vector>

using namespace caustic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view in(reinterpret_cast<const char*>(data), size);
    std::vector<SceneOverride> overrides;
    while (!in.empty()) {
        const auto [line, rest] = fuzz::splitFirstLine(in);
        in = rest;
        if (line.empty()) break;
        SceneOverride o;
        std::string error;
        if (!parseSceneOverride(std::string(line), &o, &error)) {
            FUZZ_CHECK(!error.empty(), "override refused without a message");
            continue;  // the CLI exits with the message; keep fuzzing the rest
        }
        FUZZ_CHECK(o.path + "=" + o.value == line, "the override does not split its own text");
        overrides.push_back(std::move(o));
    }
    const std::string file = fuzz::ScratchDir::get().write(reinterpret_cast<const std::uint8_t*>(in.data()),
                                                            in.size(), ".json");
    const SceneLoadResult r = loadScene(file, overrides);
    if (!r) {
        FUZZ_CHECK(!r.error.empty(), "refused without a message");
        FUZZ_CHECK(r.error.find('\n') == std::string::npos, r.error);
        return 0;
    }
    const std::string saved = sceneToJson(*r.scene);
    const SceneLoadResult again = parseScene(saved, "saved.json");
    FUZZ_CHECK(again.scene.has_value(), again.error + "\n  saved text:\n" + saved);
    FUZZ_CHECK(*again.scene == *r.scene, "the saved scene reads back different:\n" + saved);
    return 0;
}
