// The scene: plain C++ data, no GL. The single source of truth that the JSON file, the batch
// renderer and the editor's commands all read and write. Each field's key, range, default and
// meaning are written once, in the scene schema (renderer/scene_schema.cpp), from which the loader,
// the writer, the editor's inspector and docs/scene-format.md's tables all work.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace caustic {

inline constexpr int kSceneVersion = 1;

// translate / rotate / scale, composed as M = T * Rz * Ry * Rx * S (scale first, then rotation
// about x, then y, then z, then translation), angles in degrees, right-handed (a positive angle
// turns counter-clockwise when looking down the axis towards the origin). A matrix, when given,
// replaces the three.
struct Transform {
    glm::vec3 translate{0.0f};
    glm::vec3 rotate{0.0f};
    glm::vec3 scale{1.0f};
    std::optional<glm::mat4> matrix;

    glm::mat4 toMatrix() const;
    bool operator==(const Transform&) const = default;
};

enum class FovAxis { Smaller, Larger, X, Y };

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 lookAt{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovDegrees = 40.0f;          // full angle along fovAxis, (0, 180)
    FovAxis fovAxis = FovAxis::Smaller;
    float rollDegrees = 0.0f;          // turns the image about the view direction
    // Thin lens (docs/scene-format.md): apertureRadius 0 is a pinhole.
    float apertureRadius = 0.0f;       // lens radius in scene units, >= 0
    float focalDistance = 0.0f;        // along the view direction; 0: the distance to lookAt
    std::optional<glm::vec3> focusPoint;  // when set, focus on this point (overrides focalDistance)
    float squeeze = 1.0f;              // anamorphic: the lens sample's x is divided by it, > 0
    int blades = 0;                    // 0: a round aperture; >= 3: a regular polygon
    float bladeRotationDegrees = 0.0f;
    // A greyscale image over the square around the aperture's circle (relative to the scene file):
    // its transmission shapes the bokeh (thin lens and lens system; replaces the blades). Empty: none.
    std::string apertureImage;
    // A lens system instead of the thin lens (docs/lenses.md): a prescription file (relative to the
    // scene file); empty: the thin lens above. The film sits at `position`; the lens and
    // sensorWidthMm set the field of view, lensFStop the stop, and the focus is focalDistance's or
    // focusPoint's, measured from the film.
    std::string lens;
    float lensFStop = 0.0f;            // 0: wide open
    float sensorWidthMm = 36.0f;       // the film's extent along the image's longer side
    bool lensDispersion = true;        // each channel at its own wavelength (glasses with an Abbe number)
    bool operator==(const Camera&) const = default;
};

enum class LightSelection { Power, Uniform, Tree };
// The sampler of the integrator's random numbers (shaders/lib/sampler.glsl).
enum class SamplerType { Sobol, Independent };
// When Russian roulette ends paths (shaders/integrator/path.glsl; docs/design.md).
enum class RussianRoulette { Original, Mitsuba, Pbrt, Off };

// The pixel filter, importance-sampled (every sample has weight 1): box over the pixel (the
// reference renderers' choice for comparisons), tent of radius 1 pixel, or a Gaussian with
// sigma 0.5 pixel truncated at 1.5 pixels.
enum class PixelFilter { Box, Tent, Gaussian };

// The largest image side a scene, the command line or the editor accepts (a render of
// 16384 x 16384 is 268 M pixels; the film is read back in bands, renderer.h).
inline constexpr int kMaxRenderSide = 16384;

struct RenderSettings {
    int width = 800;
    int height = 600;
    int samples = 256;                 // samples per pixel
    int maxDepth = 10;                 // maximum number of scattering events on a path
    std::uint32_t seed = 0;
    LightSelection lightSelection = LightSelection::Tree;
    SamplerType sampler = SamplerType::Sobol;
    RussianRoulette russianRoulette = RussianRoulette::Mitsuba;
    PixelFilter filter = PixelFilter::Box;
    // At a smooth glass vertex, also trace the lobe not taken for the emission it sees (splitting;
    // shaders/integrator/path.glsl, docs/design.md). Unbiased either way; on by default.
    bool glassSplit = true;
    bool operator==(const RenderSettings&) const = default;
};

