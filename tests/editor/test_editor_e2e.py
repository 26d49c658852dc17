"""The real editor under Xvfb with Mesa: a scripted session (editor/script/script.h) on the
Cornell box. Checks that frames render, that an object moved by a command appears moved in the
image, that undo restores the first image exactly, that a gizmo-style drag is one undo step, that a
broken scene is refused with its JSON path while the current scene stays, that the saved scene
renders in batch mode to the same image, and that a screenshot of the whole window is written.
EditorDenoise: viewport denoising (Open Image Denoise on a worker thread) makes flat walls smooth
in the written image and in the window, keeps the brightness, and is never shown after an edit.
EditorCrashRecovery: autosave, a simulated crash, and recovery in a second session.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cli"))
from test_cli import decode_png  # noqa: E402  (the suite's small PNG reader)

BIN = os.environ.get("CAUSTIC_BIN", "")
SOURCE_DIR = os.environ.get("CAUSTIC_SOURCE_DIR", "")
CORNELL = os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")

SCRIPT = """
# Frames render.
wait_samples 4
write_image a.png
# A command moves the small box towards the middle.
select object "small box"
translate -0.3 0 0
wait_samples 4
write_image b.png
# Undo restores the first image.
undo
wait_samples 4
write_image c.png
redo
# A drag over several frames is one undo step (2: the translate and the drag).
drag 0 0.2 0 6
expect_undo_steps 2
# A broken scene is refused with its JSON path; the current scene stays.
open broken.json
expect_error objects[0].material
save moved.json
wait_samples 4
write_image d.png
snapshot
compare on
frames 2
screenshot window.png
report report.json
quit
"""


def read_png(path):
    with open(path, "rb") as f:
        ihdr, rows = decode_png(f.read())
    return ihdr, rows


def diff_stats(rows_a, rows_b):
    """(mean absolute difference per channel, fraction of pixels that differ, mean x of those)."""
    total, changed, xs, n = 0, 0, 0, 0
    for ra, rb in zip(rows_a, rows_b):
        for x, (pa, pb) in enumerate(zip(ra, rb)):
            d = sum(abs(p - q) for p, q in zip(pa, pb))
            total += d
            n += 1
            if d > 30:
                changed += 1
                xs += x
    return total / (3.0 * n), changed / float(n), (xs / changed if changed else -1)


# Limits that catch a hang, not slowness: the scripts wait for events (samples, imports, the
# denoiser), and a loaded machine only makes them come later. The tests fail on wrong results.
EDITOR_TIMEOUT = 2400


def xvfb_run(argv, env, timeout, screen, status_dir):
    """argv under xvfb-run on a screen of that size (WxHxD), with argv's own exit status.

    A shell between xvfb-run and argv writes that status to a file in status_dir: xvfb-run
    returns 5 instead of its command's status when removing its temporary folder fails after the
    command ended (CI saw that once, after the crash session's exit 3), and that is not the
    editor's doing. Without the file (Xvfb never started) xvfb-run's status stands."""
    fd, status_file = tempfile.mkstemp(prefix="exit-status-", dir=status_dir)
    os.close(fd)
    os.unlink(status_file)
    record = '"$@"; status=$?; echo "$status" > "$0"; exit "$status"'
    run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 " + screen, "sh", "-c", record, status_file] + argv,
                         capture_output=True, text=True, env=env, timeout=timeout)
    if os.path.exists(status_file):
        with open(status_file) as f:
            text = f.read().strip()
        os.unlink(status_file)
        if text and run.returncode != int(text):
            run.stderr += "(xvfb-run exited %d; the command's own status %s is the one checked)\n" % (run.returncode, text)
            run.returncode = int(text)
    return run


def run_editor(tmp, script_name, scene, extra_env=None, timeout=EDITOR_TIMEOUT):
    """One scripted editor session under xvfb-run; config (recent files, autosave) in tmp/home."""
    env = dict(os.environ)
    env.update(CAUSTIC_EDITOR_SCRIPT=os.path.join(tmp, script_name),
               CAUSTIC_EDITOR_HOME=os.path.join(tmp, "home"),
               CAUSTIC_EDITOR_WINDOW="1280x720", LP_NUM_THREADS="2")
    env.update(extra_env or {})
    return xvfb_run([BIN, scene], env, timeout, "1280x720x24", tmp)


class EditorSessionCase(unittest.TestCase):
    """What the editor's end-to-end test classes share: a temporary folder (kept with
    CAUSTIC_KEEP_E2E=1), and reading what the sessions wrote there."""

    @classmethod
    def make_tmp(cls, prefix):
        if not BIN or not os.path.exists(BIN):
            raise RuntimeError("CAUSTIC_BIN must name the caustic executable")  # fail, never skip
        cls.tmp = tempfile.mkdtemp(prefix=prefix)

    @classmethod
    def tearDownClass(cls):
        if os.environ.get("CAUSTIC_KEEP_E2E"):
            print("kept", cls.tmp, file=sys.stderr)
        else:
            shutil.rmtree(cls.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def image(self, name):
        return read_png(self.path(name))[1]

    def load(self, name):
        with open(self.path(name)) as f:
            return json.load(f)


class EditorEndToEnd(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-e2e-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "broken.json"), "w") as f:
            f.write('{"version": 1, "objects": [{"shape": "sphere", "material": "nope"}]}')
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)
        # The broken scene's error named the file and the JSON path.
        self.assertIn("broken.json", self.editor.stderr)
        self.assertIn("objects[0].material", self.editor.stderr)

    def test_2_moved_object_appears_moved_and_undo_restores(self):
        _, a = read_png(self.path("a.png"))
        _, b = read_png(self.path("b.png"))
        _, c = read_png(self.path("c.png"))
        self.assertEqual(len(a), 256)
        self.assertEqual(a, c, "undo did not restore the first image exactly")
        mean, changed, mean_x = diff_stats(a, b)
        # The box moved: a clear region changed (not noise over the whole image), and it is the
        # small box's region, right of the middle before the move.
        self.assertGreater(changed, 0.02, "the move is not visible")
        self.assertLess(changed, 0.5, "too much of the image changed for one moved box")
        self.assertGreater(mean_x, 100)

    def test_3_saved_scene_renders_the_same_in_batch(self):
        with open(self.path("moved.json")) as f:
            saved = json.load(f)
        box = [o for o in saved["objects"] if o["name"] == "small box"][0]
        self.assertAlmostEqual(box["transform"]["translate"][0], 0.035, places=4)
        self.assertAlmostEqual(box["transform"]["translate"][1], -0.5, places=4)
        out = os.path.join(self.tmp, "batch")
        r = subprocess.run([BIN, "--scene", self.path("moved.json"), "--samples", "4", "--output", out],
                           capture_output=True, text=True, timeout=EDITOR_TIMEOUT, env=dict(os.environ, LP_NUM_THREADS="2"))
        self.assertEqual(r.returncode, 0, r.stderr)
        _, batch = read_png(os.path.join(out, "moved.png"))
        _, editor = read_png(self.path("d.png"))
        mean, changed, _ = diff_stats(batch, editor)
        # Same scene, seed and samples: the same image (statistically; in practice identical).
        self.assertLess(mean, 0.5)
        self.assertLess(changed, 0.001)

    def test_4_window_screenshot(self):
        # The whole window: the panels around a viewport that shows the render the right way round
        # (the red wall left of the green one, the light near the top), as the written image d.png
        # shows it. Colours are tone mapped (ACES, sRGB), so the walls are muted: the red wall is
        # about (152, 76, 73), the green (96, 122, 76), the panels (81, 81, 81).
        def is_red(px):
            return px[0] > 80 and px[0] > 1.5 * px[1] and px[0] > 1.5 * px[2]

        def is_green(px):
            return px[1] > 60 and px[1] > 1.15 * px[0] and px[1] > 1.3 * px[2]

        ihdr, rows = read_png(self.path("window.png"))
        self.assertEqual((ihdr["width"], ihdr["height"]), (1280, 720))
        self.assertEqual(len(rows), 720)
        red = [(x, y) for y, row in enumerate(rows) for x, px in enumerate(row) if is_red(px)]
        green = [(x, y) for y, row in enumerate(rows) for x, px in enumerate(row) if is_green(px)]
        self.assertGreater(len(red), 10000, "no red wall in the window")
        self.assertGreater(len(green), 10000, "no green wall in the window")
        red_x = sum(x for x, _ in red) / len(red)
        green_x = sum(x for x, _ in green) / len(green)
        self.assertLess(red_x + 200, green_x, "the viewport is mirrored: red wall at x %.0f, green at %.0f" % (red_x, green_x))
        # The light: near-white pixels between the walls, most of them in the top quarter of the
        # walls' height (the error dialog's text is lower down).
        top, bottom = min(y for _, y in red + green), max(y for _, y in red + green)
        light = [(x, y) for y in range(top, bottom + 1) for x, px in enumerate(rows[y])
                 if min(px) >= 235 and red_x < x < green_x]
        upper = [y for _, y in light if y < top + 0.25 * (bottom - top)]
        self.assertGreater(len(upper), 500, "the light is not visible near the top of the viewport")
        # The written image has the same layout.
        _, d = read_png(self.path("d.png"))
        d_red = [x for row in d for x, px in enumerate(row) if is_red(px)]
        d_green = [x for row in d for x, px in enumerate(row) if is_green(px)]
        self.assertLess(sum(d_red) / len(d_red), 110)
        self.assertGreater(sum(d_green) / len(d_green), 146)
        # Around the viewport: the panels (ImGui's grey), not a blank or black window.
        panel = sum(1 for row in rows for (r, g, b) in row if 60 <= r <= 100 and abs(r - g) < 8 and abs(g - b) < 8)
        self.assertGreater(panel, 0.1 * 1280 * 720, "no panels around the viewport")
        self.assertGreater(len(set(px for row in rows[::8] for px in row[::8])), 1000, "the window is nearly uniform")

    def test_5_report(self):
        with open(self.path("report.json")) as f:
            report = json.load(f)
        self.assertGreater(report["rendering_frames"], 0)
        self.assertGreater(len(report["edit_to_frame_ms"]), 0)


def neighbour_noise(rows, x0, y0, x1, y1):
    """Mean absolute difference between horizontal and vertical neighbours (8-bit, per channel)
    over the box [x0, x1) x [y0, y1): high for a noisy flat region, low for a smooth one."""
    total, n = 0, 0
    for y in range(y0, y1):
        for x in range(x0, x1):
            p, r, d = rows[y][x], rows[y][x + 1], rows[y + 1][x]
            total += sum(abs(a - b) for a, b in zip(p, r)) + sum(abs(a - b) for a, b in zip(p, d))
            n += 6
    return total / float(n)


def mean_srgb_linear(rows):
    """The image's mean linear value (sRGB decoded), over all pixels and channels."""
    lut = [((v / 255.0) / 12.92) if v <= 10 else (((v / 255.0) + 0.055) / 1.055) ** 2.4 for v in range(256)]
    total, n = 0.0, 0
    for row in rows:
        for px in row:
            total += lut[px[0]] + lut[px[1]] + lut[px[2]]
            n += 3
    return total / n


