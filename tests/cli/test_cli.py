"""End-to-end tests of the batch command line: the real binary, real scenes, real files.

Run by ctest as "cli: end to end" with CAUSTIC_BIN (the caustic executable) and
CAUSTIC_SOURCE_DIR (the repository root) in the environment. Standard library only.
Renders are small (64x64 at a few samples per pixel) so the module stays fast on llvmpipe.
"""

import json
import math
from pathlib import Path
import os
import re
import shutil
import struct
import subprocess
import tempfile
import unittest
import zlib

BIN = os.environ.get("CAUSTIC_BIN", "")
SOURCE_DIR = os.environ.get("CAUSTIC_SOURCE_DIR", "")
CORNELL = os.path.join(SOURCE_DIR, "scenes", "cornell-box.json")
SMALL = ["--width", "64", "--height", "64"]
# Whether this build has Open Image Denoise (set by CMake from what it found).
HAVE_OIDN = os.environ.get("CAUSTIC_HAVE_OIDN", "") in ("1", "ON", "TRUE", "true")


# Seconds after which a run of caustic counts as hung: subprocess.TimeoutExpired then fails the
# test naming the command. Only a hang guard (nothing here is timed; a loaded machine is slow,
# not wrong), so it is generous.
HANG_GUARD = 900


def run_caustic(*args, env=None, timeout=HANG_GUARD):
    full_env = dict(os.environ)
    if env:
        full_env.update(env)
    return subprocess.run([BIN, *args], capture_output=True, text=True, env=full_env, timeout=timeout)


# --- minimal image readers -------------------------------------------------------------------

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_chunks(data):
    """Yields (type, payload) for every chunk, checking each CRC."""
    pos = len(PNG_SIGNATURE)
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        ctype = data[pos + 4:pos + 8]
        payload = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        if zlib.crc32(ctype + payload) & 0xFFFFFFFF != crc:
            raise ValueError("bad CRC in chunk %r" % ctype)
        yield ctype, payload
        pos += 12 + length


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def decode_png(data):
    """Returns (ihdr dict, rows): rows[y][x] = (r, g, b) for 8-bit RGB non-interlaced PNGs."""
    if data[:8] != PNG_SIGNATURE:
        raise ValueError("not a PNG signature: %r" % data[:8])
    chunks = list(png_chunks(data))
    if chunks[0][0] != b"IHDR":
        raise ValueError("first chunk is %r, not IHDR" % chunks[0][0])
    w, h, depth, ctype, comp, filt, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    ihdr = dict(width=w, height=h, bit_depth=depth, colour_type=ctype, interlace=interlace)
    if chunks[-1][0] != b"IEND":
        raise ValueError("last chunk is not IEND")
    if (depth, ctype, interlace) != (8, 2, 0):
        return ihdr, None
    raw = zlib.decompress(b"".join(p for t, p in chunks if t == b"IDAT"))
    bpp, stride = 3, w * 3
    if len(raw) != h * (stride + 1):
        raise ValueError("IDAT holds %d bytes, expected %d" % (len(raw), h * (stride + 1)))
    prev = bytearray(stride)
    rows = []
    for y in range(h):
        ftype = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ftype == 0:
                pred = 0
            elif ftype == 1:
                pred = a
            elif ftype == 2:
                pred = b
            elif ftype == 3:
                pred = (a + b) // 2
            elif ftype == 4:
                pred = paeth(a, b, c)
            else:
                raise ValueError("bad filter type %d in row %d" % (ftype, y))
            line[i] = (line[i] + pred) & 0xFF
        rows.append([tuple(line[x * 3:x * 3 + 3]) for x in range(w)])
        prev = line
    return ihdr, rows


def decode_hdr(data):
    """Radiance RGBE: returns (header lines, resolution line, rows of (r, g, b) floats)."""
    end = data.index(b"\n\n")
    header = data[:end].decode("ascii").split("\n")
    res_end = data.index(b"\n", end + 2)
    resolution = data[end + 2:res_end].decode("ascii")
    parts = resolution.split()
    if len(parts) != 4 or parts[0] != "-Y" or parts[2] != "+X":
        raise ValueError("unexpected resolution line %r" % resolution)
    h, w = int(parts[1]), int(parts[3])
    pos = res_end + 1
    rows = []
    for _ in range(h):
        if data[pos:pos + 2] == b"\x02\x02" and 8 <= w < 32768:  # new-style run-length encoding
            if struct.unpack(">H", data[pos + 2:pos + 4])[0] != w:
                raise ValueError("scanline width mismatch")
            pos += 4
            channels = []
            for _c in range(4):
                out = bytearray()
                while len(out) < w:
                    n = data[pos]
                    pos += 1
                    if n > 128:
                        out += bytes([data[pos]]) * (n - 128)
                        pos += 1
                    else:
                        out += data[pos:pos + n]
                        pos += n
                if len(out) != w:
                    raise ValueError("run overflows the scanline")
                channels.append(out)
            quads = list(zip(*channels))
        else:  # flat
            quads = [tuple(data[pos + 4 * i:pos + 4 * i + 4]) for i in range(w)]
            pos += 4 * w
        row = []
        for r, g, b, e in quads:
            f = 0.0 if e == 0 else 2.0 ** (e - 136)
            row.append((r * f, g * f, b * f))
        rows.append(row)
    return header, resolution, rows


