#include "editor/script/script_runner.h"

#include "editor/script/script_commands.h"
#include "editor/ui/editor_ui.h"
#include "renderer/file_util.h"
#include "renderer/image_io.h"

#include <glad/gl.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace fs = std::filesystem;

namespace caustic::editor {

bool ScriptRunner::load(const std::string& file, std::string* error) {
    std::optional<std::string> text = readTextFile(file, error);
    if (!text) return false;
    ScriptParseResult parsed = parseScript(*text, file);
    if (!parsed.error.empty()) {
        *error = parsed.error;
        return false;
    }
    m_run.file = file;
    m_run.dir = fs::path(file).parent_path().string();
    m_run.lines = std::move(parsed.lines);
    return true;
}

void ScriptRunner::step(EditorUi& ui) {
    ScriptRun& r = m_run;
    if (r.failed) return;
    if (!r.screenshotPending.empty()) return;   // finishes after this frame is drawn
    if (r.waitFrames > 0) {
        --r.waitFrames;
        return;
    }
    // Run lines until one has to wait for frames to pass.
    while (r.next < r.lines.size() && !ui.app.quit) {
        const ScriptLine& line = r.lines[r.next];
        const ScriptCommand* command = findScriptCommand(line.op);   // the parser checked it exists
        ScriptContext c{ui, ui.app, r, line, line.args};
        const ScriptStep s = command->run(c);
        if (s.kind == ScriptStep::Kind::Again) return;
        ++r.next;
        if (s.kind == ScriptStep::Kind::DoneAfterFrames) {
            r.waitFrames = s.frames;
            return;
        }
        if (r.failed) return;
    }
    if (r.next >= r.lines.size()) ui.app.quit = true;   // a script always ends the session
}

void ScriptRunner::afterDraw(EditorUi& ui, int fbWidth, int fbHeight) {
    ScriptRun& r = m_run;
    if (r.screenshotPending.empty() || fbWidth <= 0 || fbHeight <= 0) return;
    std::vector<std::uint8_t> rgba(static_cast<size_t>(fbWidth) * fbHeight * 4), rgb(static_cast<size_t>(fbWidth) * fbHeight * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, fbWidth, fbHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    for (int y = 0; y < fbHeight; ++y)          // GL rows go bottom-up, images top-down
        for (int x = 0; x < fbWidth; ++x)
            for (int c = 0; c < 3; ++c)
                rgb[(static_cast<size_t>(y) * fbWidth + x) * 3 + c] =
                    rgba[(static_cast<size_t>(fbHeight - 1 - y) * fbWidth + x) * 4 + c];
    std::string error;
    if (!writeImage8(r.screenshotPending, fbWidth, fbHeight, rgb, {{"Software", "caustic editor"}}, &error)) {
        std::fprintf(stderr, "caustic: screenshot: %s\n", error.c_str());
        r.failed = true;
        ui.app.quit = true;
    }
    r.screenshotPending.clear();
}

void ScriptRunner::afterSwap(EditorUi& ui, double frameSeconds) { m_run.recordFrame(ui, frameSeconds); }

bool ScriptRunner::offersRecovery() const { return scriptMayUseAutosave(); }

}  // namespace caustic::editor
