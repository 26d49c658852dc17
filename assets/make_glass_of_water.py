#!/usr/bin/env python3
"""Writes assets/tumbler.obj and assets/water.obj: a drinking glass and the water in it, closed
meshes with outward normals for nested dielectrics by priority (scenes/water-glass.json,
docs/materials.md "Media"). Python standard library only:  python3 assets/make_glass_of_water.py

The glass: a cylinder of radius 0.5 and height 1.2 on y = 0 with a cavity of radius 0.45 from
y = 0.08 up to the open rim (outer wall, bottom, rim ring, inner wall, cavity floor). The water: a
cylinder of radius 0.46 from y = 0.07 to y = 0.85, so it reaches 0.01 into the glass's wall and
floor; the glass takes priority there, and glass and water meet at the cavity's surface.
"""
import math
import sys

SEGMENTS = 96


class Mesh:
    def __init__(self):
        self.v, self.n, self.f = [], [], []

    def vertex(self, p, n):
        self.v.append(p)
        self.n.append(n)
        return len(self.v)  # OBJ indices start at 1

    def quad(self, a, b, c, d):  # counter-clockwise seen from the side the normal points to
        self.f.append((a, b, c))
        self.f.append((a, c, d))

    def write(self, path, comment):
        with open(path, "w") as out:
            out.write(f"# {comment} (assets/make_glass_of_water.py)\n")
            for p in self.v:
                out.write("v %.6f %.6f %.6f\n" % p)
            for n in self.n:
                out.write("vn %.6f %.6f %.6f\n" % n)
            for f in self.f:
                out.write("f " + " ".join(f"{i}//{i}" for i in f) + "\n")


def ring(radius, y, outward):
    pts = []
    for i in range(SEGMENTS):
        a = 2.0 * math.pi * i / SEGMENTS
        c, s = math.cos(a), math.sin(a)
        pts.append(((radius * c, y, radius * s), ((c, 0.0, s) if outward else (-c, 0.0, -s))))
    return pts


def wall(m, radius, y0, y1, outward):
    lo = [m.vertex(p, n) for p, n in ring(radius, y0, outward)]
    hi = [m.vertex(p, n) for p, n in ring(radius, y1, outward)]
    for i in range(SEGMENTS):
        j = (i + 1) % SEGMENTS
        # Seen from outside (outward) the ring runs clockwise with angle about +y: a, b on the
        # bottom, then up.
        if outward:
            m.quad(lo[i], hi[i], hi[j], lo[j])
        else:
            m.quad(lo[i], lo[j], hi[j], hi[i])


def disk(m, radius, y, up, inner=0.0):
    n = (0.0, 1.0 if up else -1.0, 0.0)
    outer = [m.vertex(p, n) for p, _ in ring(radius, y, True)]
    if inner > 0.0:
        inn = [m.vertex(p, n) for p, _ in ring(inner, y, True)]
        for i in range(SEGMENTS):
            j = (i + 1) % SEGMENTS
            if up:
                m.quad(inn[i], inn[j], outer[j], outer[i])
            else:
                m.quad(inn[i], outer[i], outer[j], inn[j])
        return
    centre = m.vertex((0.0, y, 0.0), n)
    for i in range(SEGMENTS):
        j = (i + 1) % SEGMENTS
        if up:
            m.f.append((centre, outer[j], outer[i]))
        else:
            m.f.append((centre, outer[i], outer[j]))


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "assets"
    glass = Mesh()
    wall(glass, 0.5, 0.0, 1.2, True)          # outer wall
    disk(glass, 0.5, 0.0, False)              # bottom, facing down
    disk(glass, 0.5, 1.2, True, inner=0.45)   # rim
    wall(glass, 0.45, 0.08, 1.2, False)       # inner wall, facing the axis (out of the glass)
    disk(glass, 0.45, 0.08, True)             # cavity floor, facing up
    glass.write(f"{folder}/tumbler.obj", "a drinking glass: radius 0.5, height 1.2, cavity radius 0.45 above y = 0.08")
    water = Mesh()
    wall(water, 0.46, 0.07, 0.85, True)
    disk(water, 0.46, 0.07, False)
    disk(water, 0.46, 0.85, True)
    water.write(f"{folder}/water.obj", "the water in assets/tumbler.obj: radius 0.46 from y = 0.07 to 0.85")


if __name__ == "__main__":
    main()
