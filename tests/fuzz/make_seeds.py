#!/usr/bin/env python3
"""Writes the small generated seed files of the image harnesses (tests/fuzz/seeds/hdr/ and
tests/fuzz/seeds/image/): Radiance HDR flat and run-length encoded (the two scanline encodings
renderer/hdr_file.cpp reads), and tiny uncompressed TGA, BMP and PPM images (formats OpenImageIO
reads that Debian's assimp-testmodels has no small example of); of the part-file harness
(tests/fuzz/seeds/part/): uncompressed OpenEXR part files, valid ones and crafted ones (a NaN sum
under a correct checksum, a header declaring far more pixels than the file holds, a missing
channel, a foreign format tag, an image size and a render time no render writes); and of the sheet harness (tests/fuzz/seeds/sheet/): layouts.
Deterministic; run it again to regenerate them after changing it."""
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))


def write(rel, data):
    path = os.path.join(here, "seeds", rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


def rgbe(r, g, b):
    import math
    v = max(r, g, b)
    if v < 1e-32:
        return bytes(4)
    m, e = math.frexp(v)
    s = m * 256.0 / v
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])


def hdr_header(w, h):
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y %d +X %d\n" % (h, w)


def pixel(x, y):
    return rgbe(0.1 + x * 0.05, 0.2 + y * 0.1, 4.0 if (x + y) % 5 == 0 else 0.5)


# Flat scanlines (width below 8 forces them).
w, h = 5, 3
write("hdr/flat.hdr", hdr_header(w, h) + b"".join(pixel(x, y) for y in range(h) for x in range(w)))

# New run-length encoding: per row 2 2 <width hi> <width lo>, then each component in runs
# (count > 128: a run of count - 128 copies; else count literal bytes).
w, h = 24, 4
body = b""
for y in range(h):
    body += bytes([2, 2, w >> 8, w & 255])
    row = [pixel(x if x < 12 else 12, y) for x in range(w)]
    for c in range(4):
        vals = [p[c] for p in row]
        body += bytes([12]) + bytes(vals[:12]) + bytes([128 + 12, vals[12]])
write("hdr/rle.hdr", hdr_header(w, h) + body)

# TGA: uncompressed true colour, 4x2, bottom-up.
w, h = 4, 2
tga = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, w, h, 24, 0)
tga += b"".join(bytes([x * 60, y * 120, 200]) for y in range(h) for x in range(w))
write("image/tiny.tga", tga)

# BMP: 24-bit, 3x2, rows padded to 4 bytes, bottom-up.
w, h = 3, 2
row = lambda y: b"".join(bytes([200, y * 100, x * 80]) for x in range(w)) + b"\0" * ((4 - (w * 3) % 4) % 4)
pixels = b"".join(row(y) for y in range(h))
bmp = b"BM" + struct.pack("<IHHI", 54 + len(pixels), 0, 0, 54)
bmp += struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(pixels), 2835, 2835, 0, 0)
write("image/tiny.bmp", bmp + pixels)

# PPM (binary P6), 3x3.
w, h = 3, 3
write("image/tiny.ppm", b"P6\n3 3\n255\n" + b"".join(bytes([x * 100, y * 100, 50]) for y in range(h) for x in range(w)))
# A Radiance file for OpenImageIO's reader too.
write("image/rle.hdr", open(os.path.join(here, "seeds", "hdr", "rle.hdr"), "rb").read())


