"""The farm's EXR reading (app/farm/caustic_farm/exr.py, the OpenEXR Python bindings) against files
caustic writes: a part file reads back bit for bit (the FNV-1a of its pixels equals the checksum
caustic stored in it), the image merged from it holds exactly sum / count in float32 in each named
layer, its half-float version exactly those values rounded to half, and a cut or damaged file is
refused by name.

Run by ctest as "farm: EXR files read with OpenEXR" with the farm's venv (.deps/farm-venv, made by
setup.sh), CAUSTIC_BIN and CAUSTIC_SOURCE_DIR. No Ray cluster."""

import os
from pathlib import Path
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.environ.get("CAUSTIC_SOURCE_DIR", os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "app", "farm"))
from caustic_farm.exr import check_complete, read_exr, read_header  # noqa: E402

BIN = os.environ.get("CAUSTIC_BIN", os.path.join(SOURCE_DIR, "build", "caustic"))
CORNELL = os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")
W, H = 40, 24
# The channels of a part file in the order its checksum covers them (app/part_file.cpp, kChannels).
PART_CHANNELS = ["sum.R", "sum.G", "sum.B", "sum.A", "sumsq.R", "sumsq.G", "sumsq.B", "albedo.R", "albedo.G",
                 "albedo.B", "albedo.A", "normal.R", "normal.G", "normal.B", "normal.A"]


def fnv1a64(data):
    h = 0xcbf29ce484222325
    for b in data:
        h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h


def caustic(*args):
    p = subprocess.run([BIN, *args], capture_output=True, text=True, env=dict(os.environ, LP_NUM_THREADS="2"))
    if p.returncode != 0:
        raise AssertionError("caustic %s failed (%d):\n%s" % (" ".join(args), p.returncode, p.stderr))
    return p.stdout.split()


class ExrFiles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="caustic-exr-"))
        (cls.part,) = caustic("--scene", CORNELL, "--width", str(W), "--height", str(H), "--samples", "8",
                              "--sample-range", "0:8", "--output", str(cls.tmp / "part"))
        (cls.float_exr,) = caustic("merge", str(cls.tmp / "float" / "cornell-box"), cls.part, "--exr", "--aovs")
        (cls.half_exr,) = caustic("merge", str(cls.tmp / "half" / "cornell-box"), cls.part, "--exr", "--aovs",
                                  "--half")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_a_part_file_reads_back_bit_for_bit(self):
        attrs, w, h, ch = read_exr(self.part)
        self.assertEqual((w, h), (W, H))
        self.assertEqual(sorted(ch), sorted(PART_CHANNELS))
        for name in PART_CHANNELS:
            self.assertEqual((ch[name].dtype, ch[name].shape), (np.float32, (H, W)), name)
        self.assertEqual((attrs["caustic:part"], attrs["caustic:sample_range"], attrs["caustic:crop"]),
                         ("caustic-part-1", "0:8", "0:%d,0:%d" % (W, H)))
        interleaved = np.stack([ch[name] for name in PART_CHANNELS], axis=-1).astype("<f4")
        self.assertEqual(fnv1a64(interleaved.tobytes()), attrs["caustic:checksum"])
        self.assertEqual(check_complete(self.part)[4], "")
        self.assertEqual(read_header(self.part)["caustic:checksum"], attrs["caustic:checksum"])

    def test_the_merged_float_image_holds_each_layer_exactly(self):
        _, _, _, part = read_exr(self.part)
        attrs, w, h, ch = read_exr(self.float_exr)
        self.assertEqual((w, h, attrs["caustic:samples"]), (W, H, "8"))
        layers = {"": "sum", "raw.": "sum", "albedo.": "albedo", "normal.": "normal"}
        self.assertEqual(sorted(ch), sorted(prefix + c for prefix in layers for c in "RGB"))
        self.assertTrue(np.all(part["sum.A"] == 8))   # every sample counted: no pixel without a mean
        for prefix, sums in layers.items():
            for c in "RGB":
                name = prefix + c
                self.assertEqual(ch[name].dtype, np.float32, name)
                expected = part[sums + "." + c] / part[sums + ".A"]   # float32 / float32, as resolveFilm
                self.assertTrue(np.array_equal(ch[name].view(np.uint32), expected.view(np.uint32)), name)

    def test_the_half_image_holds_the_float_values_rounded_to_half(self):
        _, _, _, full = read_exr(self.float_exr)
        attrs, w, h, half = read_exr(self.half_exr)
        self.assertEqual((w, h), (W, H))
        self.assertEqual(sorted(half), sorted(full))
        for name, values in half.items():
            self.assertEqual(values.dtype, np.float16, name)
            self.assertTrue(np.array_equal(values.view(np.uint16), full[name].astype(np.float16).view(np.uint16)),
                            name)

    def test_a_cut_or_damaged_file_is_refused_by_name(self):
        data = Path(self.part).read_bytes()
        cut = self.tmp / "cut.exr"
        cut.write_bytes(data[:len(data) - 200])
        problem = check_complete(str(cut))[4]
        self.assertTrue(problem.startswith("%s: not a complete OpenEXR file" % cut), problem)
        with self.assertRaises(ValueError):
            read_exr(str(cut))
        text = self.tmp / "text.exr"
        text.write_text("not an image\n")
        self.assertTrue(check_complete(str(text))[4].startswith("%s: not a complete OpenEXR file" % text))
        # Nothing of the library's messages reaches standard output (where the farm lists its files).
        probe = ("import sys; sys.path.insert(0, %r)\n"
                 "from caustic_farm.exr import check_complete\n"
                 "assert check_complete(%r)[4]\n" % (os.path.join(SOURCE_DIR, "app", "farm"), str(cut)))
        p = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout, "")


if __name__ == "__main__":
    unittest.main()
