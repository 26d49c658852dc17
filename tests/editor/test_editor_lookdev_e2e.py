"""The real editor under Xvfb with Mesa (issue 15, lookdev): multi-selection (Ctrl+click's
toggle), one material assigned to every selected object in one undo step, New material from the
preset library and Make unique, and the material preview ball: a second, small film rendered by
the same integrator that shows the selected material (matte white, then gold) on a sphere over a
checker floor, following the edit. The inspector is screenshotted with the preview open.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import json
import os
import shutil
import unittest

from test_editor_e2e import CORNELL, SOURCE_DIR, EditorSessionCase, run_editor

SCRIPT = """
wait_samples 1
select object "small box"
select_add object "large box"
expect_selected 2
assign_material red
expect_material "small box" red
expect_material "large box" red
expect_material floor white
expect_undo_steps 1
undo
expect_material "small box" white
expect_material "large box" white
expect_selected 2
redo
# New material from the library for both boxes: one step more.
new_material gold
expect_material "small box" gold
expect_material "large box" gold
expect_count materials 4
expect_undo_steps 2
# Ctrl+click on a selected one takes it out.
select_add object "small box"
expect_selected 1
# Make unique: the floor gets its own copy of the white the walls share.
select object floor
make_unique
expect_material floor "white 2"
expect_material back white
expect_count materials 5
expect_undo_steps 3
save saved.json
# The preview ball, of the floor's material (matte white), then the same material as gold.
preview_lighting studio
select material "white 2"
wait_preview 8
write_preview preview-white.png
apply_preset gold
wait_preview 8
write_preview preview-gold.png
screenshot inspector.png
# A translucent preset: the surface's subsurface (a random walk inside the ball), with its
# Subsurface section in the inspector.
apply_preset jade
wait_preview 8
write_preview preview-jade.png
screenshot inspector-jade.png
apply_preset gold
# Saved camera views: store, move away, recall (one undo step) gives the camera back.
select camera
expect_no_focus_overlay
store_view front
orbit 30 10
recall_view front
expect_views 1
save camera.json
# The focus-plane overlay: focused on the back wall (4.9 from the camera), it marks much of it.
set_focus 4.9
expect_focus_overlay 200
screenshot focus.png
set_focus 40
expect_focus_overlay 0
# F5 reloads every program, the preview's too: shaders whose every sample is dark red.
select material red
wait_preview 8
shader_dir red-shaders
key F5
wait_preview 8
write_preview preview-after-reload.png
wait_samples 4
write_image viewport-after-reload.png
quit
"""


def mean_rgb(rows, x0, y0, x1, y1):
    n, acc = 0, [0.0, 0.0, 0.0]
    for y in range(y0, y1):
        for x in range(x0, x1):
            for c in range(3):
                acc[c] += rows[y][x][c]
            n += 1
    return [a / n for a in acc]


class EditorLookdev(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-lookdev-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SCRIPT)
        # The shaders the script reloads (F5): the film adds (0.5, 0, 0) for every sample.
        red = os.path.join(cls.tmp, "red-shaders")
        shutil.copytree(os.path.join(SOURCE_DIR, "shaders"), red)
        film = os.path.join(red, "integrator", "film.glsl")
        with open(film) as f:
            text = f.read()
        assert "p.sum += vec4(L, 1.0);" in text, film
        with open(film, "w") as f:
            f.write(text.replace("p.sum += vec4(L, 1.0);", "p.sum += vec4(0.5, 0.0, 0.0, 1.0);"))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_saved_materials(self):
        scene = self.load("saved.json")
        by_name = {o["name"]: o["material"] for o in scene["objects"]}
        self.assertEqual(by_name["small box"], "gold")
        self.assertEqual(by_name["large box"], "gold")
        self.assertEqual(by_name["floor"], "white 2")
        self.assertEqual(by_name["back"], "white")
        materials = {m["name"]: m for m in scene["materials"]}
        self.assertEqual(materials["gold"]["type"], "conductor")
        self.assertEqual(materials["gold"]["metal"], "gold")
        white, copy = dict(materials["white"]), dict(materials["white 2"])
        white.pop("name"), copy.pop("name")
        self.assertEqual(white, copy)

    def test_3_preview_shows_the_material_and_follows_the_edit(self):
        white = self.image("preview-white.png")
        gold = self.image("preview-gold.png")
        self.assertEqual((len(white), len(white[0])), (128, 128))
        # The ball fills the middle of the image.
        w = mean_rgb(white, 54, 44, 74, 64)
        g = mean_rgb(gold, 54, 44, 74, 64)
        self.assertGreater(sum(w), 60, w)                # lit
        self.assertLess(abs(w[0] - w[2]), 0.15 * w[0] + 4, w)   # white is neutral
        self.assertGreater(g[0], 1.3 * g[2] + 4, g)      # gold: red well above blue
        j = mean_rgb(self.image("preview-jade.png"), 54, 44, 74, 64)
        self.assertGreater(j[1], 1.2 * max(j[0], j[2]) + 4, j)  # jade: green, lit through its walk
        # The checker floor (the bottom rows): alternating light and dark tiles.
        row = white[120]
        lum = [sum(p) for p in row]
        self.assertGreater(max(lum) - min(lum), 120, lum)

    def test_5_reloaded_shaders_reach_the_viewport_and_the_preview(self):
        # Before the fix the preview kept its own renderer with the old shaders: a lit ball.
        for name in ("preview-after-reload.png", "viewport-after-reload.png"):
            rows = self.image(name)
            r, g, b = mean_rgb(rows, 0, 0, len(rows[0]), len(rows))
            self.assertGreater(r, 100, (name, r, g, b))
            self.assertLess(g, 5, (name, r, g, b))
            self.assertLess(b, 5, (name, r, g, b))

    def test_4_recalled_view_is_the_stored_camera_and_is_kept(self):
        with open(CORNELL) as f:
            original = json.load(f)["camera"]
        camera = self.load("camera.json")["camera"]
        for key in ("position", "look_at", "up"):
            for a, b in zip(camera[key], original[key]):
                self.assertAlmostEqual(a, b, places=4)
        views = self.load(os.path.join("home", "views.json"))["scenes"]
        by_file = {os.path.basename(k): [v["name"] for v in stored] for k, stored in views.items()}
        # Stored while the scene was saved.json (the script saved it as that earlier), then
        # carried to camera.json by the Save As after it.
        self.assertEqual(by_file["saved.json"], ["front"])
        self.assertEqual(by_file["camera.json"], ["front"])


PICKER_SCRIPT = """
wait_samples 1
expect_picker_lists albedo_texture local.png
expect_picker_lists albedo_texture tex/checker.png
expect_picker_lists environment sky.hdr
select material white
pick_file albedo_texture tex/checker.png
pick_file environment sky.hdr
wait_samples 1
save saved.json
quit
"""


class EditorFilePicker(EditorSessionCase):
    """The inspector's file picker: the scene's folder and the assets folder beside it (as
    scenes/ and assets/ in this repository), and paths stored relative to the scene."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-picker-")
        scenes, assets = os.path.join(cls.tmp, "scenes"), os.path.join(cls.tmp, "assets")
        os.makedirs(os.path.join(assets, "tex"))
        os.makedirs(scenes)
        shutil.copy(CORNELL, os.path.join(scenes, "scene.json"))
        tile = os.path.join(SOURCE_DIR, "assets", "tiles", "albedo.png")
        shutil.copy(tile, os.path.join(assets, "tex", "checker.png"))
        shutil.copy(tile, os.path.join(scenes, "local.png"))
        shutil.copy(os.path.join(SOURCE_DIR, "assets", "sky.hdr"), os.path.join(assets, "sky.hdr"))
        with open(os.path.join(scenes, "script.txt"), "w") as f:
            f.write(PICKER_SCRIPT)
        cls.editor = run_editor(scenes, "script.txt", os.path.join(scenes, "scene.json"),
                                extra_env={"CAUSTIC_ASSETS_DIR": ""})

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_paths_are_relative_to_the_scene(self):
        scene = self.load(os.path.join("scenes", "saved.json"))
        white = [m for m in scene["materials"] if m["name"] == "white"][0]
        self.assertEqual(white["albedo_texture"], "../assets/tex/checker.png")
        self.assertEqual(scene["environment"]["file"], "../assets/sky.hdr")
        self.assertTrue(os.path.exists(os.path.join(self.tmp, "scenes", white["albedo_texture"])))


