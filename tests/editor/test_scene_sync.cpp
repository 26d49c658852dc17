// The render session keeps the renderer's scene in sync with the model's (issue 41: after one
// refused edit, every later edit used to be invisible). A stand-in renderer (SceneSink) compiles
// on the CPU with the real scene compiler and accepts what the real one accepts: a whole scene
// (setScene, or an update of anything but the camera and settings) only if it compiles; a camera
// or settings update as given, without compiling, as Renderer::update does. The property, after
// every step of random edit sequences, refused or not: if the model's scene compiles, the renderer
// has exactly it and no error is shown; if not, the session says it is behind, with the compiler's
// message for the model's scene (not an older one).
#include "editor/model/editor_state.h"
#include "editor/model/render_session.h"
#include "editor/model/viewport_math.h"
#include "editor/model/plain_text.h"
#include "renderer/gpu_scene.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

using namespace caustic;
using namespace caustic::editor;

namespace {

const std::string kTexture = std::string(CAUSTIC_SOURCE_DIR) + "/assets/tiles/albedo.png";
const std::string kMissing = std::string(CAUSTIC_SOURCE_DIR) + "/assets/tiles/no-such-texture.png";

bool compiles(const Scene& scene, std::string* error) {
    CompiledScene compiled;
    return compileScene(scene, readImageWithoutOpenImageIo, &compiled, error);
}

class CpuSink final : public SceneSink {
public:
    bool setScene(const Scene& scene, std::string* error) override {
        if (!compiles(scene, error)) return false;
        accept(scene);
        return true;
    }
    bool update(const Scene& scene, std::uint32_t dirty, std::string* error) override {
        if ((dirty & ~std::uint32_t(kDirtyCamera | kDirtySettings)) != 0) return setScene(scene, error);
        accept(scene);   // the renderer's fast path: nothing compiled
        return true;
    }
    int samplesDone() const override { return 1; }

    std::optional<Scene> accepted;
    int accepts = 0;

private:
    void accept(const Scene& scene) {
        accepted = scene;
        ++accepts;
    }
};

Scene startScene() {
    Scene s;
    s.render.width = 16;
    s.render.height = 12;
    s.render.samples = 4;
    for (const char* name : {"floor", "red", "blue"}) {
        Material m;
        m.name = name;
        s.materials.push_back(m);
    }
    s.materials[0].albedoTexture = kTexture;
    for (int i = 0; i < 4; ++i) {
        Object o;
        o.shape = Shape::Sphere;
        o.name = "ball " + std::to_string(i);
        o.material = s.materials[std::size_t(i % 3)].name;
        o.transform.translate = glm::vec3(float(i), 0.0f, 0.0f);
        s.objects.push_back(o);
    }
    s.environment.type = EnvironmentType::Constant;
    return s;
}

// The renderer's scene and the model's, compared as far as they show: at the model's output size
// (the session renders at the viewport's), without the target sample count and without the
// materials no object uses (edits of those, but for their texture files, wait for the next
// update: kDirtyUnseen).
Scene visible(Scene s, const Scene& model) {
    s.render.width = model.render.width;
    s.render.height = model.render.height;
    s.render.samples = 0;
    std::erase_if(s.materials, [&](const Material& m) {
        return std::none_of(s.objects.begin(), s.objects.end(), [&](const Object& o) { return o.material == m.name; });
    });
    return s;
}

bool sameScene(const Scene& rendered, const Scene& model) { return visible(rendered, model) == visible(model, model); }

void checkInSync(const RenderSession& session, const CpuSink& sink, const EditorState& state, const std::string& what) {
    INFO(what);
    std::string error;
    if (compiles(state.scene, &error)) {
        CHECK_FALSE(session.behind);
        CHECK(session.renderError.empty());
        REQUIRE(sink.accepted);
        CHECK(sameScene(*sink.accepted, state.scene));
    } else {
        CHECK(session.behind);
        CHECK(session.renderError == error);
    }
}

}  // namespace

