// The scene schema's tables and rules (scene_schema.h). Each table lists a struct's keys in the
// order they are written; docs/scene-format.md's tables are generated from these rows, so the
// `doc` strings are Markdown and say what the value means (the range, type and default columns
// are printed from the other members).
#include "renderer/scene_schema.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace caustic {

namespace {

template <class M>
struct MemberTraits;
template <class C, class V>
struct MemberTraits<V C::*> {
    using Class = C;
    using Value = V;
};

// Enum accessors for a member pointer M (Param::getEnum / setEnum / choices).
template <auto M>
int getEnumOf(const typename MemberTraits<decltype(M)>::Class& x) {
    return static_cast<int>(x.*M);
}
template <auto M>
void setEnumOf(typename MemberTraits<decltype(M)>::Class& x, int v) {
    x.*M = static_cast<typename MemberTraits<decltype(M)>::Value>(v);
}
template <auto M>
std::span<const EnumChoice> choicesOf() {
    return enumChoices(typename MemberTraits<decltype(M)>::Value{});
}

// An enum parameter of member M.
template <auto M>
Param<typename MemberTraits<decltype(M)>::Class> enumParam(std::string_view key, std::string_view label,
                                                           std::string_view doc, std::uint32_t types = ~0u) {
    Param<typename MemberTraits<decltype(M)>::Class> p;
    p.key = key;
    p.label = label;
    p.kind = ParamKind::Enum;
    p.doc = doc;
    p.types = types;
    p.getEnum = &getEnumOf<M>;
    p.setEnum = &setEnumOf<M>;
    p.choices = &choicesOf<M>;
    return p;
}

template <class... E>
constexpr std::uint32_t bits(E... e) {
    return ((1u << static_cast<unsigned>(e)) | ...);
}

std::string vectorText(const glm::vec3& v) {
    std::string out = "[";
    for (int i = 0; i < 3; ++i) {
        if (i > 0) out += ", ";
        out += shortestText(v[i]);
    }
    return out + "]";
}

}  // namespace

