#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The slope of a heap from a state file (tumble run SCENE --state-out STATE.csv).

    python3 examples/heap_angle.py STATE.csv [--bins 12]

The heap's surface is the highest body centre in each of `bins` rings around the centre of
mass (out to the radius holding 98 % of the bodies); the slope is a least-squares line through
the rings from 20 % to 85 % of that radius, and the angle its arctangent. A regression figure,
not an oracle: a collapsed column's flank is below the angle of repose of a poured heap.
"""
import argparse
import csv
import math
import sys


def heap_angle(rows, bins=12):
    pts = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in rows]
    if len(pts) < 10:
        raise ValueError("a heap needs at least 10 bodies, the state has %d" % len(pts))
    cx = sum(p[0] for p in pts) / len(pts)
    cy = sum(p[1] for p in pts) / len(pts)
    rad = [(math.hypot(x - cx, y - cy), z) for x, y, z in pts]
    rmax = sorted(r for r, _ in rad)[int(0.98 * (len(rad) - 1))]
    top = [None] * bins
    for r, z in rad:
        b = int(r / rmax * bins)
        if b < bins and (top[b] is None or z > top[b]):
            top[b] = z
    ring = [((b + 0.5) / bins * rmax, top[b]) for b in range(bins)
            if top[b] is not None and 0.2 * bins <= b < 0.85 * bins]
    if len(ring) < 2:
        raise ValueError("too few rings with bodies to fit a slope")
    mx = sum(x for x, _ in ring) / len(ring)
    my = sum(z for _, z in ring) / len(ring)
    slope = sum((x - mx) * (z - my) for x, z in ring) / sum((x - mx) ** 2 for x, _ in ring)
    return math.degrees(math.atan(-slope)), rmax, max(z for _, z in rad), top


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("state", help="CSV written by tumble run --state-out")
    ap.add_argument("--bins", type=int, default=12, help="rings around the centre (default 12)")
    a = ap.parse_args()
    try:
        with open(a.state, newline="") as f:
            rows = list(csv.DictReader(f))
        angle, rmax, height, top = heap_angle(rows, a.bins)
    except (OSError, KeyError, ValueError) as e:
        sys.exit("heap_angle.py: %s: %s" % (a.state, e))
    print("heap: %d bodies, radius %.3f m (98 %%), highest centre %.3f m" % (len(rows), rmax, height))
    print("surface by ring (m): " + " ".join("%.3f" % t if t is not None else "-" for t in top))
    print("slope angle: %.1f degrees" % angle)


if __name__ == "__main__":
    main()
