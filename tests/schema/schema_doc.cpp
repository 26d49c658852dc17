// caustic-schema-doc: docs/scene-format.md's parameter tables, generated from the scene schema
// (renderer/scene_schema.h), so the documentation cannot drift from what the loader reads.
//   caustic-schema-doc --check docs/scene-format.md   exit 1 naming each table that differs (a test)
//   caustic-schema-doc --write docs/scene-format.md   rewrite the tables in place (atomically)
// A table is the text between `<!-- schema: NAME -->` and `<!-- /schema -->` (NAME: camera,
// render, materials, objects, lights, environment); everything else in the file is left alone.
#include "renderer/file_util.h"
#include "renderer/scene_schema.h"

#include <cstdio>
#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <vector>

using namespace caustic;

namespace {

std::string kindText(ParamKind kind) {
    switch (kind) {
        case ParamKind::Float: return "number";
        case ParamKind::Int:
        case ParamKind::UInt: return "integer";
        case ParamKind::Bool: return "boolean";
        case ParamKind::Vector:
        case ParamKind::Colour:
        case ParamKind::Radiance:
        case ParamKind::OptionalPoint: return "vec3";
        case ParamKind::Transform: return "object";
        default: return "string";
    }
}

std::string vec3Text(const glm::vec3& v) {
    return "[" + shortestText(v.x) + ", " + shortestText(v.y) + ", " + shortestText(v.z) + "]";
}

// The value of p in `value` as it is written in a file.
template <class T>
std::string valueText(const Param<T>& p, const T& value) {
    if (p.kind == ParamKind::Enum) {
        const int v = p.getEnum(value);
        for (const EnumChoice& c : p.choices())
            if (c.value == v) return "\"" + std::string(c.name) + "\"";
        return "?";
    }
    return std::visit(
        [&](auto m) -> std::string {
            using M = decltype(m);
            if constexpr (std::is_same_v<M, float T::*>) return shortestText(value.*m);
            else if constexpr (std::is_same_v<M, int T::*> || std::is_same_v<M, std::uint32_t T::*>)
                return std::to_string(value.*m);
            else if constexpr (std::is_same_v<M, bool T::*>) return value.*m ? "true" : "false";
            else if constexpr (std::is_same_v<M, glm::vec3 T::*>) return vec3Text(value.*m);
            else if constexpr (std::is_same_v<M, std::string T::*>) return "\"" + value.*m + "\"";
            else if constexpr (std::is_same_v<M, std::optional<glm::vec3> T::*>)
                return value.*m ? vec3Text(*(value.*m)) : "absent";
            else if constexpr (std::is_same_v<M, Transform T::*>) return "identity";
            else return "";
        },
        p.member);
}

std::string rangeText(ParamKind kind, const Range& r, std::string_view unit) {
    std::string text;
    if (kind == ParamKind::Float || kind == ParamKind::Int || kind == ParamKind::UInt) text = r.text();
    else if (kind == ParamKind::Vector || kind == ParamKind::Colour || kind == ParamKind::Radiance ||
             kind == ParamKind::OptionalPoint)
        text = r.text() == "any" ? "any" : "each component " + r.text();
    else return "";
    if (text == "any") text.clear();
    for (std::size_t e = text.find("e+"); e != std::string::npos; e = text.find("e+")) text.erase(e + 1, 1);
    if (!unit.empty()) text += (text.empty() ? "" : " ") + std::string(unit);
    return text;
}

// A default-constructed value of each type of T (its type key set), with the type's name.
template <class T>
std::vector<std::pair<std::string, T>> typedDefaults() {
    std::vector<std::pair<std::string, T>> out;
    if constexpr (std::is_same_v<T, Material>) {
        for (const EnumChoice& c : enumChoices(MaterialType{}))
            out.emplace_back(std::string(c.name), materialDefaults(static_cast<MaterialType>(c.value)));
    } else if constexpr (std::is_same_v<T, Object>) {
        for (const EnumChoice& c : enumChoices(Shape{})) {
            Object o;
            o.shape = static_cast<Shape>(c.value);
            out.emplace_back(std::string(c.name), o);
        }
    } else if constexpr (std::is_same_v<T, Light>) {
        for (const EnumChoice& c : enumChoices(LightType{})) {
            Light l;
            l.type = static_cast<LightType>(c.value);
            out.emplace_back(std::string(c.name), l);
        }
    } else if constexpr (std::is_same_v<T, Environment>) {
        for (const EnumChoice& c : enumChoices(EnvironmentType{})) {
            Environment e;
            e.type = static_cast<EnvironmentType>(c.value);
            out.emplace_back(std::string(c.name), e);
        }
    } else {
        out.emplace_back("", T{});
    }
    return out;
}

std::string escapeCell(std::string_view text) {
    std::string out;
    for (const char c : text) {
        if (c == '|') out += "\\|";
        else out += c;
    }
    return out;
}

template <class T>
std::string table() {
    const auto defaults = typedDefaults<T>();
    const bool typed = defaults.size() > 1;
    std::string out = typed ? "| key | types | type | default | range | meaning |\n|---|---|---|---|---|---|\n"
                            : "| key | type | default | range | meaning |\n|---|---|---|---|---|\n";
    for (const Param<T>& p : schemaOf<T>()) {
        std::vector<std::string> types;
        std::vector<std::pair<std::string, std::string>> values;  // (type, default)
        for (const auto& [name, value] : defaults) {
            if (!takesKey(p, typeIndexOf(value))) continue;
            types.push_back(name);
            const std::string v = valueText(p, value);
            bool seen = false;
            for (auto& [t, existing] : values)
                if (existing == v) {
                    t += ", " + name;
                    seen = true;
                }
            if (!seen) values.emplace_back(name, v);
        }
        std::string typesText = types.size() == defaults.size() ? "all" : "";
        if (typesText.empty())
            for (const std::string& t : types) typesText += (typesText.empty() ? "" : ", ") + t;
        std::string def;
        const bool typeKey = typed && p.kind == ParamKind::Enum && (p.key == "type" || p.key == "shape");
        if (!p.defaultText.empty()) def = std::string(p.defaultText);
        else if (typeKey) def = "`" + valueText(p, T{}) + "`";  // the type of a value that gives none
        else if (values.size() == 1) def = "`" + values[0].second + "`";
        else
            for (const auto& [t, v] : values) def += (def.empty() ? "" : ", ") + ("`" + v + "` (" + t + ")");
        std::string range = rangeText(p.kind, p.range, p.unit);
        if (p.kind == ParamKind::Enum) {
            for (const EnumChoice& c : p.choices()) range += (range.empty() ? "" : ", ") + ("`\"" + std::string(c.name) + "\"`");
        }
        out += "| `" + std::string(p.key) + "` | ";
        if (typed) out += typesText + " | ";
        out += kindText(p.kind) + " | " + def + " | " + escapeCell(range) + " | " + std::string(p.doc) + " |\n";
    }
    return out;
}

const std::map<std::string, std::string (*)()>& tables() {
    static const std::map<std::string, std::string (*)()> k = {
        {"camera", &table<Camera>},     {"render", &table<RenderSettings>}, {"materials", &table<Material>},
        {"objects", &table<Object>},    {"lights", &table<Light>},          {"environment", &table<Environment>},
    };
    return k;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3 || (std::strcmp(argv[1], "--check") != 0 && std::strcmp(argv[1], "--write") != 0)) {
        std::fprintf(stderr, "usage: caustic-schema-doc --check|--write docs/scene-format.md\n");
        return 2;
    }
    const bool write = std::strcmp(argv[1], "--write") == 0;
    const std::string file = argv[2];
    std::string error;
    const std::optional<std::string> text = readTextFile(file, &error);
    if (!text) {
        std::fprintf(stderr, "caustic-schema-doc: %s\n", error.c_str());
        return 1;
    }
    std::string out;
    std::size_t at = 0;
    std::vector<std::string> seen, differing;
    const std::string open = "<!-- schema: ", close = "<!-- /schema -->";
    while (true) {
        const std::size_t start = text->find(open, at);
        if (start == std::string::npos) break;
        const std::size_t nameEnd = text->find(" -->", start);
        const std::size_t bodyStart = text->find('\n', start);
        const std::size_t end = text->find(close, start);
        if (nameEnd == std::string::npos || bodyStart == std::string::npos || end == std::string::npos) {
            std::fprintf(stderr, "%s: an unclosed '%s' block\n", file.c_str(), open.c_str());
            return 1;
        }
        const std::string name = text->substr(start + open.size(), nameEnd - start - open.size());
        const auto found = tables().find(name);
        if (found == tables().end()) {
            std::fprintf(stderr, "%s: unknown schema table '%s'\n", file.c_str(), name.c_str());
            return 1;
        }
        const std::string generated = found->second();
        if (text->substr(bodyStart + 1, end - bodyStart - 1) != generated) differing.push_back(name);
        out += text->substr(at, bodyStart + 1 - at) + generated;
        at = end;
        seen.push_back(name);
    }
    out += text->substr(at);
    int status = 0;
    for (const auto& [name, fn] : tables()) {
        if (std::find(seen.begin(), seen.end(), name) == seen.end()) {
            std::fprintf(stderr, "%s: no '<!-- schema: %s -->' table\n", file.c_str(), name.c_str());
            status = 1;
        }
    }
    if (write) {
        if (!writeFileAtomically(file, out, &error)) {
            std::fprintf(stderr, "caustic-schema-doc: %s\n", error.c_str());
            return 1;
        }
        return status;
    }
    for (const std::string& name : differing)
        std::fprintf(stderr,
                     "%s: the '%s' table differs from the scene schema (renderer/scene_schema.cpp); run "
                     "caustic-schema-doc --write %s\n",
                     file.c_str(), name.c_str(), file.c_str());
    return differing.empty() ? status : 1;
}