std::string shortestText(double value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::string shortestText(float value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

bool Range::contains(double x) const {
    if (minExclusive ? !(x > min) : !(x >= min)) return false;
    if (maxExclusive ? !(x < max) : !(x <= max)) return false;
    return !(nonZero && x == 0.0);
}

std::string Range::text() const {
    const bool lower = std::isfinite(min), upper = std::isfinite(max);
    std::string out;
    if (lower && upper) {
        out += minExclusive ? '(' : '[';
        out += shortestText(min);
        out += ", ";
        out += shortestText(max);
        out += maxExclusive ? ')' : ']';
    } else if (lower) {
        out += minExclusive ? "> " : ">= ";
        out += shortestText(min);
    } else if (upper) {
        out += maxExclusive ? "< " : "<= ";
        out += shortestText(max);
    }
    if (nonZero) out += out.empty() ? "non-zero" : ", non-zero";
    if (out.empty()) out = "any";
    return out;
}

// ---------------------------------------------------------------------------------------------
// Enums

std::span<const EnumChoice> enumChoices(FovAxis) {
    static constexpr EnumChoice k[] = {{0, "smaller", "smaller side"}, {1, "larger", "larger side"},
                                       {2, "x", "x (horizontal)"},      {3, "y", "y (vertical)"}};
    return k;
}
std::span<const EnumChoice> enumChoices(LightSelection) {
    static constexpr EnumChoice k[] = {{0, "power", "by power"}, {1, "uniform", "uniform"}, {2, "tree", "light tree"}};
    return k;
}
std::span<const EnumChoice> enumChoices(SamplerType) {
    static constexpr EnumChoice k[] = {{0, "sobol", "Sobol (Owen)"}, {1, "independent", "independent"}};
    return k;
}
std::span<const EnumChoice> enumChoices(RussianRoulette) {
    static constexpr EnumChoice k[] = {
        {0, "original", "original"}, {1, "mitsuba", "Mitsuba"}, {2, "pbrt", "pbrt"}, {3, "off", "off"}};
    return k;
}
std::span<const EnumChoice> enumChoices(PixelFilter) {
    static constexpr EnumChoice k[] = {{0, "box", "box"}, {1, "tent", "tent"}, {2, "gaussian", "Gaussian"}};
    return k;
}
std::span<const EnumChoice> enumChoices(MaterialType) {
    static constexpr EnumChoice k[] = {{0, "diffuse", "diffuse (Lambert)"},
                                       {1, "oren_nayar", "Oren-Nayar"},
                                       {2, "eon", "energy-preserving Oren-Nayar"},
                                       {3, "mirror", "mirror"},
                                       {4, "transmission", "transmission"},
                                       {5, "dielectric", "dielectric (glass)"},
                                       {6, "conductor", "conductor (metal)"},
                                       {7, "surface", "surface (layered, OpenPBR-style)"},
                                       {8, "volume", "volume (medium boundary)"}};
    return k;
}
std::span<const EnumChoice> enumChoices(Metal) {
    static constexpr EnumChoice k[] = {{0, "aluminium", "aluminium"}, {1, "gold", "gold"},
                                       {2, "copper", "copper"},       {3, "silver", "silver"},
                                       {4, "chromium", "chromium"},   {5, "platinum", "platinum"},
                                       {6, "perfect", "perfect (F = 1)"}, {7, "custom", "custom (eta, k)"}};
    return k;
}
std::span<const EnumChoice> enumChoices(Shape) {
    static constexpr EnumChoice k[] = {{0, "sphere", "sphere"}, {1, "quad", "quad"}, {2, "box", "box"}, {3, "mesh", "mesh"}};
    return k;
}
std::span<const EnumChoice> enumChoices(LightType) {
    static constexpr EnumChoice k[] = {{0, "rect", "rectangle"}, {1, "sphere", "sphere"}, {2, "point", "point"}, {3, "spot", "spot"}};
    return k;
}
std::span<const EnumChoice> enumChoices(SpotFalloff) {
    static constexpr EnumChoice k[] = {{0, "smoothstep", "smoothstep (cos)"}, {1, "linear_angle", "linear in angle (Mitsuba)"}};
    return k;
}
std::span<const EnumChoice> enumChoices(AlphaMode) {
    static constexpr EnumChoice k[] = {{0, "opaque", "opaque"}, {1, "mask", "mask (cut-outs)"}};
    return k;
}
std::span<const EnumChoice> enumChoices(EnvironmentType) {
    static constexpr EnumChoice k[] = {{0, "none", "none"}, {1, "constant", "constant"}, {2, "sky", "sky"}, {3, "map", "map (HDR image)"}};
    return k;
}

// ---------------------------------------------------------------------------------------------
// Tables

template <>
std::span<const Param<Camera>> schemaOf<Camera>() {
    using C = Camera;
    static const Param<C> k[] = {
        {.key = "position", .label = "Position", .kind = ParamKind::Vector, .member = &C::position, .range = coordinate(),
         .doc = "the eye (each coordinate within +-1e18, as `look_at`, `focus_point` and light positions: the renderer "
                "squares distances in 32-bit floats)"},
        {.key = "look_at", .label = "Look at", .kind = ParamKind::Vector, .member = &C::lookAt, .range = coordinate(),
         .doc = "the point at the centre of the image; must differ from `position`"},
        {.key = "up", .label = "Up", .kind = ParamKind::Vector, .member = &C::up,
         .doc = "non-zero, not parallel to `look_at - position`; need not be perpendicular to it"},
        {.key = "fov", .label = "Field of view", .kind = ParamKind::Float, .member = &C::fovDegrees,
         .range = openInterval(0.0, 180.0), .unit = "deg", .doc = "full field of view along `fov_axis`", .speed = 0.1f},
        enumParam<&C::fovAxis>("fov_axis", "Fov axis",
                               "which image axis `fov` spans: the shorter side (the height of a landscape image), the "
                               "longer side, horizontal or vertical"),
        {.key = "roll", .label = "Roll", .kind = ParamKind::Float, .member = &C::rollDegrees, .unit = "deg",
         .doc = "turns the image counter-clockwise about the view direction", .speed = 0.2f},
        {.key = "aperture_radius", .label = "Aperture radius", .kind = ParamKind::Float, .member = &C::apertureRadius,
         .range = atLeast(0.0), .unit = "scene units",
         .doc = "radius of the thin lens; `0` is a pinhole (everything sharp); with a `lens` it is read and ignored "
                "(the stop is `lens_f_stop`), so `--set camera.lens=...` works on a thin-lens scene",
         .applies = [](const C& c) { return c.lens.empty(); }, .speed = 0.001f},
        {.key = "focal_distance", .label = "Focal distance", .kind = ParamKind::Float, .member = &C::focalDistance,
         .range = atLeast(0.0), .unit = "scene units",
         .doc = "distance of the plane of focus along the view direction; `0` means the distance to `look_at`",
         .speed = 0.01f},
        {.key = "focus_point", .label = "Focus point", .kind = ParamKind::OptionalPoint, .member = &C::focusPoint,
         .range = coordinate(),
         .doc = "when given, focus on this point (the plane of focus passes through it); overrides "
                "`focal_distance`; must lie in front of the camera",
         .omitted = [](const C& c) { return !c.focusPoint.has_value(); }, .defaultText = "absent"},
        {.key = "squeeze", .label = "Squeeze", .kind = ParamKind::Float, .member = &C::squeeze,
         .range = greaterThan(0.0),
         .doc = "anamorphic squeeze: the lens sample's x is divided by it, so out-of-focus highlights are "
                "`squeeze` times taller than wide (the thin lens's: with a `lens` it is read and ignored)",
         .applies = [](const C& c) { return c.lens.empty(); }, .speed = 0.01f},
        {.key = "blades", .label = "Blades", .kind = ParamKind::Int, .member = &C::blades,
         .range = between(0.0, 64.0),
         .doc = "`0`: a round aperture; 3 or more: a regular polygon with that many blades (polygonal bokeh); 1 and 2 "
                "are refused",
         .speed = 0.1f},
        {.key = "blade_rotation", .label = "Blade rotation", .kind = ParamKind::Float, .member = &C::bladeRotationDegrees,
         .unit = "deg", .doc = "at 0 a polygon vertex points along the image's +x (a lens system: its stop's)", .speed = 0.5f},
        {.key = "aperture_image", .label = "Aperture image", .kind = ParamKind::File, .member = &C::apertureImage,
         .doc = "a greyscale image (relative to the scene file) over the square around the aperture's circle, row 0 "
                "at the top: its values as stored (the mean of its colour channels; 0 opaque, 1 open) shape the "
                "bokeh instead of `blades`; the thin lens draws its samples in proportion to them, a lens system's "
                "stop passes that fraction of each ray; at most 256 texels a side are kept (larger images are "
                "averaged down)",
         .omitted = [](const C& c) { return c.apertureImage.empty(); }, .nonEmpty = true, .defaultText = "none"},
        {.key = "lens", .label = "Lens", .kind = ParamKind::File, .member = &C::lens,
         .doc = "a lens prescription (`.lens`, relative to the scene file; docs/lenses.md, `assets/lenses/` holds "
                "published designs) traced instead of the thin lens: the film sits at `position`, the lens and "
                "`sensor_width` set the field of view (`fov` is then the editor's only), the focus is "
                "`focal_distance` or `focus_point` from the film, `blades` shape its stop",
         .omitted = [](const C& c) { return c.lens.empty(); }, .nonEmpty = true, .defaultText = "none",
         .section = "Lens system"},
        {.key = "lens_f_stop", .label = "f-stop", .kind = ParamKind::Float, .member = &C::lensFStop,
         .range = between(0.0, 1000.0),
         .doc = "with `lens`: the f-number the stop closes to (paraxial, at infinity focus); `0` or wider than the "
                "lens opens: wide open",
         .applies = [](const C& c) { return !c.lens.empty(); },
         .onlyWhen = [](const C&) { return std::string("only a camera with a `lens` takes lens_f_stop"); },
         .speed = 0.05f},
        {.key = "sensor_width", .label = "Sensor width", .kind = ParamKind::Float, .member = &C::sensorWidthMm,
         .range = between(1.0, 500.0), .unit = "mm",
         .doc = "with `lens`: the film's extent along the image's longer side (36: full frame)",
         .applies = [](const C& c) { return !c.lens.empty(); },
         .onlyWhen = [](const C&) { return std::string("only a camera with a `lens` takes sensor_width"); },
         .speed = 0.1f},
        {.key = "lens_dispersion", .label = "Dispersion", .kind = ParamKind::Bool, .member = &C::lensDispersion,
         .doc = "with `lens`: trace red, green and blue camera rays at the C, d and F lines through glasses with an "
                "Abbe number (chromatic aberration); `false`: every ray at d",
         .applies = [](const C& c) { return !c.lens.empty(); },
         .onlyWhen = [](const C&) { return std::string("only a camera with a `lens` takes lens_dispersion"); }},
    };
    return k;
}

template <>
std::span<const Param<RenderSettings>> schemaOf<RenderSettings>() {
    using R = RenderSettings;
    static const Param<R> k[] = {
        {.key = "width", .label = "Width", .kind = ParamKind::Int, .member = &R::width, .range = between(1, kMaxRenderSide),
         .unit = "px", .doc = "image width", .deferred = true},
        {.key = "height", .label = "Height", .kind = ParamKind::Int, .member = &R::height, .range = between(1, kMaxRenderSide),
         .unit = "px", .doc = "image height", .deferred = true},
        {.key = "samples", .label = "Target samples", .kind = ParamKind::Int, .member = &R::samples,
         .range = between(1, 1 << 24), .doc = "samples per pixel (at most 2^24)", .speed = 1.0f},
        {.key = "max_depth", .label = "Max depth", .kind = ParamKind::Int, .member = &R::maxDepth,
         .range = between(0, 1024),
         .doc = "the maximum number of scattering events on a path: `0` shows only directly visible emitters, `1` "
                "adds direct lighting, `2` one bounce of indirect light, and so on. Mitsuba 3 counts the camera ray "
                "too: caustic's `max_depth` N is Mitsuba's `max_depth` N + 1 (Mitsuba's 1 is emitters seen directly), "
                "which is what every comparison with Mitsuba uses",
         .speed = 0.1f},
        {.key = "seed", .label = "Seed", .kind = ParamKind::UInt, .member = &R::seed, .range = between(0, 4294967295.0),
         .doc = "the same scene, seed and sample count give the same image", .speed = 1.0f},
        enumParam<&R::lightSelection>("light_selection", "Light selection",
                                      "how next-event estimation picks a light, see below"),
        enumParam<&R::sampler>("sampler", "Sampler",
                               "the random numbers: Owen-scrambled Sobol points, stratified per pixel, or one "
                               "pseudo-random stream per sample (`\"independent\"`, for comparisons); either way a "
                               "pixel's sample i depends only on the scene, the seed, the pixel and i"),
        enumParam<&R::russianRoulette>(
            "russian_roulette", "Russian roulette",
            "when paths are ended at random (and the survivors weighted up): `\"mitsuba\"` (from the 5th scattering "
            "event on, survive with min(max(throughput x eta^2), 0.95), as Mitsuba 3's path integrator), "
            "`\"original\"` (from the 3rd, survive with clamp(max(throughput), 0.05, 1)), `\"pbrt\"` (from the 2nd, "
            "only while max(throughput x eta^2) < 1, survive with it, as pbrt-v4) or `\"off\"`; eta^2 is the product "
            "of the squared relative IORs of the refractions on the path. docs/design.md says why the default"),
        enumParam<&R::filter>("filter", "Pixel filter",
                              "`\"box\"` (uniform over the pixel, as reference renderers use for comparisons), "
                              "`\"tent\"` (radius 1 pixel) or `\"gaussian\"` (sigma 0.5 pixel, truncated at 1.5); "
                              "filters are importance-sampled, so every sample has weight 1"),
        {.key = "glass_split", .label = "Glass splitting", .kind = ParamKind::Bool, .member = &R::glassSplit,
         .doc = "at smooth glass (`dielectric` without roughness), also trace the reflection or refraction not taken, "
                "for the light it sees directly (the taken lobe's direct emission is weighted down to match): the same "
                "image on average with less noise in highlights and reflected lights, for one extra ray per glass "
                "entry; `false` gives the plain estimator (Mitsuba's and pbrt's), for comparisons. docs/design.md "
                "derives it"},
    };
    return k;
}

template <>
std::span<const Param<Material>> schemaOf<Material>() {
    using M = Material;
    using T = MaterialType;
    constexpr std::uint32_t diffuseTypes = bits(T::Diffuse, T::OrenNayar, T::Eon);
    constexpr std::uint32_t ggxTypes = bits(T::Transmission, T::Dielectric, T::Conductor);
    const auto custom = [](const M& m) { return m.metal == Metal::Custom; };
    const auto notCustom = [](const M& m) {
        return "only a 'custom' metal takes eta and k (this one is '" + std::string(enumName(m.metal)) + "')";
    };
    static const Param<M> k[] = {
        {.key = "name", .label = "Name", .kind = ParamKind::Name, .member = &M::name, .doc = "unique",
         .defaultText = "required"},
        enumParam<&M::type>("type", "Type", "the scattering model, docs/materials.md"),
        {.key = "albedo", .label = "Albedo", .kind = ParamKind::Colour, .member = &M::albedo, .range = between(0, 1),
         .doc = "diffuse reflectance", .types = diffuseTypes},
        {.key = "sigma", .label = "Sigma", .kind = ParamKind::Float, .member = &M::sigma, .range = between(0, 1.5708),
         .unit = "rad", .doc = "standard deviation of the facet slopes", .types = bits(T::OrenNayar), .slider = true},
        {.key = "roughness", .label = "Roughness", .kind = ParamKind::Float, .member = &M::roughness,
         .range = between(0, 1), .doc = "EON roughness r", .types = bits(T::Eon), .slider = true},
        enumParam<&M::metal>("metal", "Metal",
                             "tabulated complex IORs (docs/materials.md gives their sources); `\"perfect\"` is F = 1, "
                             "`\"custom\"` takes `eta` and `k`",
                             bits(T::Conductor)),
        {.key = "eta", .label = "Eta", .kind = ParamKind::Vector, .member = &M::eta, .range = between(1e-3, 1e3),
         .doc = "`metal` `\"custom\"` only: real part of the complex IOR per R, G, B", .types = bits(T::Conductor),
         .applies = custom, .onlyWhen = notCustom, .speed = 0.01f},
        {.key = "k", .label = "k", .kind = ParamKind::Vector, .member = &M::k, .range = between(0, 1e3),
         .doc = "`metal` `\"custom\"` only: imaginary part (extinction) per R, G, B (the Fresnel equations divide by "
                "\\|eta + ik\\|^4 in float; at 1000 a conductor reflects all but 4e-6)",
         .types = bits(T::Conductor), .applies = custom, .onlyWhen = notCustom, .speed = 0.01f},
        {.key = "tint", .label = "Tint", .kind = ParamKind::Colour, .member = &M::tint, .range = between(0, 1),
         .doc = "scales the reflected/transmitted light", .types = bits(T::Mirror) | ggxTypes},
        {.key = "ior", .label = "IOR", .kind = ParamKind::Float, .member = &M::ior, .range = [] {
             Range r = greaterThan(0.0);
             r.max = 10.0;
             return r;
         }(),
         .doc = "index of refraction n_inside / n_outside; the inside is the side the normal points away from "
                "(spheres: the interior). In a scene with media or a `priority`, a dielectric inside another takes "
                "its own index and meets the outer one at their ratio (docs/materials.md, \"Media\")",
         .types = bits(T::Transmission, T::Dielectric), .speed = 0.005f},
        {.key = "roughness", .label = "Roughness", .kind = ParamKind::Float, .member = &M::roughness,
         .range = between(0, 1),
         .doc = "GGX alpha (not \"perceptual\" roughness: alpha itself); below 0.001 the smooth (delta) model is "
                "used; a rough `transmission` is the GGX BTDF alone (no reflection lobe), except at `ior` 1, where "
                "nothing bends and it stays the delta pass-through",
         .types = ggxTypes, .slider = true},
        {.key = "energy_compensation", .label = "Energy compensation", .kind = ParamKind::Bool,
         .member = &M::energyCompensation, .doc = "the global factor 1 / (1 - 0.33 sigma^2 / (sigma^2 + 0.09))",
         .types = bits(T::OrenNayar)},
        {.key = "energy_compensation", .label = "Multiple scattering", .kind = ParamKind::Bool,
         .member = &M::energyCompensation, .doc = "multiple-scattering compensation of rough GGX",
         .types = bits(T::Conductor)},
        {.key = "sigma_a", .label = "Absorption", .kind = ParamKind::Vector, .member = &M::sigmaA,
         .range = between(0, kMaxCoefficient), .unit = "1/m",
         .doc = "`volume`: the interior medium's absorption coefficient per R, G, B (per scene unit)",
         .types = bits(T::Volume), .speed = 0.01f, .section = "Medium"},
        {.key = "sigma_s", .label = "Scattering", .kind = ParamKind::Vector, .member = &M::sigmaS,
         .range = between(0, kMaxCoefficient), .unit = "1/m",
         .doc = "`volume`: the interior medium's scattering coefficient per R, G, B (per scene unit)",
         .types = bits(T::Volume), .speed = 0.01f},
        {.key = "anisotropy", .label = "Anisotropy", .kind = ParamKind::Float, .member = &M::scatterAnisotropy,
         .range = openInterval(-1, 1),
         .doc = "`volume`: the Henyey-Greenstein g of its scattering (> 0 forward, < 0 backward, 0 isotropic)",
         .types = bits(T::Volume), .slider = true},
        // surface (shaders/bsdf/surface.glsl), grouped as OpenPBR's panels are.
        {.key = "base_color", .label = "Colour", .kind = ParamKind::Colour, .member = &M::albedo,
         .range = between(0, 1), .doc = "`surface`: the diffuse albedo of the dielectric base, F0 of the metal",
         .types = bits(T::Surface), .section = "Base"},
        {.key = "metalness", .label = "Metalness", .kind = ParamKind::Float, .member = &M::metalness,
         .range = between(0, 1), .doc = "`surface`: mixes the dielectric base (specular over diffuse) into a metal",
         .types = bits(T::Surface), .slider = true},
        {.key = "specular_weight", .label = "Weight", .kind = ParamKind::Float, .member = &M::specularWeight,
         .range = between(0, 1), .doc = "`surface`: scales the dielectric specular layer (the diffuse below gets "
                                       "what it leaves)",
         .types = bits(T::Surface), .slider = true, .section = "Specular"},
        {.key = "specular_color", .label = "Colour", .kind = ParamKind::Colour, .member = &M::specularColor,
         .range = between(0, 1), .doc = "`surface`: tints the dielectric specular, and is the metal's edge tint (F82)",
         .types = bits(T::Surface)},
        {.key = "specular_roughness", .label = "Roughness", .kind = ParamKind::Float,
         .member = &M::specularRoughness, .range = between(0, 1),
         .doc = "`surface`: perceptual roughness of the specular layer and the metal (GGX alpha = roughness^2)",
         .types = bits(T::Surface), .slider = true},
        {.key = "specular_ior", .label = "IOR", .kind = ParamKind::Float, .member = &M::specularIor,
         .range = between(1, 3), .doc = "`surface`: the dielectric base's index of refraction (relative to air)",
         .types = bits(T::Surface), .speed = 0.005f},
        {.key = "coat_weight", .label = "Weight", .kind = ParamKind::Float, .member = &M::coatWeight,
         .range = between(0, 1), .doc = "`surface`: the clear coat's strength (0: none)", .types = bits(T::Surface),
         .slider = true, .section = "Coat"},
        {.key = "coat_color", .label = "Colour", .kind = ParamKind::Colour, .member = &M::coatColor,
         .range = between(0, 1), .doc = "`surface`: the light that passes the coat is multiplied by it",
         .types = bits(T::Surface)},
        {.key = "coat_roughness", .label = "Roughness", .kind = ParamKind::Float, .member = &M::coatRoughness,
         .range = between(0, 1), .doc = "`surface`: perceptual roughness of the coat", .types = bits(T::Surface),
         .slider = true},
        {.key = "coat_ior", .label = "IOR", .kind = ParamKind::Float, .member = &M::coatIor, .range = between(1, 3),
         .doc = "`surface`: the coat's index of refraction", .types = bits(T::Surface), .speed = 0.005f},
        {.key = "sheen_weight", .label = "Weight", .kind = ParamKind::Float, .member = &M::sheenWeight,
         .range = between(0, 1), .doc = "`surface`: the sheen (fuzz) layer's strength (0: none)",
         .types = bits(T::Surface), .slider = true, .section = "Sheen"},
        {.key = "sheen_color", .label = "Colour", .kind = ParamKind::Colour, .member = &M::sheenColor,
         .range = between(0, 1), .doc = "`surface`: the sheen's colour", .types = bits(T::Surface)},
        {.key = "sheen_roughness", .label = "Roughness", .kind = ParamKind::Float, .member = &M::sheenRoughness,
         .range = between(0, 1), .doc = "`surface`: perceptual roughness of the sheen (the Charlie lobe's r = roughness^2, as glTF's; below "
                "0.265, r = 0.07)",
         .types = bits(T::Surface), .slider = true},
        {.key = "transmission_weight", .label = "Weight", .kind = ParamKind::Float, .member = &M::transmissionWeight,
         .range = between(0, 1),
         .doc = "`surface`: OpenPBR's: the share of the dielectric base (below the specular interface) that "
                "transmits, refracting into the object's interior (a closed mesh or shape) or, thin-walled, passing "
                "through the sheet; the interior is the medium the keys below describe",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.transmissionWeight == 0.0f; },
         .slider = true, .section = "Transmission"},
        {.key = "transmission_color", .label = "Transmission colour", .kind = ParamKind::Colour,
         .member = &M::transmissionColor, .range = [] {
             Range r = greaterThan(0.0);
             r.max = 1.0;
             return r;
         }(),
         .doc = "OpenPBR's: the colour that light keeps after travelling `transmission_depth` inside (Beer-Lambert "
                "extinction, sigma_t = -ln(colour) / depth per channel); `dielectric`: needs `transmission_depth` > "
                "0 unless it is [1, 1, 1]; `surface`: at depth 0 (and thin-walled) a tint of each crossing of the "
                "surface. Closed objects; overlapping ones nest by `priority` (docs/materials.md, \"Media\")",
         .types = bits(T::Dielectric, T::Surface),
         .omitted = [](const M& m) { return m.transmissionColor == glm::vec3(1.0f); }, .section = "Transmission"},
        {.key = "transmission_depth", .label = "Transmission depth", .kind = ParamKind::Float,
         .member = &M::transmissionDepth, .range = atLeast(0), .unit = "m",
         .doc = "OpenPBR's: the distance inside at which light that has not scattered has the colour "
                "`transmission_color`; 0: no medium inside (clear glass)",
         .types = bits(T::Dielectric, T::Surface), .omitted = [](const M& m) { return m.transmissionDepth == 0.0f; },
         .speed = 0.01f},
        {.key = "transmission_scatter", .label = "Transmission scatter", .kind = ParamKind::Colour,
         .member = &M::transmissionScatter, .range = between(0, 1),
         .doc = "OpenPBR's: the interior's scattering coefficient times `transmission_depth` (sigma_s = scatter / "
                "depth; the absorption is what is left of -ln(`transmission_color`) / depth, raised by a grey amount "
                "where it would be negative); needs `transmission_depth` > 0",
         .types = bits(T::Dielectric, T::Surface),
         .omitted = [](const M& m) { return m.transmissionScatter == glm::vec3(0.0f); }},
        {.key = "transmission_scatter_anisotropy", .label = "Scatter anisotropy", .kind = ParamKind::Float,
         .member = &M::scatterAnisotropy, .range = openInterval(-1, 1),
         .doc = "OpenPBR's: the interior's Henyey-Greenstein g (> 0 forward, < 0 backward scattering)",
         .types = bits(T::Dielectric, T::Surface), .omitted = [](const M& m) { return m.scatterAnisotropy == 0.0f; },
         .slider = true},
        {.key = "priority", .label = "Priority", .kind = ParamKind::Int, .member = &M::priority,
         .range = between(0, 1000),
         .doc = "nested dielectrics (Schmidt and Budge 2002): where objects overlap, the interior of the higher "
                "priority is what is there, and a surface inside it is no interface; `ior` is then the material's "
                "own, taken relative to the dielectric around it (a glass of water: the glass above the water, the "
                "water slightly larger than the glass's inside; docs/materials.md, \"Media\")",
         .types = bits(T::Dielectric, T::Volume, T::Surface), .omitted = [](const M& m) { return m.priority == 0; },
         .speed = 0.1f},
        {.key = "subsurface_weight", .label = "Weight", .kind = ParamKind::Float, .member = &M::subsurfaceWeight,
         .range = between(0, 1),
         .doc = "`surface`: OpenPBR's: the share of the dielectric base not transmitting that scatters below the "
                "surface (a random walk in the object's interior; thin-walled: diffuse transmission) instead of "
                "reflecting diffusely",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.subsurfaceWeight == 0.0f; },
         .slider = true, .section = "Subsurface"},
        {.key = "subsurface_color", .label = "Colour", .kind = ParamKind::Colour, .member = &M::subsurfaceColor,
         .range = between(0, 1),
         .doc = "`surface`: the colour a thick slab of the material shows under white light (its multiple-scattering "
                "albedo); the interior's single-scattering albedo is found from it by inverting van de Hulst's "
                "relation (docs/materials.md, \"Transmission and subsurface\")",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.subsurfaceColor == glm::vec3(0.8f); }},
        {.key = "subsurface_radius", .label = "Radius", .kind = ParamKind::Float, .member = &M::subsurfaceRadius,
         .range = [] {
             Range r = greaterThan(0.0);
             r.max = 1e6;
             return r;
         }(), .unit = "m",
         .doc = "`surface`: the interior's mean free path (times `subsurface_radius_scale` per channel): how far "
                "light travels between scattering events",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.subsurfaceRadius == 1.0f; }, .speed = 0.001f},
        {.key = "subsurface_radius_scale", .label = "Radius scale", .kind = ParamKind::Colour,
         .member = &M::subsurfaceRadiusScale, .range = [] {
             Range r = greaterThan(0.0);
             r.max = 1.0;
             return r;
         }(),
         .doc = "`surface`: the mean free path per channel, relative to `subsurface_radius` (red travels farthest in "
                "skin)",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.subsurfaceRadiusScale == glm::vec3(1.0f, 0.5f, 0.25f); }},
        {.key = "subsurface_scatter_anisotropy", .label = "Anisotropy", .kind = ParamKind::Float,
         .member = &M::subsurfaceAnisotropy, .range = openInterval(-1, 1),
         .doc = "`surface`: the interior's Henyey-Greenstein g (> 0 forward scattering, as skin's 0.8)",
         .types = bits(T::Surface), .omitted = [](const M& m) { return m.subsurfaceAnisotropy == 0.0f; },
         .slider = true},
        {.key = "geometry_thin_walled", .label = "Thin-walled", .kind = ParamKind::Bool, .member = &M::thinWalled,
         .doc = "`surface`: OpenPBR's: the surface bounds no interior but is a thin sheet (a leaf, paper, a soap "
                "bubble): transmission passes straight through it (a thin dielectric sheet of `specular_ior`, tinted "
                "by `transmission_color`), subsurface becomes diffuse transmission",
         .types = bits(T::Surface), .omitted = [](const M& m) { return !m.thinWalled; }, .section = "Geometry"},
        {.key = "emission", .label = "Emission", .kind = ParamKind::Radiance, .member = &M::emission,
         .range = between(0, kMaxRadiance), .unit = "W/(sr m^2)",
         .doc = "emitted radiance (every emitted radiance or intensity is at most 1e12: the film sums squared samples "
                "in 32-bit floats); non-zero makes every object using the material an area light (see below)",
         .section = "Emission"},
        {.key = "albedo_texture", .label = "Albedo texture", .kind = ParamKind::File, .member = &M::albedoTexture,
         .doc = "image file (relative to the scene file) replacing `albedo` (diffuse types), `base_color` (`surface`) "
                "or `tint` (the others); "
                "8-bit files are decoded from sRGB, `.hdr` / `.exr` read as linear (values above 1 clamped to 1, with a "
                "warning: an albedo reflects at most what it receives)",
         .omitted = [](const M& m) { return m.albedoTexture.empty(); }, .nonEmpty = true, .defaultText = "none",
         .section = "Textures"},
        {.key = "normal_texture", .label = "Normal texture", .kind = ParamKind::File, .member = &M::normalTexture,
         .doc = "tangent-space normal map, stored as (n + 1) / 2: x along the surface's u direction, y along v, z "
                "along the geometric normal",
         .omitted = [](const M& m) { return m.normalTexture.empty(); }, .nonEmpty = true, .defaultText = "none"},
        {.key = "normal_scale", .label = "Normal scale", .kind = ParamKind::Float, .member = &M::normalScale,
         .range = atLeast(0),
         .doc = "with `normal_texture`: multiplies the map's x and y before the normal is normalised (glTF's "
                "`normalTexture.scale`; 0 flattens it); written only with a normal texture",
         .applies = [](const M& m) { return !m.normalTexture.empty(); }, .speed = 0.01f},
        {.key = "roughness_texture", .label = "Roughness texture", .kind = ParamKind::File,
         .member = &M::roughnessTexture,
         .doc = "its first channel replaces `roughness` (or `sigma`, or a `surface`'s perceptual "
                "`specular_roughness`), linear; a dielectric or conductor with one is always rough",
         .omitted = [](const M& m) { return m.roughnessTexture.empty(); }, .nonEmpty = true, .defaultText = "none"},
        {.key = "emission_texture", .label = "Emission texture", .kind = ParamKind::File,
         .member = &M::emissionTexture,
         .doc = "its RGB multiplies the emitted radiance per point (the material's `emission`, or an object's own), "
                "as glTF's `emissiveTexture` multiplies `emissiveFactor`; decoded from sRGB unless `.hdr` / `.exr`; "
                "light sampling sees the same radiance as a ray that hits the surface (docs/materials.md)",
         .omitted = [](const M& m) { return m.emissionTexture.empty(); }, .nonEmpty = true, .defaultText = "none"},
        [] {
            auto p = enumParam<&M::alphaMode>("alpha_mode", "Alpha mode",
                                              "`\"mask\"`: rays (camera, bounce and shadow rays) pass through the points "
                                              "where `albedo_texture`'s alpha is below `alpha_cutoff`, as glTF's "
                                              "`alphaMode` `MASK` (cut-out leaves, fences); meshes only (a sphere, quad "
                                              "or box stays opaque, with a warning); `\"opaque\"` ignores the alpha");
            p.section = "Cut-outs";
            return p;
        }(),
        {.key = "alpha_cutoff", .label = "Alpha cutoff", .kind = ParamKind::Float, .member = &M::alphaCutoff,
         .range = atLeast(0),
         .doc = "with `alpha_mode` `\"mask\"`: a point whose alpha is below it is cut out (glTF's `alphaCutoff`; "
                "above 1 every point is, 0 none); written only with the mask",
         .applies = [](const M& m) { return m.alphaMode == AlphaMode::Mask; }, .speed = 0.01f},
    };
    return k;
}