# Flat regions of the Cornell box at 256 x 256: the back wall above the boxes, and the left
# (red) wall's lower part, away from the edges.
BACK_WALL = (96, 40, 160, 80)
RED_WALL = (14, 140, 34, 200)
WINDOW_BACK_WALL = (560, 170, 700, 255)

DENOISE_SCRIPT = """
wait_samples 4
expect_denoised no
write_image raw.png
# Denoise now: the worker runs OIDN; the viewport shows the result once it is back.
denoise
expect_denoised yes
write_image denoised.png
screenshot window_denoised.png
# Show raw: the live render again (the same bytes as before).
show_raw on
expect_denoised no
write_image raw_again.png
screenshot window_raw.png
show_raw off
expect_denoised yes
# More samples: the denoised image is out of date and the live render is shown.
wait_samples 16
expect_denoised no
write_image raw16.png
# Automatic: denoise when the target (here the script's sample cap) is reached.
denoise_auto on
wait_denoised
write_image denoised16.png
denoise_auto off
# An edit restarts accumulation: the denoised image is never shown for the new one.
select object "small box"
translate -0.3 0 0
wait_samples 4
frames 3
expect_denoised no
write_image moved_raw.png
screenshot window.png
# Denoise when idle (a person's session: idle pacing on): denoised at 4 spp or more, and that
# image stays shown while the render goes on (here to 24 spp, denoised again at 16).
idle on
denoise_idle on
uncap
wait_samples 8
wait_denoised 300
expect_denoised yes
uncap
wait_samples 24
expect_denoised yes
write_image idle_denoised.png
denoise_idle off
frames 2
expect_denoised no
quit
"""


