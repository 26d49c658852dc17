"""Splitting a render and merging it back (issue 17): caustic --sample-range, --crop, merge,
--variant / --list-variants, sheet and compare, through the real program.

Run by ctest as "cli: split and merge" (CAUSTIC_BIN, CAUSTIC_SOURCE_DIR) in the farm's venv: EXR
files are read by app/farm/caustic_farm/exr.py (the OpenEXR bindings, numpy), not by caustic's own
image code. The images are tiny (40x24, 16 samples) with crop edges off the kernel's 8x8 tiles, so the module stays cheap.

The bound (docs/farm.md): a whole render sums a pixel's N samples one after another in float32;
a merge adds each part's float32 sum (n_i samples) in double and rounds once. Samples are
non-negative, so each float sum is within (n - 1) u of the exact sum (u = 2^-24, Higham 2002,
eq. 4.4), and a merged mean differs from the whole render's by at most (N + n_max + 2) u
relatively (the two sums' errors, the final rounding and the division). Normals can be negative:
their bound is absolute, (N + n_max + 2) u per component of a mean of unit vectors. Crops alone
change no sum, so they merge bit for bit.
"""

import json
import os
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "app", "farm"))
from caustic_farm.exr import read_exr  # noqa: E402
from test_cli import HANG_GUARD, decode_png  # noqa: E402

BIN = os.environ.get("CAUSTIC_BIN", "")
SOURCE_DIR = os.environ.get("CAUSTIC_SOURCE_DIR", "")
CORNELL = os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")
W, H, N = 40, 24, 16
BASE = ["--scene", CORNELL, "--width", str(W), "--height", str(H), "--samples", str(N)]
U = 2.0 ** -24


def run(*args, check=True):
    p = subprocess.run([BIN, *args], capture_output=True, text=True, timeout=HANG_GUARD)
    if check and p.returncode != 0:
        raise AssertionError("caustic %s failed (%d):\n%s" % (" ".join(args), p.returncode, p.stderr))
    return p


