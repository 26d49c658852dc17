// The scene schema: every parameter of the scene's structs written down once, with its JSON key,
// inspector label, unit, kind, valid range, the types it belongs to and its documentation line;
// and the rules that tie several fields together (validate*). Everything that reads, writes, edits
// or documents a scene parameter uses this table, and nothing else:
//   - renderer/scene_io.cpp reads and writes JSON by it (unknown keys, ranges, enum names, which
//     keys a type takes, what is written), and runs the rules;
//   - the editor's inspector draws its widgets from it (bounds, labels, units, enum labels), so
//     its ranges are the loader's, and its edits are checked by the same rules;
//   - docs/scene-format.md's parameter tables are generated from it (`caustic-schema-doc`; a test
//     fails when the file and the schema disagree).
// Adding a material parameter is: a member in scene.h, a row here, the GPU conversion
// (renderer/gpu_materials.cpp) and the shader. docs/design.md, "Adding a parameter", walks it
// through.
//
// No JSON and no GL here: the editor's model uses it too.
#pragma once

#include "renderer/scene.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

namespace caustic {

// ---------------------------------------------------------------------------------------------
// Ranges

// The valid values of a number (and of each component of a vector).
struct Range {
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    bool minExclusive = false;
    bool maxExclusive = false;
    bool nonZero = false;

