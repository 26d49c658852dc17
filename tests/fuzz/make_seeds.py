#!/usr/bin/env python3
"""Writes the small generated seed files of the image harnesses (tests/fuzz/seeds/hdr/ and
tests/fuzz/seeds/image/): Radiance HDR flat and run-length encoded (the two scanline encodings
renderer/hdr_file.cpp reads), and tiny uncompressed TGA, BMP and PPM images (formats OpenImageIO
reads that Debian's assimp-testmodels has no small example of). Deterministic; run it again to
regenerate them after changing it."""
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
