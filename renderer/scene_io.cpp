// Scene JSON reading and writing. The format is documented in docs/scene-format.md.
//
// Reading and writing are driven by the scene schema (renderer/scene_schema.h): a parameter names
// its JSON key, the member it maps to, its range and the types that take it, and the same entry
// serves the unknown-key check, the reader and the writer; the schema's rules check what ties
// fields together. Transforms and the top level, whose keys are structure rather than parameters,
// keep their own small Field tables here. Readers throw SceneError (path + message) internally;
// parseScene catches it, and everything else, at the boundary.
#include "renderer/scene_io.h"

#include "renderer/file_util.h"
#include "renderer/json_depth.h"
#include "renderer/scene_schema.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <new>
#include <set>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace caustic {

namespace {

// ordered_json keeps keys in insertion order, so saved files read top to bottom like the docs.
using Json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Errors, paths, formatting

struct SceneError {
    std::string path;     // JSON path, "" for the document itself
    std::string message;
};

[[noreturn]] void fail(const std::string& path, std::string message) {
    throw SceneError{path, std::move(message)};
}

std::string member(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

// Shortest text that reads back as the same value (ints, floats and doubles alike).
template <class N>
std::string formatNumber(N value) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
    return std::string(buffer, result.ptr);
}

std::string dumpCompact(const Json& value) {
    return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// At most about `limit` bytes of value's compact JSON, ending in "..." when cut; containers deeper
// than a few levels are elided. Never serialises the whole value: a huge or deeply nested value
// (a hostile file) costs no more than a small one, and the recursion is bounded.
void appendBounded(const Json& value, std::size_t limit, int depth, std::string& out) {
    if (out.size() >= limit) return;
    if (!value.is_structured()) {
        std::string text = dumpCompact(value);
        if (text.size() > limit) text.resize(limit);  // a long string
        out += text;
        return;
    }
    const bool isObject = value.is_object();
    out += isObject ? '{' : '[';
    if (depth >= 4 && !value.empty()) {
        out += "...";
    } else {
        bool first = true;
        for (auto it = value.begin(); it != value.end(); ++it) {
            if (out.size() >= limit) break;
            if (!first) out += ',';
            first = false;
            if (isObject) out += dumpCompact(Json(it.key())) + ':';
            appendBounded(it.value(), limit, depth + 1, out);
        }
    }
    out += isObject ? '}' : ']';
}

// What a rejected value was, for messages: "string \"abc\"", "array [1,2]", "null".
std::string describe(const Json& value) {
    if (value.is_null()) return "null";
    std::string text;
    appendBounded(value, 41, 0, text);
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return std::string(value.type_name()) + " " + text;
}

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& item : items) {
        if (!out.empty()) out += ", ";
        out += item;
    }
    return out;
}

// Messages are one line whatever the user's strings contain.
std::string oneLine(std::string text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else if (c == '\t') out += "\\t";
        else if (static_cast<unsigned char>(c) < 0x20) out += '?';
        else out += c;
    }
    return out;
}

std::string formatError(const std::string& file, const std::string& path,
                        const std::string& message) {
    return oneLine(file + ": " + (path.empty() ? "" : path + ": ") + message);
}

// ---------------------------------------------------------------------------------------------
// Ranges (renderer/scene_schema.h defines them)

// Fails naming the violated bound: "must be >= 1, got -4".
template <class N>
void checkRange(N value, const Range& range, const std::string& path) {
    const double x = static_cast<double>(value);
    if (range.minExclusive ? !(x > range.min) : !(x >= range.min)) {
        fail(path, std::string("must be ") + (range.minExclusive ? "> " : ">= ") +
                       formatNumber(range.min) + ", got " + formatNumber(value));
    }
    if (range.maxExclusive ? !(x < range.max) : !(x <= range.max)) {
        fail(path, std::string("must be ") + (range.maxExclusive ? "< " : "<= ") +
                       formatNumber(range.max) + ", got " + formatNumber(value));
    }
    if (range.nonZero && x == 0.0) fail(path, "must be non-zero, got " + formatNumber(value));
}

void requireType(bool ok, const Json& value, const std::string& path, const char* expected) {
    if (!ok) fail(path, std::string("must be ") + expected + ", got " + describe(value));
}

// ---------------------------------------------------------------------------------------------
// Enum names (renderer/scene_schema.h holds the tables)

template <class E>
std::string enumText(E value) {
    const std::string_view name = enumName(value);
    if (!name.empty()) return std::string(name);
    return "<invalid " + std::to_string(static_cast<long long>(value)) + ">";
}


// ---------------------------------------------------------------------------------------------
// The scene's structs are read and written by overloads defined further down; the templates below
// (vectors, fields) need them declared first.