    bool contains(double x) const;
    // For documents and messages: "[0, 1]", "(0, 180)", ">= 0", "> 0", "non-zero", "any".
    std::string text() const;
};

inline constexpr Range kAnyValue{};

constexpr Range atLeast(double min) {
    Range range;
    range.min = min;
    return range;
}
constexpr Range greaterThan(double min) {
    Range range = atLeast(min);
    range.minExclusive = true;
    return range;
}
constexpr Range between(double min, double max) {
    Range range = atLeast(min);
    range.max = max;
    return range;
}
constexpr Range openInterval(double min, double max) {
    Range range = between(min, max);
    range.minExclusive = range.maxExclusive = true;
    return range;
}
constexpr Range nonZeroValue() {
    Range range;
    range.nonZero = true;
    return range;
}

// Limits that keep the renderer's 32-bit float arithmetic finite (issue 12; docs/reliability.md):
//  - positions of the camera and of lights within +-1e18: the shaders square distances between
//    them and surfaces (a distance up to 3.5e18 squared is 1.2e37, below FLT_MAX = 3.4e38);
//  - emitted radiance (and light intensity) at most 1e12 per channel, about 600 times the sun's
//    luminance: the film sums squared samples in float, (1e12)^2 times 2^24 samples is 1.7e31;
//  - a custom conductor's eta within [1e-3, 1e3] and k within [0, 1e3]: the complex Fresnel
//    equations divide by |eta + ik|^4 (at k = 1e38 it was inf / inf); at k = 1e3 a conductor
//    already reflects all but 4e-6 of the light.
inline constexpr double kMaxCoordinate = 1e18;
inline constexpr double kMaxRadiance = 1e12;
// A medium's absorption or scattering coefficient (per scene unit) at most 1e9: times any distance
// the scene can hold (3.5e18) it stays finite in float, and a medium that dense is opaque anyway.
inline constexpr double kMaxCoefficient = 1e9;
constexpr Range coordinate() { return between(-kMaxCoordinate, kMaxCoordinate); }

// ---------------------------------------------------------------------------------------------
// Enums: the JSON name and the inspector's label of each value, in the enum's order.

struct EnumChoice {
    int value;
    std::string_view name;   // in files and on the command line
    std::string_view label;  // in the editor
};

std::span<const EnumChoice> enumChoices(FovAxis);
std::span<const EnumChoice> enumChoices(LightSelection);
std::span<const EnumChoice> enumChoices(SamplerType);
std::span<const EnumChoice> enumChoices(RussianRoulette);
std::span<const EnumChoice> enumChoices(PixelFilter);
std::span<const EnumChoice> enumChoices(MaterialType);
std::span<const EnumChoice> enumChoices(Metal);
std::span<const EnumChoice> enumChoices(AlphaMode);
std::span<const EnumChoice> enumChoices(Shape);
std::span<const EnumChoice> enumChoices(LightType);
std::span<const EnumChoice> enumChoices(SpotFalloff);
std::span<const EnumChoice> enumChoices(EnvironmentType);

// "" for a value outside the enum.
template <class E>
    requires std::is_enum_v<E>
std::string_view enumName(E value) {
    for (const EnumChoice& c : enumChoices(E{}))
        if (c.value == static_cast<int>(value)) return c.name;
    return {};
}

// ---------------------------------------------------------------------------------------------
// Parameters

enum class ParamKind {
    Float,
    Int,
    UInt,
    Bool,
    Vector,     // glm::vec3: positions, directions, complex IOR parts
    Colour,     // glm::vec3 reflectance in [0, 1]
    Radiance,   // glm::vec3 emitted radiance or intensity, >= 0 (edited as colour x strength)
    Enum,
    Name,       // the entity's name (renamed through a command in the editor)
    Reference,  // the name of another entity (an object's material)
    File,       // a file relative to the scene file
    Transform,
    OptionalPoint,  // std::optional<glm::vec3>: absent, or a point
    Preset,     // read-only shorthand applied when reading (the sky's "preset"); no member
};

template <class T>
using ParamMember = std::variant<std::monostate, float T::*, int T::*, std::uint32_t T::*, bool T::*,
                                 glm::vec3 T::*, std::string T::*, Transform T::*,
                                 std::optional<glm::vec3> T::*>;

// One parameter of struct T.
template <class T>
struct Param {
    std::string_view key;    // JSON key
    std::string_view label;  // inspector label
    ParamKind kind = ParamKind::Float;
    ParamMember<T> member{};
    Range range{};
    std::string_view unit{};  // "deg", "rad", "px", "W/(sr m^2)", ...: shown next to the value
    std::string_view doc{};   // docs/scene-format.md's meaning column (Markdown)
    // The "type" values (MaterialType, LightType, Shape or EnvironmentType as bits) that take the
    // key; all for Camera and RenderSettings.
    std::uint32_t types = ~0u;
    // Enums: the value as int, and its choices.
    int (*getEnum)(const T&) = nullptr;
    void (*setEnum)(T&, int) = nullptr;
    std::span<const EnumChoice> (*choices)() = nullptr;
    // When set and false for a value: the parameter does not apply to it (not written, not shown
    // in the inspector). A file that still gives the key is refused with onlyWhen's message when
    // that is set ("only a 'custom' metal takes eta and k (this one is 'gold')"), and otherwise
    // read and ignored.
    bool (*applies)(const T&) = nullptr;
    std::string (*onlyWhen)(const T&) = nullptr;
    // When set and true: not written (an empty name, an absent texture, a zero emission).
    bool (*omitted)(const T&) = nullptr;
    // Files: an empty string in a file is an error (leave the key out instead).
    bool nonEmpty = false;
    // The docs' default column when the default is not a plain value ("required", "none").
    std::string_view defaultText{};
    // Inspector: drag speed per pixel (0: chosen from the range), whether to draw a slider, and
    // whether an edit applies only when the field is left (one that restarts everything, such as
    // the resolution, rather than on every step of a drag).
    float speed = 0.0f;
    bool slider = false;
    bool deferred = false;
    // Inspector: the heading of the group this parameter opens ("Specular", "Coat"): drawn as a
    // separator before it when it applies; "" continues the group before.
    std::string_view section{};
};

// The schema of each struct, in the order the keys are written.
template <class T>
std::span<const Param<T>> schemaOf();
template <> std::span<const Param<Camera>> schemaOf<Camera>();
template <> std::span<const Param<RenderSettings>> schemaOf<RenderSettings>();
template <> std::span<const Param<Material>> schemaOf<Material>();
template <> std::span<const Param<Object>> schemaOf<Object>();
template <> std::span<const Param<Light>> schemaOf<Light>();
template <> std::span<const Param<Environment>> schemaOf<Environment>();

// The struct's "type" as a bit index into Param::types (0 for untyped structs), and the name of
// its type key ("type", or "shape" for objects; "" for untyped structs).
inline int typeIndexOf(const Camera&) { return 0; }
inline int typeIndexOf(const RenderSettings&) { return 0; }
inline int typeIndexOf(const Material& m) { return static_cast<int>(m.type); }
inline int typeIndexOf(const Object& o) { return static_cast<int>(o.shape); }
inline int typeIndexOf(const Light& l) { return static_cast<int>(l.type); }
inline int typeIndexOf(const Environment& e) { return static_cast<int>(e.type); }

// Whether the parameter belongs to values of this type (the keys a file may give for it).
template <class T>
bool takesKey(const Param<T>& p, int typeIndex) {
    return typeIndex >= 0 && typeIndex < 32 && (p.types >> typeIndex & 1u) != 0;
}
// Whether the parameter applies to this value: its type takes it and its condition holds.
template <class T>
bool appliesTo(const Param<T>& p, const T& value) {
    return takesKey(p, typeIndexOf(value)) && (!p.applies || p.applies(value));
}

// The value of a new entity of that type: scene.h's defaults, and those that differ by type (an
// "eon" material's roughness is 0.5, a "transmission" material's ior is 1).
Material materialDefaults(MaterialType type);

// ---------------------------------------------------------------------------------------------
// Rules across fields, and references between entities. Each returns the first violation as the
// key it is reported at (relative to the value: "look_at", "" for the value itself) and a message.

struct RuleViolation {
    std::string key;
    std::string message;
};
std::optional<RuleViolation> checkRules(const Camera& camera);
std::optional<RuleViolation> checkRules(const RenderSettings& render);
std::optional<RuleViolation> checkRules(const Material& material);
std::optional<RuleViolation> checkRules(const Object& object);
std::optional<RuleViolation> checkRules(const Light& light);
std::optional<RuleViolation> checkRules(const Environment& environment);
// Between entities: unique material names, every object's material defined. The key is the
// full path ("objects[3].material").
std::optional<RuleViolation> checkReferences(const Scene& scene);

// The whole scene against the schema without any JSON: every parameter that applies within its
// range (finite, enums valid), every struct's rules, then the references. The first violation,
// with its full path as the loader names it ("materials[2].ior", "camera.focus_point"); nullopt
// for a scene that saveScene would write and loadScene read back.
std::optional<RuleViolation> validateScene(const Scene& scene);

// The shortest text that reads back as the same number (for messages and documents).
std::string shortestText(double value);
std::string shortestText(float value);

}  // namespace caustic