// The material models (docs/materials.md; shaders/bsdf/ has one file per model).
enum class MaterialType { Diffuse, OrenNayar, Eon, Mirror, Transmission, Dielectric, Conductor, Surface, Volume };

// Conductor presets: complex IOR (eta, k) at R, G, B (see gpu_materials.cpp conductorPreset for the
// values and their sources); Custom takes Material::eta and Material::k.
enum class Metal { Aluminium, Gold, Copper, Silver, Chromium, Platinum, Perfect, Custom };

// Whether a material cuts holes by its albedo texture's alpha (glTF's alphaMode OPAQUE / MASK;
// docs/materials.md, "Alpha cut-outs").
enum class AlphaMode { Opaque, Mask };

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    glm::vec3 albedo{0.8f};            // [0, 1] per channel (diffuse, oren_nayar, eon)
    glm::vec3 emission{0.0f};          // emitted radiance, >= 0; non-zero makes the object a light
    glm::vec3 tint{1.0f};              // specular reflectance/transmittance scale (mirror, transmission, dielectric, conductor)
    float sigma = 0.5f;                // oren_nayar: facet slope deviation, radians [0, pi/2]
    float roughness = 0.0f;            // dielectric, conductor: GGX alpha [0, 1]; eon: r [0, 1] (default 0.5 set by type)
    float ior = 1.5f;                  // dielectric (default 1.5), transmission (default 1): n_inside / n_outside
    // dielectric: Beer-Lambert absorption inside (OpenPBR's transmission_color / transmission_depth):
    // light that travels transmissionDepth inside keeps transmissionColor; depth 0: no absorption.
    glm::vec3 transmissionColor{1.0f}; // (0, 1] per channel
    float transmissionDepth = 0.0f;    // scene units, >= 0
    // dielectric: OpenPBR's transmission_scatter, the scattering coefficient times the depth
    // (sigma_s = transmissionScatter / transmissionDepth; renderer/gpu_materials.cpp).
    glm::vec3 transmissionScatter{0.0f};
    // volume (an index-matched boundary: docs/materials.md, "Media"): the interior medium's
    // absorption and scattering coefficients per scene unit.
    glm::vec3 sigmaA{0.0f};
    glm::vec3 sigmaS{0.0f};
    // dielectric (transmission_scatter_anisotropy) and volume (anisotropy): the interior medium's
    // Henyey-Greenstein g, (-1, 1).
    float scatterAnisotropy = 0.0f;
    // dielectric, volume: where interiors overlap, the one of the higher priority is what is there
    // (nested dielectrics, Schmidt and Budge 2002; integrator/medium.glsl); >= 0.
    int priority = 0;
    bool energyCompensation = false;   // oren_nayar: global factor; conductor: multiple scattering
    Metal metal = Metal::Aluminium;    // conductor
    glm::vec3 eta{1.0f};               // conductor, metal == Custom: real part of the IOR, > 0
    glm::vec3 k{0.0f};                 // conductor, metal == Custom: extinction, >= 0
    // surface (shaders/bsdf/surface.glsl; OpenPBR Surface's names and meanings): the base colour is
    // `albedo`, the emission `emission`; roughnesses are perceptual (GGX alpha = roughness^2).
    float metalness = 0.0f;            // [0, 1]: metal (F82-tint Fresnel) instead of specular + diffuse
    float specularWeight = 1.0f;       // [0, 1]: the dielectric specular layer's strength
    glm::vec3 specularColor{1.0f};     // tints the dielectric specular and the metal's edge (F82)
    float specularRoughness = 0.3f;    // [0, 1], perceptual
    float specularIor = 1.5f;          // [1, 3]
    float coatWeight = 0.0f;           // [0, 1]: the clear coat's strength
    glm::vec3 coatColor{1.0f};         // what passes the coat is multiplied by it
    float coatRoughness = 0.0f;        // [0, 1], perceptual
    float coatIor = 1.6f;              // [1, 3]
    float sheenWeight = 0.0f;          // [0, 1]
    glm::vec3 sheenColor{1.0f};
    float sheenRoughness = 0.5f;       // [0, 1], perceptual (the Charlie lobe's r = roughness^2)
    // surface: OpenPBR's transmission and subsurface (integrator/surface_parts.glsl). The transmission
    // shares transmissionColor, transmissionDepth, transmissionScatter and scatterAnisotropy with the
    // dielectric (at depth 0 the colour tints each crossing of the surface instead).
    float transmissionWeight = 0.0f;   // [0, 1]: the share of the dielectric base that transmits
    float subsurfaceWeight = 0.0f;     // [0, 1]: the share of the rest that scatters below the surface
    glm::vec3 subsurfaceColor{0.8f};   // (0, 1): the multiple-scattering albedo a thick slab shows
    float subsurfaceRadius = 1.0f;     // > 0, scene units: the mean free path, times the scale below
    glm::vec3 subsurfaceRadiusScale{1.0f, 0.5f, 0.25f};  // (0, 1] per channel
    float subsurfaceAnisotropy = 0.0f; // (-1, 1): the subsurface medium's Henyey-Greenstein g
    bool thinWalled = false;           // a sheet with no inside: transmission and subsurface pass through it
    // Texture files (relative to the scene file), "" for none. albedoTexture replaces albedo
    // (diffuse models) or tint (the others) and is decoded from sRGB unless the file is HDR;
    // normalTexture is a tangent-space normal map; roughnessTexture's first channel replaces
    // sigma or roughness.
    std::string albedoTexture{};
    std::string normalTexture{};
    std::string roughnessTexture{};
    float normalScale = 1.0f;          // with normalTexture: scales the map's tangent-space x and y (glTF's scale)
    // emissionTexture (sRGB unless HDR) multiplies the emission per point (the material's or an
    // object's own), as glTF's emissiveTexture multiplies emissiveFactor.
    std::string emissionTexture{};
    // Mask: rays pass through the points where the albedo texture's alpha is below alphaCutoff
    // (above 1: everywhere), as if nothing were there (camera, bounce and shadow rays alike).
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    bool operator==(const Material&) const = default;
};

