#!/usr/bin/python3
"""Writes cases/pier_cylinder.stl, the bridge pier of cases/channel_pier_3d.yaml: a closed circular cylinder,
diameter 0.08 m, height 0.2 m, axis vertical through the origin, base at z = 0 (the case places it with `offset`).
The side is 64 flat facets (the polygon's area is 0.16 % below the circle's); ASCII STL in metres.
Usage: /usr/bin/python3 cases/make_pier_stl.py"""
import math
import os

R, H, N = 0.04, 0.2, 64


def facet(f, a, b, c):
    ux, uy, uz = (b[i] - a[i] for i in range(3))
    vx, vy, vz = (c[i] - a[i] for i in range(3))
    n = (uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx)
    ln = math.sqrt(sum(x * x for x in n))
    f.write("  facet normal {:.9e} {:.9e} {:.9e}\n    outer loop\n".format(*(x / ln for x in n)))
    for p in (a, b, c):
        f.write("      vertex {:.9e} {:.9e} {:.9e}\n".format(*p))
    f.write("    endloop\n  endfacet\n")


def main():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pier_cylinder.stl")
    ring = [(R * math.cos(2 * math.pi * k / N), R * math.sin(2 * math.pi * k / N)) for k in range(N)]
    with open(path, "w") as f:
        f.write("solid pier_cylinder\n")
        for k in range(N):
            (x0, y0), (x1, y1) = ring[k], ring[(k + 1) % N]
            # side (outward normals: counter-clockwise seen from outside)
            facet(f, (x0, y0, 0.0), (x1, y1, 0.0), (x1, y1, H))
            facet(f, (x0, y0, 0.0), (x1, y1, H), (x0, y0, H))
            # top (normal +z) and bottom (normal -z)
            facet(f, (0.0, 0.0, H), (x0, y0, H), (x1, y1, H))
            facet(f, (0.0, 0.0, 0.0), (x1, y1, 0.0), (x0, y0, 0.0))
        f.write("endsolid pier_cylinder\n")
    print(path)


if __name__ == "__main__":
    main()
