#!/usr/bin/env python3
"""Writes assets/sky.hdr: a procedural equirectangular HDR sky (no downloaded assets).

Layout as caustic reads maps (docs/scene-format.md): row 0 is the zenith, the centre column
looks down -z. A blue gradient sky, a bright horizon band, a dim brown ground, and a sun of
angular radius 1.5 degrees at elevation 35 degrees, azimuth 40 degrees from -z towards +x, with
radiance chosen so the sun gives roughly 3/4 of the sky's light on a horizontal surface.
Radiance RGBE, flat (uncompressed) scanlines. Python standard library only:
    python3 assets/make_sky.py [out.hdr] [width]
"""
import math
import struct
import sys


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return b"\0\0\0\0"
    e = math.frexp(m)[1]
    scale = math.ldexp(1.0, -e) * 256.0
    return struct.pack("BBBB", int(r * scale), int(g * scale), int(b * scale), e + 128)


def sky(d, sun):
    y = d[1]
    if y < 0.0:  # ground: dim, slightly brighter towards the horizon
        t = min(1.0, -y * 4.0)
        return tuple(c * (1.0 - 0.5 * t) for c in (0.25, 0.2, 0.15))
    t = math.sqrt(y)
    horizon, zenith = (1.1, 1.1, 1.05), (0.25, 0.45, 0.95)
    c = [h + (z - h) * t for h, z in zip(horizon, zenith)]
    cos_sun = sum(a * b for a, b in zip(d, sun))
    if cos_sun > math.cos(math.radians(1.5)):
        return (9000.0, 8200.0, 7000.0)
    glow = math.exp((cos_sun - 1.0) * 30.0) * 2.0  # a soft halo around the sun
    return tuple(v + glow * w for v, w in zip(c, (1.0, 0.9, 0.7)))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "assets/sky.hdr"
    width = int(sys.argv[2]) if len(sys.argv) > 2 else 512
    height = width // 2
    el, az = math.radians(35.0), math.radians(40.0)
    sun = (math.cos(el) * math.sin(az), math.sin(el), -math.cos(el) * math.cos(az))
    rows = []
    for j in range(height):
        theta = math.pi * (j + 0.5) / height
        row = bytearray()
        for i in range(width):
            phi = 2.0 * math.pi * ((i + 0.5) / width - 0.5)
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            row += rgbe(*sky(d, sun))
        rows.append(bytes(row))
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nSOFTWARE=caustic assets/make_sky.py\n\n")
        f.write(b"-Y %d +X %d\n" % (height, width))
        for row in rows:
            f.write(row)
    print(out)


if __name__ == "__main__":
    main()