class EditorDenoise(EditorSessionCase):
    """Viewport denoising (Open Image Denoise on a worker thread) in the real editor."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-denoise-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(DENOISE_SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_denoised_is_smoother_and_as_bright(self):
        raw, den = self.image("raw.png"), self.image("denoised.png")
        for region in (BACK_WALL, RED_WALL):
            n_raw, n_den = neighbour_noise(raw, *region), neighbour_noise(den, *region)
            # 4 spp on a flat wall: the raw neighbours differ a lot, the denoised ones hardly.
            self.assertGreater(n_raw, 4.0, "the raw 4-spp render is not noisy? region %s" % (region,))
            self.assertLess(n_den * 4.0, n_raw, "not denoised: region %s noise %.2f -> %.2f" % (region, n_raw, n_den))
        # The brightness stays: against the raw image and against a 64-spp render.
        m_raw, m_den, m_16 = mean_srgb_linear(raw), mean_srgb_linear(den), mean_srgb_linear(self.image("raw16.png"))
        self.assertLess(abs(m_den / m_raw - 1.0), 0.05, "mean %.4f -> %.4f" % (m_raw, m_den))
        self.assertLess(abs(m_den / m_16 - 1.0), 0.05, "mean %.4f vs 16 spp %.4f" % (m_den, m_16))

    def test_3_the_viewport_shows_the_denoised_image(self):
        # The window itself (not only write_image): the back wall in the viewport, where the
        # default layout puts the fitted 256 x 256 image in a 1280 x 720 window.
        den, raw = self.image("window_denoised.png"), self.image("window_raw.png")
        n_den, n_raw = neighbour_noise(den, *WINDOW_BACK_WALL), neighbour_noise(raw, *WINDOW_BACK_WALL)
        self.assertGreater(n_raw, 2.0, "the viewport's raw image is not noisy: is the region on the image?")
        self.assertLess(n_den * 4.0, n_raw, "the viewport does not show the denoised image: %.2f vs raw %.2f" % (n_den, n_raw))

    def test_4_show_raw_shows_the_live_render(self):
        self.assertEqual(self.image("raw.png"), self.image("raw_again.png"))

    def test_5_automatic_denoise_at_target(self):
        raw16, den16 = self.image("raw16.png"), self.image("denoised16.png")
        self.assertLess(neighbour_noise(den16, *BACK_WALL) * 3.0, neighbour_noise(raw16, *BACK_WALL))

    def test_6_an_edit_shows_the_raw_render_again(self):
        moved = self.image("moved_raw.png")
        # Noisy again (4 spp, not denoised) and different from the unmoved render.
        self.assertGreater(neighbour_noise(moved, *BACK_WALL), 4.0)
        self.assertNotEqual(moved, self.image("raw.png"))

    def test_7_denoised_when_idle_while_the_render_goes_on(self):
        den = self.image("idle_denoised.png")
        self.assertLess(neighbour_noise(den, *BACK_WALL) * 3.0, neighbour_noise(self.image("moved_raw.png"), *BACK_WALL))


SESSION_1 = """
# Opened on the Cornell box: move the small box, let the periodic autosave write it, crash.
select object "small box"
translate -0.3 0 0
wait_samples 4
write_image moved.png
expect_modified yes
autosave on
wait_autosave
crash
write_image never.png
"""

SESSION_2 = """
# Started on the original file: the autosave is offered, recovered, rendered.
expect_recovery_offered
recover
expect_modified yes
wait_samples 4
write_image recovered.png
quit
"""

ORIGINAL = """
wait_samples 4
write_image original.png
quit
"""


class EditorCrashRecovery(EditorSessionCase):
    """Autosave and crash recovery through the real window: session 1 edits, autosaves (the
    periodic timer, shortened with CAUSTIC_EDITOR_AUTOSAVE_SECONDS) and crashes; session 2 on
    the same config folder is offered the autosave, recovers it, and renders the edited scene."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-recovery-")
        cls.scene = os.path.join(cls.tmp, "scene.json")
        shutil.copy(CORNELL, cls.scene)
        with open(cls.scene) as f:
            cls.scene_text = f.read()
        for name, text in (("session1.txt", SESSION_1), ("session2.txt", SESSION_2), ("original.txt", ORIGINAL)):
            with open(os.path.join(cls.tmp, name), "w") as f:
                f.write(text)
        fast = {"CAUSTIC_EDITOR_AUTOSAVE_SECONDS": "0.5"}
        cls.session1 = run_editor(cls.tmp, "session1.txt", cls.scene, fast)
        autosave = os.path.join(cls.tmp, "home", "autosave.json")
        cls.autosave_after_crash = os.path.exists(autosave)
        cls.session2 = run_editor(cls.tmp, "session2.txt", cls.scene, fast)
        # The original file, in a separate config folder (no autosave there).
        cls.original = run_editor(cls.tmp, "original.txt", cls.scene, {"CAUSTIC_EDITOR_HOME": os.path.join(cls.tmp, "home-2")})

    def test_1_session_1_crashes_and_leaves_the_autosave(self):
        self.assertEqual(self.session1.returncode, 3, self.session1.stderr)
        self.assertIn("crash", self.session1.stderr)
        self.assertTrue(self.autosave_after_crash, "no autosave.json after the crash")
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "never.png")), "the script went on after crash")
        with open(os.path.join(self.tmp, "home", "autosave.owner")) as f:
            self.assertEqual(f.read().strip(), self.scene)
        with open(self.scene) as f:
            self.assertEqual(f.read(), self.scene_text, "the crash changed the scene file")

    def test_2_session_2_recovers_the_moved_scene(self):
        self.assertEqual(self.session2.returncode, 0, self.session2.stderr)
        self.assertEqual(self.original.returncode, 0, self.original.stderr)
        moved, recovered, original = self.image("moved.png"), self.image("recovered.png"), self.image("original.png")
        mean, changed, _ = diff_stats(moved, recovered)
        self.assertLess(mean, 0.5, "the recovered scene renders differently from the moved one")
        self.assertLess(changed, 0.001)
        _, changed, _ = diff_stats(original, recovered)
        self.assertGreater(changed, 0.02, "the recovered image is the original one: the move was lost")
        with open(self.scene) as f:
            self.assertEqual(f.read(), self.scene_text, "recovery wrote the scene file (it must stay unsaved)")