template <>
std::span<const Param<Object>> schemaOf<Object>() {
    using O = Object;
    static const Param<O> k[] = {
        {.key = "name", .label = "Name", .kind = ParamKind::Name, .member = &O::name,
         .doc = "for the editor and messages only; written only if non-empty",
         .omitted = [](const O& o) { return o.name.empty(); }},
        enumParam<&O::shape>("shape", "Shape", "the canonical shapes below, or a model file"),
        {.key = "material", .label = "Material", .kind = ParamKind::Reference, .member = &O::material,
         .doc = "the `name` of a material (an object without one is an error); a `mesh` may leave it out to use its "
                "file's own materials",
         .defaultText = "required"},
        {.key = "transform", .label = "Transform", .kind = ParamKind::Transform, .member = &O::transform,
         .doc = "see [transforms](#transforms)", .defaultText = "identity"},
        {.key = "emission", .label = "Emission", .kind = ParamKind::Radiance, .member = &O::emission,
         .range = between(0, kMaxRadiance), .unit = "W/(sr m^2)",
         .doc = "the object's own emitted radiance: the object is an area light whose surface still scatters by its "
                "`material` (Mitsuba's shape with an `area` emitter and a BSDF); it replaces the material's "
                "`emission` for this object; written only when non-zero",
         .omitted = [](const O& o) { return o.emission == glm::vec3(0.0f); }},
        {.key = "two_sided", .label = "Two-sided", .kind = ParamKind::Bool, .member = &O::twoSided,
         .doc = "with `emission`: emit from the back faces too; written only with `emission`",
         .applies = [](const O& o) { return o.emission != glm::vec3(0.0f); }},
        {.key = "file", .label = "File", .kind = ParamKind::File, .member = &O::file,
         .doc = "the model file, relative to the scene file: OBJ, PLY, glTF 2.0 (`.gltf`, `.glb`), FBX, COLLADA, "
                "STL, 3DS and whatever else Assimp reads",
         .types = bits(Shape::Mesh), .defaultText = "required"},
    };
    return k;
}