Json toJson(const Transform& transform);
Json toJson(const Camera& camera);
Json toJson(const RenderSettings& render);
Json toJson(const Material& material);
Json toJson(const Object& object);
Json toJson(const Light& light);
Json toJson(const Environment& environment);
void readValue(const Json& value, const std::string& path, Transform& out, const Range&);
void readValue(const Json& value, const std::string& path, Camera& out, const Range&);
void readValue(const Json& value, const std::string& path, RenderSettings& out, const Range&);
void readValue(const Json& value, const std::string& path, Material& out, const Range&);
void readValue(const Json& value, const std::string& path, Object& out, const Range&);
void readValue(const Json& value, const std::string& path, Light& out, const Range&);
void readValue(const Json& value, const std::string& path, Environment& out, const Range&);

// ---------------------------------------------------------------------------------------------
// Value readers and writers, one overload per C++ type. The Range applies to numbers (and to
// each component of a vector); other types ignore it.

void readValue(const Json& value, const std::string& path, float& out, const Range& range) {
    requireType(value.is_number(), value, path, "a number");
    const double x = value.get<double>();
    // Doubles below FLT_MAX + half an ulp round to FLT_MAX (which prints as 3.4028235e+38, a
    // little above it); from there on they would round to infinity.
    constexpr double kFloatOverflow = 0x1.ffffffp127;
    if (!std::isfinite(x) || std::abs(x) >= kFloatOverflow) {
        fail(path, "must be a finite 32-bit float, got " + formatNumber(x));
    }
    const float f = static_cast<float>(x);
    checkRange(f, range, path);
    out = f;
}

// An integral JSON number in range: 10, 10.0 and 1e3 are integers, 10.5 is not.
long long readInteger(const Json& value, const std::string& path, const Range& range) {
    requireType(value.is_number(), value, path, "an integer");
    long long result = 0;
    if (value.is_number_unsigned()) {
        const auto u = value.get<unsigned long long>();
        if (u > static_cast<unsigned long long>(LLONG_MAX)) {
            fail(path, "must be <= " + formatNumber(range.max) + ", got " + formatNumber(u));
        }
        result = static_cast<long long>(u);
    } else if (value.is_number_integer()) {
        result = value.get<long long>();
    } else {
        const double x = value.get<double>();
        if (!std::isfinite(x) || std::floor(x) != x) {
            fail(path, "must be an integer, got " + formatNumber(x));
        }
        if (std::abs(x) > 9.0e18) fail(path, "integer out of range, got " + formatNumber(x));
        result = static_cast<long long>(x);
    }
    checkRange(result, range, path);
    return result;
}

void readValue(const Json& value, const std::string& path, int& out, const Range& range) {
    Range clamped = range;
    clamped.min = std::max(clamped.min, static_cast<double>(INT_MIN));
    clamped.max = std::min(clamped.max, static_cast<double>(INT_MAX));
    out = static_cast<int>(readInteger(value, path, clamped));
}

void readValue(const Json& value, const std::string& path, std::uint32_t& out,
               const Range& range) {
    Range clamped = range;
    clamped.min = std::max(clamped.min, 0.0);
    clamped.max = std::min(clamped.max, static_cast<double>(UINT32_MAX));
    out = static_cast<std::uint32_t>(readInteger(value, path, clamped));
}

void readValue(const Json& value, const std::string& path, bool& out, const Range&) {
    requireType(value.is_boolean(), value, path, "true or false");
    out = value.get<bool>();
}

void readValue(const Json& value, const std::string& path, std::string& out, const Range&) {
    requireType(value.is_string(), value, path, "a string");
    const auto& text = value.get_ref<const std::string&>();
    // A file name would be cut at the NUL by every OS call ("a.png\u0000.jpg" opens "a.png").
    if (text.find('\0') != std::string::npos) fail(path, "must not contain a NUL character (\\u0000)");
    out = text;
}

void readValue(const Json& value, const std::string& path, glm::vec3& out, const Range& range) {
    requireType(value.is_array() && value.size() == 3, value, path, "an array of 3 numbers");
    glm::vec3 result;
    for (std::size_t i = 0; i < 3; ++i) {
        readValue(value[i], element(path, i), result[static_cast<glm::length_t>(i)], range);
    }
    out = result;
}

void readValue(const Json& value, const std::string& path, std::optional<glm::vec3>& out, const Range& range) {
    glm::vec3 v{};
    readValue(value, path, v, range);
    out = v;
}

// One of the choices' names; returns its value.
int readChoice(const Json& value, const std::string& path, std::span<const EnumChoice> choices) {
    requireType(value.is_string(), value, path, "a string");
    const auto& text = value.get_ref<const std::string&>();
    std::vector<std::string> allowed;
    for (const EnumChoice& c : choices) {
        if (c.name == text) return c.value;
        allowed.emplace_back(c.name);
    }
    fail(path, "unknown value '" + text + "' (allowed: " + join(allowed) + ")");
}

template <class E>
    requires std::is_enum_v<E>
void readValue(const Json& value, const std::string& path, E& out, const Range&) {
    out = static_cast<E>(readChoice(value, path, enumChoices(E{})));
}

