#!/usr/bin/env python3
"""Writes the shipped aperture images (greyscale 8-bit PNGs, 128 x 128, 4 x 4 supersampled edges):
star.png (a five-pointed star), heart.png (the heart curve x = 16 sin^3 t, y = 13 cos t - 5 cos 2t -
2 cos 3t - cos 4t), ring.png (an annulus: a mirror lens's doughnut bokeh) and cats-eye.png (two
discs' intersection: the cat's eye of a vignetted lens everywhere in the frame, for the thin lens). Standard library only:
python3 assets/apertures/make_apertures.py"""
import math
import os
import struct
import zlib

N, SS = 128, 4


def write_png(path, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", N, N, 8, 0, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def inside_polygon(x, y, poly):
    inside = False
    for i in range(len(poly)):
        (x0, y0), (x1, y1) = poly[i], poly[(i + 1) % len(poly)]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def image(test):
    rows = []
    for j in range(N):
        row = []
        for i in range(N):
            hits = 0
            for sj in range(SS):
                for si in range(SS):
                    x = 2.0 * (i + (si + 0.5) / SS) / N - 1.0
                    y = 1.0 - 2.0 * (j + (sj + 0.5) / SS) / N   # +y up, row 0 at the top
                    hits += test(x, y)
            row.append(round(255 * hits / (SS * SS)))
        rows.append(row)
    return rows


star = [(0.95 * (1.0 if k % 2 == 0 else 0.4) * math.cos(math.pi / 2 + k * math.pi / 5),
         0.95 * (1.0 if k % 2 == 0 else 0.4) * math.sin(math.pi / 2 + k * math.pi / 5)) for k in range(10)]
heart = [(16 * math.sin(t) ** 3 / 17.5, (13 * math.cos(t) - 5 * math.cos(2 * t) - 2 * math.cos(3 * t) - math.cos(4 * t) + 2.5) / 17.5)
         for t in (2 * math.pi * k / 400 for k in range(400))]
here = os.path.dirname(os.path.abspath(__file__))
write_png(os.path.join(here, "star.png"), image(lambda x, y: inside_polygon(x, y, star)))
write_png(os.path.join(here, "heart.png"), image(lambda x, y: inside_polygon(x, y, heart)))
write_png(os.path.join(here, "ring.png"), image(lambda x, y: 0.45 <= math.hypot(x, y) <= 0.97))
write_png(os.path.join(here, "cats-eye.png"), image(lambda x, y: math.hypot(x - 0.45, y) <= 0.97 and math.hypot(x + 0.45, y) <= 0.97))