template <>
std::span<const Param<Light>> schemaOf<Light>() {
    using L = Light;
    using T = LightType;
    static const Param<L> k[] = {
        {.key = "name", .label = "Name", .kind = ParamKind::Name, .member = &L::name,
         .doc = "for the editor and messages only; written only if non-empty",
         .omitted = [](const L& l) { return l.name.empty(); }},
        enumParam<&L::type>("type", "Type", "the kind of light, see below"),
        {.key = "color", .label = "Colour", .kind = ParamKind::Radiance, .member = &L::color,
         .range = between(0, kMaxRadiance),
         .doc = "**radiance** W/(sr m^2) for `rect` and `sphere`, **intensity** W/sr for `point` and `spot`"},
        {.key = "transform", .label = "Transform", .kind = ParamKind::Transform, .member = &L::transform,
         .doc = "places the canonical quad, see [transforms](#transforms)", .types = bits(T::Rect),
         .defaultText = "identity"},
        {.key = "two_sided", .label = "Two-sided", .kind = ParamKind::Bool, .member = &L::twoSided,
         .doc = "emit from the back face too", .types = bits(T::Rect)},
        {.key = "position", .label = "Position", .kind = ParamKind::Vector, .member = &L::position,
         .range = coordinate(), .doc = "centre", .types = bits(T::Sphere, T::Point, T::Spot)},
        {.key = "radius", .label = "Radius", .kind = ParamKind::Float, .member = &L::radius, .range = greaterThan(0),
         .unit = "scene units", .doc = "the sphere's radius", .types = bits(T::Sphere), .speed = 0.002f},
        {.key = "direction", .label = "Direction", .kind = ParamKind::Vector, .member = &L::direction,
         .doc = "non-zero (need not be unit length)", .types = bits(T::Spot)},
        {.key = "inner_angle", .label = "Inner angle", .kind = ParamKind::Float, .member = &L::innerAngle,
         .range = between(0, 180), .unit = "deg", .doc = "half-angle: full intensity inside it; at most `outer_angle`",
         .types = bits(T::Spot), .speed = 0.2f},
        {.key = "outer_angle", .label = "Outer angle", .kind = ParamKind::Float, .member = &L::outerAngle,
         .range = [] {
             Range r = between(0, 180);
             r.minExclusive = true;
             return r;
         }(),
         .unit = "deg", .doc = "half-angle: no light outside it", .types = bits(T::Spot), .speed = 0.2f},
        enumParam<&L::falloff>("falloff", "Falloff",
                               "between the two angles: `\"smoothstep\"` (in cos theta, pbrt-v4's) or "
                               "`\"linear_angle\"` (linear in the angle, Mitsuba 3's `spot`), see below",
                               bits(T::Spot)),
    };
    return k;
}