// Every element with the same Range; the vector is replaced, not appended to.
template <class T>
void readValue(const Json& value, const std::string& path, std::vector<T>& out,
               const Range& range) {
    requireType(value.is_array(), value, path, "an array");
    std::vector<T> result;
    result.reserve(value.size());
    for (std::size_t i = 0; i < value.size(); ++i) {
        T item{};
        readValue(value[i], element(path, i), item, range);
        result.push_back(std::move(item));
    }
    out = std::move(result);
}

// nlohmann stores doubles, and widening x would print 0.1f as 0.10000000149011612. Store instead the
// double nearest to x's shortest decimal form, which prints as that short form and reads back
// (to double, then to float) as x; fall back to the exact widening in the rare case it does not.
Json toJson(float x) {
    char buffer[64];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
    double shortest = 0.0;
    const auto parsed = std::from_chars(buffer, end, shortest);
    if (parsed.ec == std::errc() && static_cast<float>(shortest) == x) {
        // Whole numbers as integers ("[0, 1, 0]", not "[0.0, 1.0, 0.0]"); -0 keeps its sign.
        if (std::abs(shortest) < 1e15 && std::trunc(shortest) == shortest && !std::signbit(x)) {
            return static_cast<long long>(shortest);
        }
        return shortest;
    }
    return static_cast<double>(x);
}

Json toJson(int x) { return x; }
Json toJson(std::uint32_t x) { return x; }
Json toJson(bool x) { return x; }
Json toJson(const std::string& x) { return x; }
Json toJson(const glm::vec3& v) { return Json::array({toJson(v.x), toJson(v.y), toJson(v.z)}); }

Json choiceJson(int value, std::span<const EnumChoice> choices) {
    for (const EnumChoice& c : choices)
        if (c.value == value) return std::string(c.name);
    return nullptr;  // an invalid enum value; saveScene's validation reports it
}

template <class E>
    requires std::is_enum_v<E>
Json toJson(E value) {
    return choiceJson(static_cast<int>(value), enumChoices(E{}));
}

Json toJson(const std::optional<glm::vec3>& v) { return v ? toJson(*v) : Json(nullptr); }

template <class T>
Json toJson(const std::vector<T>& items) {
    Json out = Json::array();
    for (const T& item : items) out.push_back(toJson(item));
    return out;
}

// ---------------------------------------------------------------------------------------------
// Field tables

template <class T>
struct Field {
    std::string_view key;
    std::function<void(const Json&, const std::string&, T&)> read;
    std::function<Json(const T&)> write;    // empty: never written
    std::function<bool(const T&)> omit;     // empty: always written
};

template <class T>
using Fields = std::vector<Field<T>>;

// The usual field: a member read with readValue(range) and written with toJson.
template <class T, class V>
Field<T> field(std::string_view key, V T::*memberPtr, Range range = kAnyValue) {
    return {key,
            [memberPtr, range](const Json& value, const std::string& path, T& out) {
                readValue(value, path, out.*memberPtr, range);
            },
            [memberPtr](const T& in) { return toJson(in.*memberPtr); },
            {}};
}

template <class T>
std::string keyList(const Fields<T>& fields) {
    std::vector<std::string> keys;
    for (const Field<T>& f : fields) keys.emplace_back(f.key);
    return join(keys);
}

// Reads the keys of a JSON object in file order; an unknown key is an error. Keys that are absent
// keep out's current value (the defaults of scene.h). `what` qualifies the unknown-key message
// (" for a 'point' light").
template <class T>
void readFields(const Json& value, const std::string& path, const Fields<T>& fields, T& out,
                const std::string& what = "") {
    requireType(value.is_object(), value, path, "an object");
    for (auto it = value.begin(); it != value.end(); ++it) {
        const auto found = std::find_if(fields.begin(), fields.end(),
                                        [&](const Field<T>& f) { return f.key == it.key(); });
        const std::string keyPath = member(path, it.key());
        if (found == fields.end()) {
            fail(keyPath, "unknown key" + what + " (allowed: " + keyList(fields) + ")");
        }
        found->read(it.value(), keyPath, out);
    }
}

