// Fuzz harness: the scene reader (renderer/scene_io.h parseScene) on arbitrary bytes.
// Properties beyond "no crash, no hang, no leak, no undefined behaviour":
//   - a refused text gets a non-empty one-line message;
//   - an accepted scene passes checkEntity for each of its entities (the editor's rules are the
//     file's rules), and saving it (sceneToJson) then reading that back gives the same scene.
// Seeds: scenes/*.json.
#include "renderer/scene_io.h"
#include "tests/fuzz/fuzz_common.h"

using namespace caustic;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const SceneLoadResult r = parseScene(text, "fuzz.json");
    if (!r) {
        FUZZ_CHECK(!r.error.empty(), "refused without a message");
        FUZZ_CHECK(r.error.find('\n') == std::string::npos, r.error);
        return 0;
    }
    const Scene& s = *r.scene;
    FUZZ_CHECK(r.error.empty(), r.error);
    auto entityOk = [](const std::string& problem) { FUZZ_CHECK(problem.empty(), problem); };
    entityOk(checkEntity(s.camera, "camera"));
    entityOk(checkEntity(s.render, "render"));
    entityOk(checkEntity(s.environment, "environment"));
    for (const Material& m : s.materials) entityOk(checkEntity(m, "materials[]"));
    for (const Object& o : s.objects) entityOk(checkEntity(o, "objects[]"));
    for (const Light& l : s.lights) entityOk(checkEntity(l, "lights[]"));

    const std::string saved = sceneToJson(s);
    FUZZ_CHECK(!saved.empty(), "sceneToJson returned nothing");
    const SceneLoadResult again = parseScene(saved, "saved.json");
    FUZZ_CHECK(again.scene.has_value(), again.error + "\n  saved text:\n" + saved);
    FUZZ_CHECK(*again.scene == s, "the saved scene reads back different:\n" + saved);
    return 0;
}