template <>
std::span<const Param<Environment>> schemaOf<Environment>() {
    using E = Environment;
    using T = EnvironmentType;
    static const Param<E> k[] = {
        enumParam<&E::type>("type", "Type", "`\"none\"` is black"),
        {.key = "preset", .label = "Preset", .kind = ParamKind::Preset,
         .doc = "a named look, `\"default\"` or `\"original\"` (below): sets `horizon`, `zenith` and `intensity`; any "
                "of the three the object also gives overrides it; never written (a saved scene holds the values)",
         .types = bits(T::Sky), .defaultText = "none"},
        {.key = "radiance", .label = "Radiance", .kind = ParamKind::Radiance, .member = &E::radiance,
         .range = between(0, kMaxRadiance), .unit = "W/(sr m^2)", .doc = "radiance from every direction",
         .types = bits(T::Constant)},
        {.key = "horizon", .label = "Horizon", .kind = ParamKind::Radiance, .member = &E::horizon,
         .range = between(0, kMaxRadiance), .unit = "W/(sr m^2)", .doc = "radiance at the horizon",
         .types = bits(T::Sky)},
        {.key = "zenith", .label = "Zenith", .kind = ParamKind::Radiance, .member = &E::zenith,
         .range = between(0, kMaxRadiance), .unit = "W/(sr m^2)", .doc = "radiance straight up (+y)",
         .types = bits(T::Sky)},
        {.key = "file", .label = "File", .kind = ParamKind::File, .member = &E::file,
         .doc = "an equirectangular HDR image (`.hdr`, `.exr`, anything OpenImageIO reads), relative to the scene "
                "file",
         .types = bits(T::Map), .defaultText = "required"},
        {.key = "rotation", .label = "Rotation", .kind = ParamKind::Float, .member = &E::rotation, .unit = "deg",
         .doc = "about +y (right-handed: positive turns the map counter-clockwise seen from above)",
         .types = bits(T::Map), .speed = 0.5f},
        {.key = "intensity", .label = "Intensity", .kind = ParamKind::Float, .member = &E::intensity,
         .range = between(0, kMaxRadiance),
         .doc = "scales the whole environment; times the radiance (or the sky's brighter colour, or the map's "
                "brightest texel) at most 1e12",
         .types = bits(T::Constant, T::Sky, T::Map), .speed = 0.01f},
        {.key = "medium_sigma_a", .label = "Absorption", .kind = ParamKind::Vector, .member = &E::mediumSigmaA,
         .range = between(0, kMaxCoefficient), .unit = "1/m",
         .doc = "the scene's medium (fog, filling everything outside the objects, the camera included): absorption "
                "coefficient per R, G, B (per scene unit). With any medium here the environment is seen only "
                "through it (an infinite fog hides it: bound fog by a `volume` object instead, docs/materials.md)",
         .omitted = [](const E& e) { return e.mediumSigmaA == glm::vec3(0.0f); }, .speed = 0.001f, .section = "Fog"},
        {.key = "medium_sigma_s", .label = "Scattering", .kind = ParamKind::Vector, .member = &E::mediumSigmaS,
         .range = between(0, kMaxCoefficient), .unit = "1/m",
         .doc = "the scene's medium: scattering coefficient per R, G, B (per scene unit)",
         .omitted = [](const E& e) { return e.mediumSigmaS == glm::vec3(0.0f); }, .speed = 0.001f},
        {.key = "medium_anisotropy", .label = "Anisotropy", .kind = ParamKind::Float, .member = &E::mediumAnisotropy,
         .range = openInterval(-1, 1), .doc = "the scene's medium: Henyey-Greenstein g (> 0 forward scattering)",
         .omitted = [](const E& e) { return e.mediumAnisotropy == 0.0f; }, .slider = true},
    };
    return k;
}