BLENDER_SCRIPT = """
wait_samples 1
keymap blender
select object "small box"
focus viewport
mouse_move 0 0
# G, the mouse 60 pixels right, Enter: one undo step.
key G
expect_modal yes
mouse_move 60 0
key Enter
expect_modal no
expect_undo_steps 1
save grabbed.json
# G then Esc: nothing changes, no step.
key G
mouse_move 40 0
key Escape
expect_modal no
expect_undo_steps 1
save cancelled.json
# G, Z (Blender's up: the scene's y axis only), the mouse up and sideways, a click confirms
# (its release selects nothing: the small box stays selected).
key G
key Z
mouse_move 30 -50
mouse_click left
expect_undo_steps 2
save constrained.json
# Shift+D: a copy, grabbed; a right click cancels the move and keeps the copy.
key Shift+D
expect_count objects {m}
expect_modal yes
mouse_move 50 0
mouse_click right
expect_modal no
expect_undo_steps 3
# H hides the selection in the viewport only; Alt+H shows it again.
select object "large box"
key H
expect_hidden 1
wait_samples 1
expect_rendered_objects {n}
key Alt+H
expect_hidden 0
wait_samples 1
expect_rendered_objects {m}
# Numpad 7: the free view from the top; the saved camera stays where it was until Camera to view.
key Numpad7
save numpad7.json
key Ctrl+Alt+Numpad0
save top.json
screenshot blender.png
# View > UI scale: the monitor's (1 under Xvfb: ImGui's 13-pixel font), then 200%.
expect_font_size 13
ui_scale 2
frames 2
expect_font_size 26
screenshot scaled.png
quit
"""


