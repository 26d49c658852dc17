"""Hostile input and hard limits through the real program (issue 12, docs/reliability.md).

Run by ctest as "cli: hostile input", with the environment of "cli: end to end". Each test is a
failure that used to happen: a full disk that exited 0 over a truncated image, a deeply nested
scene that crashed, a FIFO or /dev/zero that hung, a huge image header or render size that died
with "std::bad_alloc", a long scene name that failed. Hangs are guarded by subprocess timeouts;
nothing asserts a duration. Standard library only.
"""

import os
from pathlib import Path
import resource
import shutil
import signal
import subprocess
import struct
import tempfile
import unittest
import zlib

import test_cli as cli

# 16x16 at 2 spp: every test here is about what happens around the render, not the image.
TINY = ["--width", "16", "--height", "16", "--samples", "2"]
HANG_GUARD = cli.HANG_GUARD  # seconds; only so that a regression fails instead of hanging the suite


def scene_with(tmp, name="scene.json", material_extra="", environment=None, objects=None):
    """A one-sphere scene written into tmp; returns its path."""
    mat = '{"name": "white", "albedo": [0.8, 0.8, 0.8]%s}' % material_extra
    objs = objects or '[{"shape": "sphere", "material": "white"}]'
    env = environment or '{"type": "constant", "radiance": [1, 1, 1]}'
    text = ('{"version": 1, "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]}, '
            '"materials": [%s], "objects": %s, "environment": %s}' % (mat, objs, env))
    path = Path(tmp) / name
    path.write_text(text)
    return str(path)


def temporaries(folder):
    return sorted(p.name for p in Path(folder).iterdir() if ".tmp-" in p.name)