template <class T>
Json writeFields(const T& in, const Fields<T>& fields) {
    Json out = Json::object();
    for (const Field<T>& f : fields) {
        if (f.write && !(f.omit && f.omit(in))) out[std::string(f.key)] = f.write(in);
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Transform

void readScale(const Json& value, const std::string& path, Transform& out) {
    if (value.is_number()) {
        float s = 1.0f;
        readValue(value, path, s, nonZeroValue());
        out.scale = glm::vec3(s);
        return;
    }
    requireType(value.is_array() && value.size() == 3, value, path,
                "a number or an array of 3 numbers");
    readValue(value, path, out.scale, nonZeroValue());
}

// 16 numbers, row-major (the way a matrix is written on paper); glm is column-major.
void readMatrix(const Json& value, const std::string& path, Transform& out) {
    requireType(value.is_array() && value.size() == 16, value, path,
                "an array of 16 numbers (row-major)");
    glm::mat4 m(1.0f);
    for (int row = 0; row < 4; ++row) {
        for (int col = 0; col < 4; ++col) {
            const auto i = static_cast<std::size_t>(row * 4 + col);
            readValue(value[i], element(path, i), m[col][row], kAnyValue);
        }
    }
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) {
        fail(path, "the last row must be [0, 0, 0, 1] (an affine transform)");
    }
    const double det = glm::determinant(glm::dmat4(m));
    if (!(std::abs(det) > 1e-12)) {
        fail(path, "must be invertible, but its determinant is " + formatNumber(det));
    }
    out.matrix = m;
}

const Fields<Transform>& transformFields() {
    static const Fields<Transform> kFields = {
        field("translate", &Transform::translate),
        field("rotate", &Transform::rotate),
        {"scale", readScale, {}, {}},
        {"matrix", readMatrix, {}, {}},
    };
    return kFields;
}

void readValue(const Json& value, const std::string& path, Transform& out, const Range&) {
    readFields(value, path, transformFields(), out);
    if (value.contains("matrix")) {
        for (const char* key : {"translate", "rotate", "scale"}) {
            if (value.contains(key)) {
                fail(member(path, key),
                     "cannot be combined with 'matrix' (a matrix replaces translate, rotate and "
                     "scale)");
            }
        }
    }
}

Json toJson(const Transform& t) {
    Json out = Json::object();
    if (t.matrix) {
        Json m = Json::array();
        for (int row = 0; row < 4; ++row) {
            for (int col = 0; col < 4; ++col) m.push_back(toJson((*t.matrix)[col][row]));
        }
        out["matrix"] = std::move(m);
    } else {
        out["translate"] = toJson(t.translate);
        out["rotate"] = toJson(t.rotate);
        out["scale"] = toJson(t.scale);
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// The schema's structs (camera, render settings, materials, objects, lights, environment):
// read and written parameter by parameter (renderer/scene_schema.h), then checked by its rules.

template <class T>
void readParam(const Param<T>& p, const Json& value, const std::string& path, T& out) {
    if (p.kind == ParamKind::Preset) return;  // applied by the struct's reader, before the keys
    if (p.kind == ParamKind::Enum) {
        p.setEnum(out, readChoice(value, path, p.choices()));
        return;
    }
    std::visit(
        [&](auto memberPtr) {
            if constexpr (!std::is_same_v<decltype(memberPtr), std::monostate>) {
                readValue(value, path, out.*memberPtr, p.range);
                if constexpr (std::is_same_v<decltype(memberPtr), std::string T::*>) {
                    // A file name written only when set: an empty string is an error rather than a
                    // quiet "no texture" (leaving the key out says that).
                    if (p.nonEmpty && (out.*memberPtr).empty())
                        fail(path, std::string("must not be empty (leave the key out for ") +
                                       (p.key == "lens" ? "the thin lens" : p.key == "aperture_image" ? "a round aperture" : "no texture") + ")");
                }
            }
        },
        p.member);
}

template <class T>
Json writeParam(const Param<T>& p, const T& in) {
    if (p.kind == ParamKind::Enum) return choiceJson(p.getEnum(in), p.choices());
    return std::visit(
        [&](auto memberPtr) -> Json {
            if constexpr (std::is_same_v<decltype(memberPtr), std::monostate>) return nullptr;
            else return toJson(in.*memberPtr);
        },
        p.member);
}

// The key every value of T is typed by ("type", "shape"), or "" for untyped structs.
template <class T>
constexpr std::string_view typeKeyOf() {
    if constexpr (std::is_same_v<T, Object>) return "shape";
    else if constexpr (std::is_same_v<T, Camera> || std::is_same_v<T, RenderSettings>) return "";
    else return "type";
}
template <class T>
constexpr const char* nounOf() {
    if constexpr (std::is_same_v<T, Material>) return "material";
    else if constexpr (std::is_same_v<T, Object>) return "object";
    else if constexpr (std::is_same_v<T, Light>) return "light";
    else return "environment";
}

std::string typeNameOf(const Material& v) { return enumText(v.type); }
std::string typeNameOf(const Object& v) { return enumText(v.shape); }
std::string typeNameOf(const Light& v) { return enumText(v.type); }
std::string typeNameOf(const Environment& v) { return enumText(v.type); }

// The parameter of key `key` that values of type `type` take, or null.
template <class T>
const Param<T>* findParam(std::string_view key, int type) {
    for (const Param<T>& p : schemaOf<T>())
        if (p.key == key && takesKey(p, type)) return &p;
    return nullptr;
}

// Reads a schema struct: its type key first (keeping the default when absent), then every key
// in file order (an unknown key is an error, one the value's type does not take too), then the
// keys given that do not apply to this value, then the rules across its fields. Keys that are
// absent keep out's current value (the defaults of scene.h, and materialDefaults).
template <class T>
void readParams(const Json& value, const std::string& path, T& out) {
    requireType(value.is_object(), value, path, "an object");
    constexpr std::string_view typeKey = typeKeyOf<T>();
    std::string what;
    if constexpr (!typeKey.empty()) {
        if (const auto it = value.find(typeKey); it != value.end()) {
            readParam(*findParam<T>(typeKey, 0), *it, member(path, typeKey), out);
            if constexpr (std::is_same_v<T, Material>) out = materialDefaults(out.type);
        }
        what = " for a '" + typeNameOf(out) + "' " + nounOf<T>();
    }
    const int type = typeIndexOf(out);
    for (auto it = value.begin(); it != value.end(); ++it) {
        const std::string keyPath = member(path, it.key());
        const Param<T>* p = findParam<T>(it.key(), type);
        if (!p) {
            std::vector<std::string> keys;
            for (const Param<T>& q : schemaOf<T>())
                if (takesKey(q, type)) keys.emplace_back(q.key);
            fail(keyPath, "unknown key" + what + " (allowed: " + join(keys) + ")");
        }
        if (it.key() != typeKey) readParam(*p, it.value(), keyPath, out);
    }
    for (auto it = value.begin(); it != value.end(); ++it) {
        const Param<T>* p = findParam<T>(it.key(), type);
        if (p->applies && p->onlyWhen && !p->applies(out)) fail(member(path, it.key()), p->onlyWhen(out));
    }
    if (const auto v = checkRules(out)) fail(v->key.empty() ? path : member(path, v->key), v->message);
}

// Writes what applies to the value, in the schema's order.
template <class T>
Json writeParams(const T& in) {
    Json out = Json::object();
    for (const Param<T>& p : schemaOf<T>()) {
        if (p.kind == ParamKind::Preset || !appliesTo(p, in) || (p.omitted && p.omitted(in))) continue;
        out[std::string(p.key)] = writeParam(p, in);
    }
    return out;
}

void readValue(const Json& value, const std::string& path, Camera& out, const Range&) { readParams(value, path, out); }
void readValue(const Json& value, const std::string& path, RenderSettings& out, const Range&) {
    readParams(value, path, out);
}
void readValue(const Json& value, const std::string& path, Object& out, const Range&) { readParams(value, path, out); }
void readValue(const Json& value, const std::string& path, Light& out, const Range&) { readParams(value, path, out); }

void readValue(const Json& value, const std::string& path, Material& out, const Range&) {
    if (value.is_object() && !value.contains("name"))
        fail(path, "missing key 'name' (every material needs a unique name)");
    readParams(value, path, out);
}

void readValue(const Json& value, const std::string& path, Environment& out, const Range&) {
    // A sky preset first, so that the horizon, zenith or intensity the file gives override it
    // wherever they stand. "preset" on another type is left to readParams' unknown-key error.
    const auto type = value.is_object() ? value.find("type") : value.end();
    const bool sky = type != value.end() ? *type == "sky" : out.type == EnvironmentType::Sky;
    if (const auto preset = value.is_object() ? value.find("preset") : value.end(); sky && preset != value.end()) {
        std::string name;
        readValue(*preset, member(path, "preset"), name, kAnyValue);
        const SkyPreset* found = findSkyPreset(name);
        if (!found) {
            std::vector<std::string> names;
            for (const SkyPreset& p : skyPresets()) names.emplace_back(p.name);
            fail(member(path, "preset"), "unknown value '" + name + "' (allowed: " + join(names) + ")");
        }
        applySkyPreset(*found, out);
    }
    readParams(value, path, out);
}

Json toJson(const Camera& v) { return writeParams(v); }
Json toJson(const RenderSettings& v) { return writeParams(v); }
Json toJson(const Material& v) { return writeParams(v); }
Json toJson(const Object& v) { return writeParams(v); }
Json toJson(const Light& v) { return writeParams(v); }
Json toJson(const Environment& v) { return writeParams(v); }

// ---------------------------------------------------------------------------------------------
// Scene

const Fields<Scene>& sceneFields() {
    static const Fields<Scene> kFields = {
        // Checked before anything else in readScene; always written as the current version.
        {"version", [](const Json&, const std::string&, Scene&) {},
         [](const Scene&) { return Json(kSceneVersion); }, {}},
        field("camera", &Scene::camera),
        field("render", &Scene::render),
        field("materials", &Scene::materials),
        field("objects", &Scene::objects),
        field("lights", &Scene::lights),
        field("environment", &Scene::environment),
    };
    return kFields;
}

void readScene(const Json& root, Scene& scene) {
    if (!root.is_object()) fail("", "the top level must be a JSON object, got " + describe(root));
    const auto version = root.find("version");
    if (version == root.end()) {
        fail("version", "missing (a scene file must contain \"version\": " +
                            std::to_string(kSceneVersion) + ")");
    }
    const long long v = readInteger(*version, "version", kAnyValue);
    if (v != kSceneVersion) {
        fail("version", "unsupported scene version " + std::to_string(v) +
                            " (this build reads version " + std::to_string(kSceneVersion) + ")");
    }

    readFields(root, "", sceneFields(), scene);

    if (const auto broken = checkReferences(scene)) fail(broken->key, broken->message);
}

// ---------------------------------------------------------------------------------------------
// Parsing

// Follows the JSON path while nlohmann parses, to report duplicate keys (nlohmann would keep the
// last silently) and to name the value whose number overflowed (nlohmann's error has no position).
class PathTracker {
public:
    bool onEvent(Json::parse_event_t event, const Json& parsed) {
        using Event = Json::parse_event_t;
        switch (event) {
        case Event::object_start:
        case Event::array_start:
            countElement();
            m_frames.push_back(Frame{event == Event::array_start, 0, {}, {}});
            break;
        case Event::object_end:
        case Event::array_end:
            if (!m_frames.empty()) m_frames.pop_back();
            break;
        case Event::key:
            if (!m_frames.empty() && parsed.is_string()) {
                Frame& top = m_frames.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second && !m_duplicate) {
                    m_duplicate = member(pathOfParents(), top.key);
                }
            }
            break;
        case Event::value: countElement(); break;
        }
        return true;
    }

    const std::optional<std::string>& duplicate() const { return m_duplicate; }

    // The path of the value being parsed (not yet reported to onEvent).
    std::string currentPath() const {
        if (m_frames.empty()) return "";
        const Frame& top = m_frames.back();
        return top.isArray ? element(pathOfParents(), top.count) : member(pathOfParents(), top.key);
    }

private:
    struct Frame {
        bool isArray = false;
        std::size_t count = 0;        // arrays: elements started so far
        std::string key;              // objects: the latest key
        std::set<std::string> keys;   // objects: every key so far
    };

    void countElement() {
        if (!m_frames.empty() && m_frames.back().isArray) ++m_frames.back().count;
    }

    // The path of the innermost open object/array.
    std::string pathOfParents() const {
        std::string path;
        for (std::size_t i = 0; i + 1 < m_frames.size(); ++i) {
            const Frame& frame = m_frames[i];
            path = frame.isArray ? element(path, frame.count - 1) : member(path, frame.key);
        }
        return path;
    }

    std::vector<Frame> m_frames;
    std::optional<std::string> m_duplicate;
};

// "<file>:<line>:<column>" of the 1-based byte offset `byte`; columns count UTF-8 code points.
std::string textPosition(const std::string& file, const std::string& text, std::size_t byte) {
    const std::size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
    std::size_t line = 1;
    std::size_t column = 1;
    for (std::size_t i = 0; i < end; ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {
            ++column;
        }
    }
    return file + ":" + std::to_string(line) + ":" + std::to_string(column);
}

// "<file>:<line>:<column>: JSON syntax error: <explanation>"; byte is nlohmann's 1-based offset of
// the character where parsing stopped.
std::string syntaxError(const std::string& file, const std::string& text, std::size_t byte,
                        const std::string& what) {
    // what() reads "[json.exception.parse_error.101] parse error at line 3, column 8: <explanation>".
    std::string explanation = what;
    if (const std::size_t at = what.find("parse error"); at != std::string::npos) {
        if (const std::size_t colon = what.find(": ", at); colon != std::string::npos) {
            explanation = what.substr(colon + 2);
        }
    } else if (const std::size_t bracket = what.find("] "); bracket != std::string::npos) {
        explanation = what.substr(bracket + 2);
    }
    return oneLine(textPosition(file, text, byte) + ": JSON syntax error: " + explanation);
}

// Scene files nest a few levels (objects[2].transform.matrix is three arrays and objects deep);
// 64 leaves room for anything written by hand and keeps every recursive walk over a parsed value
// (error messages, the writer, nlohmann's own dump) shallow. A file nested 100,000 deep used to
// overflow the stack in an error message.
constexpr int kMaxJsonDepth = 64;

std::string tooDeepMessage() {
    return "arrays and objects nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";
}

// At most 60 bytes of a user's text, for messages.
std::string shortened(const std::string& text) {
    return text.size() <= 60 ? text : text.substr(0, 57) + "...";
}

}  // namespace

bool parseJsonStrict(const std::string& jsonText, const std::string& fileForMessages, nlohmann::json* out,
                     std::string* error) {
    if (const std::size_t at = jsonTooDeepAt(jsonText, kMaxJsonDepth); at != std::string_view::npos) {
        *error = oneLine(textPosition(fileForMessages, jsonText, at + 1) + ": " + tooDeepMessage());
        return false;
    }
    PathTracker tracker;
    try {
        *out = Json::parse(jsonText, [&tracker](int, Json::parse_event_t event, Json& parsed) {
            return tracker.onEvent(event, parsed);
        });
    } catch (const Json::parse_error& e) {
        *error = syntaxError(fileForMessages, jsonText, e.byte, e.what());
        return false;
    } catch (const Json::out_of_range&) {
        *error = formatError(fileForMessages, tracker.currentPath(), "number out of range (must be a finite number)");
        return false;
    }
    if (tracker.duplicate()) {
        *error = formatError(fileForMessages, *tracker.duplicate(), "duplicate key (each key may appear only once per object)");
        return false;
    }
    return true;
}

SceneLoadResult parseScene(const std::string& jsonText, const std::string& fileForMessages) {
    SceneLoadResult result;
    try {
        if (const std::size_t at = jsonTooDeepAt(jsonText, kMaxJsonDepth); at != std::string_view::npos) {
            result.error = oneLine(textPosition(fileForMessages, jsonText, at + 1) + ": " + tooDeepMessage());
            return result;
        }
        PathTracker tracker;
        Json root;
        try {
            root = Json::parse(jsonText, [&tracker](int, Json::parse_event_t event, Json& parsed) {
                return tracker.onEvent(event, parsed);
            });
        } catch (const Json::parse_error& e) {
            result.error = syntaxError(fileForMessages, jsonText, e.byte, e.what());
            return result;
        } catch (const Json::out_of_range& e) {
            // 406: a number like 1e999 that overflows a double. what() ends with "parsing '<token>'".
            const std::string what = e.what();
            const std::size_t open = what.find('\'');
            const std::size_t close = what.rfind('\'');
            const std::string token =
                open != std::string::npos && close > open ? what.substr(open + 1, close - open - 1)
                                                          : what;
            fail(tracker.currentPath(), "number out of range (must be a finite number), got " + token);
        }
        if (tracker.duplicate()) {
            fail(*tracker.duplicate(), "duplicate key (each key may appear only once per object)");
        }
        Scene scene;
        readScene(root, scene);
        result.scene = std::move(scene);
    } catch (const SceneError& e) {
        result.error = formatError(fileForMessages, e.path, e.message);
    } catch (const std::bad_alloc&) {
        result.error = fileForMessages + ": out of memory while reading the scene";
    } catch (const std::exception& e) {
        result.error = oneLine(fileForMessages + ": internal error: " + e.what());
    } catch (...) {
        result.error = fileForMessages + ": internal error while reading the scene";
    }
    if (!result.error.empty()) result.scene.reset();
    return result;
}

namespace {

// A scene file's read (`read` returns its result), with whatever escapes it (out of memory, an
// exception not foreseen) turned into a message naming the file: never a crash.
template <class Read>
SceneLoadResult guardedSceneRead(const std::string& file, Read&& read) {
    try {
        return read();
    } catch (const std::bad_alloc&) {
        return SceneLoadResult{std::nullopt, file + ": out of memory while reading the scene"};
    } catch (...) {
        return SceneLoadResult{std::nullopt, file + ": internal error while reading the scene"};
    }
}

}  // namespace

SceneLoadResult loadScene(const std::string& file) {
    return guardedSceneRead(file, [&] {
        std::string error;
        const std::optional<std::string> text = readTextFile(file, &error);
        if (!text) return SceneLoadResult{std::nullopt, oneLine(error)};
        SceneLoadResult result = parseScene(*text, file);
        if (result.scene) result.scene->sourcePath = file;
        return result;
    });
}

bool parseSceneOverride(const std::string& text, SceneOverride* out, std::string* error) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0) {
        *error = "expected <json.path>=<value>, got '" + text + "'";
        return false;
    }
    out->path = text.substr(0, eq);
    out->value = text.substr(eq + 1);
    return true;
}