TEST_CASE("scene sync: after a refused edit, later edits still reach the renderer (the dof repro)", "[editor][sync]") {
    EditorState state;
    state.scene = startScene();
    RenderSession session;
    CpuSink sink;
    double now = 1.0;
    auto step = [&](const std::string& what) {
        session.sync(sink, state, now, false);
        now += 0.5;
        checkInSync(session, sink, state, what);
    };
    step("first upload");
    REQUIRE(sink.accepts == 1);

    // The floor's texture set to a file that does not exist: refused, the last good scene stays.
    Material floor = state.scene.materials[0];
    floor.albedoTexture = kMissing;
    REQUIRE(state.apply(makeSetMaterial(state, 0, floor)));
    step("missing texture");
    REQUIRE(session.behind);
    CHECK(session.renderError.find("no-such-texture.png") != std::string::npos);

    // Delete 3 of the 4 objects, the floor's among them: the scene is still refused (the renderer
    // reads every material's textures, used or not, as batch mode does), and says so; the renderer
    // keeps the last good scene, all 4.
    std::string why;
    for (int i = 0; i < 3; ++i) {
        REQUIRE(state.apply(makeDelete(state, EntityRef{EntityKind::Object, 0}, &why), &why));
        step("delete " + std::to_string(i));
    }
    CHECK(session.behind);
    CHECK(session.renderError.find("no-such-texture.png") != std::string::npos);
    CHECK(sink.accepted->objects.size() == 4);
    // Clearing the texture of the material no object uses any more: the renderer gets the scene
    // with its one object (this edit used to wait for another, and every later edit with it).
    floor.albedoTexture.clear();
    REQUIRE(state.apply(makeSetMaterial(state, 0, floor)));
    step("texture cleared");
    CHECK_FALSE(session.behind);
    CHECK(sink.accepted->objects.size() == 1);

    // Undo back to the refused state and further: each step tried whole.
    REQUIRE(state.undo());
    step("undo the clearing");
    CHECK(session.behind);
    REQUIRE(state.undo());
    step("undo a delete");
    CHECK(session.behind);
    for (int i = 0; i < 3; ++i) REQUIRE(state.undo());
    step("undo to before the texture");
    CHECK_FALSE(session.behind);
    CHECK(sink.accepted->objects.size() == 4);
    CHECK(sink.accepted->materials[0].albedoTexture == kTexture);

    // An unused material given a missing texture is refused at once, not when something else
    // changes (its edit restarts the render once; unused materials' other edits do not).
    REQUIRE(state.apply(makeAddMaterial(state)));
    step("add material");
    Material spare = state.scene.materials.back();
    spare.albedoTexture = kMissing;
    REQUIRE(state.apply(makeSetMaterial(state, int(state.scene.materials.size()) - 1, spare)));
    step("unused material's missing texture");
    CHECK(session.behind);
    // Edits meanwhile are kept: a move, then the texture cleared; the renderer has both.
    Object moved = state.scene.objects[1];
    moved.transform.translate.y = 3.0f;
    REQUIRE(state.apply(makeSetObject(state, 1, moved)));
    step("moved while behind");
    CHECK(sink.accepted->objects[1].transform.translate.y != 3.0f);
    spare.albedoTexture.clear();
    REQUIRE(state.apply(makeSetMaterial(state, int(state.scene.materials.size()) - 1, spare)));
    step("spare cleared");
    CHECK_FALSE(session.behind);
    CHECK(sink.accepted->objects[1].transform.translate.y == 3.0f);
    spare.albedo = glm::vec3(0.2f);
    const int before = sink.accepts;
    REQUIRE(state.apply(makeSetMaterial(state, int(state.scene.materials.size()) - 1, spare)));
    step("unused material's colour");
    CHECK(sink.accepts == before);

    // The target sample count alone restarts nothing, behind or not.
    const int accepts = sink.accepts;
    RenderSettings rs = state.scene.render;
    rs.samples = 8;
    REQUIRE(state.apply(makeSetRender(state, rs)));
    step("target");
    CHECK(sink.accepts == accepts);
}