Material materialDefaults(MaterialType type) {
    Material m;
    m.type = type;
    if (type == MaterialType::Eon) m.roughness = 0.5f;
    if (type == MaterialType::Transmission) m.ior = 1.0f;
    return m;
}

// ---------------------------------------------------------------------------------------------
// Rules

std::optional<RuleViolation> checkRules(const Camera& c) {
    const glm::dvec3 view = glm::dvec3(c.lookAt) - glm::dvec3(c.position);
    const glm::dvec3 up(c.up);
    if (view == glm::dvec3(0.0))
        return RuleViolation{"look_at", "must differ from position (both are " + vectorText(c.position) + ")"};
    if (up == glm::dvec3(0.0)) return RuleViolation{"up", "must be non-zero"};
    if (c.blades == 1 || c.blades == 2)
        return RuleViolation{"blades", "must be 0 (round) or at least 3, got " + std::to_string(c.blades)};
    if (c.focusPoint && glm::dot(glm::dvec3(*c.focusPoint) - glm::dvec3(c.position), view) <= 0.0)
        return RuleViolation{"focus_point", "must lie in front of the camera"};
    if (glm::length(glm::cross(glm::normalize(view), glm::normalize(up))) < 1e-6)
        return RuleViolation{"up", "must not be parallel to the view direction (look_at - position)"};
    return std::nullopt;
}