// Canonical shapes, before the object's transform:
//   sphere: the unit sphere at the origin;
//   quad:   the square [-1, 1]^2 in the z = 0 plane, front side facing +z;
//   box:    the cube [-1, 1]^3 (six quads facing outward).
//   mesh:   the triangles of a model file (OBJ, PLY, glTF, FBX, ... through Assimp), in the
//           file's own coordinates (node transforms baked in).
enum class Shape { Sphere, Quad, Box, Mesh };

struct Object {
    std::string name;
    Shape shape = Shape::Sphere;
    std::string material;              // name of an entry of Scene::materials; meshes: empty means
                                       // the model file's own materials (mapImportedMaterial)
    Transform transform;
    std::string file;                  // mesh: the model file, relative to the scene file
    // The object's own emission (an area emitter with a surface, like Mitsuba's shape + area
    // emitter): radiance (W sr^-1 m^-2), >= 0. Non-zero replaces the material's emission for this
    // object (its surface still scatters by the material) and emits from the front faces only
    // (quad: +z before the transform; sphere and box: outside; mesh: the triangles' winding,
    // counter-clockwise seen from the front) unless twoSided. Zero: the material's emission, if
    // any, from both faces.
    glm::vec3 emission{0.0f};
    bool twoSided = false;             // with emission: emit from the back faces too
    bool emits() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
    bool operator==(const Object&) const = default;
};

enum class LightType { Rect, Sphere, Point, Spot };
// How a spot light falls off between its inner and outer angle (docs/scene-format.md):
// smoothstep in cos theta (pbrt-v4's), or linear in the angle (Mitsuba 3's).
enum class SpotFalloff { Smoothstep, LinearAngle };