class SplitMerge(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="caustic-split-"))
        run(*BASE, "--exr", "--aovs", "--png", "--output", str(cls.tmp / "whole"))
        cls.whole = read_exr(str(cls.tmp / "whole" / "cornell-box.exr"))
        # Two sample ranges of the left crop, the right crop whole, and the left crop cut in two.
        cls.left = cls.part("parts", samples="0:8", crop="0:13,0:24")
        cls.rest = cls.part("parts", samples="8:16", crop="0:13,0:24")
        cls.right = cls.part("parts", samples="0:16", crop="13:40,0:24")
        cls.top = cls.part("parts", samples="0:16", crop="0:13,0:10")
        cls.bottom = cls.part("parts", samples="0:16", crop="0:13,10:24")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def part(cls, folder, *extra, samples=None, crop=None):
        args = list(BASE) + list(extra) + ["--output", str(cls.tmp / folder)]
        if samples:
            args += ["--sample-range", samples]
        if crop:
            args += ["--crop", crop]
        out = run(*args).stdout.split()
        assert len(out) == 1 and out[0].endswith(".exr") and ".part-" in out[0], out
        return out[0]

    def merge(self, out, parts, *extra, check=True):
        return run("merge", str(self.tmp / out), *parts, *extra, check=check)

    def test_crops_merge_bit_for_bit(self):
        parts = [self.top, self.bottom, self.right]
        # A part holds its crop's sums, each pixel's count being the range's length.
        _, pw, ph, ch = read_exr(self.right)
        self.assertEqual((pw, ph), (27, 24))
        self.assertEqual(np.unique(ch["sum.A"]).tolist(), [16.0])
        self.merge("crops/merged.exr", parts, "--aovs", "--png")
        _, w, h, merged = read_exr(str(self.tmp / "crops" / "merged.exr"))
        self.assertEqual((w, h), (W, H))
        for name in ("R", "G", "B", "albedo.R", "albedo.G", "normal.B", "raw.R"):
            self.assertTrue(np.array_equal(merged[name].view(np.uint32), self.whole[3][name].view(np.uint32)), name)
        png = lambda p: decode_png(Path(p).read_bytes())[1]
        self.assertEqual(png(self.tmp / "crops" / "merged.png"), png(self.tmp / "whole" / "cornell-box.png"))

    def test_sample_ranges_and_crops_equal_the_whole_within_the_bound(self):
        p = self.merge("ranges/merged.exr", [self.left, self.rest, self.right], "--aovs")
        self.assertIn("merged 3 parts", p.stderr)
        attrs, w, h, merged = read_exr(str(self.tmp / "ranges" / "merged.exr"))
        self.assertEqual(attrs["caustic:samples"], "16")
        self.assertEqual(attrs["caustic:sample_range"], "0:16")
        n_max = 16
        bound = (N + n_max + 2) * U
        worst = 0.0
        f64 = lambda ch, name: ch[name].astype(np.float64)
        for name in ("R", "G", "B", "albedo.R", "albedo.G", "albedo.B"):
            a, b = f64(merged, name), f64(self.whole[3], name)
            diff, m = np.abs(a - b), np.maximum(np.abs(a), np.abs(b))
            beyond = diff > bound * m
            self.assertFalse(beyond.any(), "%s: %r vs %r" % (name, a[beyond][:4], b[beyond][:4]))
            worst = max(worst, float(np.max(np.where(m > 0, diff / np.where(m > 0, m, 1.0), 0.0))))
        for name in ("normal.R", "normal.G", "normal.B"):
            self.assertLessEqual(float(np.max(np.abs(f64(merged, name) - f64(self.whole[3], name)))), bound, name)
        # The split really changed the sums' rounding somewhere (else the bound was not tested).
        self.assertGreater(np.count_nonzero(merged["R"] != self.whole[3]["R"]), 0)
        print("2 ranges x 2 crops: largest relative difference %.3g, bound %.3g" % (worst, bound))

    def test_merge_refusals_name_the_files(self):
        left, right, rest = self.left, self.right, self.rest

        def refused(parts, *needles, code=1):
            p = self.merge("refuse/bad.png", parts, check=False)
            self.assertEqual(p.returncode, code, p.stderr)
            for needle in needles:
                self.assertIn(needle, p.stderr)
            self.assertFalse((self.tmp / "refuse" / "bad.png").exists())

        seed = self.part("seed", "--seed", "7", samples="8:16", crop="0:13,0:24")
        refused([left, right, seed], "different seeds", seed, left)
        size = self.part("size", "--width", "48", samples="8:16", crop="0:13,0:24")
        refused([left, right, size], "different sizes", size)
        scene = self.part("scene", "--set", "camera.fov=30", samples="8:16", crop="0:13,0:24")
        refused([left, right, scene], "different renders", scene)
        refused([left, right, self.top], "overlap", "samples [0, 8) of pixels 0:13,0:10", left, self.top)
        refused([left, right], "every pixel needs the same samples")
        late = self.part("late", samples="12:16", crop="0:13,0:24")
        refused([left, late, right], "no part holds samples [8, 12)", left, late)   # a gap
        refused([left, rest], "no part holds pixels 13:40,0:24")
        refused([left, right, rest, rest], "named twice", code=2)
        # Damaged, truncated, and not a part at all.
        data = Path(rest).read_bytes()
        damaged = self.tmp / "refuse" / "damaged.exr"
        damaged.parent.mkdir(exist_ok=True)
        mid = len(data) * 3 // 4
        damaged.write_bytes(data[:mid] + bytes(b ^ 0x5A for b in data[mid:mid + 8]) + data[mid + 8:])
        refused([left, right, str(damaged)], str(damaged))
        truncated = self.tmp / "refuse" / "truncated.exr"
        truncated.write_bytes(data[: len(data) // 2])
        refused([left, right, str(truncated)], str(truncated))
        whole = str(self.tmp / "whole" / "cornell-box.exr")
        refused([left, right, whole], "not a caustic part file", whole)
        # compare reads images, not parts: a part (sums and counts in 15 channels) is refused by
        # name rather than compared by its first three channels.
        p = run("compare", rest, whole, check=False)
        self.assertEqual(p.returncode, 1, p.stderr)
        self.assertIn(rest + ": is a part of a split render", p.stderr)
        refused([left, right, str(self.tmp / "missing.exr")], "missing.exr")

    def test_command_line_refusals(self):
        for args, needle in [
            (["--sample-range", "5:5"], "--sample-range"),
            (["--sample-range", "8:4"], "--sample-range"),
            (["--sample-range", "x"], "--sample-range"),
            (["--sample-range", "0:32"], "goes past --samples 16"),
            (["--crop", "0:41,0:24"], "outside the 40x24 image"),
            (["--crop", "5:5,0:24"], "--crop"),
            (["--crop", "0:8"], "--crop"),
            (["--crop", "0:8,0:8", "--png"], "caustic merge"),
            (["--sample-range", "0:8", "--oidn"], "caustic merge"),
            (["--sample-range", "0:8", "--time", "1"], "--time"),
            (["--variant", "0"], "--variant needs --sweep"),
            (["--sweep", "camera.fov=30,40", "--variant", "2"], "0 to 1"),
        ]:
            p = run(*BASE, "--output", str(self.tmp / "cli"), *args, check=False)
            self.assertEqual(p.returncode, 2, (args, p.stderr))
            self.assertIn(needle, p.stderr, args)
        for args, needle in [
            (["merge", "out.png"], "expected <out> <part.exr>"),
            (["merge", "out.png", "a.exr", "--samples", "4"], "--samples is not an option of caustic merge"),
            (["compare", "a.exr"], "expected <image> <reference>"),
            (["sheet"], "expected <layout.json>"),
        ]:
            p = run(*args, check=False)
            self.assertEqual(p.returncode, 2, (args, p.stderr))
            self.assertIn(needle, p.stderr, args)
        self.assertFalse((self.tmp / "cli").exists() and any((self.tmp / "cli").iterdir()))

    def test_variants_one_at_a_time_and_the_sheet(self):
        sweep = ["--sweep", "camera.fov=25,40"]
        listed = [json.loads(l) for l in run(*BASE, *sweep, "--list-variants").stdout.splitlines()]
        self.assertEqual([v["index"] for v in listed], [0, 1])
        self.assertEqual(listed[1]["label"], "camera.fov=40")
        self.assertEqual(listed[1]["suffix"], "-1")
        self.assertEqual((listed[0]["width"], listed[0]["height"], listed[0]["samples"], listed[0]["columns"]), (W, H, N, 2))
        one = [json.loads(l) for l in run(*BASE, "--list-variants").stdout.splitlines()]
        self.assertEqual([(v["label"], v["suffix"], v["width"]) for v in one], [("", "", W)])
        run(*BASE, *sweep, "--output", str(self.tmp / "sweep"))
        out = run(*BASE, *sweep, "--variant", "1", "--output", str(self.tmp / "one")).stdout.split()
        self.assertEqual([Path(p).name for p in out], ["cornell-box-1.png"])   # no sheet for one variant
        png = lambda p: decode_png(Path(p).read_bytes())[1]
        self.assertEqual(png(out[0]), png(self.tmp / "sweep" / "cornell-box-1.png"))
        layout = {"output": "sheet.png", "columns": 2,
                  "cells": [{"image": str(self.tmp / "sweep" / ("cornell-box-%d.png" % v["index"])), "label": v["label"]}
                            for v in listed]}
        (self.tmp / "one" / "layout.json").write_text(json.dumps(layout))
        run("sheet", str(self.tmp / "one" / "layout.json"))
        self.assertEqual(png(self.tmp / "one" / "sheet.png"), png(self.tmp / "sweep" / "cornell-box-sheet.png"))
        bad = self.tmp / "one" / "bad.json"
        bad.write_text(json.dumps({"output": "x.png", "columns": 2, "cells": [{"image": 3}]}))
        p = run("sheet", str(bad), check=False)
        self.assertEqual(p.returncode, 1)
        self.assertIn("cells[0].image", p.stderr)
        # The layout is read as strictly as a scene: a duplicate key, an unknown cell key and a NUL
        # in the output name are errors naming their place, and nothing is written.
        image = str(self.tmp / "sweep" / "cornell-box-0.png")
        cases = [('{"output": "x.png", "output": "y.png", "columns": 1, "cells": [{"image": %s}]}' % json.dumps(image),
                  "output: duplicate key"),
                 (json.dumps({"output": "x.png", "columns": 1, "cells": [{"image": image, "lable": "typo"}]}),
                  "cells[0].lable: unknown key"),
                 (json.dumps({"output": "x\u0000.png", "columns": 1, "cells": [{"image": image}]}),
                  "output: expected a file name (not empty, no NUL character)")]
        for text, needle in cases:
            bad.write_text(text)
            p = run("sheet", str(bad), check=False)
            self.assertEqual(p.returncode, 1, p.stderr)
            self.assertIn(str(bad) + ": " + needle, p.stderr)
            self.assertFalse((self.tmp / "one" / "x.png").exists())
            self.assertFalse((self.tmp / "one" / "y.png").exists())

    def test_compare_against_independent_metrics(self):
        noisy = self.tmp / "noisy"
        run(*BASE, "--samples", "2", "--exr", "--output", str(noisy))
        ref = str(self.tmp / "whole" / "cornell-box.exr")
        img = str(noisy / "cornell-box.exr")
        p = run("compare", img, ref, "--map", str(noisy / "map.png"))
        got = json.loads(p.stdout)
        a, b = read_exr(img)[3], self.whole[3]
        se = rel = 0.0
        count = 0
        for c in "RGB":
            x, y = a[c].astype(np.float64), b[c].astype(np.float64)
            se += float(np.sum((x - y) ** 2))
            rel += float(np.sum((x - y) ** 2 / (y * y + 0.01)))
            count += x.size
        self.assertAlmostEqual(got["rmse"], (se / count) ** 0.5, delta=1e-9 + 1e-6 * got["rmse"])
        self.assertAlmostEqual(got["relmse"], rel / count, delta=1e-12 + 1e-6 * got["relmse"])
        self.assertGreater(got["relmse"], 0.0)
        ihdr, _ = decode_png((noisy / "map.png").read_bytes())
        self.assertEqual((ihdr["width"], ihdr["height"]), (W, H))
        same = json.loads(run("compare", ref, ref).stdout)
        self.assertEqual((same["rmse"], same["relmse"], same["max_abs"]), (0.0, 0.0, 0.0))


if __name__ == "__main__":
    unittest.main()
