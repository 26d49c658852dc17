"""The real editor under Xvfb with Mesa (the bugs a new user hits first): scripted sessions on
the Cornell box. EditorDeleteKey: Del deletes the selection when the viewport or the outliner has
the keyboard (keyboard navigation made ImGui's WantCaptureKeyboard always true, so it never did),
and not when another panel does. EditorSaveAsElsewhere: the sky-spheres scene (which names
../assets/sky.hdr) saved into a sub-folder and into the parent of its folder still batch-renders,
to the same image as the original (its relative paths used to be written unchanged).
EditorNoNeedlessRestart: a new target sample count and a new, unused material keep the
accumulated image; moving an object restarts it. EditorFallbackNotice: when the integrator built
for the scene does not compile, the status bar says the general one renders it.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import json
import os
import shutil
import subprocess
import unittest

from test_editor_e2e import BIN, CORNELL, SOURCE_DIR, EditorSessionCase, diff_stats, read_png, run_editor

DELETE_SCRIPT = """
wait_samples 1
select object "small box"
# The inspector has the keys: Del is not a delete there.
focus inspector
key Delete
expect_undo_steps 0
expect_count objects {n}
# The viewport: the small box goes, one undo step.
focus viewport
key Delete
expect_undo_steps 1
expect_count objects {m}
undo
expect_count objects {n}
# The outliner, likewise.
select object "small box"
focus outliner
key Delete
expect_undo_steps 1
expect_count objects {m}
quit
"""


class EditorDeleteKey(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-delete-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(CORNELL) as f:
            n = len(json.load(f)["objects"])
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(DELETE_SCRIPT.format(n=n, m=n - 1))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_delete_key(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)


SAVE_AS_SCRIPT = """
save sub/deeper/sky.json
save up.json
quit
"""


class EditorSaveAsElsewhere(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-saveas-")
        # The session saves the scene from its own folder into tmp/sub/deeper/ and tmp/: neither
        # is where ../assets/sky.hdr resolves from scenes/.
        os.makedirs(os.path.join(cls.tmp, "sub", "deeper"))
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SAVE_AS_SCRIPT)
        cls.original = os.path.join(SOURCE_DIR, "scenes", "sky-spheres.json")
        cls.editor = run_editor(cls.tmp, "script.txt", cls.original)
        cls.renders = {}
        for name, scene in (("original", cls.original), ("deeper", os.path.join(cls.tmp, "sub", "deeper", "sky.json")),
                            ("up", os.path.join(cls.tmp, "up.json"))):
            out = os.path.join(cls.tmp, "out-" + name)
            cls.renders[name] = (subprocess.run(
                [BIN, "--scene", scene, "--samples", "2", "--set", "render.width=96", "--set", "render.height=64",
                 "--output", out], capture_output=True, text=True, timeout=1200), out)

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_saved_copies_name_the_same_map(self):
        with open(self.original) as f:
            self.assertEqual(json.load(f)["environment"]["file"], "../assets/sky.hdr")
        sky = os.path.abspath(os.path.join(SOURCE_DIR, "assets", "sky.hdr"))
        # Relative still, from the new folder.
        self.assertEqual(self.load(os.path.join("sub", "deeper", "sky.json"))["environment"]["file"],
                         os.path.relpath(sky, os.path.join(self.tmp, "sub", "deeper")))
        self.assertEqual(self.load("up.json")["environment"]["file"], os.path.relpath(sky, self.tmp))

    def test_3_copies_render_the_same_image_in_batch(self):
        for name, (run, out) in self.renders.items():
            self.assertEqual(run.returncode, 0, name + ": " + run.stderr)
        original = read_png(os.path.join(self.renders["original"][1], "sky-spheres.png"))[1]
        for name, png in (("deeper", "sky.png"), ("up", "up.png")):
            copy = read_png(os.path.join(self.renders[name][1], png))[1]
            mean, changed, _ = diff_stats(original, copy)
            self.assertLess(mean, 0.01, name)
            self.assertEqual(changed, 0.0, name)


RESTART_SCRIPT = """
wait_samples 3
mark
set_samples 300
frames 3
expect_restarted no
add_material
frames 3
expect_restarted no
expect_count materials {materials}
set_samples 2
frames 3
expect_restarted no
# The check can fail: a real edit restarts.
select object "small box"
translate 0.1 0 0
frames 3
expect_restarted yes
quit
"""


class EditorNoNeedlessRestart(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-restart-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(CORNELL) as f:
            materials = len(json.load(f)["materials"]) + 1
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(RESTART_SCRIPT.format(materials=materials))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_target_and_unused_material_keep_the_image(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)


FALLBACK_SCRIPT = """
wait_samples 1
expect_message "rendering with the general one"
quit
"""


class EditorFallbackNotice(EditorSessionCase):
    """The integrator built for the scene fails to compile (a copy of the shaders broken where only
    the scene-specialised build reads them): the general integrator renders it, and the status bar
    says so instead of only the terminal."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-fallback-")
        shaders = os.path.join(cls.tmp, "shaders")
        shutil.copytree(os.path.join(SOURCE_DIR, "shaders"), shaders)
        features = os.path.join(shaders, "scene", "features.glsl")
        with open(features) as f:
            text = f.read()
        with open(features, "w") as f:
            f.write("#ifdef CAUSTIC_MATERIALS\n#error a specialised build broken on purpose\n#endif\n" + text)
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(FALLBACK_SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"),
                                extra_env={"CAUSTIC_SHADER_DIR": shaders, "CAUSTIC_SPECIALIZE": "1"})

    def test_notice(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)
        self.assertIn("failed to build, using the general one", self.editor.stderr)


if __name__ == "__main__":
    unittest.main()
