#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes scenes/drum-mesh.stl, the drum with lifters of scenes/drum-mesh.toml, as a triangle mesh.

The drum of scenes/drum.toml (radius 0.15 m about the y axis, from y = -0.03 to 0.03) as a binary
STL: its side a band of N flat facets (the vertices on the circle, turned by half a facet so that
a facet lies flat at the bottom), its two ends fans about the axis, and L lifters: radial plates
H high along the whole depth (0.5 mm short of the ends, their outer edge 0.1 mm inside the
facets), the first at the top. A mesh wall is thin and two-sided: the spheres meet the facets'
inner faces and both faces of the lifters. Run from anywhere: python3 scenes/drum_mesh.py [N [L [H]]]
(default 72 facets, 4 lifters 15 mm high).
"""
import math
import sys

from hopper_mesh import write_binary_stl  # next to this script

RADIUS, Y0, Y1 = 0.15, -0.03, 0.03


def point(radius, angle, y):
    """A point at `radius` from the axis, `angle` from +x towards +z, at y."""
    return (radius * math.cos(angle), y, radius * math.sin(angle))


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 72
    lifters = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    height = float(sys.argv[3]) if len(sys.argv) > 3 else 0.015
    angles = [-0.5 * math.pi + 2 * math.pi * (k + 0.5) / n for k in range(n)]
    back = [point(RADIUS, a, Y0) for a in angles]
    front = [point(RADIUS, a, Y1) for a in angles]
    tris = []
    for k in range(n):
        j = (k + 1) % n
        tris += [(back[k], back[j], front[j]), (back[k], front[j], front[k])]  # the side
        tris += [((0.0, Y0, 0.0), back[j], back[k]), ((0.0, Y1, 0.0), front[k], front[j])]  # the ends
    outer = RADIUS * math.cos(math.pi / n) - 1e-4
    for k in range(lifters):
        a = 0.5 * math.pi + 2 * math.pi * k / lifters
        p = [point(outer, a, Y0 + 5e-4), point(outer, a, Y1 - 5e-4), point(outer - height, a, Y1 - 5e-4),
             point(outer - height, a, Y0 + 5e-4)]
        tris += [(p[0], p[1], p[2]), (p[0], p[2], p[3])]
    write_binary_stl("drum-mesh.stl", b"tumble scenes/drum_mesh.py: a drum with lifters", tris)


if __name__ == "__main__":
    main()
