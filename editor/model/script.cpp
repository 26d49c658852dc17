#include "editor/model/script.h"

#include <charconv>
#include <cstdlib>
#include <map>

namespace caustic::editor {
namespace {

struct Signature { int minArgs, maxArgs; const char* numeric; };  // numeric: 'n' per numeric arg position

// The command table; docs/editor.md describes each command.
const std::map<std::string, Signature>& commands() {
    static const std::map<std::string, Signature> table = {
        {"wait_samples", {1, 1, "n"}},        // render until N samples per pixel (and stop there)
        {"frames", {1, 1, "n"}},              // let N frames pass
        {"select", {1, 2, ""}},               // select <kind> [name]
        {"translate", {3, 3, "nnn"}},         // move the selection by (x y z): one command
        {"drag", {4, 4, "nnnn"}},             // drag the selection by (x y z) over N frames: one undo step
        {"orbit", {2, 2, "nn"}},              // orbit the camera (yaw pitch degrees)
        {"set_samples", {1, 1, "n"}},         // the render's target samples per pixel
        {"undo", {0, 0, ""}},
        {"redo", {0, 0, ""}},
        {"open", {1, 1, ""}},                 // open a scene (its meshes import in the background)
        {"wait_open", {0, 1, "n"}},           // wait until the open finished: adopted, refused or dropped [timeout s]
        {"uncap", {0, 0, ""}},                // lift wait_samples' cap: render on to the scene's target
        {"save", {0, 1, ""}},                 // save [as file]
        {"write_image", {1, 1, ""}},          // the film, tone mapped as in batch mode (PNG)
        {"screenshot", {1, 1, ""}},           // the whole window (PNG)
        {"snapshot", {0, 0, ""}},             // lookdev snapshot
        {"compare", {1, 1, ""}},              // on | off: split view snapshot | live
        {"render_to_file", {1, 1, ""}},       // render the scene's samples and write the PNG
        {"expect_error", {1, 1, ""}},         // the last error message contains the text
        {"expect_message", {1, 1, ""}},       // the last message, info or error, contains the text
        {"expect_undo_steps", {1, 1, "n"}},
        {"report", {1, 1, ""}},               // frame-time and edit-latency figures as JSON
        {"denoise", {0, 1, "n"}},             // denoise now and wait until the viewport shows it [timeout s]
        {"wait_denoised", {0, 1, "n"}},       // wait until a denoised image is shown (auto) [timeout s]
        {"denoise_auto", {1, 1, ""}},         // on | off: denoise when the target samples are reached
        {"show_raw", {1, 1, ""}},             // on | off: show the raw render instead of the denoised one
        {"expect_denoised", {1, 1, ""}},      // yes | no: the viewport shows a denoised image
        {"autosave", {1, 1, ""}},             // on | off: periodic autosave (needs $CAUSTIC_EDITOR_HOME)
        {"viewport", {1, 1, ""}},             // output (the default) | panel: the viewport's render size
        {"autosave_now", {0, 0, ""}},         // write the autosave now (needs $CAUSTIC_EDITOR_HOME)
        {"wait_autosave", {0, 1, "n"}},       // wait for the next periodic autosave [timeout s]
        {"crash", {0, 0, ""}},                // exit at once (status 3) without any clean-up
        {"expect_recovery_offered", {0, 0, ""}},   // the recovery prompt is open
        {"recover", {0, 0, ""}},              // answer the recovery prompt with "Recover"
        {"expect_modified", {1, 1, ""}},      // yes | no: the scene has unsaved changes
        {"import_mesh", {1, 1, ""}},          // import a model file in the background (the object appears when ready)
        {"set_mesh_file", {1, 1, ""}},        // the selected mesh object's file, imported in the background
        {"wait_import", {0, 1, "n"}},         // wait until every import finished and its edit applied [timeout s]
        {"frame", {0, 0, ""}},                // frame the selection (F), or everything
        {"touch", {1, 1, ""}},                // set a file's modification time to now (as an outside edit would)
        {"focus", {1, 1, ""}},                // focus a panel: viewport | outliner | inspector
        {"key", {1, 1, ""}},                  // press and release a key (Delete, F, W, E, R, F6) as the keyboard would
        {"expect_count", {2, 2, ""}},         // expect_count objects|lights|materials N
        {"add_material", {0, 0, ""}},         // Add > Material (a new one, used by nothing)
        {"mark", {0, 0, ""}},                 // remember where accumulation is (for expect_restarted)
        {"expect_restarted", {1, 1, ""}},     // yes | no: accumulation restarted since `mark`
        {"select_add", {2, 2, ""}},           // select_add object NAME: as Ctrl+click (adds, or takes out)
        {"expect_selected", {1, 1, "n"}},     // N objects are selected
        {"assign_material", {1, 1, ""}},      // give every selected object this material (one undo step)
        {"new_material", {0, 1, ""}},         // New material [preset] for the selected objects
        {"make_unique", {0, 0, ""}},          // Make unique: a copy of the selection's shared material
        {"apply_preset", {1, 1, ""}},         // the selected material (or the object's) takes a library preset
        {"expect_material", {2, 2, ""}},      // expect_material OBJECT MATERIAL
        {"preview_lighting", {1, 1, ""}},     // scene | studio: the material preview's lighting
        {"wait_preview", {1, 2, "nn"}},       // until the material preview has N samples of the current material [timeout s]
        {"write_preview", {1, 1, ""}},        // the material preview as PNG
        {"shader_dir", {1, 1, ""}},           // the folder F5 (key F5) reloads the shaders from (tests of the reload)
        {"pick_file", {2, 2, ""}},            // pick_file SLOT NAME: the file picker's entry NAME for a slot (albedo_texture, normal_texture, roughness_texture of the selected material; environment)
        {"expect_picker_lists", {2, 2, ""}},  // expect_picker_lists SLOT NAME: the picker for SLOT lists NAME
        {"set_focus", {1, 1, "n"}},           // the camera's focal distance (the focus point cleared): one edit
        {"expect_focus_overlay", {1, 1, "n"}},   // the focus overlay is shown with at least N cells marked (0: shown)
        {"expect_no_focus_overlay", {0, 0, ""}},
        {"store_view", {1, 1, ""}},           // store the camera as a saved view NAME
        {"recall_view", {1, 1, ""}},          // recall saved view NAME (one undo step)
        {"expect_views", {1, 1, "n"}},        // the scene has N saved camera views
        {"ui_scale", {1, 1, "n"}},            // View > UI scale: a factor, 0 to follow the monitor
        {"expect_font_size", {1, 1, "n"}},    // the UI's font size in pixels
        {"show_help", {1, 1, ""}},            // on | off: the Help > Keyboard and mouse window
        {"record_sizes", {0, 0, ""}},         // the report's viewport_sizes start afresh
        {"window_size", {2, 2, "nn"}},        // resize the window (W H)
        {"idle", {1, 1, ""}},                 // on | off: idle pacing (off in scripts unless asked: they measure frames)
        {"keymap", {1, 1, ""}},               // default | blender: View > Key map
        {"expect_keymap", {1, 1, ""}},        // default | blender: the key map in use (kept between sessions)
        {"mouse_move", {2, 2, "nn"}},         // move the mouse by (dx dy) pixels over the viewport (from its centre the first time)
        {"mouse_click", {1, 1, ""}},          // left | right: click where the mouse is
        {"expect_hidden", {1, 1, "n"}},       // N objects are hidden in the viewport
        {"expect_rendered_objects", {1, 1, "n"}},   // the viewport's renderer has N objects
        {"expect_modal", {1, 1, ""}},         // yes | no: a G / R / S transform is in progress
        {"quit", {0, 0, ""}},
    };
    return table;
}

}  // namespace

bool parseFloat(const std::string& s, float* out) {
    if (s.empty()) return false;
    char* end = nullptr;
    const float v = std::strtof(s.c_str(), &end);
    if (end != s.c_str() + s.size()) return false;
    *out = v;
    return true;
}

bool parseInt(const std::string& s, int* out) {
    int v = 0;
    auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || ptr != s.data() + s.size()) return false;
    *out = v;
    return true;
}