def exr_header(data):
    """Parses the OpenEXR header attributes into {name: (type, bytes)}."""
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR magic number: %r" % data[:4])
    pos = 8
    attrs = {}

    def cstring(p):
        e = data.index(b"\0", p)
        return data[p:e].decode("ascii"), e + 1

    while data[pos] != 0:
        name, pos = cstring(pos)
        atype, pos = cstring(pos)
        (size,) = struct.unpack("<i", data[pos:pos + 4])
        pos += 4
        attrs[name] = (atype, data[pos:pos + size])
        pos += size
    return attrs


def exr_channels(chlist):
    """chlist payload -> {channel name: pixel type} (0 uint, 1 half, 2 float)."""
    out, pos = {}, 0
    while chlist[pos] != 0:
        e = chlist.index(b"\0", pos)
        name = chlist[pos:e].decode("ascii")
        (ptype,) = struct.unpack("<i", chlist[e + 1:e + 5])
        out[name] = ptype
        pos = e + 1 + 16
    return out


def exr_pixels(data):
    """Decodes a scanline OpenEXR file (no or ZIP compression, half or float channels) into
    {channel name: rows of floats}."""
    attrs = exr_header(data)
    channels = exr_channels(attrs["channels"][1])  # sorted by name, as stored
    x0, y0, x1, y1 = struct.unpack("<iiii", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    compression = attrs["compression"][1][0]
    if compression not in (0, 3):
        raise ValueError("compression %d not supported here" % compression)
    lines_per_chunk = 16 if compression == 3 else 1
    pos = 8  # skip to the end of the header: the attribute list ends with an empty name
    while data[pos] != 0:
        pos = data.index(b"\0", data.index(b"\0", pos) + 1) + 1
        (size,) = struct.unpack("<i", data[pos:pos + 4])
        pos += 4 + size
    pos += 1
    nchunks = (h + lines_per_chunk - 1) // lines_per_chunk
    offsets = struct.unpack("<%dQ" % nchunks, data[pos:pos + 8 * nchunks])
    names = sorted(channels)
    sizes = {1: 2, 2: 4}
    out = {n: [] for n in names}
    for off in offsets:
        y, size = struct.unpack("<ii", data[off:off + 8])
        raw = data[off + 8:off + 8 + size]
        lines = min(lines_per_chunk, y1 + 1 - y)
        expected = lines * w * sum(sizes[channels[n]] for n in names)
        if compression == 3 and size < expected:
            t = bytearray(zlib.decompress(raw))
            for i in range(1, len(t)):  # undo the predictor, then the interleaving
                t[i] = (t[i - 1] + t[i] - 128) & 0xFF
            half = (len(t) + 1) // 2
            raw = bytearray(len(t))
            raw[0::2] = t[:half]
            raw[1::2] = t[half:]
        p = 0
        for _ in range(lines):
            for n in names:
                fmt = "<%d%s" % (w, "e" if channels[n] == 1 else "f")
                nbytes = w * sizes[channels[n]]
                out[n].append(list(struct.unpack(fmt, bytes(raw[p:p + nbytes]))))
                p += nbytes
    return out


def region_mean(rows, x0, x1, y0, y1):
    n = (x1 - x0) * (y1 - y0)
    sums = [0.0, 0.0, 0.0]
    for y in range(y0, y1):
        for x in range(x0, x1):
            for c in range(3):
                sums[c] += rows[y][x][c]
    return [s / n for s in sums]


def stray_files(folder, expected=()):
    """Everything in folder (recursively) that is not in expected (names relative to folder)."""
    found = []
    for root, dirs, files in os.walk(folder):
        for name in files + dirs:
            rel = os.path.relpath(os.path.join(root, name), folder)
            if rel not in expected:
                found.append(rel)
    return sorted(found)


class CliTestCase(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not BIN or not os.path.isfile(BIN):
            raise RuntimeError("CAUSTIC_BIN must name the caustic executable, got %r" % BIN)
        if not os.path.isfile(CORNELL):
            raise RuntimeError("CAUSTIC_SOURCE_DIR must name the repository root, got %r" % SOURCE_DIR)

    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="caustic-cli-")
        self.tmp = self._tmp.name

    def tearDown(self):
        self._tmp.cleanup()

    def assertFailsWith(self, result, *needles, code=None):
        self.assertNotEqual(result.returncode, 0, "expected failure; stderr:\n" + result.stderr)
        if code is not None:
            self.assertEqual(result.returncode, code, result.stderr)
        for needle in needles:
            self.assertIn(needle, result.stderr)
        self.assertEqual(result.stdout, "", "a failed run must list no written files")

    def write_scene(self, name, mutate):
        with open(CORNELL) as f:
            scene = json.load(f)
        mutate(scene)
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            json.dump(scene, f, indent=2)
        return path


class TestRenderAllFormats(CliTestCase):
    """One 64x64 render of the Cornell box written as PNG, HDR and EXR, checked in detail."""

    @classmethod
    def setUpClass(cls):
        super().setUpClass()
        cls._tmp_class = tempfile.TemporaryDirectory(prefix="caustic-cli-formats-")
        cls.out = os.path.join(cls._tmp_class.name, "out")
        cls.result = run_caustic("--scene", CORNELL, *SMALL, "--samples", "8",
                                 "--png", "--hdr", "--exr", "--output", cls.out)

    @classmethod
    def tearDownClass(cls):
        cls._tmp_class.cleanup()

    def setUp(self):
        super().setUp()
        self.assertEqual(self.result.returncode, 0, self.result.stderr)

    def read(self, ext):
        with open(os.path.join(self.out, "cornell-box" + ext), "rb") as f:
            return f.read()

    def test_stdout_lists_exactly_the_three_files(self):
        lines = self.result.stdout.splitlines()
        self.assertEqual(len(lines), 3, self.result.stdout)
        self.assertEqual(sorted(os.path.basename(p) for p in lines),
                         ["cornell-box.exr", "cornell-box.hdr", "cornell-box.png"])
        for path in lines:
            self.assertTrue(os.path.isfile(path), path)
            self.assertEqual(os.path.realpath(os.path.dirname(path)), os.path.realpath(self.out))
        self.assertEqual(stray_files(self.out), ["cornell-box.exr", "cornell-box.hdr", "cornell-box.png"])

    def test_summary_on_stderr(self):
        summary = [l for l in self.result.stderr.splitlines() if "spp" in l]
        self.assertTrue(summary, "no summary line with 'spp' on stderr:\n" + self.result.stderr)
        self.assertIn("64x64", summary[-1])
        self.assertIn("8 spp", summary[-1])

    def test_png_header_and_content(self):
        ihdr, rows = decode_png(self.read(".png"))
        self.assertEqual(ihdr, dict(width=64, height=64, bit_depth=8, colour_type=2, interlace=0))
        self.assertEqual(len(rows), 64)
        pixels = [p for row in rows for p in row]
        self.assertGreater(max(max(p) for p in pixels), 100, "the image is (nearly) black")
        self.assertGreater(len(set(pixels)), 50, "the image is (nearly) uniform")
        # The red wall (x = -1) is on the left of the image, the green wall on the right.
        left = region_mean(rows, 2, 8, 16, 48)
        right = region_mean(rows, 56, 62, 16, 48)
        self.assertGreater(left[0], 1.5 * left[1], "left wall is not red: %s" % left)
        self.assertGreater(left[0], 1.5 * left[2], "left wall is not red: %s" % left)
        self.assertGreater(right[1], 1.5 * right[0], "right wall is not green: %s" % right)
        self.assertGreater(right[1], 1.5 * right[2], "right wall is not green: %s" % right)
        # The ceiling light is seen directly: a small near-white patch, centred, in the top quarter.
        lit = [(x, y) for y in range(16) for x in range(64) if min(rows[y][x]) >= 200]
        self.assertGreaterEqual(len(lit), 10, "the light is not visible near the top")
        self.assertLessEqual(len(lit), 80, "too much of the top quarter is white")
        mean_x = sum(x for x, _ in lit) / len(lit)
        self.assertTrue(27 <= mean_x <= 36, "the light is not centred: mean x %.1f" % mean_x)

    def test_hdr_header_and_content(self):
        data = self.read(".hdr")
        self.assertTrue(data.startswith(b"#?RADIANCE") or data.startswith(b"#?RGBE"), data[:16])
        header, resolution, rows = decode_hdr(data)
        self.assertEqual(resolution, "-Y 64 +X 64")
        self.assertIn("FORMAT=32-bit_rle_rgbe", header)
        self.assertEqual(len(rows), 64)
        self.assertTrue(all(len(r) == 64 for r in rows))
        # Linear values: the same walls, and light-coloured radiance, not an all-zero image.
        left = region_mean(rows, 2, 8, 16, 48)
        right = region_mean(rows, 56, 62, 16, 48)
        self.assertGreater(left[0], 2 * left[1], left)
        self.assertGreater(right[1], 2 * right[0], right)
        self.assertGreater(max(max(p) for row in rows for p in row), 1.0, "no pixel brighter than 1")

    def test_exr_header(self):
        data = self.read(".exr")
        self.assertEqual(data[:4], b"\x76\x2f\x31\x01")
        # 64x64x3 floats are 48 KiB raw; noise compresses poorly, so well above 4 KiB, and a
        # sane writer stays below 4x raw.
        self.assertGreater(len(data), 64 * 64)
        self.assertLess(len(data), 4 * 64 * 64 * 3 * 4 + 4096)
        attrs = exr_header(data)
        self.assertEqual(attrs["dataWindow"][0], "box2i")
        self.assertEqual(struct.unpack("<iiii", attrs["dataWindow"][1]), (0, 0, 63, 63))
        channels = exr_channels(attrs["channels"][1])
        for c in "RGB":
            self.assertIn(c, channels)
            self.assertEqual(channels[c], 2, "channel %s is not 32-bit float" % c)


class TestOutput(CliTestCase):
    def test_default_is_png_only_named_after_scene_in_nested_new_folder(self):
        out = os.path.join(self.tmp, "a", "b", "c")
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                        "--output", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout.splitlines(), [os.path.join(out, "cornell-box.png")])
        self.assertEqual(stray_files(out), ["cornell-box.png"])
        with open(os.path.join(out, "cornell-box.png"), "rb") as f:
            ihdr, _ = decode_png(f.read())
        self.assertEqual((ihdr["width"], ihdr["height"]), (16, 16))

    def test_output_flag_with_equals_and_one_format(self):
        out = os.path.join(self.tmp, "eq")
        r = run_caustic("--scene=" + CORNELL, "--width=16", "--height=8", "--samples=2", "--hdr",
                        "--output=" + out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(stray_files(out), ["cornell-box.hdr"])
        with open(os.path.join(out, "cornell-box.hdr"), "rb") as f:
            _, resolution, _ = decode_hdr(f.read())
        self.assertEqual(resolution, "-Y 8 +X 16")

    def test_width_or_height_alone_keeps_the_aspect_ratio(self):
        scene = json.loads(Path(CORNELL).read_text())
        scene["render"]["width"], scene["render"]["height"] = 300, 200
        path = os.path.join(self.tmp, "wide.json")
        Path(path).write_text(json.dumps(scene))
        for flags, size in ((["--width", "30"], (30, 20)), (["--height", "7"], (11, 7)),  # 10.5 rounds up
                            (["--width", "1"], (1, 1)), (["--width", "16", "--height", "5"], (16, 5))):
            out = os.path.join(self.tmp, "aspect-" + "-".join(flags))
            r = run_caustic("--scene", path, *flags, "--samples", "1", "--output", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "wide.png"), "rb") as f:
                ihdr, _ = decode_png(f.read())
            self.assertEqual((ihdr["width"], ihdr["height"]), size, flags)

    def test_same_seed_same_bytes_other_seed_other_bytes(self):
        def render(seed, folder):
            out = os.path.join(self.tmp, folder)
            r = run_caustic("--scene", CORNELL, *SMALL, "--samples", "4", "--hdr", "--seed", seed,
                            "--output", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "cornell-box.hdr"), "rb") as f:
                return f.read()

        a, b, c = render("7", "a"), render("7", "b"), render("8", "c")
        self.assertEqual(a, b, "same seed gave different images")
        self.assertNotEqual(a, c, "a different seed gave the same image")


