#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The peers' clump benchmark state, written for tumble and for LAMMPS from one body list.

usage: clumps.py N OUTDIR        (N = 16000, 128000 or 960000 particles)

Writes OUTDIR/clumps_N.toml (a tumble scene with every body listed, the physics of
scenes/bench-128k.toml: the report's law), OUTDIR/clumps_N_hooke-history.toml (the same bodies
under LAMMPS's own model, law = "hooke-history" with the constants of bench/peers/in.clumps:
k_n 2e4, k_t 5714.2857, gamma_n 86.17, gamma_t 43.085, mu 0.5) and OUTDIR/clumps_N.data (a
LAMMPS data file, atom_style hybrid sphere bond, for bench/peers/in.clumps).

The lattice is the peers' clump scene: bodies of 8 spheres (radius 0.5, mass 1, density 6/pi)
at the corners of a cube of edge 0.5 around the centre; nx x ny x nz bodies at spacing 1.65;
each lattice position jittered uniformly by +-0.025 per component; the lowest layer 0.05 above
the ground z = 0; velocities uniform in +-0.5 per component, no spin. The random numbers are
Python's Mersenne Twister with seed 12345, drawn per body in the order jitter x, y, z, then
velocity x, y, z, so any generator that follows the same recipe writes the same bodies.
"""
import math
import sys

from peer_files import jittered_lattice, write_data, write_scene

DIMS = {16000: (20, 20, 5), 128000: (40, 40, 10), 960000: (80, 75, 20)}
SPACING, HALF, RADIUS = 1.65, 0.75, 0.5
OFFSETS = [(sx * 0.25, sy * 0.25, sz * 0.25) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def bodies(n):
    return jittered_lattice(DIMS[n], SPACING, HALF + 0.05, 0.025, 0.5)


CONTACT = {
    'report': ['stiffness = 2.0e4', 'damping = 43.1', 'shear = 21.5'],
    # LAMMPS's gran/hooke/history as bench/peers/in.clumps gives it.
    'hooke-history': ['law = "hooke-history"', 'stiffness = 2.0e4', 'tangential_stiffness = 5714.2857',
                      'gamma_n = 86.17', 'gamma_t = 43.085', 'friction = 0.5'],
}


def write_tumble(path, n, bs, law='report'):
    lines = ['# The peers\' clump benchmark, %d particles (bench/peers/clumps.py): the physics of' % n,
             '# scenes/bench-128k.toml with every body listed, under the law "%s".' % law, '',
             '[scene]', 'name = "clumps-%d"' % n, 'dt = 5.0e-4', 'steps = 2500', 'gravity = [0.0, 0.0, -9.81]', '',
             '[contact]'] + CONTACT[law] + ['',
             '[ground]', 'height = 0.0', 'stiffness = 2.0e4', 'friction = 0.5', '',
             '[[shape]]', 'name = "clump"']
    for o in OFFSETS:
        lines += ['[[shape.sphere]]', 'offset = [%g, %g, %g]' % o, 'radius = 0.5', 'mass = 1.0',
                  'elasticity = 0.5']
    write_scene(path, lines, 'clump', bs)


def write_lammps(path, n, bs):
    nx, ny, nz = DIMS[n]
    density = 6.0 / math.pi  # mass 1 for a sphere of diameter 1
    # hybrid sphere bond: type x y z diameter density molecule
    atoms = ['1 %.9g %.9g %.9g 1.0 %.9g %d' % (b[0] + o[0], b[1] + o[1], b[2] + o[2], density, mol)
             for mol, b in enumerate(bs, start=1) for o in OFFSETS]
    write_data(path, 'clumps N=%d written by bench/peers/clumps.py' % n,
               ((-1.0, nx * SPACING + 1.0), (-1.0, ny * SPACING + 1.0), (0.0, nz * SPACING + 2.0)), atoms,
               [b[3:] for b in bs for _ in OFFSETS])


def main():
    if len(sys.argv) != 3 or int(sys.argv[1]) not in DIMS:
        sys.exit('usage: clumps.py N OUTDIR   (N in %s)' % ', '.join(str(k) for k in sorted(DIMS)))
    n, out = int(sys.argv[1]), sys.argv[2]
    bs = bodies(n)
    write_tumble('%s/clumps_%d.toml' % (out, n), n, bs)
    write_tumble('%s/clumps_%d_hooke-history.toml' % (out, n), n, bs, 'hooke-history')
    write_lammps('%s/clumps_%d.data' % (out, n), n, bs)
    print('wrote %s/clumps_%d.toml, clumps_%d_hooke-history.toml and .data: %d bodies, %d particles' %
          (out, n, n, len(bs), 8 * len(bs)))


if __name__ == '__main__':
    main()
