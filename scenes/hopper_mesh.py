#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes scenes/hopper-mesh.stl, the hopper of scenes/hopper-mesh.toml as a triangle mesh.

The hopper of scenes/hopper.toml (a cone from radius 0.065 m at z = 0 to 0.1 m at z = 0.05 under
a cylinder of radius 0.1 m up to z = 0.6) as a binary STL: each surface a band of N flat facets
around the z axis (the vertices on the true surface), the cylinder in four rings. The spheres
meet the facets' inner faces; a mesh wall is two-sided, so the winding does not matter.
Run from anywhere: python3 scenes/hopper_mesh.py [N] (default 48 facets around).
"""
import math
import os
import struct
import sys


def ring(radius, z, n):
    return [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n), z) for k in range(n)]


def band(lower, upper):
    """Two triangles per quad between two rings of the same count."""
    n = len(lower)
    out = []
    for k in range(n):
        a, b = lower[k], lower[(k + 1) % n]
        c, d = upper[(k + 1) % n], upper[k]
        out += [(a, b, c), (a, c, d)]
    return out


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 48
    rings = [ring(0.065, 0.0, n), ring(0.1, 0.05, n)]
    rings += [ring(0.1, 0.05 + 0.55 * (k + 1) / 4, n) for k in range(4)]
    tris = []
    for lo, hi in zip(rings, rings[1:]):
        tris += band(lo, hi)
    write_binary_stl("hopper-mesh.stl", b"tumble scenes/hopper_mesh.py: the hopper of hopper.toml", tris)


def write_binary_stl(name, header, tris):
    """Writes the triangles (three (x, y, z) corners each) as a binary STL next to this script,
    with their unit normals and an 80-byte header (scenes/drum_mesh.py uses it too)."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), name)
    with open(path, "wb") as f:
        f.write(header.ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            e1 = [t[1][i] - t[0][i] for i in range(3)]
            e2 = [t[2][i] - t[0][i] for i in range(3)]
            nrm = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
            length = math.sqrt(sum(c * c for c in nrm))
            f.write(struct.pack("<3f", *[c / length for c in nrm]))
            for v in t:
                f.write(struct.pack("<3f", *v))
            f.write(struct.pack("<H", 0))
    print(f"{path}: {len(tris)} triangles")


if __name__ == "__main__":
    main()