class TestCommandLine(CliTestCase):
    def test_help(self):
        r = run_caustic("--help")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("usage:", r.stdout)
        self.assertIn("--scene", r.stdout)

    def test_version(self):
        r = run_caustic("--version")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(r.stdout.startswith("caustic "), r.stdout)
        self.assertGreater(len(r.stdout.strip()), len("caustic"))

    def test_no_scene_without_display_explains(self):
        # Without --scene caustic opens the editor; with no display it must say so and point to
        # batch mode, not crash.
        r = run_caustic(env={"DISPLAY": "", "WAYLAND_DISPLAY": ""})
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("--scene", r.stderr)
        self.assertRegex(r.stderr.lower(), "display|window")

    def test_unknown_option(self):
        r = run_caustic("--scene", CORNELL, "--bogus-flag")
        self.assertFailsWith(r, "--bogus-flag", code=2)

    def test_negative_samples_on_command_line(self):
        r = run_caustic("--scene", CORNELL, "--samples", "-4")
        self.assertFailsWith(r, "--samples", code=2)

    def test_oidn_guides_value_is_checked(self):
        r = run_caustic("--scene", CORNELL, "--oidn", "--oidn-guides", "blurry")
        self.assertFailsWith(r, "--oidn-guides", code=2)


class TestAovsAndDenoising(CliTestCase):
    """--aovs (albedo and normal passes) and --oidn (Open Image Denoise)."""

    def test_aovs_as_png_and_hdr_files(self):
        out = os.path.join(self.tmp, "aov")
        r = run_caustic("--scene", CORNELL, "--width", "32", "--height", "32", "--samples", "2", "--aovs",
                        "--png", "--hdr", "--output", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        names = ["cornell-box" + s + e for e in (".png", ".hdr") for s in ("", "-albedo", "-normal")]
        self.assertEqual(sorted(os.path.basename(p) for p in r.stdout.split()), sorted(names))
        _, albedo = decode_png(Path(out, "cornell-box-albedo.png").read_bytes())
        _, normal = decode_png(Path(out, "cornell-box-normal.png").read_bytes())
        # Left wall: red reflectance (0.570, 0.043, 0.044 in the scene, sRGB-encoded: no tone curve)
        # and its normal +x, remapped to (1, 0.5, 0.5).
        left_albedo = region_mean(albedo, 1, 3, 10, 22)
        self.assertAlmostEqual(left_albedo[0], 199, delta=3)  # 255 * srgbEncode(0.570)
        self.assertLess(left_albedo[1], 90)
        left_normal = region_mean(normal, 1, 3, 10, 22)
        for got, want in zip(left_normal, (255, 128, 128)):
            self.assertAlmostEqual(got, want, delta=3)
        # The back wall faces the camera (+z): (0.5, 0.5, 1) in the normal HDR file, linear.
        _, _, nrows = decode_hdr(Path(out, "cornell-box-normal.hdr").read_bytes())
        back = region_mean(nrows, 12, 20, 8, 12)
        for got, want in zip(back, (0.5, 0.5, 1.0)):
            self.assertAlmostEqual(got, want, delta=0.02)

    def test_multilayer_exr_layers_metadata_and_half(self):
        out = os.path.join(self.tmp, "exr")
        args = ["--scene", CORNELL, "--width", "32", "--height", "32", "--samples", "4", "--seed", "5",
                "--aovs", "--exr", "--half", "--output", out]
        if HAVE_OIDN:
            args.append("--oidn")
        r = run_caustic(*args)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual([os.path.basename(p) for p in r.stdout.split()], ["cornell-box.exr"])
        data = Path(out, "cornell-box.exr").read_bytes()
        attrs = exr_header(data)
        channels = exr_channels(attrs["channels"][1])
        layers = ["raw", "albedo", "normal"] + (["denoised"] if HAVE_OIDN else [])
        expected = {c for c in "RGB"} | {l + "." + c for l in layers for c in "RGB"}
        self.assertEqual(set(channels), expected)
        self.assertEqual(set(channels.values()), {1}, "--half: every channel is 16-bit half")
        meta = {k: v[1].decode() for k, v in attrs.items() if v[0] == "string"}
        self.assertEqual(meta["caustic:samples"], "4")
        self.assertEqual(meta["caustic:seed"], "5")
        self.assertEqual(meta["caustic:scene"], CORNELL)
        self.assertGreater(float(meta["caustic:render_seconds"]), 0.0)
        self.assertTrue(meta["Software"].startswith("caustic "), meta["Software"])
        if HAVE_OIDN:
            self.assertIn("Open Image Denoise", meta["caustic:denoiser"])
        px = exr_pixels(data)
        # The layers hold what they say: normals unit-length on the walls, in [-1, 1]; the left
        # wall's normal is +x; albedo in [0, 1]; R, G, B is the final (denoised) image.
        nx, ny, nz = px["normal.R"][16][1], px["normal.G"][16][1], px["normal.B"][16][1]
        self.assertAlmostEqual(nx, 1.0, delta=0.01)
        self.assertAlmostEqual(ny, 0.0, delta=0.01)
        self.assertAlmostEqual(nz, 0.0, delta=0.01)
        self.assertTrue(all(0.0 <= v <= 1.0 for row in px["albedo.G"] for v in row))
        final = "denoised" if HAVE_OIDN else "raw"
        self.assertEqual(px["R"], px[final + ".R"])
        if HAVE_OIDN:
            self.assertNotEqual(px["raw.R"], px["denoised.R"])

    def test_oidn(self):
        out = os.path.join(self.tmp, "oidn")
        r = run_caustic("--scene", CORNELL, "--width", "32", "--height", "32", "--samples", "2", "--oidn",
                        "--output", out)
        if not HAVE_OIDN:
            # Without the library: a clear message before anything renders, no files.
            self.assertFailsWith(r, "--oidn", "Open Image Denoise", code=1)
            self.assertFalse(os.path.exists(out) and os.listdir(out))
            return
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual([os.path.basename(p) for p in r.stdout.split()], ["cornell-box.png"])
        # Which device OIDN picked is reported: the CPU here, CUDA on an NVIDIA machine.
        self.assertRegex(r.stderr, r"denoised in [0-9.]+ s: Open Image Denoise 2\.5\.1, .*device (CPU|CUDA)")


class TestEnvironmentMap(CliTestCase):
    def test_envmap_lights_the_scene(self):
        sky = os.path.join(SOURCE_DIR, "assets", "sky.hdr")
        out = os.path.join(self.tmp, "env")
        dark = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                           "--output", out, "--hdr")
        self.assertEqual(dark.returncode, 0, dark.stderr)
        lit_out = os.path.join(self.tmp, "env-lit")
        lit = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                          "--output", lit_out, "--hdr", "--envmap", sky)
        self.assertEqual(lit.returncode, 0, lit.stderr)
        # The box is open at the front: the sky adds light, so the image gets brighter.
        def mean(path):
            _, _, rows = decode_hdr(Path(path).read_bytes())
            return sum(sum(p) for row in rows for p in row) / (16 * 16 * 3)
        self.assertGreater(mean(lit.stdout.split()[0]), mean(dark.stdout.split()[0]))

    def test_missing_envmap_names_the_file(self):
        path = os.path.join(self.tmp, "no-such-sky.hdr")
        r = run_caustic("--scene", CORNELL, "--width", "8", "--height", "8", "--samples", "1",
                        "--output", os.path.join(self.tmp, "o"), "--envmap", path)
        self.assertFailsWith(r, path, code=1)
        self.assertIn("environment.file", r.stderr)


    def test_sky_preset_original_is_fill_light(self):
        # The same box under --sky (a white-to-blue key light) and --sky-preset original (scaled
        # to fill light, docs/scene-format.md): the preset lights the open box less.
        means = {}
        for flags in (["--sky"], ["--sky-preset", "original"]):
            out = os.path.join(self.tmp, flags[-1])
            r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                            "--max-depth", "1", "--output", out, "--hdr", *flags)
            self.assertEqual(r.returncode, 0, r.stderr)
            _, _, rows = decode_hdr(Path(r.stdout.split()[0]).read_bytes())
            means[flags[-1]] = [sum(p[c] for row in rows for p in row) / 256 for c in range(3)]
        key, fill = means["--sky"], means["original"]
        self.assertLess(fill[2], 0.8 * key[2], means)  # the key sky's blue zenith is 1, the fill's 0.3


