// Inspector widgets from the scene schema (param_widgets.h).
#include "editor/ui/param_widgets.h"

#include "editor/model/plain_text.h"

#include "editor/ui/asset_picker.h"

#include "editor/model/viewport_math.h"
#include "editor/ui/editor_ui.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <cstring>
#include <map>

namespace caustic::editor {

std::vector<WidgetRecord>* g_widgetTrace = nullptr;

void traceWidget(std::string_view key, ParamKind kind, double min, double max) {
    if (g_widgetTrace) g_widgetTrace->push_back({std::string(key), kind, min, max});
}

void Edit::track(bool c, bool discrete) {
    changed |= c;
    if ((discrete && c) || ImGui::IsItemDeactivatedAfterEdit()) seal = true;
    if (ImGui::IsItemActive()) {
        ui.app.session.interacting = true;
        ui.app.session.lastInteraction = ImGui::GetTime();
    }
}

void Edit::commit(std::unique_ptr<Command> command) {
    std::string why;
    if (changed && command && !ui.app.state.applyContinuous(std::move(command), &why)) notify(ui, why, true);
    if (seal) ui.app.state.seal();
}

namespace {

// The widget's bounds for a range: the valid interval as floats (an exclusive bound moved one
// float inwards); unbounded sides at +-kBig, and (0, 0) for "no limit" (ImGui clamps only when
// min < max).
constexpr float kBig = 1e30f;
struct Bounds {
    float min = 0.0f, max = 0.0f;
};
Bounds boundsOf(const Range& r) {
    if (!std::isfinite(r.min) && !std::isfinite(r.max)) return {};
    Bounds b{-kBig, kBig};
    if (std::isfinite(r.min)) {
        b.min = static_cast<float>(r.min);
        if (r.minExclusive || static_cast<double>(b.min) < r.min) b.min = std::nextafter(b.min, kBig);
    }
    if (std::isfinite(r.max)) {
        b.max = static_cast<float>(r.max);
        if (r.maxExclusive || static_cast<double>(b.max) > r.max) b.max = std::nextafter(b.max, -kBig);
    }
    return b;
}

// A value the user typed (Ctrl+click, or a colour's text field), brought into the range.
float clampInto(float v, const Range& r) {
    if (!std::isfinite(v)) v = 0.0f;
    const Bounds b = boundsOf(r);
    if (b.min < b.max) v = std::clamp(v, b.min, b.max);
    return v;
}

// "%.4g deg": the unit after the number.
template <class T>
std::string formatOf(const Param<T>& p, const char* number = "%.4g") {
    std::string f = number;
    if (!p.unit.empty()) {
        f += ' ';
        f += p.unit;
    }
    return f;
}

template <class T>
float dragSpeed(const Param<T>& p, const Bounds& b) {
    if (p.speed > 0.0f) return p.speed;
    if (b.min < b.max && b.max - b.min < 1e6f) return (b.max - b.min) / 200.0f;
    return 0.01f;
}

// A typed value outside the parameter's range is set to the nearest one it allows, and the status
// bar says so (1e30 used to become 1,000,000 without a word). A drag never leaves the range.
void announceClamp(Edit& e, std::string_view label, float typed, float kept) {
    char text[160];
    std::snprintf(text, sizeof text, "%.*s: %g is outside what the scene allows; set to %g", int(label.size()), label.data(),
                  double(typed), double(kept));
    notify(e.ui, text);
}

template <class T>
void floatWidget(Edit& e, const Param<T>& p, float* value) {
    const Bounds b = boundsOf(p.range);
    traceWidget(p.key, p.kind, b.min, b.max);
    float v = *value;
    const std::string label(p.label);
    bool c = false;
    if (p.slider && b.min < b.max && b.max - b.min < 1e6f)
        c = ImGui::SliderFloat(label.c_str(), &v, b.min, b.max, formatOf(p, "%.3f").c_str());
    else
        c = ImGui::DragFloat(label.c_str(), &v, dragSpeed(p, b), b.min, b.max, formatOf(p).c_str());
    e.track(c);
    if (c) {
        *value = clampInto(v, p.range);
        if (*value != v && std::isfinite(v)) announceClamp(e, p.label, v, *value);
    }
}

template <class T>
void vectorWidget(Edit& e, const Param<T>& p, glm::vec3* value) {
    const Bounds b = boundsOf(p.range);
    traceWidget(p.key, p.kind, b.min, b.max);
    glm::vec3 v = *value;
    const std::string label(p.label);
    bool c = false;
    if (p.kind == ParamKind::Colour)
        c = ImGui::ColorEdit3(label.c_str(), &v.x, ImGuiColorEditFlags_Float);
    else
        c = ImGui::DragFloat3(label.c_str(), &v.x, dragSpeed(p, b) > 1.0f ? 0.01f : dragSpeed(p, b), b.min, b.max,
                              formatOf(p, "%.3f").c_str());
    e.track(c);
    if (c)
        for (int i = 0; i < 3; ++i) {
            (*value)[i] = clampInto(v[i], p.range);
            if ((*value)[i] != v[i] && std::isfinite(v[i])) announceClamp(e, p.label, v[i], (*value)[i]);
        }
}

template <class T>
void intWidget(Edit& e, const Param<T>& p, int* value) {
    const Bounds b = boundsOf(p.range);
    const int lo = b.min < b.max ? static_cast<int>(std::max(b.min, -2.0e9f)) : 0;
    const int hi = b.min < b.max ? static_cast<int>(std::min(b.max, 2.0e9f)) : 0;
    traceWidget(p.key, p.kind, lo, hi);
    const std::string label(p.label);
    if (p.deferred) {
        // Applied when the field is left: a half-typed width would restart everything.
        static std::map<std::string, int, std::less<>> s_typing;
        const auto it = s_typing.find(p.key);
        int v = it != s_typing.end() ? it->second : *value;
        ImGui::InputInt(label.c_str(), &v, 0, 0);
        if (ImGui::IsItemActive()) s_typing[std::string(p.key)] = v;
        if (ImGui::IsItemDeactivated()) {
            s_typing.erase(std::string(p.key));
            if (ImGui::IsItemDeactivatedAfterEdit() && std::clamp(v, lo, hi) != *value) {
                *value = std::clamp(v, lo, hi);
                e.changed = e.seal = true;
            }
        }
        return;
    }
    int v = *value;
    const bool c = ImGui::DragInt(label.c_str(), &v, std::max(p.speed, 0.05f), lo, hi, formatOf(p, "%d").c_str());
    e.track(c);
    if (c) *value = lo < hi ? std::clamp(v, lo, hi) : v;
}

template <class T>
void uintWidget(Edit& e, const Param<T>& p, std::uint32_t* value) {
    traceWidget(p.key, p.kind, 0.0, 4294967295.0);
    std::uint32_t v = *value;
    const std::uint32_t lo = 0, hi = 0xffffffffu;
    const bool c = ImGui::DragScalar(std::string(p.label).c_str(), ImGuiDataType_U32, &v, std::max(p.speed, 0.05f),
                                     &lo, &hi, "%u");
    e.track(c);
    if (c) *value = v;
}

template <class T>
void enumWidget(Edit& e, const Param<T>& p, T& value) {
    const auto choices = p.choices();
    traceWidget(p.key, p.kind, 0, static_cast<double>(choices.size()) - 1);
    const int current = p.getEnum(value);
    const char* preview = "?";
    for (const EnumChoice& c : choices)
        if (c.value == current) preview = c.label.data();
    if (ImGui::BeginCombo(std::string(p.label).c_str(), preview)) {
        for (const EnumChoice& c : choices) {
            if (ImGui::Selectable(c.label.data(), c.value == current) && c.value != current) {
                p.setEnum(value, c.value);
                e.changed = e.seal = true;
            }
        }
        ImGui::EndCombo();
    }
}

// A file: typed and applied on Enter (or cleared, for an optional texture).
template <class T>
void fileWidget(Edit& e, const Param<T>& p, std::string* value) {
    traceWidget(p.key, p.kind);
    char buffer[1024];
    std::strncpy(buffer, value->c_str(), sizeof buffer - 1);
    buffer[sizeof buffer - 1] = '\0';
    const std::string label(p.label);
    // The picker's "..." sits between the field and its label.
    const float full = ImGui::CalcItemWidth();
    ImGui::SetNextItemWidth(std::max(1.0f, full - assetPickerButtonWidth() - ImGui::GetStyle().ItemInnerSpacing.x));
    const std::string fieldId = "##" + label;
    if (ImGui::InputTextWithHint(fieldId.c_str(), p.nonEmpty ? "(none)" : "", buffer, sizeof buffer,
                                 ImGuiInputTextFlags_EnterReturnsTrue) &&
        *value != buffer) {
        *value = buffer;
        e.changed = e.seal = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("relative to the scene file; Enter applies%s", p.nonEmpty ? ", empty removes it" : "");
    ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
    // The camera's `lens` picks from the lens library (assets/lenses/); every other file is an image.
    const AssetKind kind = std::is_same_v<T, Environment> ? AssetKind::EnvironmentMap
                           : std::is_same_v<T, Camera> && p.key == "lens" ? AssetKind::Lens
                                                                           : AssetKind::Texture;
    if (const std::optional<AssetFile> picked = assetPickerButton(e.ui, label.c_str(), kind); picked && picked->stored != *value) {
        *value = picked->stored;
        e.changed = e.seal = true;
    }
    ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::TextUnformatted(label.c_str());
}

}  // namespace

bool colourAndStrength(Edit& e, const char* colourLabel, const char* strengthLabel, glm::vec3* value,
                       double maxStrength) {
    float strength = std::max({value->x, value->y, value->z});
    glm::vec3 tint = strength > 0.0f ? *value / strength : glm::vec3(1.0f);
    bool c1 = ImGui::ColorEdit3(colourLabel, &tint.x, ImGuiColorEditFlags_Float);
    e.track(c1);
    bool c2 = ImGui::DragFloat(strengthLabel, &strength, 0.05f, 0.0f, static_cast<float>(maxStrength), "%.4g");
    e.track(c2);
    if (c1 || c2) {
        strength = std::clamp(std::isfinite(strength) ? strength : 0.0f, 0.0f, static_cast<float>(maxStrength));
        *value = glm::clamp(tint, glm::vec3(0.0f), glm::vec3(1.0f)) * strength;
    }
    return c1 || c2;
}

void transformWidgets(Edit& e, Transform* t) {
    if (t->matrix) {
        ImGui::TextDisabled("Transform: a matrix (from the file)");
        if (ImGui::Button("Convert to translate / rotate / scale")) {
            *t = transformFromMatrix(*t->matrix);
            e.track(true, true);
        }
        return;
    }
    e.track(ImGui::DragFloat3("Translate", &t->translate.x, 0.01f, 0.0f, 0.0f, "%.3f"));
    e.track(ImGui::DragFloat3("Rotate (deg)", &t->rotate.x, 0.5f, 0.0f, 0.0f, "%.1f"));
    e.track(ImGui::DragFloat3("Scale", &t->scale.x, 0.005f, 0.0f, 0.0f, "%.3f"));
}

template <class T>
void drawParams(Edit& e, T& value, const std::function<bool(const Param<T>&, T&)>& special) {
    // A section's heading once, at the first of its parameters that applies (the surface's
    // Transmission starts at transmission_weight, the dielectric's at transmission_color).
    std::string_view section;
    for (const Param<T>& p : schemaOf<T>()) {
        if (!appliesTo(p, value)) continue;
        if (!p.section.empty() && p.section != section) {
            ImGui::SeparatorText(std::string(p.section).c_str());
            section = p.section;
        }
        ImGui::PushID(p.key.data(), p.key.data() + p.key.size());
        if (special && special(p, value)) {
            ImGui::PopID();
            continue;
        }
        switch (p.kind) {
            case ParamKind::Enum: enumWidget(e, p, value); break;
            case ParamKind::Radiance: {
                traceWidget(p.key, p.kind, 0.0, p.range.max);
                const std::string colour(p.label), strength = std::string(p.label) + " strength";
                colourAndStrength(e, colour.c_str(), strength.c_str(), &(value.*std::get<glm::vec3 T::*>(p.member)),
                                  p.range.max);
                break;
            }
            case ParamKind::Float: floatWidget(e, p, &(value.*std::get<float T::*>(p.member))); break;
            case ParamKind::Int: intWidget(e, p, &(value.*std::get<int T::*>(p.member))); break;
            case ParamKind::UInt: uintWidget(e, p, &(value.*std::get<std::uint32_t T::*>(p.member))); break;
            case ParamKind::Bool:
                traceWidget(p.key, p.kind);
                e.track(ImGui::Checkbox(std::string(p.label).c_str(), &(value.*std::get<bool T::*>(p.member))), true);
                break;
            case ParamKind::Vector:
            case ParamKind::Colour: vectorWidget(e, p, &(value.*std::get<glm::vec3 T::*>(p.member))); break;
            case ParamKind::File: fileWidget(e, p, &(value.*std::get<std::string T::*>(p.member))); break;
            case ParamKind::Transform:
                traceWidget(p.key, p.kind);
                ImGui::SeparatorText(std::string(p.label).c_str());
                transformWidgets(e, &(value.*std::get<Transform T::*>(p.member)));
                break;
            case ParamKind::OptionalPoint: {
                auto& point = value.*std::get<std::optional<glm::vec3> T::*>(p.member);
                const Bounds b = boundsOf(p.range);
                traceWidget(p.key, p.kind, b.min, b.max);
                bool on = point.has_value();
                std::string check = "Use " + std::string(p.label);
                if (check.size() > 4) check[4] = static_cast<char>(std::tolower(static_cast<unsigned char>(check[4])));
                if (ImGui::Checkbox(check.c_str(), &on)) {
                    e.changed = e.seal = true;
                    if (on) point = glm::vec3(0.0f);
                    else point.reset();
                }
                if (point) {
                    glm::vec3 v = *point;
                    const bool c = ImGui::DragFloat3(std::string(p.label).c_str(), &v.x, 0.01f, b.min, b.max, "%.3f");
                    e.track(c);
                    if (c)
                        for (int i = 0; i < 3; ++i) (*point)[i] = clampInto(v[i], p.range);
                }
                break;
            }
            case ParamKind::Name:
            case ParamKind::Reference: {
                // Without a special widget: shown, not edited here.
                traceWidget(p.key, p.kind);
                const std::string& text = value.*std::get<std::string T::*>(p.member);
                ImGui::LabelText(std::string(p.label).c_str(), "%s", text.c_str());
                break;
            }
            case ParamKind::Preset: traceWidget(p.key, p.kind); break;  // drawn by `special` (sky presets)
        }
        if (ImGui::IsItemHovered() && !p.doc.empty() && p.kind != ParamKind::File)
            ImGui::SetTooltip("%s", plainText(p.doc).c_str());   // the schema's Markdown as text
        ImGui::PopID();
    }
}

template void drawParams(Edit&, Camera&, const std::function<bool(const Param<Camera>&, Camera&)>&);
template void drawParams(Edit&, RenderSettings&,
                         const std::function<bool(const Param<RenderSettings>&, RenderSettings&)>&);
template void drawParams(Edit&, Material&, const std::function<bool(const Param<Material>&, Material&)>&);
template void drawParams(Edit&, Object&, const std::function<bool(const Param<Object>&, Object&)>&);
template void drawParams(Edit&, Light&, const std::function<bool(const Param<Light>&, Light&)>&);
template void drawParams(Edit&, Environment&, const std::function<bool(const Param<Environment>&, Environment&)>&);

}  // namespace caustic::editor
