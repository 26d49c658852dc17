"""The real editor under Xvfb with Mesa: a scripted session (editor/model/script.h) on the
Cornell box. Checks that frames render, that an object moved by a command appears moved in the
image, that undo restores the first image exactly, that a gizmo-style drag is one undo step, that a
broken scene is refused with its JSON path while the current scene stays, that the saved scene
renders in batch mode to the same image, and that a screenshot of the whole window is written.

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


class EditorEndToEnd(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not BIN or not os.path.exists(BIN):
            raise RuntimeError("CAUSTIC_BIN must name the caustic executable")  # fail, never skip
        cls.tmp = tempfile.mkdtemp(prefix="caustic-editor-e2e-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(os.path.join(cls.tmp, "broken.json"), "w") as f:
            f.write('{"version": 1, "objects": [{"shape": "sphere", "material": "nope"}]}')
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SCRIPT)
        env = dict(os.environ)
        env.update(CAUSTIC_EDITOR_SCRIPT=os.path.join(cls.tmp, "script.txt"),
                   CAUSTIC_EDITOR_HOME=os.path.join(cls.tmp, "home"),
                   CAUSTIC_EDITOR_WINDOW="1280x720", LP_NUM_THREADS="2")
        cls.editor = subprocess.run(
            ["xvfb-run", "-a", "-s", "-screen 0 1280x720x24", BIN, os.path.join(cls.tmp, "scene.json")],
            capture_output=True, text=True, env=env, timeout=240)

    @classmethod
    def tearDownClass(cls):
        if os.environ.get("CAUSTIC_KEEP_E2E"):
            print("kept", cls.tmp, file=sys.stderr)
        else:
            shutil.rmtree(cls.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

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
                           capture_output=True, text=True, timeout=120, env=dict(os.environ, LP_NUM_THREADS="2"))
        self.assertEqual(r.returncode, 0, r.stderr)
        _, batch = read_png(os.path.join(out, "moved.png"))
        _, editor = read_png(self.path("d.png"))
        mean, changed, _ = diff_stats(batch, editor)
        # Same scene, seed and samples: the same image (statistically; in practice identical).
        self.assertLess(mean, 0.5)
        self.assertLess(changed, 0.001)

    def test_4_window_screenshot(self):
        ihdr, _ = read_png(self.path("window.png"))
        self.assertEqual((ihdr["width"], ihdr["height"]), (1280, 720))
        self.assertGreater(os.path.getsize(self.path("window.png")), 50_000)   # not a blank window

    def test_5_report(self):
        with open(self.path("report.json")) as f:
            report = json.load(f)
        self.assertGreater(report["rendering_frames"], 0)
        self.assertGreater(len(report["edit_to_frame_ms"]), 0)


if __name__ == "__main__":
    unittest.main()
