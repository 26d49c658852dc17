#!/usr/bin/env python3
"""Writes assets/knot.obj: a (2, 3) torus knot tube with smooth normals and UVs (no downloaded
assets). Python standard library only:  python3 assets/make_meshes.py [out.obj] [segments] [sides]

The knot's centre line is r(t) = ((2 + cos 3t) cos 2t, sin 3t, (2 + cos 3t) sin 2t) / 3; the tube
has radius 0.15, built on the curve's parallel-transported frame so it does not twist.
"""
import math
import sys


def curve(t):
    r = 2.0 + math.cos(3.0 * t)
    return (r * math.cos(2.0 * t) / 3.0, math.sin(3.0 * t) / 3.0, r * math.sin(2.0 * t) / 3.0)


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def add(a, b): return tuple(x + y for x, y in zip(a, b))
def mul(a, s): return tuple(x * s for x in a)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def norm(a): return mul(a, 1.0 / math.sqrt(dot(a, a)))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "assets/knot.obj"
    segments = int(sys.argv[2]) if len(sys.argv) > 2 else 400
    sides = int(sys.argv[3]) if len(sys.argv) > 3 else 24
    radius = 0.15
    ts = [2.0 * math.pi * i / segments for i in range(segments)]
    points = [curve(t) for t in ts]
    tangents = [norm(sub(points[(i + 1) % segments], points[i - 1])) for i in range(segments)]
    # Parallel transport of a normal along the closed curve, then spread the closing twist evenly.
    n = norm(cross(tangents[0], (0.0, 1.0, 0.0)))
    normals = []
    for i in range(segments):
        n = norm(sub(n, mul(tangents[i], dot(n, tangents[i]))))
        normals.append(n)
    end = norm(sub(n, mul(tangents[0], dot(n, tangents[0]))))
    twist = math.atan2(dot(cross(normals[0], end), tangents[0]), dot(normals[0], end))
    lines = ["# (2, 3) torus knot, caustic assets/make_meshes.py"]
    for i in range(segments):
        t, n0 = tangents[i], normals[i]
        angle = -twist * i / segments
        b0 = cross(t, n0)
        n1 = add(mul(n0, math.cos(angle)), mul(b0, math.sin(angle)))
        b1 = cross(t, n1)
        for j in range(sides):
            a = 2.0 * math.pi * j / sides
            d = add(mul(n1, math.cos(a)), mul(b1, math.sin(a)))
            p = add(points[i], mul(d, radius))
            lines.append("v %.6f %.6f %.6f" % p)
            lines.append("vn %.6f %.6f %.6f" % d)
            lines.append("vt %.6f %.6f" % (i / segments * 8.0, j / sides))
    for i in range(segments):
        for j in range(sides):
            a = i * sides + j + 1
            b = ((i + 1) % segments) * sides + j + 1
            c = ((i + 1) % segments) * sides + (j + 1) % sides + 1
            d = i * sides + (j + 1) % sides + 1
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, b, b, b, c, c, c))
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, c, c, c, d, d, d))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(out)


if __name__ == "__main__":
    main()
