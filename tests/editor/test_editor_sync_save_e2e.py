"""The real editor under Xvfb with Mesa: the viewport never shows a scene that no longer exists
without saying so, and Save is honest (issue 41, items 1, 2 and 5).

EditorLastGoodScene: scenes/dof.json; the floor's albedo texture typed as a missing file (the
renderer refuses the scene, the viewport shows the last good one and says so); 8 of 10 objects
deleted, the floor among them (still refused: the floor's material names the missing file); the
texture field cleared on the now unused material: the renderer must then have the 2 objects (it
kept rendering all 10 and converged before). Then Save: of a refused scene it asks first and
quotes the reason (Cancel writes nothing; "Save anyway" into a folder that does not exist creates
it); of a renderable scene into a missing folder it asks to create the folder. Batch mode then
refuses the first saved file and renders the second, as the prompts said.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import json
import os
import shutil
import subprocess
import unittest

from test_editor_e2e import BIN, SOURCE_DIR, EditorSessionCase, run_editor

DOF = os.path.join(SOURCE_DIR, "scenes", "dof.json")

SCRIPT = """
viewport output
set_samples 64
wait_samples 1
expect_viewport_scene current
select material floor
set_texture albedo_texture missing.png
frames 2
expect_viewport_scene last_good
expect_error missing.png
expect_rendered_objects 10
screenshot last-good.png
# Delete 8 of the 10 objects, the floor first.
focus viewport
select object floor
key Delete
select object near
key Delete
select object glass
key Delete
select object far
key Delete
select object "lamp 1"
key Delete
select object "lamp 2"
key Delete
select object "lamp 4"
key Delete
select object "lamp 5"
key Delete
frames 2
expect_count objects 2
expect_viewport_scene last_good
expect_rendered_objects 10
# The texture cleared on the floor material, which no object uses now.
select material floor
set_texture albedo_texture ""
frames 2
expect_viewport_scene current
expect_rendered_objects 2
wait_samples 2
write_image after-fix.png
# Save of a refused scene asks first, with the reason.
set_texture albedo_texture missing.png
frames 2
expect_viewport_scene last_good
save refused.json
expect_save_prompt missing.png
answer_save cancel
expect_save_prompt no
expect_modified yes
save new/folder/refused.json
expect_save_prompt missing.png
expect_save_prompt new/folder
answer_save save
expect_save_prompt no
expect_modified no
# A renderable scene into a missing folder: the prompt asks to create it, nothing else.
set_texture albedo_texture ""
frames 2
expect_viewport_scene current
save other/ok.json
expect_save_prompt other
answer_save save
expect_modified no
quit
"""


class EditorLastGoodScene(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-sync-")
        shutil.copy(DOF, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_cancel_writes_nothing(self):
        self.assertFalse(os.path.exists(self.path("refused.json")))

    def test_3_saved_files_do_what_the_prompts_said(self):
        refused = self.path("new/folder/refused.json")
        ok = self.path("other/ok.json")
        self.assertTrue(os.path.exists(refused))
        self.assertTrue(os.path.exists(ok))
        self.assertEqual(len(self.load("other/ok.json")["objects"]), 2)
        batch = [BIN, "--scene", refused, "--set", "render.samples=1", "--output", self.path("out")]
        r = subprocess.run(batch, capture_output=True, text=True, timeout=600)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("missing.png", r.stderr)
        batch = [BIN, "--scene", ok, "--set", "render.samples=1", "--output", self.path("out")]
        r = subprocess.run(batch, capture_output=True, text=True, timeout=600)
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_4_screenshot_shows_the_bar(self):
        # The red bar over the viewport's top edge: many strongly red pixels in the screenshot.
        rows = self.image("last-good.png")
        red = sum(1 for row in rows for (r, g, b) in row if r > 100 and g < 40 and b < 40)
        self.assertGreater(red, 2000)


NEW_SCENE_SCRIPT = """
new_scene
viewport output
expect_count objects 1
expect_count lights 1
add_object sphere
add_light point
expect_count lights 2
import_mesh {glb}
wait_import
expect_count objects 3
expect_material leaf ""
select object leaf
set_samples 16
wait_samples 16
write_image new-scene.png
screenshot new-scene-window.png
save starter.json
quit
"""


class EditorNewScene(EditorSessionCase):
    """A new scene is something to build on (ground, key light, camera at eye height); an import
    keeps its file's materials."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-new-")
        shutil.copy(DOF, os.path.join(cls.tmp, "scene.json"))
        glb = os.path.join(SOURCE_DIR, "tests", "data", "gltf", "leaf.glb")
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(NEW_SCENE_SCRIPT.format(glb=glb))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_the_render_shows_a_lit_ground_and_a_sky(self):
        rows = self.image("new-scene.png")
        h = len(rows)
        def mean(y0, y1):
            px = [p for row in rows[y0:y1] for p in row]
            return [sum(c[i] for c in px) / len(px) for i in range(3)]
        sky, ground = mean(0, h // 8), mean(h - h // 8, h)
        # Neither black (no light) nor blown out; the ground is lit (not the sky's colour: grey).
        self.assertGreater(sum(ground), 60)
        self.assertLess(sum(ground), 700)
        self.assertGreater(sky[2], sky[0])   # the sky is blue

    def test_3_the_saved_starter_scene(self):
        scene = self.load("starter.json")
        self.assertAlmostEqual(scene["camera"]["position"][1], 1.6, places=3)
        leaf = [o for o in scene["objects"] if o["name"] == "leaf"][0]
        self.assertEqual(leaf.get("material", ""), "")   # the file's own materials


BUILD_SCRIPT = """
viewport output
wait_samples 2
write_image white.png
expect_building no
hold_builds on
select material white
apply_preset gold
frames 20
expect_building yes
expect_restarted yes
screenshot building.png
hold_builds off
wait_samples 4
expect_building no
write_image gold.png
quit
"""


class EditorBuildsInBackground(EditorSessionCase):
    """A program build never blocks the window: with the builder held (so the build is outstanding
    however fast this machine compiles), 20 frames pass with "Building shaders..." shown; once it
    builds, the image is of the edited scene."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-builds-")
        with open(os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")) as f:
            scene = json.load(f)
        scene["render"].update(width=48, height=48)
        with open(os.path.join(cls.tmp, "scene.json"), "w") as f:
            json.dump(scene, f)
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(BUILD_SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_the_built_program_renders_the_edit(self):
        # The white walls and boxes turned gold: red over blue goes up across the image.
        def red_over_blue(name):
            px = [p for row in self.image(name) for p in row]
            return sum(p[0] for p in px) / max(1, sum(p[2] for p in px))
        self.assertGreater(red_over_blue("gold.png"), 1.3 * red_over_blue("white.png"))


if __name__ == "__main__":
    unittest.main()