class TestEveryScene(CliTestCase):
    """Every scene shipped in scenes/ loads and renders a few samples: no error, no NaN or
    infinite sample (the summary counts the ones the film drops), finite pixels, some light."""

    def test_every_scene_renders_without_nan(self):
        scenes = sorted(Path(SOURCE_DIR, "scenes").glob("*.json"))
        self.assertGreaterEqual(len(scenes), 20)  # the gallery's included: none may go missing quietly
        for scene in scenes:
            with self.subTest(scene=scene.name):
                out = os.path.join(self.tmp, scene.stem)
                r = run_caustic("--scene", str(scene), "--width", "48", "--height", "32", "--samples", "2",
                                "--output", out, "--exr")
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn(" 0 NaN/Inf samples dropped", r.stderr)
                channels = exr_pixels(Path(r.stdout.split()[0]).read_bytes())
                values = [v for name in ("R", "G", "B") for row in channels[name] for v in row]
                self.assertEqual(len(values), 3 * 48 * 32)
                self.assertTrue(all(math.isfinite(v) and v >= 0.0 for v in values), scene.name)
                self.assertGreater(sum(values), 0.0, scene.name + " renders black")


def write_png_rgb(path, width, height, pixel):
    """A tiny 8-bit RGB PNG, every pixel = pixel (r, g, b), filter 0 on every row."""
    raw = b"".join(b"\x00" + bytes(pixel) * width for _ in range(height))
    def chunk(ctype, payload):
        return (struct.pack(">I", len(payload)) + ctype + payload +
                struct.pack(">I", zlib.crc32(ctype + payload) & 0xFFFFFFFF))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    Path(path).write_bytes(PNG_SIGNATURE + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) +
                           chunk(b"IEND", b""))