TEST_CASE("scene sync: random edit sequences, refused or not, leave the renderer with the model's scene or say why", "[editor][sync]") {
    std::mt19937 rng(20261207);
    int behindSteps = 0, syncedSteps = 0;
    for (int sequence = 0; sequence < 24; ++sequence) {
        EditorState state;
        state.scene = startScene();
        RenderSession session;
        CpuSink sink;
        double now = 1.0;
        session.sync(sink, state, now, false);
        for (int i = 0; i < 30; ++i) {
            auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
            const int nObjects = int(state.scene.objects.size()), nMaterials = int(state.scene.materials.size());
            std::string what, why;
            switch (pick(11)) {
            case 0: {
                const int m = pick(nMaterials);
                Material mat = state.scene.materials[std::size_t(m)];
                const int t = pick(3);
                mat.albedoTexture = t == 0 ? "" : t == 1 ? kTexture : kMissing;
                what = "texture of material " + std::to_string(m) + " = " + std::to_string(t);
                state.apply(makeSetMaterial(state, m, mat), &why);
                break;
            }
            case 1:
                if (nObjects > 0) {
                    const int o = pick(nObjects);
                    what = "delete object " + std::to_string(o);
                    if (auto del = makeDelete(state, EntityRef{EntityKind::Object, o}, &why)) state.apply(std::move(del), &why);
                }
                break;
            case 2:
                what = "add sphere";
                state.apply(makeAddObject(state, Shape::Sphere), &why);
                break;
            case 3: {
                const int m = pick(nMaterials);
                Material mat = state.scene.materials[std::size_t(m)];
                mat.albedo = glm::vec3(float(pick(100)) / 100.0f);
                what = "albedo of material " + std::to_string(m);
                state.apply(makeSetMaterial(state, m, mat), &why);
                break;
            }
            case 4: what = "undo"; state.undo(); break;
            case 5: what = "redo"; state.redo(); break;
            case 6: {
                RenderSettings rs = state.scene.render;
                rs.samples = 1 + pick(64);
                what = "samples";
                state.apply(makeSetRender(state, rs), &why);
                break;
            }
            case 7: what = "add material"; state.apply(makeAddMaterial(state), &why); break;
            case 8:
                if (nObjects > 0) {
                    const int o = pick(nObjects);
                    Object obj = state.scene.objects[std::size_t(o)];
                    obj.material = state.scene.materials[std::size_t(pick(nMaterials))].name;
                    what = "assign material to object " + std::to_string(o);
                    state.apply(makeSetObject(state, o, obj), &why);
                }
                break;
            case 9:
                if (nObjects > 0) {
                    const int o = pick(nObjects);
                    Object obj = state.scene.objects[std::size_t(o)];
                    obj.transform.translate.z += 0.5f;
                    what = "move object " + std::to_string(o);
                    state.apply(makeSetObject(state, o, obj), &why);
                }
                break;
            default: {
                Camera c = state.scene.camera;
                c.fovDegrees = 30.0f + float(pick(40));
                what = "camera fov";
                state.apply(makeSetCamera(state, c), &why);
                break;
            }
            }
            session.sync(sink, state, now, false);
            now += 0.5;
            checkInSync(session, sink, state, "sequence " + std::to_string(sequence) + ", step " + std::to_string(i) + ": " + what);
            (session.behind ? behindSteps : syncedSteps) += 1;
        }
    }
    // Both states were visited often (the property was tested on each, not trivially).
    CHECK(behindSteps > 100);
    CHECK(syncedSteps > 100);
}

TEST_CASE("a new scene has a ground, a key light aimed at the look-at point and a camera at eye height", "[editor][defaults]") {
    EditorState s;
    s.newScene();
    REQUIRE(s.scene.objects.size() == 1);
    REQUIRE(s.scene.lights.size() == 1);
    CHECK(s.scene.camera.position.y == Approx(1.6f));
    const Light& key = s.scene.lights[0];
    const glm::vec3 facing = glm::normalize(glm::vec3(key.transform.toMatrix() * glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)));
    const glm::vec3 toTarget = glm::normalize(s.scene.camera.lookAt - key.transform.translate);
    CHECK(glm::dot(facing, toTarget) > 0.999f);
    // The ground faces up and passes under the look-at point; a default sphere there rests on it.
    const Object ground = s.scene.objects[0];   // a copy: the add below may move the list
    const glm::vec3 up = glm::normalize(glm::vec3(ground.transform.toMatrix() * glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)));
    CHECK(up.y > 0.999f);
    REQUIRE(s.apply(makeAddObject(s, Shape::Sphere)));
    const Object& ball = s.scene.objects.back();
    CHECK(ball.transform.translate.y - ball.transform.scale.y == Approx(ground.transform.translate.y).margin(1e-6));
    // It is a scene batch mode renders.
    std::string error;
    CHECK(compiles(s.scene, &error));
    INFO(error);
    // The bare scene (EditorState(), the model's tests) stays empty.
    EditorState bare;
    CHECK(bare.scene.objects.empty());
    CHECK(bare.scene.lights.empty());
}

