#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Binary collisions under hooke-history, run by tumble and by LAMMPS gran/hooke/history.

    python3 validation/lammps/binary_collisions.py TUMBLE_BIN [OUT_DIR] [--lmp lmp]

Five pairs of spheres, far apart from each other, collide once each (head-on, oblique sticking,
oblique sliding, with spin, unequal spheres) with the same parameters in both codes: k_n, k_t =
2/7 k_n, gamma_n, gamma_t = gamma_n / 2 (both times m_eff), mu, no gravity, no ground. After the
collisions every sphere's velocity and spin must agree to 1e-3 of the pair's speed (spin times
the radius). What may differ, by design: the integrator (tumble's leapfrog, LAMMPS's velocity
Verlet; dt is t_c / 250), the lever to the contact point (tumble r - delta/2, LAMMPS r), the
contact velocity's spin term (LAMMPS weights the spins by the radii), and tumble's float
positions against LAMMPS's doubles: a step moves a sphere by some 20 ulp of its coordinate here,
and finer steps make the rounding, not the physics, dominate (measured largest differences:
2.3e-4, 4.8e-4 and 1.4e-3 at 250, 500 and 1000 steps per contact; delta / r up to 3e-3).

Exits 77 (a skip for ctest) with a message when LAMMPS (lmp) is not installed: apt-get install
lammps. Writes the scene, the LAMMPS deck and both results to OUT_DIR (default: a temporary one).
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile

KN, GAMMA_N, MU = 1.0e6, 500.0, 0.3  # zeta = 0.18 for m_eff = 0.5: e = 0.57
KT, GAMMA_T = KN * 2.0 / 7.0, GAMMA_N / 2.0
STEPS_PER_CONTACT = 250
TOL = 1e-3

# (name, r1, m1, r2, m2, closing speed, tangential speed, spin of sphere 1 about z)
CASES = [
    ("head-on", 0.5, 1.0, 0.5, 1.0, 1.0, 0.0, 0.0),
    ("oblique, sticking", 0.5, 1.0, 0.5, 1.0, 1.0, 0.1, 0.0),
    ("oblique, sliding", 0.5, 1.0, 0.5, 1.0, 1.0, 2.0, 0.0),
    ("spinning", 0.5, 1.0, 0.5, 1.0, 1.0, 0.0, 6.0),
    ("unequal", 0.5, 1.0, 0.3, 0.25, 2.0, 0.5, -3.0),
]
SPACING = 10.0  # m between pairs along y: they never meet


def spheres():
    """Per sphere: radius, mass, position, velocity, spin (world frame), in pair order."""
    out = []
    for k, (_, r1, m1, r2, m2, vn, vt, w1) in enumerate(CASES):
        y = SPACING * k
        gap = 1e-5  # they start apart and close in
        # Momentum zero: each sphere's share of the relative velocity by the other's mass.
        f1, f2 = m2 / (m1 + m2), m1 / (m1 + m2)
        out.append((r1, m1, (-r1 - 0.5 * gap, y, 0.0), (f1 * vn, f1 * vt, 0.0), (0.0, 0.0, w1)))
        out.append((r2, m2, (r2 + 0.5 * gap, y, 0.0), (-f2 * vn, -f2 * vt, 0.0), (0.0, 0.0, 0.0)))
    return out


def timing():
    """dt and steps: t_c / STEPS_PER_CONTACT of the lightest pair, run to 1.5 t_c of the slowest."""
    tcs = []
    for _, r1, m1, r2, m2, _, _, _ in CASES:
        meff = m1 * m2 / (m1 + m2)
        w0 = math.sqrt(KN / meff)
        zeta = GAMMA_N / (2.0 * w0)
        tcs.append(math.pi / (w0 * math.sqrt(1.0 - zeta * zeta)))
    dt = min(tcs) / STEPS_PER_CONTACT
    gap_time = 1e-5 / min(c[5] for c in CASES)
    return dt, int(math.ceil((1.5 * max(tcs) + gap_time) / dt))


def tumble_scene(dt, steps):
    lines = ["# binary collisions: tumble's side of validation/lammps/binary_collisions.py",
             "[scene]", 'name = "binary-collisions"', "dt = %.9g" % dt, "steps = %d" % steps,
             "gravity = [0.0, 0.0, 0.0]", "",
             "[contact]", 'law = "hooke-history"', "stiffness = %.9g" % KN,
             "tangential_stiffness = %.9g" % KT, "gamma_n = %.9g" % GAMMA_N, "gamma_t = %.9g" % GAMMA_T,
             "friction = %.9g" % MU, ""]
    for i, (r, m, x, v, w) in enumerate(spheres()):
        lines += ["[[shape]]", 'name = "s%d"' % i, "[[shape.sphere]]", "radius = %.9g" % r, "mass = %.9g" % m, ""]
    for i, (r, m, x, v, w) in enumerate(spheres()):
        lines += ["[[body]]", 'shape = "s%d"' % i, "position = [%.9g, %.9g, %.9g]" % x,
                  "velocity = [%.9g, %.9g, %.9g]" % v, "angular_velocity = [%.9g, %.9g, %.9g]" % w, ""]
    return "\n".join(lines)