def png_header_only(width, height):
    """A PNG whose IHDR declares width x height, with a few bytes of image data."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)

    def chunk(kind, payload):
        return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", zlib.crc32(kind + payload) & 0xFFFFFFFF)

    return cli.PNG_SIGNATURE + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b"")


class HostileTestCase(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="caustic-hostile-")
        self.addCleanup(shutil.rmtree, self.tmp, ignore_errors=True)

    def run_caustic(self, *args, preexec_fn=None, env=None):
        full_env = dict(os.environ)
        full_env.update(env or {})
        return subprocess.run([cli.BIN, *args], capture_output=True, text=True, env=full_env,
                              timeout=HANG_GUARD, preexec_fn=preexec_fn)

    def assertFailsWith(self, result, code, *fragments):
        message = "rc %d\nstdout: %s\nstderr: %s" % (result.returncode, result.stdout, result.stderr)
        self.assertEqual(result.returncode, code, message)
        for fragment in fragments:
            self.assertIn(fragment, result.stderr, message)
        self.assertNotIn("unexpected failure", result.stderr, message)
        self.assertNotIn("bad_alloc", result.stderr, message)


class TestFullDisk(HostileTestCase):
    """A file size limit makes write() fail with EFBIG, as a full disk fails it with ENOSPC."""

    LIMIT = 2048

    def limited(self):
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # fail the write instead of killing the process
        resource.setrlimit(resource.RLIMIT_FSIZE, (self.LIMIT, self.LIMIT))

    def check_format(self, flag, ext):
        out = os.path.join(self.tmp, "out")
        args = ["--scene", cli.CORNELL, "--width", "64", "--height", "64", "--samples", "2", flag, "--output", out]
        good = self.run_caustic(*args, "--seed", "1")
        self.assertEqual(good.returncode, 0, good.stderr)
        target = Path(out) / ("cornell-box" + ext)
        before = target.read_bytes()
        self.assertGreater(len(before), self.LIMIT)  # else the limit would not bite
        # The shader cache must not be what hits the limit.
        failed = self.run_caustic(*args, "--seed", "2", preexec_fn=self.limited,
                                  env={"MESA_SHADER_CACHE_DISABLE": "true"})
        self.assertFailsWith(failed, 1, str(target) + ": cannot write:", "File too large")
        self.assertNotIn(str(target), failed.stdout)  # not reported as written
        self.assertEqual(target.read_bytes(), before)  # the previous good file survives
        self.assertEqual(temporaries(out), [])

    def test_png(self):
        self.check_format("--png", ".png")

    def test_hdr(self):
        self.check_format("--hdr", ".hdr")

    def test_exr(self):
        self.check_format("--exr", ".exr")


class TestDeepNesting(HostileTestCase):
    def test_scene_nested_100000_deep_is_refused(self):
        path = Path(self.tmp) / "deep.json"
        path.write_text('{"version": 1, "camera": ' + "[" * 100000 + "]" * 100000 + "}")
        result = self.run_caustic("--scene", str(path), *TINY, "--output", self.tmp)
        self.assertFailsWith(result, 1, str(path) + ":1:89: arrays and objects nested deeper than 64 levels")

    def test_deep_set_value_is_refused(self):
        deep = "[" * 50000 + "]" * 50000  # 100 KB: below the 128 KB limit of one argument
        result = self.run_caustic("--scene", cli.CORNELL, "--set", "camera.fov=" + deep, *TINY, "--output", self.tmp)
        self.assertFailsWith(result, 1, "--set camera.fov=[[[", "the value has arrays and objects nested deeper than 64 levels")
        self.assertLess(len(result.stderr), 400)


class TestNonRegularImages(HostileTestCase):
    """A FIFO or a device as an image: refused at once, naming it (it used to hang)."""

    def fifo(self, name):
        path = os.path.join(self.tmp, name)
        os.mkfifo(path)
        return path

    def test_fifo_and_dev_zero_as_environment_map(self):
        for path, kind in ((self.fifo("sky.hdr"), "a FIFO (named pipe)"), ("/dev/zero", "a character device")):
            with self.subTest(path=path):
                result = self.run_caustic("--scene", cli.CORNELL, "--envmap", path, *TINY, "--output", self.tmp)
                self.assertFailsWith(result, 1, path + ": cannot read: " + kind + ", not a regular file")

    def test_fifo_and_dev_zero_as_texture(self):
        for path, kind in ((self.fifo("brick.png"), "a FIFO (named pipe)"), ("/dev/zero", "a character device")):
            with self.subTest(path=path):
                scene = scene_with(self.tmp, material_extra=', "albedo_texture": "%s"' % path)
                result = self.run_caustic("--scene", scene, *TINY, "--output", self.tmp)
                self.assertFailsWith(result, 1, "albedo_texture", path + ": cannot read: " + kind)


class TestHugeImageHeaders(HostileTestCase):
    """A header declaring 100000x100000 is refused from the header, naming the file and the size."""

    def files(self):
        png = Path(self.tmp) / "huge.png"
        png.write_bytes(png_header_only(100000, 100000))
        hdr = Path(self.tmp) / "huge.hdr"
        hdr.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n" + b"\x01" * 64)
        return [str(png), str(hdr)]

    def test_as_environment_map(self):
        for path in self.files():
            with self.subTest(path=path):
                result = self.run_caustic("--scene", cli.CORNELL, "--envmap", path, *TINY, "--output", self.tmp)
                self.assertFailsWith(result, 1, path + ": declares 100000x100000 pixels, more than the limit")

    def test_as_texture(self):
        for path in self.files():
            with self.subTest(path=path):
                scene = scene_with(self.tmp, material_extra=', "albedo_texture": "%s"' % path)
                result = self.run_caustic("--scene", scene, *TINY, "--output", self.tmp)
                self.assertFailsWith(result, 1, "materials[0].albedo_texture", path + ": declares 100000x100000 pixels")


class TestClearFailures(HostileTestCase):
    def test_empty_envmap_is_a_usage_error(self):
        result = self.run_caustic("--scene", cli.CORNELL, "--envmap", "", *TINY, "--output", self.tmp)
        self.assertFailsWith(result, 2, "--envmap: expected an image file, got ''")

    def test_set_with_a_huge_index(self):
        for index in ("99", "99999999999999999999999"):
            with self.subTest(index=index):
                result = self.run_caustic("--scene", cli.CORNELL, "--set", "objects[%s].shape=sphere" % index,
                                          *TINY, "--output", self.tmp)
                self.assertFailsWith(result, 1, "objects[%s]: no such element (the array has" % index)

    def test_render_size_beyond_memory(self):
        with open("/proc/meminfo") as f:
            available = next(int(line.split()[1]) * 1024 for line in f if line.startswith("MemAvailable:"))
        if 16384 * 16384 * 300 < available:
            self.skipTest("this machine has memory for a 16384x16384 render")
        result = self.run_caustic("--scene", cli.CORNELL, "--width", "16384", "--height", "16384", "--samples", "1",
                                  "--output", self.tmp)
        self.assertFailsWith(result, 1, "render size 16384x16384 needs about", "GiB is available")
        self.assertEqual(list(Path(self.tmp).iterdir()), [])  # failed before anything was written


class TestNeedlessRefusals(HostileTestCase):
    def test_scene_name_of_240_characters(self):
        name = "c" * 240 + ".json"
        scene = Path(self.tmp) / name
        shutil.copy(cli.CORNELL, scene)
        out = os.path.join(self.tmp, "out")
        result = self.run_caustic("--scene", str(scene), *TINY, "--output", out)
        self.assertEqual(result.returncode, 0, result.stderr)
        written = Path(out) / ("c" * 240 + ".png")
        self.assertEqual(result.stdout.split(), [str(written)])
        self.assertTrue(written.read_bytes().startswith(cli.PNG_SIGNATURE))
        self.assertEqual(temporaries(out), [])

    def test_model_with_missing_texture_and_a_scene_material(self):
        Path(self.tmp, "model.mtl").write_text("newmtl painted\nKd 0.8 0.8 0.8\nmap_Kd missing.png\n")
        Path(self.tmp, "model.obj").write_text(
            "mtllib model.mtl\nusemtl painted\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n")
        own = scene_with(self.tmp, "own.json", objects='[{"shape": "mesh", "file": "model.obj", "material": "white"}]')
        result = self.run_caustic("--scene", own, *TINY, "--output", self.tmp)
        self.assertEqual(result.returncode, 0, result.stderr)
        # With the file's own material the texture is needed, and its absence names it.
        files = scene_with(self.tmp, "files.json", objects='[{"shape": "mesh", "file": "model.obj"}]')
        result = self.run_caustic("--scene", files, *TINY, "--output", self.tmp)
        self.assertFailsWith(result, 1, "objects[0].file", os.path.join(self.tmp, "missing.png"))


if __name__ == "__main__":
    unittest.main()