class EditorBlenderKeys(EditorSessionCase):
    """The Blender-style key map driven by keys and mouse events through ImGui's input queue."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-blender-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(CORNELL) as f:
            cls.original = json.load(f)
        n = len(cls.original["objects"])
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(BLENDER_SCRIPT.format(n=n, m=n + 1))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))
        # The next session (same config folder) starts with the key map and UI scale chosen above.
        cls.layout = ""
        ini = os.path.join(cls.tmp, "home", "layout.ini")
        if os.path.exists(ini):
            with open(ini) as f:
                cls.layout = f.read()
        with open(os.path.join(cls.tmp, "again.txt"), "w") as f:
            f.write("expect_keymap blender\nexpect_font_size 26\nkeymap default\nui_scale 0\nquit\n")
        cls.again = run_editor(cls.tmp, "again.txt", os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "again-2.txt"), "w") as f:
            f.write("expect_keymap default\nexpect_font_size 13\nquit\n")
        cls.again2 = run_editor(cls.tmp, "again-2.txt", os.path.join(cls.tmp, "scene.json"))

    def test_6_key_map_and_ui_scale_are_kept_between_sessions(self):
        self.assertIn("[Caustic][Preferences]\nKeymap=blender\nUiScale=2\n", self.layout)
        self.assertIn("[Window]", self.layout)   # the layout is in the same file, written whole
        self.assertEqual(self.again.returncode, 0, self.again.stderr)
        self.assertEqual(self.again2.returncode, 0, self.again2.stderr)

    def box(self, name):
        return [o for o in self.load(name)["objects"] if o["name"] == "small box"][0]["transform"]["translate"]

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_grab_moves_right_and_escape_cancels(self):
        before = [o for o in self.original["objects"] if o["name"] == "small box"][0]["transform"]["translate"]
        grabbed = self.box("grabbed.json")
        self.assertGreater(grabbed[0], before[0] + 0.05)   # screen right is +x from this camera
        self.assertAlmostEqual(grabbed[1], before[1], places=4)
        self.assertAlmostEqual(grabbed[2], before[2], places=4)
        self.assertEqual(self.box("cancelled.json"), grabbed)

    def test_3_axis_constraint(self):
        grabbed, constrained = self.box("grabbed.json"), self.box("constrained.json")
        self.assertAlmostEqual(constrained[0], grabbed[0], places=4)
        self.assertGreater(constrained[1], grabbed[1] + 0.05)   # up the screen is +y
        self.assertAlmostEqual(constrained[2], grabbed[2], places=4)

    def test_4_numpad_top_view(self):
        # The numpad view moved the free view only (Blender's way); Camera to view moved the camera.
        self.assertEqual(self.load("numpad7.json")["camera"], self.load("constrained.json")["camera"])
        camera = self.load("top.json")["camera"]
        self.assertAlmostEqual(camera["position"][0], 0.0, places=3)
        self.assertAlmostEqual(camera["position"][2], 0.0, places=3)
        self.assertAlmostEqual(camera["position"][1], 3.9, places=3)


if __name__ == "__main__":
    unittest.main()
