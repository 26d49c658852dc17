#!/usr/bin/env python3
"""Writes the textured-mesh gallery asset (no downloaded assets), Python standard library only:

    python3 assets/make_textured.py [folder]        (default: assets/tiles)

into the folder:
  torus.obj      a torus (major radius 1, minor 0.35, in the y = 0 plane) with normals and UVs:
                 u runs 0..3 around the ring, v 0..1 around the tube, so the 4 x 4 tiles of the
                 textures repeat 12 times around and 4 times across; counter-clockwise from outside
  albedo.png     metal tiles (copper, brass, steel, teal patina; 8-bit sRGB) in dark grout
  normal.png     tangent-space normal map, (n + 1) / 2: x along u, y along v, z along the normal;
                 the tiles are raised with bevelled edges, grooves between them
  roughness.png  GGX alpha in the first channel (linear, x 255): polished, satin and brushed
                 tiles (0.02, 0.15, 0.45) and rough grout (0.7)
  torus.gltf, torus.bin, metallic_roughness.png
                 the same torus as glTF 2.0 with its own material: base colour albedo.png, normal
                 map normal.png, and the metallic-roughness texture glTF defines (section 3.9.2:
                 G = perceptual roughness, the square root of the alpha above; B = metalness, 1
                 everywhere; R unused), for caustic's mapping of a file's materials

The top row of an image is v = 1 (docs/scene-format.md, textures). The PNGs are written with
zlib directly (filter 0 rows), 256 x 256 RGB.
"""
import json
import math
import os
import struct
import sys
import zlib

SIZE = 256          # texels per side
TILES = 4           # tiles per side of the texture
GROOVE = 0.035      # half the grout width, in tile units
BEVEL = 0.09        # where the bevel reaches the tile's flat top

# Per tile (x + y * TILES, hashed): its colour (sRGB) and its alpha.
PALETTE = [(0.96, 0.64, 0.54), (0.91, 0.78, 0.42), (0.76, 0.77, 0.79), (0.45, 0.76, 0.68)]
ALPHAS = [0.02, 0.15, 0.45]
GROUT_COLOUR = (0.16, 0.15, 0.14)
GROUT_ALPHA = 0.7


def write_png(path, width, height, rows):
    """rows: height lists of width (r, g, b) tuples of floats in [0, 1], top row first."""
    raw = bytearray()
    for row in rows:
        raw.append(0)
        for r, g, b in row:
            raw += bytes(max(0, min(255, int(round(c * 255.0)))) for c in (r, g, b))

    def chunk(kind, payload):
        body = kind + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body) & 0xffffffff)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(bytes(raw), 9)))
        f.write(chunk(b"IEND", b""))


def smoothstep(a, b, x):
    t = max(0.0, min(1.0, (x - a) / (b - a)))
    return t * t * (3.0 - 2.0 * t)


def tile_of(u, v):
    """(tile index hash, distance to the tile's edge in tile units) at texture coordinates u, v."""
    x, y = u * TILES, v * TILES
    ix, iy = int(math.floor(x)) % TILES, int(math.floor(y)) % TILES
    fx, fy = x - math.floor(x), y - math.floor(y)
    edge = min(fx, 1.0 - fx, fy, 1.0 - fy)
    h = (ix * 7 + iy * 13 + ix * iy * 5) % 11
    return h, edge


def height(u, v):
    _, edge = tile_of(u, v)
    return smoothstep(GROOVE, BEVEL, edge)


def textures():
    albedo, normal, rough = [], [], []
    d = 0.5 / SIZE                      # finite-difference step in uv
    amplitude = 0.025                   # tile height in uv units (how strong the bevel is)
    for row in range(SIZE):
        v = 1.0 - (row + 0.5) / SIZE     # the top row is v = 1
        a_row, n_row, r_row = [], [], []
        for col in range(SIZE):
            u = (col + 0.5) / SIZE
            h, edge = tile_of(u, v)
            grout = edge < GROOVE
            if grout:
                a_row.append(GROUT_COLOUR)
                r_row.append((GROUT_ALPHA,) * 3)
            else:
                c = PALETTE[h % len(PALETTE)]
                # A faint brushed streak along u so the tiles are not flat colour.
                streak = 0.96 + 0.04 * math.sin(2.0 * math.pi * (v * 61.0 + 0.3 * math.sin(u * 17.0)))
                a_row.append(tuple(x * streak for x in c))
                r_row.append((ALPHAS[h % len(ALPHAS)],) * 3)
            dhdu = (height(u + d, v) - height(u - d, v)) / (2.0 * d) * amplitude
            dhdv = (height(u, v + d) - height(u, v - d)) / (2.0 * d) * amplitude
            nx, ny, nz = -dhdu, -dhdv, 1.0
            inv = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
            n_row.append(tuple(0.5 * (c * inv) + 0.5 for c in (nx, ny, nz)))
        albedo.append(a_row)
        normal.append(n_row)
        rough.append(r_row)
    return albedo, normal, rough