class TestMaterialTextures(CliTestCase):
    def scene_with_texture(self, texture):
        scene = {
            "version": 1,
            "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 60},
            "materials": [{"name": "brick", "albedo_texture": texture}],
            "objects": [{"shape": "quad", "material": "brick"}],
            "environment": {"type": "constant", "radiance": [1, 1, 1]},
        }
        path = os.path.join(self.tmp, "textured.json")
        Path(path).write_text(json.dumps(scene))
        return path

    def test_png_albedo_texture_loads_and_renders(self):
        write_png_rgb(os.path.join(self.tmp, "red.png"), 3, 2, (255, 0, 0))
        out = os.path.join(self.tmp, "tex")
        r = run_caustic("--scene", self.scene_with_texture("red.png"), "--width", "16", "--height", "16",
                        "--samples", "4", "--output", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        _, rows = decode_png(Path(r.stdout.split()[0]).read_bytes())
        r_, g_, b_ = rows[8][8]  # the quad fills the centre: red under a white sky
        self.assertGreater(r_, 100)
        self.assertLess(g_, 20)
        self.assertLess(b_, 20)

    def test_missing_texture_names_the_file_and_the_material(self):
        r = run_caustic("--scene", self.scene_with_texture("no-such-texture.png"), "--width", "8",
                        "--height", "8", "--samples", "1", "--output", os.path.join(self.tmp, "o"))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("no-such-texture.png", r.stderr)
        self.assertIn("'brick'", r.stderr)
        self.assertIn("materials[0].albedo_texture", r.stderr)


class TestScriptedRenders(CliTestCase):
    def test_set_overrides_a_value_and_is_validated(self):
        out = os.path.join(self.tmp, "set")
        base = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                           "--output", out, "--hdr")
        self.assertEqual(base.returncode, 0, base.stderr)
        _, _, rows = decode_hdr(Path(base.stdout.split()[0]).read_bytes())
        dark = sum(sum(p) for row in rows for p in row)
        # A brighter light through --set gives a brighter image; the override is a JSON value.
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "2",
                        "--output", out, "--hdr", "--set", "objects[ceiling light].emission=[180, 140, 70]")
        self.assertEqual(r.returncode, 0, r.stderr)
        _, _, rows = decode_hdr(Path(r.stdout.split()[0]).read_bytes())
        self.assertAlmostEqual(sum(sum(p) for row in rows for p in row) / dark, 10.0, delta=0.3)
        # A bad override is reported with its JSON path, like a bad file.
        bad = run_caustic("--scene", CORNELL, "--output", out, "--set", "camera.fov=500")
        self.assertFailsWith(bad, "camera.fov", code=1)
        missing = run_caustic("--scene", CORNELL, "--output", out, "--set", "materials[gold].albedo=[1,1,1]")
        self.assertFailsWith(missing, "materials[gold]", code=1)

    def test_sweep_of_two_values_of_two_parameters(self):
        out = os.path.join(self.tmp, "sweep")
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "12", "--samples", "1",
                        "--output", out, "--sweep", "camera.fov=30,50",
                        "--sweep", "materials[red].albedo=[0.9,0.1,0.1],[0.1,0.1,0.9]")
        self.assertEqual(r.returncode, 0, r.stderr)
        files = r.stdout.split()
        self.assertEqual(len(files), 5, files)  # four variants and the sheet
        for f in files[:4]:
            ihdr, _ = decode_png(Path(f).read_bytes())
            self.assertEqual((ihdr["width"], ihdr["height"]), (16, 12))
        sheet = files[4]
        self.assertTrue(sheet.endswith("cornell-box-sheet.png"))
        ihdr, _ = decode_png(Path(sheet).read_bytes())
        w, h = ihdr["width"], ihdr["height"]
        # 2 x 2 cells of 16 x 12 with padding and label lines: wider than two, taller than two.
        self.assertGreater(w, 32)
        self.assertGreater(h, 24)
        self.assertLess(w, 3 * 16)
        self.assertEqual(len(set(files)), 5)

    def test_time_budget(self):
        out = os.path.join(self.tmp, "time")
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--time", "1",
                        "--output", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stderr, r"\b([2-9]|[1-9][0-9]+)\d* spp in 1\.[0-9]+ s")
        both = run_caustic("--scene", CORNELL, "--time", "1", "--samples", "4", "--output", out)
        self.assertFailsWith(both, "--time", code=2)


