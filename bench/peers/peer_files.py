# SPDX-License-Identifier: MIT
"""The files both generators (clumps.py, spheres.py) write: a tumble scene that lists every
body, and a LAMMPS/LIGGGHTS data file (its header, box, Atoms and Velocities sections)."""


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