TEST_CASE("a new light is placed clear of the objects at the look-at point", "[editor][defaults]") {
    EditorState s;
    s.newScene();
    // A box 2 units tall around the look-at point: the light goes above it.
    REQUIRE(s.apply(makeAddObject(s, Shape::Box)));
    Object box = s.scene.objects.back();
    box.transform.scale = glm::vec3(1.0f);
    REQUIRE(s.apply(makeSetObject(s, int(s.scene.objects.size()) - 1, box)));
    for (LightType type : {LightType::Point, LightType::Rect, LightType::Sphere, LightType::Spot}) {
        REQUIRE(s.apply(makeAddLight(s, type)));
        const Light& l = s.scene.lights.back();
        const glm::vec3 p = type == LightType::Rect ? l.transform.translate : l.position;
        for (int i = 0; i < int(s.scene.objects.size()); ++i) {
            const auto b = entityBounds(s.scene, EntityRef{EntityKind::Object, i});
            REQUIRE(b);
            const bool inside = glm::all(glm::greaterThanEqual(p, b->first)) && glm::all(glm::lessThanEqual(p, b->second));
            CHECK_FALSE(inside);
        }
        CHECK(p.y > box.transform.translate.y + 1.0f);
    }
}

TEST_CASE("new objects go where the viewport looks: the free view's look-at point where there is one", "[editor][defaults]") {
    EditorState s;
    s.newScene();
    REQUIRE(s.apply(makeAddObject(s, Shape::Sphere)));
    CHECK(s.scene.objects.back().transform.translate == s.scene.camera.lookAt);
    Camera view = s.scene.camera;
    view.lookAt = glm::vec3(4.0f, 0.5f, -3.0f);
    view.position = view.lookAt + glm::vec3(0.0f, 1.0f, 5.0f);
    s.moveView(view, true, true);
    REQUIRE(s.apply(makeAddObject(s, Shape::Box)));
    CHECK(s.scene.objects.back().transform.translate == view.lookAt);
    REQUIRE(s.apply(makeAddLight(s, LightType::Point)));
    CHECK(s.scene.lights.back().position.x == view.lookAt.x);
    CHECK(s.scene.lights.back().position.z == view.lookAt.z);
}

TEST_CASE("tooltips show the schema's Markdown as plain text", "[editor][tooltips]") {
    CHECK(plainText("must differ from `position`") == "must differ from position");
    CHECK(plainText("**bold** and *this*, then `a*b` and 2 * pi") == "bold and this, then a*b and 2 * pi");
    CHECK(plainText("see [the format](docs/scene-format.md) here") == "see the format here");
    // Every tooltip the inspector shows: no backtick, no link syntax left.
    for (const std::string_view doc : {std::string_view("the eye (each coordinate within +-1e18, as `look_at`)"),
                                       std::string_view("`0`: wide open; [f-number](https://x)")}) {
        const std::string t = plainText(doc);
        CHECK(t.find('`') == std::string::npos);
        CHECK(t.find("](") == std::string::npos);
    }
}

TEST_CASE("the free view (Blender key map) moves apart from the render camera, and Camera to view moves the camera", "[editor][view]") {
    EditorState s;
    s.newScene();
    const Camera camera = s.scene.camera;
    (void)s.takeDirty();
    // Navigating in the free-view mode: the scene camera stays, no undo step, the view moved.
    Camera orbited = camera;
    orbited.position = glm::vec3(3.0f, 2.0f, 1.0f);
    s.moveView(orbited, true, true);
    CHECK(s.scene.camera == camera);
    CHECK(s.history.undoCount() == 0);
    REQUIRE(s.freeView);
    CHECK(s.viewCamera().position == orbited.position);
    CHECK((s.takeDirty() & kDirtyCamera) != 0);
    // The viewport renders through it; Render to file (output size) through the camera.
    RenderSession session;
    CHECK(session.viewportScene(s, {16, 12}).camera.position == orbited.position);
    session.outputSize = true;
    CHECK(session.viewportScene(s, {16, 12}).camera == camera);
    session.outputSize = false;
    // A sync after switching to the output size sends the camera change even with no edit.
    CpuSink sink;
    session.sync(sink, s, 1.0, false);
    REQUIRE(sink.accepted);
    CHECK(sink.accepted->camera.position == orbited.position);
    session.outputSize = true;
    session.sync(sink, s, 2.0, false);
    CHECK(sink.accepted->camera == camera);
    session.outputSize = false;
    // Numpad 0: through the camera, and back to the same free view.
    s.toggleCameraView();
    CHECK_FALSE(s.freeView);
    CHECK(s.viewCamera() == camera);
    s.toggleCameraView();
    REQUIRE(s.freeView);
    CHECK(s.freeView->position == orbited.position);
    // Camera to view: one undo step; the camera keeps its own settings (fov), takes the view's place.
    s.freeView->fovDegrees = 10.0f;
    REQUIRE(s.cameraToView());
    CHECK(s.history.undoCount() == 1);
    CHECK(s.scene.camera.position == orbited.position);
    CHECK(s.scene.camera.fovDegrees == camera.fovDegrees);
    CHECK_FALSE(s.freeView);
    REQUIRE(s.undo());
    CHECK(s.scene.camera == camera);
    // The default key map's navigation edits the camera (lookdev: the viewport is the camera).
    s.moveView(orbited, false, false);
    CHECK(s.scene.camera.position == orbited.position);
    CHECK(s.history.undoCount() == 1);
    // With the free view turned on (View > Free view), the default map's navigation moves it.
    s.toggleCameraView();
    REQUIRE(s.freeView);
    Camera elsewhere = orbited;
    elsewhere.position = glm::vec3(-2.0f, 1.0f, 4.0f);
    s.moveView(elsewhere, false, true);
    CHECK(s.scene.camera.position == orbited.position);
    CHECK(s.freeView->position == elsewhere.position);
    CHECK(s.history.undoCount() == 1);
    s.toggleCameraView();
    // A new scene starts looking through its camera.
    s.moveView(camera, true, true);
    REQUIRE(s.freeView);
    s.newScene();
    CHECK_FALSE(s.freeView);
}