def tiff(w, h, spp, depth=1):
    """An uncompressed little-endian 8-bit TIFF, one strip per depth slice (TIFFTAG_IMAGEDEPTH,
    32997, is the SGI volume extension libtiff and OpenImageIO read)."""
    slice_bytes = w * h * spp
    entries = []  # (tag, type, count, value bytes)
    SHORT, LONG = 3, 4

    def e(tag, typ, values):
        fmt = "<H" if typ == SHORT else "<I"
        entries.append((tag, typ, len(values), b"".join(struct.pack(fmt, v) for v in values)))

    n_tags = 12 + (1 if spp > 3 else 0) + (1 if depth > 1 else 0)
    ifd_at = 8
    data_at = ifd_at + 2 + 12 * n_tags + 4
    extra = b""  # out-of-line values, then the pixels

    def place(raw):
        nonlocal extra
        at = data_at + len(extra)
        extra += raw + (b"\0" if len(raw) % 2 else b"")
        return at

    e(256, LONG, [w])
    e(257, LONG, [h])
    e(258, SHORT, [8] * spp)
    e(259, SHORT, [1])
    e(262, SHORT, [2])
    strips_tag = len(entries)
    e(273, LONG, [0] * depth)
    e(277, SHORT, [spp])
    e(278, LONG, [h])
    e(279, LONG, [slice_bytes] * depth)
    e(282, LONG, [0])  # placeholders for the RATIONAL resolutions, fixed below
    e(283, LONG, [0])
    e(284, SHORT, [1])
    if spp > 3:
        e(338, SHORT, [0] * (spp - 3))
    if depth > 1:
        e(32997, LONG, [depth])
    # Resolutions as RATIONAL 72/1.
    for i, (tag, typ, count, raw) in enumerate(entries):
        if tag in (282, 283):
            entries[i] = (tag, 5, 1, struct.pack("<II", 72, 1))
    # Out-of-line values (more than 4 bytes) first, then the pixels.
    offsets = {}
    for i, (tag, typ, count, raw) in enumerate(entries):
        if len(raw) > 4 and tag != 273:
            offsets[i] = place(raw)
    strip_offsets_raw_at = place(b"\0" * 4 * depth) if depth > 1 else None
    pixels_at = data_at + len(extra)
    pixels = bytes((x * 37 + y * 11 + c * 5 + z * 101) & 255 for z in range(depth) for y in range(h)
                   for x in range(w) for c in range(spp))
    strip_offsets = [pixels_at + z * slice_bytes for z in range(depth)]
    raw_offsets = b"".join(struct.pack("<I", v) for v in strip_offsets)
    if depth > 1:
        extra = extra[:strip_offsets_raw_at - data_at] + raw_offsets + extra[strip_offsets_raw_at - data_at + 4 * depth:]
        offsets[strips_tag] = strip_offsets_raw_at
    else:
        entries[strips_tag] = (273, LONG, 1, raw_offsets)
    ifd = struct.pack("<H", len(entries))
    for i, (tag, typ, count, raw) in enumerate(entries):
        value = struct.pack("<I", offsets[i]) if i in offsets else raw.ljust(4, b"\0")
        ifd += struct.pack("<HHI", tag, typ, count) + value
    ifd += struct.pack("<I", 0)
    return b"II*\0" + struct.pack("<I", ifd_at) + ifd + extra + pixels


write("image/tiny.tif", tiff(4, 3, 3))
write("image/six-channels.tif", tiff(3, 2, 6))   # more channels than RGBA: 4 are kept


# ---- Part files (app/part_file.cpp): single-part scanline OpenEXR, uncompressed ----------------
# The channels in the order of the part's checksum (kChannels in app/part_file.cpp).
PART_CHANNELS = ["sum.R", "sum.G", "sum.B", "sum.A", "sumsq.R", "sumsq.G", "sumsq.B", "albedo.R", "albedo.G",
                 "albedo.B", "albedo.A", "normal.R", "normal.G", "normal.B", "normal.A"]


def fnv1a64(data):
    h = 0xcbf29ce484222325
    for b in data:
        h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
    return "%016x" % h


def exr_attr(name, typ, value):
    return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(value)) + value


def exr(w, h, channels, pixel, strings, data_window=None):
    """A scanline OpenEXR file, no compression, one scanline per chunk, 32-bit float channels.
    pixel(x, y, name) gives each value; strings are extra string attributes."""
    names = sorted(channels)  # OpenEXR keeps channels sorted by name, in the header and the data
    chlist = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names) + b"\0"
    x0, y0, x1, y1 = data_window or (0, 0, w - 1, h - 1)
    box = struct.pack("<iiii", x0, y0, x1, y1)
    header = struct.pack("<ii", 20000630, 2)
    header += exr_attr("channels", "chlist", chlist)
    header += exr_attr("compression", "compression", b"\0")
    header += exr_attr("dataWindow", "box2i", box)
    header += exr_attr("displayWindow", "box2i", box)
    header += exr_attr("lineOrder", "lineOrder", b"\0")
    header += exr_attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += exr_attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    header += exr_attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    for key, value in strings:
        header += exr_attr(key, "string", value.encode())
    header += b"\0"
    rows = []
    for y in range(h):
        data = b"".join(struct.pack("<f", pixel(x, y, n)) for n in names for x in range(w))
        rows.append(struct.pack("<ii", y0 + y, len(data)) + data)
    at = len(header) + 8 * h
    table = b""
    for r in rows:
        table += struct.pack("<Q", at)
        at += len(r)
    return header + table + b"".join(rows)