std::optional<RuleViolation> checkRules(const RenderSettings&) { return std::nullopt; }

std::optional<RuleViolation> checkRules(const Material& m) {
    if (m.name.empty()) return RuleViolation{"name", "must not be empty"};
    // OpenPBR reads a colour at depth 0 as a surface tint; caustic's dielectric has `tint` for that,
    // so a colour that would be ignored is refused rather than silently dropped.
    if (m.type == MaterialType::Dielectric && m.transmissionDepth == 0.0f && m.transmissionColor != glm::vec3(1.0f))
        return RuleViolation{"transmission_color",
                             "needs transmission_depth > 0 (at depth 0 there is no absorption; `tint` tints the surface)"};
    if ((m.type == MaterialType::Dielectric || (m.type == MaterialType::Surface && !m.thinWalled)) &&
        m.transmissionDepth == 0.0f && m.transmissionScatter != glm::vec3(0.0f))
        return RuleViolation{"transmission_scatter", "needs transmission_depth > 0 (it is a coefficient times the depth)"};
    if (m.type == MaterialType::Volume && m.emission != glm::vec3(0.0f))
        return RuleViolation{"emission", "a volume has no surface to emit from (its boundary is invisible)"};
    if (m.type == MaterialType::Volume && !m.emissionTexture.empty())
        return RuleViolation{"emission_texture", "a volume has no surface to emit from (its boundary is invisible)"};
    return std::nullopt;
}