ScriptParseResult parseScript(const std::string& text, const std::string& fileForMessages) {
    ScriptParseResult result;
    int lineNo = 0;
    size_t pos = 0;
    while (pos <= text.size()) {
        size_t eol = text.find('\n', pos);
        if (eol == std::string::npos) eol = text.size();
        std::string line = text.substr(pos, eol - pos);
        pos = eol + 1;
        ++lineNo;
        std::vector<std::string> words;
        std::string word;
        bool inQuotes = false, hasWord = false;
        for (size_t i = 0; i < line.size(); ++i) {
            const char c = line[i];
            if (inQuotes) {
                if (c == '"') inQuotes = false;
                else word += c;
            } else if (c == '"') {
                inQuotes = true;
                hasWord = true;
            } else if (c == '#') {
                break;
            } else if (c == ' ' || c == '\t' || c == '\r') {
                if (hasWord) words.push_back(word);
                word.clear();
                hasWord = false;
            } else {
                word += c;
                hasWord = true;
            }
        }
        auto fail = [&](const std::string& why) {
            result.error = fileForMessages + ":" + std::to_string(lineNo) + ": " + why;
            result.lines.clear();
            return result;
        };
        if (inQuotes) return fail("unterminated quote");
        if (hasWord) words.push_back(word);
        if (words.empty()) continue;
        ScriptLine sl{lineNo, words[0], std::vector<std::string>(words.begin() + 1, words.end())};
        auto it = commands().find(sl.op);
        if (it == commands().end()) return fail("unknown command '" + sl.op + "'");
        const Signature& sig = it->second;
        const int n = static_cast<int>(sl.args.size());
        if (n < sig.minArgs || n > sig.maxArgs)
            return fail(sl.op + ": expected " + std::to_string(sig.minArgs) +
                        (sig.maxArgs != sig.minArgs ? " to " + std::to_string(sig.maxArgs) : std::string()) +
                        " arguments, got " + std::to_string(n));
        for (int i = 0; sig.numeric[i] && i < n; ++i) {
            float f = 0.0f;
            if (!parseFloat(sl.args[static_cast<size_t>(i)], &f))
                return fail(sl.op + ": argument " + std::to_string(i + 1) + ": expected a number, got '" +
                            sl.args[static_cast<size_t>(i)] + "'");
        }
        result.lines.push_back(std::move(sl));
    }
    return result;
}

}  // namespace caustic::editor