def part_value(x, y, name):
    layer, c = name.split(".")
    base = {"sum": 2.0, "sumsq": 3.0, "albedo": 0.5, "normal": 0.25}[layer]
    if name in ("sum.A", "albedo.A", "normal.A"):
        return 4.0  # the sample counts
    return base + 0.125 * x + 0.0625 * y + {"R": 0.0, "G": 0.01, "B": 0.02}[c]


def part(image_w, image_h, crop, samples, value=part_value, channels=PART_CHANNELS, overrides=(), data_window=None):
    cx0, cx1, cy0, cy1 = crop
    w, h = cx1 - cx0, cy1 - cy0
    interleaved = b"".join(struct.pack("<f", value(x, y, n)) for y in range(h) for x in range(w)
                           for n in PART_CHANNELS if n in channels)
    meta = dict([
        ("caustic:part", "caustic-part-1"),
        ("caustic:scene", "scenes/cornell-box.json"),
        ("caustic:render_hash", "0123456789abcdef"),
        ("caustic:version", "0.1.0"),
        ("caustic:variant", ""),
        ("caustic:seed", "7"),
        ("caustic:image_size", "%dx%d" % (image_w, image_h)),
        ("caustic:sample_range", "%d:%d" % samples),
        ("caustic:crop", "%d:%d,%d:%d" % crop),
        ("caustic:render_seconds", "0.250000"),
        ("caustic:dropped", "0"),
        ("caustic:checksum", fnv1a64(interleaved)),
    ])
    meta.update(dict(overrides))
    return exr(w, h, channels, value, sorted(meta.items()), data_window)


write("part/crop.exr", part(5, 4, (1, 4, 0, 2), (0, 4)))
write("part/whole.exr", part(2, 2, (0, 2, 0, 2), (4, 12)))
write("part/nan-sum.exr", part(2, 1, (0, 2, 0, 1), (0, 4),
                               value=lambda x, y, n: float("nan") if (n == "sum.G" and x == 1) else part_value(x, y, n)))
write("part/negative-count.exr", part(2, 1, (0, 2, 0, 1), (0, 4),
                                      value=lambda x, y, n: -1.0 if n == "sum.A" else part_value(x, y, n)))
write("part/missing-channel.exr", part(2, 1, (0, 2, 0, 1), (0, 4), channels=PART_CHANNELS[:-1]))
write("part/foreign-format.exr", part(2, 1, (0, 2, 0, 1), (0, 4), overrides=[("caustic:part", "caustic-part-0")]))
# Metadata no render writes: an image larger than any render, a render time that is not a number.
write("part/image-size.exr", part(20000, 4, (0, 2, 0, 1), (0, 4)))
write("part/seconds-nan.exr", part(2, 1, (0, 2, 0, 1), (0, 4), overrides=[("caustic:render_seconds", "nan")]))
# The header declares 16384 x 8192 pixels; the file holds one scanline of two.
write("part/huge-header.exr", part(16384, 8192, (0, 2, 0, 1), (0, 4), data_window=(0, 0, 16383, 8191)))


# ---- Sheet layouts (caustic sheet) ------------------------------------------------------------
write("sheet/two-columns.json", b"""{"output": "sheet.png", "columns": 2, "cells": [
  {"image": "a.png", "label": "roughness 0.1"},
  {"image": "b.png", "label": "roughness 0.5\\nmetal"},
  {"image": "c.png"}
]}
""")
write("sheet/long-labels.json", ("""{"output": "out/sheet.png", "columns": 1, "cells": [
  {"image": "wide-image-name.png", "label": "%s"},
  {"image": "x.png", "label": "%s"}
]}
""" % ("a label long enough to wrap over several lines " * 3, "\\n".join(["line"] * 20) + " \\u00e9\\u00e9")).encode())
write("sheet/one-cell.json", b'{"output": "s.png", "columns": 4096, "cells": [{"image": "/abs/a.exr", "label": ""}]}')