namespace {

// Follows (creating objects on the way where keys are missing) a path like a.b[2].c[name].
Json* resolveOverridePath(Json& root, const std::string& path, std::string* error) {
    Json* node = &root;
    std::size_t i = 0;
    std::string walked;
    while (i < path.size()) {
        if (path[i] == '.') { ++i; continue; }
        if (path[i] == '[') {
            const std::size_t close = path.find(']', i);
            if (close == std::string::npos) { *error = "unclosed '[' in '" + path + "'"; return nullptr; }
            const std::string key = path.substr(i + 1, close - i - 1);
            walked += "[" + key + "]";
            if (!node->is_array()) { *error = walked + ": not an array"; return nullptr; }
            const bool numeric = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) { return c >= '0' && c <= '9'; });
            Json* found = nullptr;
            if (numeric) {
                std::size_t index = 0;
                const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), index);
                if (ec == std::errc() && end == key.data() + key.size() && index < node->size()) found = &(*node)[index];
            } else {
                for (Json& item : *node)
                    if (item.is_object() && item.contains("name") && item["name"] == key) found = &item;
            }
            if (!found) {
                *error = walked + ": no such element (the array has " + std::to_string(node->size()) + ")";
                return nullptr;
            }
            node = found;
            i = close + 1;
            continue;
        }
        const std::size_t end = path.find_first_of(".[", i);
        const std::string key = path.substr(i, end == std::string::npos ? std::string::npos : end - i);
        walked += (walked.empty() ? "" : ".") + key;
        if (node->is_null()) *node = Json::object();
        if (!node->is_object()) { *error = walked + ": the parent is not an object"; return nullptr; }
        node = &(*node)[key];
        i = end == std::string::npos ? path.size() : end;
    }
    return node;
}

}  // namespace

