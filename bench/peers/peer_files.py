# SPDX-License-Identifier: MIT
"""What both generators (clumps.py, spheres.py) share: the jittered lattice of bodies, and the
files they write: a tumble scene that lists every body, and a LAMMPS/LIGGGHTS data file (its
header, box, Atoms and Velocities sections)."""
import random


def jittered_lattice(dims, spacing, z0, jitter, speed):
    """(x, y, z, vx, vy, vz) of nx x ny x nz bodies at `spacing`, the lowest layer at z0, each
    position jittered uniformly by +-jitter per component, velocities uniform in +-speed; Python's
    Mersenne Twister with seed 12345, drawn per body in the order jitter x, y, z, then velocity
    x, y, z."""
    nx, ny, nz = dims
    rng = random.Random(12345)
    out = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                x = (i + 0.5) * spacing + rng.uniform(-jitter, jitter)
                y = (j + 0.5) * spacing + rng.uniform(-jitter, jitter)
                z = z0 + k * spacing + rng.uniform(-jitter, jitter)
                v = [rng.uniform(-speed, speed) for _ in range(3)]
                out.append((x, y, z, v[0], v[1], v[2]))
    return out


def write_scene(path, lines, shape, bodies):
    """The scene's `lines` (its tables), then a [[body]] of `shape` per (x, y, z, vx, vy, vz)."""
    lines = list(lines)
    for b in bodies:
        lines += ['[[body]]', 'shape = "%s"' % shape, 'position = [%.9g, %.9g, %.9g]' % b[:3],
                  'velocity = [%.9g, %.9g, %.9g]' % b[3:]]
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def write_data(path, title, box, atoms, velocities):
    """A data file of one atom type: `box` ((xlo, xhi), (ylo, yhi), (zlo, zhi)), the Atoms lines
    (each atom's fields after its id, as the atom style wants them) and each atom's velocity
    (vx, vy, vz; no spin)."""
    with open(path, 'w') as f:
        f.write('%s\n\n' % title)
        f.write('%d atoms\n1 atom types\n' % len(atoms))
        for (lo, hi), axis in zip(box, 'xyz'):
            f.write('%.6f %.6f %slo %shi\n' % (lo, hi, axis, axis))
        f.write('\nAtoms\n\n')
        for a, fields in enumerate(atoms, start=1):
            f.write('%d %s\n' % (a, fields))
        f.write('\nVelocities\n\n')
        for a, v in enumerate(velocities, start=1):
            f.write('%d %.9g %.9g %.9g 0 0 0\n' % (a, v[0], v[1], v[2]))