class TestBadInput(CliTestCase):
    def render(self, scene, *extra, env=None):
        self.out = os.path.join(self.tmp, "out")
        return run_caustic("--scene", scene, "--width", "16", "--height", "16", "--samples", "1",
                           "--output", self.out, *extra, env=env)

    def assertNoOutput(self):
        if os.path.exists(self.out):
            self.assertEqual(stray_files(self.out), [], "a failed run left files behind")

    def test_missing_scene_file(self):
        path = os.path.join(self.tmp, "no-such-scene.json")
        r = self.render(path)
        self.assertFailsWith(r, path, code=1)
        self.assertNoOutput()

    def test_malformed_json_names_file_and_line_column(self):
        path = os.path.join(self.tmp, "broken.json")
        with open(path, "w") as f:
            f.write('{\n  "version": 1,\n  "camera": { "fov": 40,, }\n}\n')
        r = self.render(path)
        self.assertFailsWith(r, "broken.json")
        self.assertRegex(r.stderr, r"broken\.json:3:\d+")
        self.assertNoOutput()

    def test_unknown_key_names_json_path(self):
        path = self.write_scene("typo.json", lambda s: s["camera"].__setitem__("fvo", 40))
        r = self.render(path)
        self.assertFailsWith(r, "typo.json", "camera.fvo")
        self.assertNoOutput()

    def test_negative_samples_in_scene(self):
        path = self.write_scene("neg.json", lambda s: s["render"].__setitem__("samples", -4))
        # No --samples override here: the scene's own value must be validated.
        self.out = os.path.join(self.tmp, "out")
        r = run_caustic("--scene", path, "--output", self.out)
        self.assertFailsWith(r, "render.samples")
        self.assertNoOutput()

    def test_unwritable_output_folder(self):
        # A path under a regular file cannot be created even by root (chmod would not stop root).
        afile = os.path.join(self.tmp, "afile")
        with open(afile, "w") as f:
            f.write("not a folder")
        out = os.path.join(afile, "sub")
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "1",
                        "--output", out)
        self.assertFailsWith(r, out, code=1)
        self.assertEqual(stray_files(self.tmp), ["afile"])

    def test_shader_compile_error_names_file_and_line(self):
        shaders = os.path.join(self.tmp, "shaders")
        shutil.copytree(os.path.join(SOURCE_DIR, "shaders"), shaders)
        env_file = os.path.join(shaders, "lights", "environment.glsl")
        with open(env_file) as f:
            lines = f.read().count("\n")
        with open(env_file, "a") as f:
            f.write("\nthis is not GLSL (\n")
        r = self.render(CORNELL, env={"CAUSTIC_SHADER_DIR": shaders})
        self.assertFailsWith(r, "lights/environment.glsl", code=1)
        # The error points into the appended text, i.e. past the original last line.
        found = [int(n) for n in
                 re.findall(r"lights/environment\.glsl[:(](\d+)", r.stderr)]
        self.assertTrue(found, r.stderr)
        self.assertTrue(all(n > lines for n in found), "line numbers %s, file had %d lines" % (found, lines))
        self.assertNoOutput()

    def test_failed_write_leaves_no_temporary_file(self):
        # A folder squatting on the target name makes the final rename fail after the data is
        # written: the temporary file must be removed and nothing reported on stdout.
        out = os.path.join(self.tmp, "out")
        os.makedirs(os.path.join(out, "cornell-box.png"))
        r = run_caustic("--scene", CORNELL, "--width", "16", "--height", "16", "--samples", "1",
                        "--output", out)
        self.assertFailsWith(r, "cornell-box.png", code=1)
        self.assertEqual(stray_files(out), ["cornell-box.png"])
        self.assertEqual(os.listdir(os.path.join(out, "cornell-box.png")), [])


if __name__ == "__main__":
    unittest.main()