SceneLoadResult loadScene(const std::string& file, const std::vector<SceneOverride>& overrides) {
    if (overrides.empty()) return loadScene(file);
    return guardedSceneRead(file, [&] {
        std::string error;
        const std::optional<std::string> text = readTextFile(file, &error);
        if (!text) return SceneLoadResult{std::nullopt, oneLine(error)};
        Json root;
        try {
            if (jsonTooDeepAt(*text, kMaxJsonDepth) != std::string_view::npos) return parseScene(*text, file);  // says where
            root = Json::parse(*text);
        } catch (const std::exception&) {
            return parseScene(*text, file);  // reports the syntax error with line and column
        }
        for (const SceneOverride& o : overrides) {
            const std::string what = "--set " + shortened(o.path + "=" + o.value) + ": ";
            Json* target = resolveOverridePath(root, o.path, &error);
            if (!target) return SceneLoadResult{std::nullopt, oneLine(what + error)};
            if (jsonTooDeepAt(o.value, kMaxJsonDepth) != std::string_view::npos)
                return SceneLoadResult{std::nullopt, oneLine(what + "the value has " + tooDeepMessage())};
            try {
                *target = Json::parse(o.value);
            } catch (const std::exception&) {
                *target = o.value;  // not JSON: a string
            }
        }
        SceneLoadResult result = parseScene(root.dump(2), file + " (with --set)");
        if (result.scene) result.scene->sourcePath = file;
        return result;
    });
}