def lammps_inputs(dt, steps):
    sp = spheres()
    ymax = SPACING * len(CASES)
    data = ["binary collisions: LAMMPS's side of validation/lammps/binary_collisions.py", "",
            "%d atoms" % len(sp), "1 atom types", "",
            "-5 5 xlo xhi", "-5 %g ylo yhi" % ymax, "-5 5 zlo zhi", "", "Atoms # sphere", ""]
    for i, (r, m, x, v, w) in enumerate(sp):
        rho = m / (math.pi / 6.0 * (2 * r) ** 3)
        data.append("%d 1 %.17g %.17g %.17g %.17g %.17g" % (i + 1, 2 * r, rho, x[0], x[1], x[2]))
    data += ["", "Velocities", ""]
    for i, (r, m, x, v, w) in enumerate(sp):
        data.append("%d %.17g %.17g %.17g %.17g %.17g %.17g" % ((i + 1,) + v + w))
    deck = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f", "newton off",
            "comm_modify vel yes", "read_data data.lmp",
            "pair_style gran/hooke/history %.17g %.17g %.17g %.17g %.17g 1" % (KN, KT, GAMMA_N, GAMMA_T, MU),
            "pair_coeff * *", "neighbor 0.05 bin", "neigh_modify delay 0 every 1 check yes",
            "timestep %.17g" % dt, "fix integ all nve/sphere", "thermo 0", "run %d" % steps,
            "write_dump all custom final.dump id vx vy vz omegax omegay omegaz modify sort id format float %.17g"]
    return "\n".join(data) + "\n", "\n".join(deck) + "\n"


def read_tumble_state(path):
    import csv
    sp = spheres()
    rows = list(csv.DictReader(open(path)))
    out = []
    for (r, m, _, _, _), row in zip(sp, rows):
        inertia = 0.4 * m * r * r
        out.append(tuple(float(row[k]) for k in ("vx", "vy", "vz")) +
                   tuple(float(row[k]) / inertia for k in ("lx", "ly", "lz")))
    return out


def read_dump(path):
    lines = open(path).read().splitlines()
    start = lines.index(next(l for l in lines if l.startswith("ITEM: ATOMS"))) + 1
    return [tuple(float(v) for v in l.split()[1:7]) for l in lines[start:] if l.strip()]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tumble")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--lmp", default="lmp")
    a = ap.parse_args()
    lmp = shutil.which(a.lmp)
    if lmp is None:
        print("binary_collisions: LAMMPS (%s) is not installed; skipped (apt-get install lammps)" % a.lmp)
        return 77
    out = a.out or tempfile.mkdtemp(prefix="tumble-lammps-")
    os.makedirs(out, exist_ok=True)
    dt, steps = timing()
    open(os.path.join(out, "collisions.toml"), "w").write(tumble_scene(dt, steps))
    data, deck = lammps_inputs(dt, steps)
    open(os.path.join(out, "data.lmp"), "w").write(data)
    open(os.path.join(out, "in.collisions"), "w").write(deck)
    print("%d collisions, dt %.3g s, %d steps, in %s" % (len(CASES), dt, steps, out))
    t = subprocess.run([os.path.abspath(a.tumble), "run", "collisions.toml", "--state-out", "tumble.csv"], cwd=out,
                       capture_output=True, text=True)
    if t.returncode != 0:
        print("binary_collisions: tumble failed (status %d):\n%s" % (t.returncode, t.stderr))
        return 1
    if subprocess.run([lmp, "-in", "in.collisions", "-log", "lammps.log", "-screen", "none"], cwd=out).returncode != 0:
        print("binary_collisions: LAMMPS failed; see %s" % os.path.join(out, "lammps.log"))
        return 1
    t, l = read_tumble_state(os.path.join(out, "tumble.csv")), read_dump(os.path.join(out, "final.dump"))
    if len(t) != len(l):
        print("binary_collisions: %d spheres from tumble, %d from LAMMPS" % (len(t), len(l)))
        return 1
    sp = spheres()
    worst, failed = 0.0, False
    print("%-20s %6s %10s %10s %10s %12s" % ("case", "sphere", "v_x", "v_y", "omega_z", "max |diff|"))
    for i, (ti, li) in enumerate(zip(t, l)):
        case = CASES[i // 2]
        scale = math.hypot(case[5], case[6])  # the pair's relative speed
        r = sp[i][0]
        diff = max(max(abs(ti[k] - li[k]) for k in range(3)), r * max(abs(ti[k] - li[k]) for k in range(3, 6))) / scale
        worst = max(worst, diff)
        failed |= not diff <= TOL
        for name, vals in (("tumble", ti), ("LAMMPS", li)):
            print("%-20s %6s %10.6f %10.6f %10.5f %12s" % (case[0] if name == "tumble" else "", "%d %s" % (i % 2, name),
                                                          vals[0], vals[1], vals[5], "%.2e" % diff if name == "LAMMPS" else ""))
    print("largest difference %.2e of the pair's speed (tolerance %g): %s" % (worst, TOL, "FAIL" if failed else "ok"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
