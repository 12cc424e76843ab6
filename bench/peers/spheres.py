#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Single spheres under Hertz-Mindlin, written for tumble and for LIGGGHTS from one body list.

usage: spheres.py N OUTDIR        (N = 16000 or 128000 spheres)

Writes OUTDIR/spheres_N_hertz-mindlin.toml (a tumble scene, law = "hertz-mindlin", every body
listed) and OUTDIR/spheres_N.data (a LIGGGHTS data file, atom_style sphere, for
bench/peers/in.spheres_hertz). SI units: spheres of radius 5 mm and density 2500 kg/m^3 of one
material (E = 1e7 Pa, nu = 0.3, e = 0.5, mu = 0.5, also the ground's), dt = 5e-5 s (the Hertz
contact of two spheres meeting at 0.5 m/s lasts about 1.7 ms: 34 steps), gravity 9.81 m/s^2,
the ground z = 0. The lattice: nx x ny x nz spheres at spacing 2.2 radii, each position
jittered uniformly by +-0.05 radii per component, the lowest layer 0.1 radii above the ground,
velocities uniform in +-0.25 m/s per component, no spin; Python's Mersenne Twister with seed
12345, drawn per sphere in the order jitter x, y, z, then velocity x, y, z.
"""
import sys

from peer_files import jittered_lattice, write_data, write_scene

DIMS = {16000: (40, 40, 10), 128000: (80, 80, 20)}
RADIUS, DENSITY = 0.005, 2500.0
YOUNG, POISSON, RESTITUTION, FRICTION = 1.0e7, 0.3, 0.5, 0.5
SPACING = 2.2 * RADIUS
DT = 5.0e-5


def spheres(n):
    return jittered_lattice(DIMS[n], SPACING, 1.1 * RADIUS, 0.05 * RADIUS, 0.25)


def write_tumble(path, n, bs):
    lines = ['# Single spheres under Hertz-Mindlin, %d spheres (bench/peers/spheres.py), against' % n,
             '# LIGGGHTS (bench/peers/in.spheres_hertz) on the same bodies.', '',
             '[scene]', 'name = "spheres-%d"' % n, 'dt = %g' % DT, 'steps = 2500', 'gravity = [0.0, 0.0, -9.81]', '',
             '[contact]', 'law = "hertz-mindlin"', '',
             '[[material]]', 'name = "glass"', 'density = %g' % DENSITY, 'youngs_modulus = %g' % YOUNG,
             'poisson_ratio = %g' % POISSON, 'restitution = %g' % RESTITUTION, 'friction = %g' % FRICTION, '',
             '[ground]', 'height = 0.0', 'material = "glass"', '',
             '[[shape]]', 'name = "ball"', '[[shape.sphere]]', 'radius = %g' % RADIUS, 'material = "glass"']
    write_scene(path, lines, 'ball', bs)


def write_liggghts(path, n, bs):
    nx, ny, nz = DIMS[n]
    # atom_style sphere: type diameter density x y z
    atoms = ['1 %.9g %.9g %.9g %.9g %.9g' % (2 * RADIUS, DENSITY, b[0], b[1], b[2]) for b in bs]
    write_data(path, 'spheres N=%d written by bench/peers/spheres.py' % n,
               ((-SPACING, (nx + 1) * SPACING), (-SPACING, (ny + 1) * SPACING), (0.0, (nz + 4) * SPACING)), atoms,
               [b[3:] for b in bs])


def main():
    if len(sys.argv) != 3 or int(sys.argv[1]) not in DIMS:
        sys.exit('usage: spheres.py N OUTDIR   (N in %s)' % ', '.join(str(k) for k in sorted(DIMS)))
    n, out = int(sys.argv[1]), sys.argv[2]
    bs = spheres(n)
    write_tumble('%s/spheres_%d_hertz-mindlin.toml' % (out, n), n, bs)
    write_liggghts('%s/spheres_%d.data' % (out, n), n, bs)
    print('wrote %s/spheres_%d_hertz-mindlin.toml and spheres_%d.data: %d spheres' % (out, n, n, len(bs)))


if __name__ == '__main__':
    main()
