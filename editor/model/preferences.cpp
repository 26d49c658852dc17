#include "editor/model/preferences.h"

#include <charconv>
#include <cmath>

namespace caustic::editor {

void readPreferenceLine(std::string_view line, Preferences* p) {
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.remove_suffix(1);
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos) return;
    const std::string_view key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "Keymap") {
        if (value == "default") p->keymap = KeymapStyle::Default;
        else if (value == "blender") p->keymap = KeymapStyle::Blender;
    } else if (key == "UiScale") {
        float v = 0.0f;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
        if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v)) return;
        if (v == 0.0f || (v >= kMinUiScale && v <= kMaxUiScale)) p->uiScale = v;
    }
}

std::string writePreferenceLines(const Preferences& p) {
    char scale[32];
    const auto [end, ec] = std::to_chars(scale, scale + sizeof scale, p.uiScale);
    return std::string("Keymap=") + (p.keymap == KeymapStyle::Blender ? "blender" : "default") + "\n" +
           "UiScale=" + std::string(scale, ec == std::errc() ? end : scale) + "\n";
}

}  // namespace caustic::editor