CORRUPT_AUTOSAVE = """
# Started with an autosave that cannot be read: the editor says so and goes on with the scene.
wait_samples 4
write_image started.png
quit
"""


class EditorCorruptAutosave(EditorSessionCase):
    """An autosave cut short (as a crash mid-write of another tool or a full disk leaves it): the
    editor names the file and what is wrong with it, keeps it aside and opens the scene as usual;
    the clean exit does not remove it."""

    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-corrupt-autosave-")
        cls.scene = os.path.join(cls.tmp, "scene.json")
        shutil.copy(CORNELL, cls.scene)
        home = os.path.join(cls.tmp, "home")
        os.makedirs(home)
        cls.autosave = os.path.join(home, "autosave.json")
        with open(CORNELL) as f:
            cls.cut = f.read()[:300]
        with open(cls.autosave, "w") as f:
            f.write(cls.cut)
        with open(os.path.join(home, "autosave.owner"), "w") as f:
            f.write(cls.scene + "\n")
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(CORRUPT_AUTOSAVE)
        cls.session = run_editor(cls.tmp, "script.txt", cls.scene)

    def test_the_autosave_is_reported_and_kept(self):
        self.assertEqual(self.session.returncode, 0, self.session.stderr)
        self.assertIn("the autosave %s could not be read" % self.autosave, self.session.stderr)
        self.assertIn(self.autosave + ":", self.session.stderr)   # the parser's place in it
        kept = os.path.join(self.tmp, "home", "autosave.unreadable-1.json")
        self.assertIn("kept as " + kept, self.session.stderr)
        with open(kept) as f:
            self.assertEqual(f.read(), self.cut)
        self.assertTrue(os.path.exists(os.path.join(self.tmp, "home", "autosave.unreadable-1.owner")))
        self.assertEqual(len(self.image("started.png")), 256, "the editor did not go on to render the scene")


if __name__ == "__main__":
    unittest.main()
