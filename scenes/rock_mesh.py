#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes scenes/rock.obj, the grain of scenes/rocks.toml: a rock-like closed mesh.

An icosahedron subdivided twice (320 triangles, 162 vertices) whose vertices are pushed out or
in along their direction by a smooth random bump field (three low-order "blobs" from a fixed
linear congruential generator, so the file is the same with any Python), then stretched to
about 30 x 22 x 16 mm: an angular, flattened pebble about 22 mm across. Outward winding, every
edge shared by two triangles (tumble clump checks it).
Run from anywhere: python3 scenes/rock_mesh.py
"""
import math
import os

state = 20261207


def uniform():
    """A number in [0, 1) from a 32-bit linear congruential generator (Numerical Recipes)."""
    global state
    state = (1664525 * state + 1013904223) % 2**32
    return state / 2**32


def normalized(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def icosphere(levels):
    t = (1 + math.sqrt(5)) / 2
    vs = [normalized(v) for v in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                                  (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    fs = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
          (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
          (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                middle[key] = len(vs)
                vs.append(normalized(tuple((p + q) / 2 for p, q in zip(vs[a], vs[b]))))
            return middle[key]

        out = []
        for a, b, c in fs:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        fs = out
    return vs, fs


def main():
    vs, fs = icosphere(2)
    blobs = [(normalized((2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1)), 0.25 * (2 * uniform() - 1))
             for _ in range(3)]
    out = []
    for v in vs:
        r = 1.0
        for d, h in blobs:
            r += h * max(0.0, sum(a * b for a, b in zip(v, d))) ** 2
        r *= 1 + 0.06 * (2 * uniform() - 1)  # facets: a little roughness per vertex
        out.append((0.015 * r * v[0], 0.011 * r * v[1], 0.008 * r * v[2]))
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "rock.obj")
    with open(path, "w") as f:
        f.write("# scenes/rock_mesh.py: a rock-like pebble for scenes/rocks.toml (m)\n")
        for x, y, z in out:
            f.write("v %.6f %.6f %.6f\n" % (x, y, z))
        for a, b, c in fs:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    print("wrote %s: %d vertices, %d triangles" % (path, len(out), len(fs)))


main()