TEST_CASE("the selection outline follows the selected objects' silhouettes", "[editor][outline]") {
    // 6 x 4 cells: object 0 a 2 x 2 square at (1, 1), object 1 beside it at (3, 1) - (3, 2), sky -1.
    const int w = 6, h = 4;
    std::vector<int> shown(std::size_t(w * h), -1);
    for (int y = 1; y <= 2; ++y) {
        shown[std::size_t(y * w + 1)] = shown[std::size_t(y * w + 2)] = 0;
        shown[std::size_t(y * w + 3)] = 1;
    }
    // Only object 0 selected (active): its square's 8 unit edges, the 2 it shares with object 1 included.
    auto edges = selectionOutline(shown, w, h, [](int o) { return o == 0 ? 2 : 0; });
    CHECK(edges.size() == 8);
    for (const OutlineEdge& e : edges) {
        CHECK(e.mark == 2);
        CHECK(glm::length(e.b - e.a) == Approx(1.0f));
        CHECK(e.a.x >= 1.0f);
        CHECK(e.b.x <= 3.0f);
    }
    // Both selected, 0 active: the shared edge is drawn once, as the active one's.
    edges = selectionOutline(shown, w, h, [](int o) { return o == 0 ? 2 : o == 1 ? 1 : 0; });
    CHECK(edges.size() == 8 + 4);
    int shared = 0;
    for (const OutlineEdge& e : edges) shared += e.a.x == 3.0f && e.b.x == 3.0f;
    CHECK(shared == 2);
    // Nothing selected: nothing drawn; an object touching the border is closed by the border.
    CHECK(selectionOutline(shown, w, h, [](int) { return 0; }).empty());
    std::vector<int> full(std::size_t(w * h), 5);
    CHECK(selectionOutline(full, w, h, [](int o) { return o == 5 ? 1 : 0; }).size() == std::size_t(2 * (w + h)));
}

TEST_CASE("the automatic viewport scale gives 4 samples a second at the largest of 1, 1/2, 1/4 and does not flip", "[editor][viewport]") {
    const double panel = 900.0 * 600.0;
    // Fast enough for 4 spp/s at full size.
    CHECK(chooseViewportScale(panel * 5.0, panel, 1.0f) == 1.0f);
    // 1 spp/s at full size: half the side is 4 spp/s.
    CHECK(chooseViewportScale(panel * 1.0, panel, 1.0f) == 0.5f);
    // Slower: a quarter, and no less however slow.
    CHECK(chooseViewportScale(panel * 0.3, panel, 1.0f) == 0.25f);
    CHECK(chooseViewportScale(panel * 0.001, panel, 1.0f) == 0.25f);
    // Going back up needs twice the rate: at 0.5, a rate of exactly 4 spp/s at full size stays at
    // 0.5; 8 spp/s goes up.
    CHECK(chooseViewportScale(panel * 4.0, panel, 0.5f) == 0.5f);
    CHECK(chooseViewportScale(panel * 8.0, panel, 0.5f) == 1.0f);
    // Staying: at 0.5 with 1 spp/s at full size (4 at half) it stays.
    CHECK(chooseViewportScale(panel * 1.0, panel, 0.5f) == 0.5f);
    // No measurement: unchanged.
    CHECK(chooseViewportScale(0.0, panel, 0.5f) == 0.5f);
}
