"""The real editor under Xvfb with Mesa (issue 15): the viewport renders at its panel's size, which
follows the window when it is resized, and after an edit it reaches full resolution in steps
(1/8 -> 1/4 -> 1/2 -> 1 as samples allow), each step once the size before it had a whole sample.
The script's report lists the render size, divisor and samples at every change.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import os
import shutil
import unittest

from test_editor_e2e import CORNELL, EditorSessionCase, run_editor

SCRIPT = """
viewport panel
wait_samples 1
report big.json
window_size 900 560
wait_samples 1
report small.json
record_sizes
select object "small box"
translate 0.1 0 0
wait_samples 1
report edit.json
quit
"""


class EditorViewportSize(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-viewport-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))   # 256 x 256
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(SCRIPT)
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_1_session_succeeds(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)

    def test_2_render_size_follows_the_panel(self):
        big, small = self.load("big.json"), self.load("small.json")
        for r in (big, small):
            w, h, divisor, _ = r["viewport_sizes"][-1]
            self.assertEqual(divisor, 1)
            self.assertEqual([w, h], r["viewport_resolution"])
            self.assertEqual(w, h)                      # the square output frame fitted into the panel
            self.assertEqual([r["width"], r["height"]], [256, 256])   # the output resolution stays
        self.assertGreater(big["viewport_resolution"][0], 256)       # sharper than the output: the panel's pixels
        self.assertLess(small["viewport_resolution"][0], big["viewport_resolution"][0] - 50)   # the window shrank

    def test_3_edit_refines_in_steps_to_full_resolution(self):
        sizes = self.load("edit.json")["viewport_sizes"]
        full = self.load("edit.json")["viewport_resolution"]
        # From the coarsest size after the edit on (while the edit is fresh, the preview may get
        # coarser still if a sample does not fit the frame).
        coarsest = max(s[2] for s in sizes)
        first = max(i for i, s in enumerate(sizes) if s[2] == coarsest)
        steps = sizes[first:]
        divisors = [s[2] for s in steps]
        self.assertGreater(len(divisors), 1, sizes)
        self.assertEqual(divisors[-1], 1, sizes)
        self.assertEqual(steps[-1][:2], full, sizes)
        for a, b in zip(divisors, divisors[1:]):
            self.assertEqual(b * 2, a, sizes)           # by halves, never skipping back to coarse
        for s in steps[:-1]:
            self.assertGreaterEqual(s[3], 1, sizes)     # each step once the size before had a whole sample


if __name__ == "__main__":
    unittest.main()