namespace {

// Writes the value and reads it back with the file reader's rules.
template <class T>
std::string checkByRoundTrip(const T& value, const std::string& path) {
    try {
        T copy{};
        readValue(toJson(value), path, copy, kAnyValue);
        return "";
    } catch (const SceneError& e) {
        return oneLine(e.path.empty() ? e.message : e.path + ": " + e.message);
    } catch (const std::bad_alloc&) {
        return path + ": out of memory";
    } catch (const std::exception& e) {
        return oneLine(path + ": " + e.what());
    }
}

}  // namespace

std::string checkEntity(const Object& value, const std::string& path) { return checkByRoundTrip(value, path); }
std::string checkEntity(const Light& value, const std::string& path) { return checkByRoundTrip(value, path); }
std::string checkEntity(const Material& value, const std::string& path) { return checkByRoundTrip(value, path); }
std::string checkEntity(const Camera& value, const std::string& path) { return checkByRoundTrip(value, path); }
std::string checkEntity(const RenderSettings& value, const std::string& path) { return checkByRoundTrip(value, path); }
std::string checkEntity(const Environment& value, const std::string& path) { return checkByRoundTrip(value, path); }

namespace {

// Pretty JSON with 2-space indentation, but arrays of numbers/strings on one line ("[0, 1, 0]").
void appendPretty(const Json& value, std::size_t indent, std::string& out) {
    if (!value.is_structured()) {
        out += dumpCompact(value);
        return;
    }
    const bool isObject = value.is_object();
    if (value.empty()) {
        out += isObject ? "{}" : "[]";
        return;
    }
    if (!isObject && std::none_of(value.begin(), value.end(),
                                  [](const Json& item) { return item.is_structured(); })) {
        out += '[';
        for (std::size_t i = 0; i < value.size(); ++i) {
            if (i > 0) out += ", ";
            out += dumpCompact(value[i]);
        }
        out += ']';
        return;
    }
    out += isObject ? "{\n" : "[\n";
    bool first = true;
    for (auto it = value.begin(); it != value.end(); ++it) {
        if (!first) out += ",\n";
        first = false;
        out.append(indent + 2, ' ');
        if (isObject) out += dumpCompact(Json(it.key())) + ": ";
        appendPretty(it.value(), indent + 2, out);
    }
    out += '\n';
    out.append(indent, ' ');
    out += isObject ? '}' : ']';
}

}  // namespace

std::string sceneToJson(const Scene& scene) {
    try {
        std::string out;
        appendPretty(writeFields(scene, sceneFields()), 0, out);
        out += '\n';
        return out;
    } catch (...) {
        return std::string();
    }
}

bool saveScene(const Scene& scene, const std::string& file, std::string* error) {
    try {
        const std::string text = sceneToJson(scene);
        if (text.empty()) {
            if (error) *error = file + ": cannot write: out of memory";
            return false;
        }
        // Refuse to write a file that would not load (NaN, dangling material, ...).
        const SceneLoadResult check = parseScene(text, file);
        if (!check) {
            if (error) {
                const std::string prefix = file + ": ";
                const std::string reason = check.error.starts_with(prefix)
                                               ? check.error.substr(prefix.size())
                                               : check.error;
                *error = file + ": not saved, the scene is invalid: " + reason;
            }
            return false;
        }
        return writeFileAtomically(file, text, error);
    } catch (...) {
        if (error) *error = file + ": cannot write: out of memory";
        return false;
    }
}

}  // namespace caustic
