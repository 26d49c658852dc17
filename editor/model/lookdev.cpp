#include "editor/model/lookdev.h"

#include "editor/model/viewport_math.h"
#include "renderer/camera.h"
#include "renderer/gpu_materials.h"
#include "renderer/scene_schema.h"

#include <algorithm>
#include <cmath>

namespace caustic::editor {
namespace {

Material metal(const char* name, Metal which, float alpha) {
    Material m = materialDefaults(MaterialType::Conductor);
    m.name = name;
    m.metal = which;
    m.roughness = alpha;                  // GGX alpha
    m.energyCompensation = alpha > 0.05f; // multiple scattering keeps rough metal bright
    return m;
}

Material glass(const char* name, float ior, float alpha, glm::vec3 tint = glm::vec3(1.0f)) {
    Material m = materialDefaults(MaterialType::Dielectric);
    m.name = name;
    m.ior = ior;
    m.roughness = alpha;
    m.tint = tint;
    return m;
}

// A dielectric with an interior medium, in OpenPBR's terms: the colour kept after `depth` scene
// units, the scattering coefficient times the depth, its anisotropy.
Material tinted(const char* name, float ior, float alpha, glm::vec3 colour, float depth, glm::vec3 scatter = glm::vec3(0.0f),
                float anisotropy = 0.0f) {
    Material m = glass(name, ior, alpha);
    m.transmissionColor = colour;
    m.transmissionDepth = depth;
    m.transmissionScatter = scatter;
    m.scatterAnisotropy = anisotropy;
    return m;
}

Material volume(const char* name, glm::vec3 sigmaA, glm::vec3 sigmaS, float anisotropy) {
    Material m = materialDefaults(MaterialType::Volume);
    m.name = name;
    m.sigmaA = sigmaA;
    m.sigmaS = sigmaS;
    m.scatterAnisotropy = anisotropy;
    return m;
}

Material surface(const char* name, glm::vec3 base, float roughness) {
    Material m = materialDefaults(MaterialType::Surface);
    m.name = name;
    m.albedo = base;
    m.specularRoughness = roughness;      // perceptual
    return m;
}

// The surface with subsurface scattering (OpenPBR's subsurface: colour, mean free path radius x
// scale per channel, anisotropy; docs/materials.md), for objects of about a scene unit.
Material subsurface(const char* name, glm::vec3 colour, float radius, glm::vec3 scale, float roughness, float ior,
                    float anisotropy = 0.0f) {
    Material m = materialDefaults(MaterialType::Surface);
    m.name = name;
    m.albedo = colour;  // what the rest of the base (none here) and the preview's swatch show
    m.subsurfaceWeight = 1.0f;
    m.subsurfaceColor = colour;
    m.subsurfaceRadius = radius;
    m.subsurfaceRadiusScale = scale;
    m.subsurfaceAnisotropy = anisotropy;
    m.specularRoughness = roughness;
    m.specularIor = ior;
    return m;
}

Material matte(const char* name, MaterialType type, glm::vec3 albedo) {
    Material m = materialDefaults(type);
    m.name = name;
    m.albedo = albedo;
    return m;
}

}  // namespace

std::span<const LibraryMaterial> materialLibrary() {
    static const std::vector<LibraryMaterial> library = [] {
        std::vector<LibraryMaterial> l;
        // Metals: measured complex IORs (renderer/gpu_materials.cpp conductorPreset).
        l.push_back({"Metals", metal("gold", Metal::Gold, 0.04f)});
        l.push_back({"Metals", metal("copper", Metal::Copper, 0.08f)});
        l.push_back({"Metals", metal("aluminium", Metal::Aluminium, 0.06f)});
        l.push_back({"Metals", metal("brushed aluminium", Metal::Aluminium, 0.35f)});
        l.push_back({"Metals", metal("silver", Metal::Silver, 0.02f)});
        l.push_back({"Metals", metal("chrome", Metal::Chromium, 0.01f)});
        l.push_back({"Metals", metal("platinum", Metal::Platinum, 0.1f)});
        // Glass and liquids: dielectrics (GGX alpha 0: smooth).
        l.push_back({"Glass", glass("glass", 1.5f, 0.0f)});
        l.push_back({"Glass", glass("rough glass", 1.5f, 0.15f)});
        l.push_back({"Glass", glass("frosted glass", 1.5f, 0.45f)});
        // Coloured by absorption inside (the colour deepens with thickness), for objects of about a
        // scene unit.
        l.push_back({"Glass", tinted("green bottle glass", 1.52f, 0.0f, {0.3f, 0.7f, 0.35f}, 0.5f)});
        l.push_back({"Glass", tinted("amber glass", 1.52f, 0.0f, {0.8f, 0.45f, 0.1f}, 0.5f)});
        l.push_back({"Glass", tinted("honey", 1.49f, 0.0f, {0.85f, 0.5f, 0.08f}, 0.3f, {0.03f, 0.02f, 0.01f})});
        l.push_back({"Glass", tinted("milky glass", 1.5f, 0.05f, {0.55f, 0.6f, 0.7f}, 0.3f, {0.45f, 0.45f, 0.45f}, 0.2f)});
        l.push_back({"Glass", glass("water", 1.333f, 0.0f)});
        l.push_back({"Glass", glass("diamond", 2.42f, 0.0f)});
        // Plastics and coatings: the layered surface (a dielectric specular over a diffuse base).
        for (const Material& m : materialPresets())
            if (m.name == "plastic") l.push_back({"Plastics", m});
        l.push_back({"Plastics", surface("rough plastic", {0.08f, 0.25f, 0.6f}, 0.6f)});
        l.push_back({"Plastics", surface("glossy white plastic", {0.8f, 0.8f, 0.78f}, 0.12f)});
        {
            Material rubber = surface("black rubber", {0.03f, 0.03f, 0.03f}, 0.75f);
            rubber.specularWeight = 0.5f;
            l.push_back({"Plastics", rubber});
        }
        {
            Material ceramic = surface("glazed ceramic", {0.75f, 0.72f, 0.65f}, 0.5f);
            ceramic.coatWeight = 1.0f;
            ceramic.coatRoughness = 0.05f;
            ceramic.coatIor = 1.5f;
            l.push_back({"Plastics", ceramic});
        }
        for (const Material& m : materialPresets())
            if (m.name != "plastic") l.push_back({"Coated and cloth", m});
        // Matte.
        l.push_back({"Matte", matte("matte white", MaterialType::Diffuse, glm::vec3(0.8f))});
        l.push_back({"Matte", matte("matte grey", MaterialType::Diffuse, glm::vec3(0.18f))});
        {
            Material clay = matte("clay", MaterialType::Eon, {0.55f, 0.33f, 0.22f});
            clay.roughness = 1.0f;
            l.push_back({"Matte", clay});
        }
        {
            Material plaster = matte("plaster", MaterialType::OrenNayar, {0.85f, 0.84f, 0.8f});
            plaster.sigma = 0.5f;
            l.push_back({"Matte", plaster});
        }
        // Translucent: the surface's subsurface (a random walk inside) and transmission.
        l.push_back({"Translucent", subsurface("jade", {0.32f, 0.72f, 0.45f}, 0.08f, {1.0f, 1.0f, 0.8f}, 0.15f, 1.61f)});
        l.push_back({"Translucent", subsurface("marble", {0.92f, 0.9f, 0.86f}, 0.03f, {1.0f, 0.9f, 0.75f}, 0.25f, 1.5f)});
        l.push_back({"Translucent", subsurface("wax", {0.93f, 0.8f, 0.55f}, 0.05f, {1.0f, 0.6f, 0.35f}, 0.35f, 1.45f)});
        l.push_back({"Translucent", subsurface("skin", {0.85f, 0.56f, 0.45f}, 0.02f, {1.0f, 0.35f, 0.2f}, 0.45f, 1.4f, 0.8f)});
        l.push_back({"Translucent", subsurface("milk", {0.95f, 0.93f, 0.87f}, 0.01f, {1.0f, 0.85f, 0.65f}, 0.1f, 1.35f)});
        {
            Material tinted = materialDefaults(MaterialType::Surface);
            tinted.name = "coloured glass (surface)";
            tinted.specularRoughness = 0.0f;
            tinted.transmissionWeight = 1.0f;
            tinted.transmissionColor = {0.2f, 0.5f, 0.85f};
            tinted.transmissionDepth = 0.3f;
            l.push_back({"Translucent", tinted});
        }
        {
            Material leaf = subsurface("leaf", {0.25f, 0.55f, 0.1f}, 1.0f, glm::vec3(1.0f), 0.4f, 1.45f, 0.3f);
            leaf.albedo = {0.1f, 0.3f, 0.05f};
            leaf.subsurfaceWeight = 0.6f;
            leaf.thinWalled = true;
            l.push_back({"Translucent", leaf});
        }
        // Media: volumes (a shape that only bounds its medium), coefficients per scene unit.
        l.push_back({"Media", volume("fog", glm::vec3(0.02f), glm::vec3(0.45f), 0.5f)});
        l.push_back({"Media", volume("smoke", {0.4f, 0.42f, 0.45f}, glm::vec3(2.0f), 0.3f)});
        {
            Material mirror = materialDefaults(MaterialType::Mirror);
            mirror.name = "mirror";
            l.push_back({"Mirror", mirror});
        }
        return l;
    }();
    return library;
}

const Material* findLibraryMaterial(std::string_view name) {
    for (const LibraryMaterial& l : materialLibrary())
        if (l.material.name == name) return &l.material;
    return nullptr;
}

std::string_view materialTypeArtistName(MaterialType type) {
    // Short enough for the inspector's field; the menu adds the model's own name.
    switch (type) {
        case MaterialType::Diffuse: return "Matte";
        case MaterialType::OrenNayar: return "Rough matte";
        case MaterialType::Eon: return "Rough matte, EON";
        case MaterialType::Mirror: return "Mirror";
        case MaterialType::Transmission: return "Clear refraction";
        case MaterialType::Dielectric: return "Glass, water, gems";
        case MaterialType::Conductor: return "Metal";
        case MaterialType::Surface: return "Plastic, paint";
        case MaterialType::Volume: return "Fog, smoke (a medium)";
    }
    return "?";
}

int materialUsers(const Scene& scene, const std::string& name) {
    int n = 0;
    for (const Object& o : scene.objects) n += o.material == name;
    return n;
}

namespace {

bool validObjects(const EditorState& s, const std::vector<int>& objects, std::string* why) {
    for (int i : objects)
        if (i < 0 || static_cast<size_t>(i) >= s.scene.objects.size()) {
            if (why) *why = "no object " + std::to_string(i);
            return false;
        }
    return true;
}

std::string objectsText(const EditorState& s, const std::vector<int>& objects) {
    if (objects.size() == 1) return "'" + s.scene.objects[static_cast<size_t>(objects[0])].name + "'";
    return std::to_string(objects.size()) + " objects";
}

// The steps that give `objects` the material `name` (none for an object that has it already).
std::vector<std::unique_ptr<Command>> assignSteps(const EditorState& s, const std::vector<int>& objects,
                                                  const std::string& name) {
    std::vector<std::unique_ptr<Command>> steps;
    for (int i : objects) {
        Object o = s.scene.objects[static_cast<size_t>(i)];
        if (o.material == name) continue;
        o.material = name;
        steps.push_back(makeSetObject(s, i, std::move(o)));
    }
    return steps;
}

}  // namespace

std::unique_ptr<Command> makeAssignMaterial(const EditorState& s, const std::vector<int>& objects,
                                            const std::string& material, std::string* why) {
    if (!validObjects(s, objects, why)) return nullptr;
    if (!s.scene.findMaterial(material)) {
        if (why) *why = "no material named '" + material + "'";
        return nullptr;
    }
    auto steps = assignSteps(s, objects, material);
    if (steps.empty()) {
        if (why) *why = objects.empty() ? "no object is selected" : "the selection has material '" + material + "' already";
        return nullptr;
    }
    return std::make_unique<CompoundCommand>("Assign material '" + material + "' to " + objectsText(s, objects),
                                             std::move(steps), s.selection, s.selectedObjects());
}

namespace {

// Adds a copy of `preset` (or the default material) under a free name, and gives it to `objects`.
std::vector<std::unique_ptr<Command>> newMaterialSteps(const EditorState& s, const std::vector<int>& objects,
                                                       const Material* preset, std::string* name) {
    std::vector<std::string> taken;
    for (const Material& m : s.scene.materials) taken.push_back(m.name);
    *name = uniqueName(preset ? preset->name : std::string("material"), taken);
    std::vector<std::unique_ptr<Command>> steps;
    steps.push_back(makeAddMaterial(s, preset));   // names it *name, by the same rule
    for (auto& c : assignSteps(s, objects, *name)) steps.push_back(std::move(c));
    return steps;
}

}  // namespace

std::unique_ptr<Command> makeNewMaterialFor(const EditorState& s, const std::vector<int>& objects,
                                            const Material* preset, std::string* why) {
    if (!validObjects(s, objects, why)) return nullptr;
    if (objects.empty()) return makeAddMaterial(s, preset);
    std::string name;
    auto steps = newMaterialSteps(s, objects, preset, &name);
    return std::make_unique<CompoundCommand>("New material '" + name + "' for " + objectsText(s, objects),
                                             std::move(steps), s.selection, s.selectedObjects());
}

std::unique_ptr<Command> makeMakeUnique(const EditorState& s, const std::vector<int>& objects, std::string* why) {
    if (!validObjects(s, objects, why)) return nullptr;
    if (objects.empty()) {
        if (why) *why = "no object is selected";
        return nullptr;
    }
    const std::string shared = s.scene.objects[static_cast<size_t>(objects[0])].material;
    for (int i : objects)
        if (s.scene.objects[static_cast<size_t>(i)].material != shared) {
            if (why) *why = "the selected objects have different materials";
            return nullptr;
        }
    const Material* m = s.scene.findMaterial(shared);
    if (!m) {
        if (why) *why = shared.empty() ? "the object uses its file's own materials" : "no material named '" + shared + "'";
        return nullptr;
    }
    if (materialUsers(s.scene, shared) <= static_cast<int>(objects.size())) {
        if (why) *why = "material '" + shared + "' is used by the selection alone: it is unique already";
        return nullptr;
    }
    const Material copy = *m;
    std::string name;
    auto steps = newMaterialSteps(s, objects, &copy, &name);
    return std::make_unique<CompoundCommand>("Make unique: '" + name + "' (a copy of '" + shared + "') for " +
                                                 objectsText(s, objects),
                                             std::move(steps), s.selection, s.selectedObjects());
}

std::unique_ptr<Command> makeApplyPreset(const EditorState& s, int index, const Material& preset) {
    Material m = preset;
    m.name = s.scene.materials.at(static_cast<size_t>(index)).name;
    return makeSetMaterial(s, index, std::move(m));
}

Scene makeBokehPreviewScene(const Scene& edited, const LensCamera* lens, int width, int samples) {
    Scene p;
    p.sourcePath = edited.sourcePath;   // the lens file and the aperture image resolve from there
    p.camera = edited.camera;
    const double aspect = double(edited.render.width) / double(std::max(edited.render.height, 1));
    p.render.width = width;
    p.render.height = std::clamp(int(std::lround(width / aspect)), 8, 4 * width);
    p.render.samples = samples;
    p.render.maxDepth = 1;
    p.render.seed = 0;
    const CameraFrame frame = cameraFrame(p.camera, p.render.width, p.render.height);
    const double depth = 10.0 * frame.focalDistance;
    // The points' radiance: a defocused point of radius r spreads over a disc of about the
    // entrance pupil's diameter A at that depth (the blur at 10 times the focus distance is 9 A
    // across, in the scene), so radiance (9 A / r)^2 makes the discs' brightness about 1.
    const double pupil = lens && !p.camera.lens.empty() ? lens->efl / lens->fNumber / kMillimetresPerSceneUnit
                                                        : 2.0 * p.camera.apertureRadius;
    const double radius = 0.002 * depth;
    const float radiance = float(std::clamp(std::pow(9.0 * std::max(pupil, radius) / radius, 2.0), 1.0, 1e7));
    Material point;
    point.name = "bokeh point";
    point.albedo = glm::vec3(0.0f);
    point.emission = glm::vec3(radiance);
    p.materials.push_back(point);
    for (int j = 0; j < kBokehPreviewRows; ++j)
        for (int i = 0; i < kBokehPreviewColumns; ++i) {
            // Spread over the frame, the outer ones 8 % in from its edges.
            const glm::vec2 pixel(float(p.render.width) * (0.08f + 0.84f * float(i) / float(kBokehPreviewColumns - 1)),
                                  float(p.render.height) * (0.08f + 0.84f * float(j) / float(kBokehPreviewRows - 1)));
            const Ray ray = cameraRay(p.camera, p.render.width, p.render.height, pixel, lens);
            const double along = glm::dot(glm::dvec3(ray.direction), frame.forward);
            if (!(along > 1e-6)) continue;
            const glm::dvec3 at = glm::dvec3(ray.origin) + glm::dvec3(ray.direction) *
                                  ((depth - glm::dot(glm::dvec3(ray.origin) - frame.position, frame.forward)) / along);
            Object o;
            o.name = "bokeh point " + std::to_string(j * kBokehPreviewColumns + i);
            o.shape = Shape::Sphere;
            o.material = point.name;
            o.transform.translate = glm::vec3(at);
            o.transform.scale = glm::vec3(float(radius));
            p.objects.push_back(std::move(o));
        }
    return p;
}

Scene makePreviewScene(const Scene& edited, const Material& material, PreviewLighting lighting, int size, int samples) {
    Scene p;
    p.sourcePath = edited.sourcePath;   // the material's textures and the environment map resolve from there
    p.render.width = p.render.height = size;
    p.render.samples = samples;
    p.render.maxDepth = 8;
    p.render.seed = 0;
    p.camera.position = {0.0f, 1.1f, 4.2f};
    p.camera.lookAt = {0.0f, -0.05f, 0.0f};
    p.camera.fovDegrees = 34.0f;

    Material ball = material;
    ball.name = kPreviewMaterialName;
    p.materials.push_back(ball);
    for (auto [name, grey] : {std::pair{"preview checker light", 0.65f}, std::pair{"preview checker dark", 0.12f}}) {
        Material tile;
        tile.name = name;
        tile.albedo = glm::vec3(grey);
        p.materials.push_back(std::move(tile));
    }
    Object ballObject;
    ballObject.name = "ball";
    ballObject.shape = Shape::Sphere;
    ballObject.material = kPreviewMaterialName;
    p.objects.push_back(std::move(ballObject));
    // The floor: 8 x 8 tiles of 0.75 (quads face +z; turned to face +y), just under the ball.
    constexpr int kTiles = 8;
    constexpr float kTile = 0.75f;
    for (int z = 0; z < kTiles; ++z)
        for (int x = 0; x < kTiles; ++x) {
            Object t;
            t.name = "tile " + std::to_string(z * kTiles + x);
            t.shape = Shape::Quad;
            t.material = (x + z) % 2 ? "preview checker dark" : "preview checker light";
            t.transform.translate = {(float(x) - kTiles / 2 + 0.5f) * kTile, -1.0f, (float(z) - kTiles / 2 + 0.5f) * kTile};
            t.transform.rotate = {-90.0f, 0.0f, 0.0f};
            t.transform.scale = {kTile / 2, kTile / 2, 1.0f};
            p.objects.push_back(std::move(t));
        }
    const bool studio = lighting == PreviewLighting::Studio || edited.environment.type == EnvironmentType::None;
    if (studio) {
        // A key light above and to the left of the camera, and a dim even fill.
        Light key;
        key.name = "key";
        key.type = LightType::Sphere;
        key.color = glm::vec3(40.0f);
        key.position = {-2.5f, 3.5f, 3.0f};
        key.radius = 0.8f;
        p.lights.push_back(std::move(key));
        p.environment.type = EnvironmentType::Constant;
        p.environment.radiance = glm::vec3(0.25f);
        if (lighting == PreviewLighting::Scene && edited.environment.type == EnvironmentType::None) return p;
    }
    if (lighting == PreviewLighting::Scene) p.environment = edited.environment;
    return p;
}

}  // namespace caustic::editor