def torus_arrays(rings=72, sides=28, major=1.0, minor=0.35, repeat_u=3.0, repeat_v=1.0):
    """(positions, normals, uvs, triangles) of the torus torus() writes, 0-based."""
    pos, nor, uv, tris = [], [], [], []
    for i in range(rings + 1):
        phi = 2.0 * math.pi * i / rings
        for j in range(sides + 1):
            theta = 2.0 * math.pi * j / sides
            nor.append((math.cos(theta) * math.cos(phi), math.sin(theta), math.cos(theta) * math.sin(phi)))
            pos.append(((major + minor * math.cos(theta)) * math.cos(phi), minor * math.sin(theta),
                        (major + minor * math.cos(theta)) * math.sin(phi)))
            uv.append((repeat_u * i / rings, repeat_v * j / sides))
    stride = sides + 1
    for i in range(rings):
        for j in range(sides):
            a, b = i * stride + j, (i + 1) * stride + j
            tris += [(a, a + 1, b + 1), (a, b + 1, b)]
    return pos, nor, uv, tris


def gltf(folder, mr_name="metallic_roughness.png"):
    """torus.gltf + torus.bin: the torus with a metallic-roughness material (glTF 2.0)."""
    pos, nor, uv, tris = torus_arrays()
    blob = bytearray()
    views = []
    for data, fmt in ((pos, "<3f"), (nor, "<3f"), ([(u, 1.0 - v) for u, v in uv], "<2f")):
        start = len(blob)
        for item in data:
            blob += struct.pack(fmt, *item)
        views.append((start, len(blob) - start))
    start = len(blob)
    for t in tris:
        blob += struct.pack("<3H", *t)
    views.append((start, len(blob) - start))
    with open(os.path.join(folder, "torus.bin"), "wb") as f:
        f.write(blob)
    lo = [min(p[k] for p in pos) for k in range(3)]
    hi = [max(p[k] for p in pos) for k in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "caustic assets/make_textured.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "torus"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"name": "metal tiles",
                       "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 1.0,
                                                "roughnessFactor": 1.0, "metallicRoughnessTexture": {"index": 1}},
                       "normalTexture": {"index": 2}}],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}],
        "images": [{"uri": "albedo.png"}, {"uri": mr_name}, {"uri": "normal.png"}],
        "buffers": [{"uri": "torus.bin", "byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": n} for o, n in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5126, "count": len(nor), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": len(uv), "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 3 * len(tris), "type": "SCALAR"},
        ],
    }
    with open(os.path.join(folder, "torus.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def torus(path, rings=72, sides=28, major=1.0, minor=0.35, repeat_u=3.0, repeat_v=1.0):
    lines = ["# torus with UVs, caustic assets/make_textured.py"]
    for i in range(rings + 1):           # the seam is duplicated so the UVs can run 0..repeat
        phi = 2.0 * math.pi * i / rings
        for j in range(sides + 1):
            theta = 2.0 * math.pi * j / sides
            n = (math.cos(theta) * math.cos(phi), math.sin(theta), math.cos(theta) * math.sin(phi))
            p = ((major + minor * math.cos(theta)) * math.cos(phi), minor * math.sin(theta),
                 (major + minor * math.cos(theta)) * math.sin(phi))
            lines.append("v %.5f %.5f %.5f" % p)
            lines.append("vn %.4f %.4f %.4f" % n)
            lines.append("vt %.5f %.5f" % (repeat_u * i / rings, repeat_v * j / sides))
    stride = sides + 1
    for i in range(rings):
        for j in range(sides):
            a, b = i * stride + j + 1, (i + 1) * stride + j + 1
            c, d = b + 1, a + 1
            # Counter-clockwise seen from outside: at phi = theta = 0, d - a runs along +y (theta)
            # and b - a along +z (phi), and (d - a) x (b - a) = +x, the outward normal there.
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, d, d, d, c, c, c))
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, c, c, c, b, b, b))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "tiles")
    os.makedirs(folder, exist_ok=True)
    albedo, normal, rough = textures()
    write_png(os.path.join(folder, "albedo.png"), SIZE, SIZE, albedo)
    write_png(os.path.join(folder, "normal.png"), SIZE, SIZE, normal)
    write_png(os.path.join(folder, "roughness.png"), SIZE, SIZE, rough)
    # glTF's packed texture: G = perceptual roughness = sqrt(alpha), B = metalness (all metal).
    packed = [[(0.0, math.sqrt(r[0]), 1.0) for r in row] for row in rough]
    write_png(os.path.join(folder, "metallic_roughness.png"), SIZE, SIZE, packed)
    torus(os.path.join(folder, "torus.obj"))
    gltf(folder)
    for name in ("torus.obj", "albedo.png", "normal.png", "roughness.png", "metallic_roughness.png",
                 "torus.gltf", "torus.bin"):
        p = os.path.join(folder, name)
        print(p, os.path.getsize(p), "bytes")


if __name__ == "__main__":
    main()
