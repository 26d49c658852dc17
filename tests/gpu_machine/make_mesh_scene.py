#!/usr/bin/env python3
"""Writes the issue 16 mesh scene: a (p, q) torus knot tube of about N triangles as a binary PLY,
and a scene that places it twice (two instances of one mesh: the two-level BVH) on a ground
quad under the HDR sky, as scenes/mesh-knot.json places assets/knot.obj.

    make_mesh_scene.py OUTDIR [--triangles 1048576]

OUTDIR gets big-knot.ply and mesh-big.json (the scene names the PLY by its absolute path and the
sky by the checkout's assets/sky.hdr). Pure Python (the GPU machine has no numpy): about 10 s for
a million triangles. Nothing is random: the same N gives the same file.
"""
import argparse
import json
import math
import os
import struct


def torus_knot(p, q, t):
    r = 2.0 + math.cos(q * t)
    return (r * math.cos(p * t), r * math.sin(p * t), -math.sin(q * t))


def write_knot_ply(path, triangles):
    # A tube of `rings` x `sides` quads (2 triangles each) around the (2, 3) torus knot.
    sides = max(8, int(round(math.sqrt(triangles / 2.0 / 8.0))))
    rings = max(16, triangles // (2 * sides))
    radius = 0.45
    verts = []
    for i in range(rings):
        t = 2.0 * math.pi * i / rings
        c = torus_knot(2, 3, t)
        n = torus_knot(2, 3, t + 1e-3)
        tangent = [n[k] - c[k] for k in range(3)]
        tl = math.sqrt(sum(x * x for x in tangent))
        tangent = [x / tl for x in tangent]
        # A frame around the tangent: any vector not parallel to it, made orthogonal.
        up = (0.0, 0.0, 1.0) if abs(tangent[2]) < 0.9 else (1.0, 0.0, 0.0)
        b = [tangent[1] * up[2] - tangent[2] * up[1], tangent[2] * up[0] - tangent[0] * up[2],
             tangent[0] * up[1] - tangent[1] * up[0]]
        bl = math.sqrt(sum(x * x for x in b))
        b = [x / bl for x in b]
        nrm = [b[1] * tangent[2] - b[2] * tangent[1], b[2] * tangent[0] - b[0] * tangent[2],
               b[0] * tangent[1] - b[1] * tangent[0]]
        for j in range(sides):
            a = 2.0 * math.pi * j / sides
            ca, sa = math.cos(a), math.sin(a)
            verts.append(tuple(c[k] + radius * (ca * nrm[k] + sa * b[k]) for k in range(3)))
    faces = []
    for i in range(rings):
        i1 = (i + 1) % rings
        for j in range(sides):
            j1 = (j + 1) % sides
            a, b_, c, d = i * sides + j, i1 * sides + j, i1 * sides + j1, i * sides + j1
            faces.append((a, b_, c))
            faces.append((a, c, d))
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\n"
                 f"comment (2, 3) torus knot tube, {rings} x {sides}, tests/gpu_machine/make_mesh_scene.py\n"
                 f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
                 f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        f.write(b"".join(struct.pack("<3f", *v) for v in verts))
        f.write(b"".join(struct.pack("<B3i", 3, *t) for t in faces))
    return len(faces)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("--triangles", type=int, default=1 << 20)
    args = ap.parse_args()
    os.makedirs(args.outdir, exist_ok=True)
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    ply = os.path.abspath(os.path.join(args.outdir, "big-knot.ply"))
    count = write_knot_ply(ply, args.triangles)
    scene = {
        "version": 1,
        "camera": {"position": [0, 1.4, 4.2], "look_at": [0, 0.45, 0], "fov": 38, "fov_axis": "x"},
        "render": {"width": 480, "height": 320, "samples": 64, "max_depth": 8},
        "materials": [
            {"name": "ground", "type": "diffuse", "albedo": [0.22, 0.22, 0.22]},
            {"name": "gold", "type": "conductor", "metal": "gold", "roughness": 0.15},
            {"name": "clay", "type": "diffuse", "albedo": [0.8, 0.35, 0.25]},
        ],
        "objects": [
            {"name": "ground", "shape": "quad", "material": "ground",
             "transform": {"rotate": [-90, 0, 0], "scale": 10}},
            {"name": "gold knot", "shape": "mesh", "file": ply, "material": "gold",
             "transform": {"translate": [-0.75, 0.5, 0], "rotate": [0, 20, 0], "scale": 0.22}},
            {"name": "clay knot", "shape": "mesh", "file": ply, "material": "clay",
             "transform": {"translate": [0.8, 0.5, -0.3], "rotate": [90, 0, 30], "scale": [0.2, 0.2, 0.28]}},
        ],
        "environment": {"type": "map", "file": os.path.join(root, "assets", "sky.hdr"), "intensity": 0.45},
    }
    out = os.path.join(args.outdir, "mesh-big.json")
    with open(out, "w") as f:
        json.dump(scene, f, indent=2)
    print(f"{out}: {count} triangles in {ply}")


if __name__ == "__main__":
    main()
