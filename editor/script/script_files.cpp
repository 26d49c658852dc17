// Script commands about files and background work: open and save, images and reports, mesh
// imports, the autosave and crash recovery (docs/editor.md, "Scripts").
#include "editor/script/script_commands.h"

#include "editor/script/script_run.h"
#include "editor/ui/editor_ui.h"
#include "editor/ui/material_preview.h"
#include "editor/ui/mesh_import.h"
#include "renderer/file_util.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace caustic::editor {
namespace {

// A failure shows the error and keeps the scene; the opened scene's meshes import in the background.
ScriptStep open(ScriptContext& c) {
    openFile(c.ui, c.resolve(c.a[0]));
    c.markEdit();
    return ScriptStep::done();
}

// Until the scene being opened is adopted (or refused) [timeout s].
ScriptStep waitOpen(ScriptContext& c) {
    const double timeout = c.a.empty() ? kScriptWaitSeconds : double(c.num(0));
    return ScriptStep::doneIf(c.run.waitFor(c.ui, c.line, !c.app.meshImports->opening(), timeout, "still opening"));
}

// As Save / Save As: saves, or opens the "Save scene?" prompt (answer_save answers it).
ScriptStep save(ScriptContext& c) {
    const std::string file = c.a.empty() ? c.app.state.path : c.resolve(c.a[0]);
    std::string error;
    if (requestSave(c.ui, file, &error) == SaveResult::Failed) c.fail(error);
    return ScriptStep::done();
}

ScriptStep check(ScriptContext& c, bool ok, const std::string& why) {
    if (!ok) c.fail(why);
    return ScriptStep::done();
}

// The "Save scene?" prompt is open and says TEXT (or is not open: `no`).
ScriptStep expectSavePrompt(ScriptContext& c) {
    const SavePrompt& p = c.ui.savePrompt;
    if (c.a[0] == "no") return check(c, !p.isOpen(), "the save prompt is open for " + p.file);
    if (!p.isOpen()) return check(c, false, "no save prompt is open");
    const std::string said = p.refusedBecause + "\n" + p.missingFolder;
    return check(c, said.find(c.a[0]) != std::string::npos, "the save prompt says: " + said);
}

// Presses the prompt's Save (save) or Cancel (cancel).
ScriptStep answerSave(ScriptContext& c) {
    if (!c.ui.savePrompt.isOpen()) { c.fail("no save prompt is open"); return ScriptStep::done(); }
    answerSavePrompt(c.ui, c.a[0] == "save");
    return ScriptStep::done();
}

// What the viewport shows: the denoised image while it is shown.
ScriptStep writeImage(ScriptContext& c) {
    std::string error;
    if (!writeViewportImage(c.ui, c.resolve(c.a[0]), &error)) c.fail(error);
    return ScriptStep::done();
}

// Written after this frame is drawn (ScriptRunner::afterDraw).
ScriptStep screenshot(ScriptContext& c) {
    c.run.screenshotPending = c.resolve(c.a[0]);
    return ScriptStep::doneAfterFrames(0);
}

ScriptStep renderToFile(ScriptContext& c) {
    if (!c.run.renderStarted) {
        startRenderToFile(c.ui, c.resolve(c.a[0]));
        c.run.renderStarted = true;
        return ScriptStep::again();
    }
    if (c.app.renderToFile) return ScriptStep::again();   // still rendering
    c.run.renderStarted = false;
    return ScriptStep::done();
}

ScriptStep report(ScriptContext& c) {
    std::string error;
    if (!writeFileAtomically(c.resolve(c.a[0]), c.run.reportJson(c.ui), &error)) c.fail(error);
    return ScriptStep::done();
}

// Starts a background import; the object appears when it is ready.
ScriptStep importMesh(ScriptContext& c) {
    c.app.meshImports->importFile(c.ui, c.resolve(c.a[0]));
    return ScriptStep::done();
}

// The selected mesh object's file, through the same background import.
ScriptStep setMeshFile(ScriptContext& c) {
    const EditorState& s = c.app.state;
    const bool mesh = s.selection.kind == EntityKind::Object && s.selection.index >= 0 &&
                      static_cast<size_t>(s.selection.index) < s.scene.objects.size() &&
                      s.scene.objects[static_cast<size_t>(s.selection.index)].shape == Shape::Mesh;
    if (!mesh) { c.fail("select a mesh object first"); return ScriptStep::done(); }
    c.app.meshImports->setObjectFile(c.ui, s.selection.index, c.resolve(c.a[0]));
    return ScriptStep::done();
}

// Until every import has finished and its edit applied [timeout s].
ScriptStep waitImport(ScriptContext& c) {
    const double timeout = c.a.empty() ? kScriptWaitSeconds : double(c.num(0));
    return ScriptStep::doneIf(c.run.waitFor(c.ui, c.line, !c.app.meshImports->pending(), timeout, "still importing"));
}

// As if another program had written the file.
ScriptStep touch(ScriptContext& c) {
    std::error_code ec;
    std::filesystem::last_write_time(c.resolve(c.a[0]), std::filesystem::file_time_type::clock::now(), ec);
    if (ec) c.fail(c.resolve(c.a[0]) + ": " + ec.message());
    return ScriptStep::done();
}

ScriptStep writePreview(ScriptContext& c) {
    std::string why;
    if (!c.app.preview->writeImage(c.resolve(c.a[0]), c.ui, &why)) c.fail(why);
    return ScriptStep::done();
}

// Where the next reload (F5) reads the shaders from.
ScriptStep shaderDir(ScriptContext& c) {
    c.app.shaderDir = c.resolve(c.a[0]);
    return ScriptStep::done();
}

// Scripts never touch the user's autosave: only with $CAUSTIC_EDITOR_HOME (a test's folder).
bool autosaveAllowed(ScriptContext& c) {
    if (scriptMayUseAutosave()) return true;
    c.fail("scripts use the autosave only when $CAUSTIC_EDITOR_HOME names the config folder");
    return false;
}

ScriptStep autosave(ScriptContext& c) {
    if (!autosaveAllowed(c)) return ScriptStep::done();
    bool on = false;
    if (!c.onOff(&on)) return ScriptStep::done();
    c.run.autosave = on;
    c.app.lastAutosave = glfwGetTime();   // the interval counts from here
    return ScriptStep::done();
}

ScriptStep autosaveNow(ScriptContext& c) {
    if (!autosaveAllowed(c)) return ScriptStep::done();
    EditorUi& ui = c.ui;
    if (!ui.app.state.modified()) { c.fail("nothing to autosave: no unsaved changes"); return ScriptStep::done(); }
    std::string error;
    if (!ui.app.autosave.write(ui.app.state.scene, ui.app.state.path, &error)) { c.fail(error); return ScriptStep::done(); }
    ++ui.app.autosaveWrites;
    return ScriptStep::done();
}

// The periodic autosave has written since this line started.
ScriptStep waitAutosave(ScriptContext& c) {
    const bool first = c.run.startLine();
    if (!autosaveAllowed(c)) return ScriptStep::done();
    const double timeout = c.a.empty() ? kScriptWaitSeconds : double(c.num(0));
    if (!c.run.autosave) { c.fail("autosave is off (autosave on)"); return ScriptStep::done(); }
    if (first) c.run.countAtStart = c.app.autosaveWrites;
    if (c.app.autosaveWrites > c.run.countAtStart) return ScriptStep::done();
    if (c.run.secondsOnLine() > timeout) { c.fail("no autosave within " + std::to_string(int(timeout)) + " s"); return ScriptStep::done(); }
    return ScriptStep::again();
}

// A simulated crash: no destructors, no clean exit, so the autosave stays behind.
ScriptStep crash(ScriptContext& c) {
    std::fprintf(stderr, "caustic: script %s:%d: crash: exiting without clean-up\n", c.run.file.c_str(), c.line.line);
    std::_Exit(3);
}

ScriptStep recover(ScriptContext& c) {
    c.run.startLine();
    if (!c.run.pressed) {
        if (!c.app.recovered) { c.fail("no recovery was offered"); return ScriptStep::done(); }
        c.run.pressRecover = true;   // the prompt's "Recover" button takes it next frame
        c.run.pressed = true;
        return ScriptStep::again();
    }
    if (c.app.recovered) {
        if (c.run.secondsOnLine() > kScriptWaitSeconds) c.fail("the recovery prompt did not take the answer");
        else return ScriptStep::again();
    }
    return ScriptStep::done();
}

const ScriptCommand kCommands[] = {
    {"open", 1, 1, "", open},                          // open a scene (its meshes import in the background)
    {"wait_open", 0, 1, "n", waitOpen},                // wait until the open finished: adopted, refused or dropped [timeout s]
    {"save", 0, 1, "", save},                          // save [as file] (may open the save prompt)
    {"expect_save_prompt", 1, 1, "", expectSavePrompt},   // the save prompt is open and says TEXT; `no`: not open
    {"answer_save", 1, 1, "", answerSave},             // save | cancel: answer the save prompt
    {"write_image", 1, 1, "", writeImage},             // the film, tone mapped as in batch mode (PNG)
    {"screenshot", 1, 1, "", screenshot},              // the whole window (PNG)
    {"render_to_file", 1, 1, "", renderToFile},        // render the scene's samples and write the PNG
    {"report", 1, 1, "", report},                      // frame-time and edit-latency figures as JSON
    {"import_mesh", 1, 1, "", importMesh},             // import a model file in the background (the object appears when ready)
    {"set_mesh_file", 1, 1, "", setMeshFile},          // the selected mesh object's file, imported in the background
    {"wait_import", 0, 1, "n", waitImport},            // wait until every import finished and its edit applied [timeout s]
    {"touch", 1, 1, "", touch},                        // set a file's modification time to now (as an outside edit would)
    {"write_preview", 1, 1, "", writePreview},         // the material preview as PNG
    {"shader_dir", 1, 1, "", shaderDir},               // the folder F5 (key F5) reloads the shaders from (tests of the reload)
    {"autosave", 1, 1, "", autosave},                  // on | off: periodic autosave (needs $CAUSTIC_EDITOR_HOME)
    {"autosave_now", 0, 0, "", autosaveNow},           // write the autosave now (needs $CAUSTIC_EDITOR_HOME)
    {"wait_autosave", 0, 1, "n", waitAutosave},        // wait for the next periodic autosave [timeout s]
    {"crash", 0, 0, "", crash},                        // exit at once (status 3) without any clean-up
    {"recover", 0, 0, "", recover},                    // answer the recovery prompt with "Recover"
};

}  // namespace

std::span<const ScriptCommand> scriptFileCommands() { return kCommands; }

}  // namespace caustic::editor