struct Light {
    std::string name;
    LightType type = LightType::Point;
    // rect: radiance (W sr^-1 m^-2) of the canonical quad under `transform`, emitted from its front
    //       (+z before the transform) only, unless twoSided.
    // sphere: radiance of a sphere at `position` with `radius`.
    // point / spot: intensity (W sr^-1) at `position`.
    glm::vec3 color{1.0f};             // radiance or intensity, >= 0
    Transform transform;               // rect only
    bool twoSided = false;             // rect only
    glm::vec3 position{0.0f};          // sphere, point, spot
    float radius = 0.1f;               // sphere, > 0
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // spot
    float innerAngle = 20.0f;          // spot: full intensity inside this half-angle (degrees)
    float outerAngle = 30.0f;          // spot: zero outside this half-angle (degrees)
    SpotFalloff falloff = SpotFalloff::Smoothstep;  // spot
    bool operator==(const Light&) const = default;
};

enum class EnvironmentType { None, Constant, Sky, Map };

struct Environment {
    EnvironmentType type = EnvironmentType::None;
    glm::vec3 radiance{1.0f};          // constant
    glm::vec3 horizon{1.0f, 1.0f, 1.0f};     // sky: radiance at the horizon
    glm::vec3 zenith{0.3f, 0.5f, 1.0f};      // sky: radiance straight up
    std::string file;                  // map: an equirectangular HDR image (relative to the scene file)
    float rotation = 0.0f;             // map: degrees about +y (right-handed)
    float intensity = 1.0f;            // scales the whole environment, >= 0
    // The scene's medium (fog): it fills everything outside the objects, the camera included.
    // Absorption and scattering coefficients per scene unit, Henyey-Greenstein g; zero: vacuum.
    glm::vec3 mediumSigmaA{0.0f};
    glm::vec3 mediumSigmaS{0.0f};
    float mediumAnisotropy = 0.0f;
    bool operator==(const Environment&) const = default;
};

// Named looks of the sky (docs/scene-format.md, "environment"): a preset is a shorthand for the
// sky's horizon, zenith and intensity, applied when a scene is read (`"preset"`, then any of the
// three keys the file gives override it) or by `caustic --sky-preset`; it is not stored, so a
// saved scene holds the values. "default" is Environment's own sky (a white horizon to a blue
// zenith at full strength: a key light); "original" is the original renderer's look, a dark teal
// horizon to a white zenith scaled down to read as fill light.
struct SkyPreset {
    std::string_view name;
    glm::vec3 horizon;
    glm::vec3 zenith;
    float intensity;
};
std::span<const SkyPreset> skyPresets();
const SkyPreset* findSkyPreset(std::string_view name);   // null when there is none of that name
// Makes env a sky with the preset's horizon, zenith and intensity (other members untouched).
void applySkyPreset(const SkyPreset& preset, Environment& env);

struct Scene {
    int version = kSceneVersion;
    Camera camera;
    RenderSettings render;
    std::vector<Material> materials;
    std::vector<Object> objects;
    std::vector<Light> lights;
    Environment environment;

    // Where the scene was loaded from (not saved); relative paths in the file are relative to it.
    std::string sourcePath;

    const Material* findMaterial(const std::string& name) const;
    bool operator==(const Scene& o) const {
        return version == o.version && camera == o.camera && render == o.render &&
               materials == o.materials && objects == o.objects && lights == o.lights &&
               environment == o.environment;
    }
};

// The one rule for the files a scene names (textures, meshes, environment maps): a relative path
// is relative to `folder` ("": the working directory); an absolute one stays as it is.
std::string resolvePathIn(const std::string& folder, const std::string& file);
// The folder of the scene's file ("" for a scene not read from a file), and a path it names
// resolved against that folder.
std::string sceneFolder(const Scene& scene);
std::string resolveScenePath(const Scene& scene, const std::string& file);

}  // namespace caustic
