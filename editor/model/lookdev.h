// Lookdev in the editor's model (no ImGui, no GL): the material library (presets an artist knows
// by name), artist names for the material models, the edits that give materials to the selected
// objects (assign, New, Make unique, apply a preset), and the scene of the material preview ball
// (a sphere on a checker floor, rendered by the same integrator in a small second film:
// editor/ui/material_preview.h).
#pragma once

#include "editor/model/editor_state.h"
#include "renderer/lens.h"
#include "renderer/scene.h"

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace caustic::editor {

// One preset of the library: its group ("Metals", "Glass", ...) and the material (named after
// the preset). The renderer's own presets (renderer/gpu_materials.h materialPresets: plastic,
// varnished wood, car paint, velvet) are part of it.
struct LibraryMaterial {
    std::string_view group;
    Material material;
};
std::span<const LibraryMaterial> materialLibrary();
const Material* findLibraryMaterial(std::string_view name);   // null when none has that name

// What an artist calls a material model, for the inspector's type menu ("Metal", "Glass, water,
// gems", "Plastic, paint": the layered surface); the menu shows the schema's label beside it and
// the file format's names stay the schema's.
std::string_view materialTypeArtistName(MaterialType type);

// Gives every object of `objects` (indices) the material `material`: one undo step ("Assign
// material 'gold' to 3 objects"). Null with *why when an index or the material does not exist,
// or nothing would change.
std::unique_ptr<Command> makeAssignMaterial(const EditorState& s, const std::vector<int>& objects,
                                            const std::string& material, std::string* why);
// A new material (a copy of `preset`, or the default material) given to every object of
// `objects`: one undo step. With no objects it is only added.
std::unique_ptr<Command> makeNewMaterialFor(const EditorState& s, const std::vector<int>& objects,
                                            const Material* preset, std::string* why);
// Make unique: a copy of the material the objects share ("gold 2"), given to them alone, so edits
// no longer reach the other objects that use it. Null with *why when the objects do not all have
// one same material, or nothing else uses it (it is unique already).
std::unique_ptr<Command> makeMakeUnique(const EditorState& s, const std::vector<int>& objects, std::string* why);
// Material `index` takes the preset's model and parameters; its name stays (so its objects keep
// it). One undo step.
std::unique_ptr<Command> makeApplyPreset(const EditorState& s, int index, const Material& preset);
// How many objects use the material named `name`.
int materialUsers(const Scene& scene, const std::string& name);

// The material preview's lighting: the scene's environment (with a studio light when the scene
// has none), or the studio alone (a key light and a dim even fill).
enum class PreviewLighting { Scene, Studio };

// The preview ball's scene: the material on a unit sphere over a checker floor (two diffuse
// greys), seen by a fixed camera, at size x size pixels, `samples` samples, lit as asked. Files
// the material and environment name resolve from the edited scene's folder (sourcePath is kept).
Scene makePreviewScene(const Scene& edited, const Material& material, PreviewLighting lighting, int size = 128,
                       int samples = 64);
// The camera's bokeh preview (the camera inspector): the edited camera as it is (thin lens or lens
// system, its stop, blades, aperture image and focus) looking at a 5 x 3 grid of small bright
// points spread over its frame at ten times its focus distance, on black, so each point's
// defocused image shows the bokeh's shape at that place of the frame (cat's eyes towards the
// edges). `lens`: the renderer's prepared lens system for a camera with one (its rays place the
// points where the lens sees them; the pinhole of fov otherwise). width x (width / aspect) pixels.
Scene makeBokehPreviewScene(const Scene& edited, const LensCamera* lens, int width = 256, int samples = 64);
inline constexpr int kBokehPreviewColumns = 5, kBokehPreviewRows = 3;

// The ball's material inside the preview scene (a fixed name that no scene material can clash
// with in it).
inline constexpr const char* kPreviewMaterialName = "preview ball";

}  // namespace caustic::editor