std::optional<RuleViolation> checkRules(const Object& o) {
    if (o.shape == Shape::Mesh && o.file.empty()) return RuleViolation{"file", "a mesh object needs a model file"};
    if (o.shape == Shape::Mesh && o.material.empty() && o.emits())
        return RuleViolation{"emission",
                             "a mesh that uses its file's materials cannot take an object emission (give it a scene "
                             "material)"};
    return std::nullopt;
}

std::optional<RuleViolation> checkRules(const Light& l) {
    if (l.type != LightType::Spot) return std::nullopt;
    if (l.direction == glm::vec3(0.0f)) return RuleViolation{"direction", "must be non-zero"};
    if (l.innerAngle > l.outerAngle)
        return RuleViolation{"inner_angle", "must be <= outer_angle (" + shortestText(l.outerAngle) + "), got " +
                                                shortestText(l.innerAngle)};
    return std::nullopt;
}

std::optional<RuleViolation> checkRules(const Environment& e) {
    // The product is what the shaders use (times a map's texels, which the compiler checks).
    const glm::dvec3 c = e.type == EnvironmentType::Constant ? glm::dvec3(e.radiance)
                         : e.type == EnvironmentType::Sky    ? glm::max(glm::dvec3(e.horizon), glm::dvec3(e.zenith))
                                                             : glm::dvec3(0.0);
    const double peak = std::max({c.x, c.y, c.z}) * double(e.intensity);
    if (peak > kMaxRadiance)
        return RuleViolation{"intensity", "times the radiance gives " + shortestText(peak) + ", more than " +
                                              shortestText(kMaxRadiance) + " (the most a channel may emit)"};
    return std::nullopt;
}

std::optional<RuleViolation> checkReferences(const Scene& scene) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const std::string& name = scene.materials[i].name;
        const auto previous = std::find(names.begin(), names.end(), name);
        if (previous != names.end())
            return RuleViolation{"materials[" + std::to_string(i) + "].name",
                                 "duplicate material name '" + name + "' (also materials[" +
                                     std::to_string(previous - names.begin()) + "])"};
        names.push_back(name);
    }
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    known = names.empty() ? "no materials are defined" : "known: " + known;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Object& o = scene.objects[i];
        const std::string path = "objects[" + std::to_string(i) + "].material";
        if (o.material.empty() && o.shape == Shape::Mesh) continue;  // the file's own materials
        if (o.material.empty()) return RuleViolation{path, "missing; every object needs a material (" + known + ")"};
        if (!scene.findMaterial(o.material))
            return RuleViolation{path, "unknown material '" + o.material + "' (" + known + ")"};
    }
    return std::nullopt;
}

// ---------------------------------------------------------------------------------------------
// Validation of a whole scene

namespace {

std::string outside(double v, const Range& r) { return "must be in " + r.text() + ", got " + shortestText(v); }

template <class T>
std::optional<RuleViolation> validateValue(const T& value, const std::string& path) {
    for (const Param<T>& p : schemaOf<T>()) {
        if (!appliesTo(p, value) || p.kind == ParamKind::Preset) continue;
        const std::string key = path + "." + std::string(p.key);
        if (p.kind == ParamKind::Enum) {
            const int v = p.getEnum(value);
            bool known = false;
            for (const EnumChoice& c : p.choices()) known = known || c.value == v;
            if (!known) return RuleViolation{key, "is not one of the allowed values"};
            continue;
        }
        std::optional<RuleViolation> bad;
        std::visit(
            [&](auto m) {
                using M = decltype(m);
                auto check = [&](double x, const std::string& at) {
                    if (!bad && (!std::isfinite(x) || !p.range.contains(x))) bad = RuleViolation{at, outside(x, p.range)};
                };
                if constexpr (std::is_same_v<M, float T::*> || std::is_same_v<M, int T::*> ||
                              std::is_same_v<M, std::uint32_t T::*>) {
                    check(double(value.*m), key);
                } else if constexpr (std::is_same_v<M, glm::vec3 T::*>) {
                    for (int i = 0; i < 3; ++i) check(double((value.*m)[i]), key + "[" + std::to_string(i) + "]");
                } else if constexpr (std::is_same_v<M, std::optional<glm::vec3> T::*>) {
                    if (value.*m)
                        for (int i = 0; i < 3; ++i) check(double((*(value.*m))[i]), key + "[" + std::to_string(i) + "]");
                } else if constexpr (std::is_same_v<M, Transform T::*>) {
                    const Transform& t = value.*m;
                    const glm::mat4 matrix = t.toMatrix();
                    for (int c = 0; c < 4; ++c)
                        for (int r = 0; r < 4; ++r)
                            if (!bad && !std::isfinite(matrix[c][r])) bad = RuleViolation{key, "must be finite"};
                    if (!bad && !t.matrix && (t.scale.x == 0.0f || t.scale.y == 0.0f || t.scale.z == 0.0f))
                        bad = RuleViolation{key + ".scale", "must be non-zero"};
                }
            },
            p.member);
        if (bad) return bad;
    }
    if (auto v = checkRules(value)) return RuleViolation{v->key.empty() ? path : path + "." + v->key, v->message};
    return std::nullopt;
}

template <class T>
std::optional<RuleViolation> validateAll(const std::vector<T>& items, const char* name) {
    for (std::size_t i = 0; i < items.size(); ++i)
        if (auto v = validateValue(items[i], std::string(name) + "[" + std::to_string(i) + "]")) return v;
    return std::nullopt;
}

}  // namespace

std::optional<RuleViolation> validateScene(const Scene& scene) {
    if (auto v = validateValue(scene.camera, "camera")) return v;
    if (auto v = validateValue(scene.render, "render")) return v;
    if (auto v = validateAll(scene.materials, "materials")) return v;
    if (auto v = validateAll(scene.objects, "objects")) return v;
    if (auto v = validateAll(scene.lights, "lights")) return v;
    if (auto v = validateValue(scene.environment, "environment")) return v;
    return checkReferences(scene);
}

}  // namespace caustic
