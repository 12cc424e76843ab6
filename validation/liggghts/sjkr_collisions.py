#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Cohesive collisions under hertz-mindlin + sjkr, run by tumble and by LIGGGHTS 3.8 cohesion sjkr.

    python3 validation/liggghts/sjkr_collisions.py TUMBLE_BIN [OUT_DIR] [--liggghts liggghts]

Millimetre spheres (E 10 MPa, nu 0.3, mu 0.3, 2500 kg/m^3) of four materials that differ in the
cohesion energy density k_c and the restitution e: a (1e5 J/m^3, e 0.5), b (4e5, 0.5), c (1e5, 1)
and d (4e5, 1); a-b and c-d mix to 2e5. Three scenes, run by both codes with the same dt:
- pairs (no gravity, no ground; the pairs 5 mm apart along z, so they never meet): a head-on
  collision at 0.03 m/s that cohesion turns into a bound pair, one at 0.3 m/s that rebounds with
  e 0.35 instead of 0.5, an oblique one, and two of unequal radii and materials (1 mm against
  0.6 mm: bound head-on, and oblique);
- ground (gravity, the ground z = 0 of material a: LIGGGHTS fix wall/gran with the same model): a
  sphere of a and one of b dropped from 0.1 mm above it stick to it;
- ground, override: the same with [ground] cohesion_energy_density = 2.5e5 for every sphere.
At the end every sphere's velocity and spin (times the radius) must agree to 1e-3 of the case's
speed (the pair's relative speed, the ground's impact speed), a pair must be bound or apart as
named in both, and each bound pair's or grounded sphere's overlap must agree to 1e-3 of itself,
with the other code and with the static equilibrium solved here (Hertz against k_c A, plus m g on
the ground). What may differ, by design: the integrator (tumble's leapfrog, LIGGGHTS's velocity
Verlet; dt is the shortest Hertz contact time of the impacts / 50), tumble's float positions
against LIGGGHTS's doubles, and the
tangential force where a damped contact sticks (docs/model.md#hertz-mindlin): tumble caps spring
and dashpot together, LIGGGHTS the spring alone and adds the dashpot uncapped while the spring is
below the cap (at the start of every contact, and again after the cohesion has pulled the normal
force through zero). In LIGGGHTS alone, tangential_damping off moves the oblique collisions of
the damped materials by 2.5e-2 of their speed, so the oblique pairs are of the undamped materials
c and d, where the two models are the same.

Why 50 steps per contact and not more: a float position near 1 mm moves by no less than half its
ulp (5.8e-11 m) per step, so below 0.5 ulp / dt tumble cannot resolve a velocity, and a bound
pair's last oscillation freezes where that floor stops it. Measured (2026-12-07, tumble against
LIGGGHTS): at 250 steps per contact the floor is 8.8e-5 m/s, 2.9e-3 of the bound pair's speed,
and the overlap ends 5.9e-3 from the equilibrium (FAIL); at 100, 7.0e-4 and 1.4e-3; at 50,
1.7e-4 of the speed and 3.6e-4 of the overlap, the rebound, oblique and unequal cases within
1e-5 and the grounded spheres within 3e-5 of the equilibrium.

The Coulomb limit is mu |F_n| with F_n the normal force without the cohesion, in both codes:
LIGGGHTS 3.8's default (tangential_reduce off; its manual's wording reads the other way, its code
and the Debian build leave the cohesion out of the limit; LIGGGHTS up to 3.3 added it).
On a plane LIGGGHTS's contact area is pi (r^2 - d^2), d the distance of the
centre from the plane (times area_ratio, 1 for a primitive wall, and once more when the force is
applied).

Exits 77 (a skip for ctest) with a message when LIGGGHTS (liggghts) is not installed: apt-get
install liggghts. Writes the scenes, the decks and all results to OUT_DIR (default: a temporary
one).
"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile

YOUNG, POISSON, FRICTION, DENSITY = 1.0e7, 0.3, 0.3, 2500.0
# (name, k_c in J/m^3, restitution); LIGGGHTS atom types 1.., then the ground's (material a's)
MATERIALS = [("a", 1.0e5, 0.5), ("b", 4.0e5, 0.5), ("c", 1.0e5, 1.0), ("d", 4.0e5, 1.0)]
GROUND_TYPE = len(MATERIALS) + 1
GRAVITY = 9.81
STEPS_PER_CONTACT = 50
T_END = 0.03  # s: the bound pairs and the grounded spheres have come to rest by then
TOL = 1e-3

# (name, r1, material 1, r2, material 2, closing speed, tangential speed); all bound or apart at the end
PAIRS = [
    ("head-on, bound", 1.0e-3, 0, 1.0e-3, 0, 0.03, 0.0),
    ("head-on, rebound", 1.0e-3, 0, 1.0e-3, 0, 0.3, 0.0),
    ("oblique", 1.0e-3, 2, 1.0e-3, 2, 0.5, 1.0),
    ("unequal, bound", 1.0e-3, 0, 0.6e-3, 1, 0.05, 0.0),
    ("unequal, oblique", 1.0e-3, 2, 0.6e-3, 3, 0.5, 2.0),
]
PAIR_SPACING = 5.0e-3  # m along z between pairs
GAP = 1.0e-6  # m between the surfaces at the start
DROP = 1.0e-4  # m: each sphere's lowest point above the ground at the start
GROUNDED = [(1.0e-3, 0, -3.0e-3), (0.8e-3, 1, 3.0e-3)]  # (radius, material, x) on the ground
GROUNDS = [("ground", None), ("ground, override", 2.5e5)]  # (name, [ground] cohesion_energy_density)


def mass(r):
    return DENSITY * 4.0 / 3.0 * math.pi * r ** 3


def ystar():
    return 1.0 / (2.0 * (1.0 - POISSON ** 2) / YOUNG)


def kc_pair(mi, mj):
    """The pair's cohesion energy density: the geometric mean (one material: its own)."""
    return MATERIALS[mi][1] if mi == mj else math.sqrt(MATERIALS[mi][1] * MATERIALS[mj][1])


def kc_ground(mi, override):
    return override if override is not None else kc_pair(mi, 0)


def impact_speed():
    return math.sqrt(2.0 * GRAVITY * DROP)


def pair_spheres():
    """Per sphere: radius, material, position, velocity (world frame), in pair order."""
    out = []
    for k, (_, r1, m1, r2, m2, vn, vt) in enumerate(PAIRS):
        z = PAIR_SPACING * (k - 0.5 * (len(PAIRS) - 1))
        M1, M2 = mass(r1), mass(r2)
        f1, f2 = M2 / (M1 + M2), M1 / (M1 + M2)  # momentum zero
        out.append((r1, m1, (-r1 - 0.5 * GAP, 0.0, z), (f1 * vn, f1 * vt, 0.0)))
        out.append((r2, m2, (r2 + 0.5 * GAP, 0.0, z), (-f2 * vn, -f2 * vt, 0.0)))
    return out


def ground_spheres():
    return [(r, m, (x, 0.0, r + DROP), (0.0, 0.0, 0.0)) for r, m, x in GROUNDED]


def hertz_time(r1, r2, v, wall=False):
    """The Hertz contact time (no cohesion) of an impact at v: 2.87 (m*^2 / (R* Y*^2 v))^(1/5)."""
    ms = mass(r1) if wall else mass(r1) * mass(r2) / (mass(r1) + mass(r2))
    rs = r1 if wall else r1 * r2 / (r1 + r2)
    return 2.87 * (ms * ms / (rs * ystar() ** 2 * v)) ** 0.2


def timing():
    tcs = [hertz_time(c[1], c[3], c[5]) for c in PAIRS] + [hertz_time(r, 0, impact_speed(), True) for r, _, _ in GROUNDED]
    dt = min(tcs) / STEPS_PER_CONTACT
    return dt, int(math.ceil(T_END / dt))


def area(delta, ri, rj):
    """LIGGGHTS's contact area at overlap delta: two spheres (rj > 0) or a sphere on a plane (rj 0)."""
    if rj == 0.0:
        d = ri - delta
        return math.pi * (ri * ri - d * d)
    r = ri + rj - delta
    return -math.pi / 4.0 * ((r - ri - rj) * (r + ri - rj) * (r - ri + rj) * (r + ri + rj)) / (r * r)


def equilibrium(ri, rj, kc, load):
    """The overlap at rest: Hertz 4/3 Y* sqrt(R*) delta^1.5 = k_c A(delta) + load, by bisection."""
    rs = ri if rj == 0.0 else ri * rj / (ri + rj)
    f = lambda d: 4.0 / 3.0 * ystar() * math.sqrt(rs) * d ** 1.5 - kc * area(d, ri, rj) - load
    lo, hi = 0.0, 0.5 * (min(ri, rj) if rj else ri)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0.0 else (lo, mid)
    return 0.5 * (lo + hi)


def tumble_scene(name, dt, steps, spheres, ground, override):
    lines = ["# %s: tumble's side of validation/liggghts/sjkr_collisions.py" % name,
             "[scene]", 'name = "sjkr-%s"' % name.replace(", ", "-"), "dt = %.9g" % dt, "steps = %d" % steps,
             "gravity = [0.0, 0.0, %.9g]" % (-GRAVITY if ground else 0.0), "",
             "[contact]", 'law = "hertz-mindlin"', 'cohesion = "sjkr"', ""]
    for mname, kc, e in MATERIALS:
        lines += ["[[material]]", 'name = "%s"' % mname, "density = %.9g" % DENSITY, "youngs_modulus = %.9g" % YOUNG,
                  "poisson_ratio = %.9g" % POISSON, "restitution = %.9g" % e, "friction = %.9g" % FRICTION,
                  "cohesion_energy_density = %.9g" % kc, ""]
    if ground:
        lines += ["[ground]", "height = 0.0", 'material = "%s"' % MATERIALS[0][0]]
        if override is not None:
            lines.append("cohesion_energy_density = %.9g" % override)
        lines.append("")
    for i, (r, m, x, v) in enumerate(spheres):
        lines += ["[[shape]]", 'name = "s%d"' % i, "[[shape.sphere]]", "radius = %.9g" % r,
                  'material = "%s"' % MATERIALS[m][0], ""]
    for i, (r, m, x, v) in enumerate(spheres):
        lines += ["[[body]]", 'shape = "s%d"' % i, "position = [%.9g, %.9g, %.9g]" % x,
                  "velocity = [%.9g, %.9g, %.9g]" % v, ""]
    return "\n".join(lines)


def liggghts_inputs(name, tag, dt, steps, spheres, ground, override):
    lo = [min(x[k] - r for r, _, x, _ in spheres) - 0.05 for k in range(3)]
    hi = [max(x[k] + r for r, _, x, _ in spheres) + 0.05 for k in range(3)]
    if ground:
        lo[2] = -1e-3
    data = ["%s: LIGGGHTS's side of validation/liggghts/sjkr_collisions.py" % name, "",
            "%d atoms" % len(spheres), "%d atom types" % GROUND_TYPE, ""]
    data += ["%.17g %.17g %slo %shi" % (lo[k], hi[k], a, a) for k, a in enumerate("xyz")]
    data += ["", "Atoms", ""]
    for i, (r, m, x, v) in enumerate(spheres):  # atom_style sphere: id type diameter density x y z
        data.append("%d %d %.17g %.17g %.17g %.17g %.17g" % (i + 1, m + 1, 2 * r, DENSITY, x[0], x[1], x[2]))
    data += ["", "Velocities", ""]
    for i, (r, m, x, v) in enumerate(spheres):
        data.append("%d %.17g %.17g %.17g 0 0 0" % ((i + 1,) + v))
    n = GROUND_TYPE

    def matrix(f):
        return "%d %s" % (n, " ".join("%.17g" % f(i, j) for i in range(n) for j in range(n)))

    def kc(i, j):  # types 0-based; the last type is the ground's
        if i == n - 1 and j == n - 1:
            return MATERIALS[0][1]
        if i == n - 1 or j == n - 1:
            return kc_ground(min(i, j), override)
        return kc_pair(i, j)

    def restitution(i, j):  # the smaller (tumble's mixing), the ground's of material a
        return min(MATERIALS[0 if k == n - 1 else k][2] for k in (i, j))

    model, settings = "model hertz tangential history cohesion sjkr", ""
    deck = ["# %s: LIGGGHTS's side of validation/liggghts/sjkr_collisions.py" % name,
            "units si", "atom_style sphere", "atom_modify map array", "boundary m m m", "newton off",
            "communicate single vel yes", "read_data data.%s" % tag,
            "fix m1 all property/global youngsModulus peratomtype %s" % " ".join(["%.17g" % YOUNG] * n),
            "fix m2 all property/global poissonsRatio peratomtype %s" % " ".join(["%.17g" % POISSON] * n),
            "fix m3 all property/global coefficientRestitution peratomtypepair %s" % matrix(restitution),
            "fix m4 all property/global coefficientFriction peratomtypepair %s" % matrix(lambda i, j: FRICTION),
            "fix m5 all property/global cohesionEnergyDensity peratomtypepair %s" % matrix(kc),
            "pair_style gran %s %s" % (model, settings), "pair_coeff * *",
            "neighbor 2e-4 bin", "neigh_modify delay 0 every 1 check yes", "timestep %.17g" % dt]
    if ground:
        deck += ["fix grav all gravity %.17g vector 0 0 -1" % GRAVITY,
                 "fix ground all wall/gran %s primitive type %d zplane 0.0 %s" % (model, GROUND_TYPE, settings)]
    deck += ["fix integ all nve/sphere", "thermo_style custom step atoms", "thermo %d" % steps,
             "dump final all custom %d %s.dump id x y z vx vy vz omegax omegay omegaz" % (steps, tag),
             'dump_modify final sort id format "%s"' % " ".join(["%d"] + ["%.17g"] * 9),
             "run %d" % steps]
    return "\n".join(data) + "\n", "\n".join(deck) + "\n"


def read_tumble_state(path, spheres):
    """Per sphere: x, y, z, vx, vy, vz, wx, wy, wz."""
    out = []
    for (r, m, _, _), row in zip(spheres, csv.DictReader(open(path))):
        inertia = 0.4 * mass(r) * r * r
        out.append(tuple(float(row[k]) for k in ("x", "y", "z", "vx", "vy", "vz")) +
                   tuple(float(row[k]) / inertia for k in ("lx", "ly", "lz")))
    return out


def read_dump(path):
    """The last snapshot of a LIGGGHTS dump: per atom x, y, z, vx, vy, vz, wx, wy, wz."""
    lines = open(path).read().splitlines()
    start = max(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS")) + 1
    return [tuple(float(v) for v in l.split()[1:10]) for l in lines[start:] if l.strip()]


def run_both(out, tag, toml, data, deck, tumble, liggghts):
    open(os.path.join(out, "%s.toml" % tag), "w").write(toml)
    open(os.path.join(out, "data.%s" % tag), "w").write(data)
    open(os.path.join(out, "in.%s" % tag), "w").write(deck)
    t = subprocess.run([tumble, "run", "%s.toml" % tag, "--state-out", "tumble_%s.csv" % tag], cwd=out,
                       capture_output=True, text=True)
    if t.returncode != 0:
        print("sjkr_collisions: tumble failed on %s.toml (status %d):\n%s" % (tag, t.returncode, t.stderr))
        return False
    if subprocess.run([liggghts, "-in", "in.%s" % tag, "-log", "log.%s" % tag, "-screen", "none"],
                      cwd=out).returncode != 0:
        print("sjkr_collisions: LIGGGHTS failed; see %s" % os.path.join(out, "log.%s" % tag))
        return False
    return True


def compare(spheres, t, l, scale):
    """The largest velocity / spin (times r) difference of the spheres over `scale`."""
    worst = 0.0
    for (r, _, _, _), ti, li in zip(spheres, t, l):
        worst = max(worst, max(abs(ti[k] - li[k]) for k in range(3, 6)) / scale,
                    r * max(abs(ti[k] - li[k]) for k in range(6, 9)) / scale)
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tumble")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--liggghts", default="liggghts")
    a = ap.parse_args()
    liggghts = shutil.which(a.liggghts)
    if liggghts is None:
        print("sjkr_collisions: LIGGGHTS (%s) is not installed; skipped (apt-get install liggghts)" % a.liggghts)
        return 77
    out = a.out or tempfile.mkdtemp(prefix="tumble-liggghts-")
    os.makedirs(out, exist_ok=True)
    tumble = os.path.abspath(a.tumble)
    dt, steps = timing()
    print("%d pairs and %d x %d spheres on the ground, dt %.3g s, %d steps, in %s"
          % (len(PAIRS), len(GROUNDS), len(GROUNDED), dt, steps, out))
    failed, worst_v, worst_d = False, 0.0, 0.0

    def check_overlap(dt_, dl, de):
        """Bound or grounded: the two codes' overlaps against each other and the equilibrium."""
        nonlocal failed, worst_d
        diff = max(abs(dt_ - dl), abs(dt_ - de), abs(dl - de)) / de
        worst_d = max(worst_d, diff)
        failed |= not diff <= TOL
        return "overlap um: tumble %.6f LIGGGHTS %.6f rest %.6f  rel diff %.2e" % (dt_ * 1e6, dl * 1e6, de * 1e6, diff)

    # The pairs.
    sp = pair_spheres()
    if not run_both(out, "pairs", tumble_scene("pairs", dt, steps, sp, False, None),
                    *liggghts_inputs("pairs", "pairs", dt, steps, sp, False, None), tumble, liggghts):
        return 1
    t, l = read_tumble_state(os.path.join(out, "tumble_pairs.csv"), sp), read_dump(os.path.join(out, "pairs.dump"))
    if len(t) != len(sp) or len(l) != len(sp):
        print("sjkr_collisions: %d spheres from tumble, %d from LIGGGHTS, %d written" % (len(t), len(l), len(sp)))
        return 1
    print("%-20s %-9s %11s %11s %11s %11s %10s" % ("pair", "code", "v1_x", "v1_y", "v2_x", "w1_z r1", "|diff|/v"))
    for k, (name, r1, m1, r2, m2, vn, vt) in enumerate(PAIRS):
        i = 2 * k
        scale = math.hypot(vn, vt)
        diff = compare(sp[i:i + 2], t[i:i + 2], l[i:i + 2], scale)
        worst_v = max(worst_v, diff)
        failed |= not diff <= TOL
        gaps = []
        for name_, s in (("tumble", t), ("LIGGGHTS", l)):
            gaps.append(math.dist(s[i][:3], s[i + 1][:3]) - r1 - r2)
            print("%-20s %-9s %11.7f %11.7f %11.7f %11.7f %10s" % (
                name if name_ == "tumble" else "", name_, s[i][3], s[i][4], s[i + 1][3], r1 * s[i][8],
                "%.2e" % diff if name_ == "LIGGGHTS" else ""))
        bound = [g < 0.0 for g in gaps]
        want = name.endswith(", bound")
        note = "%s, %s" % ("bound" if bound[0] else "apart", "bound" if bound[1] else "apart")
        if bound[0] != want or bound[1] != want:
            failed = True
            print("%20s %s: expected %s" % ("", note, "bound" if want else "apart"))
        elif want:
            print("%20s %s" % ("", check_overlap(-gaps[0], -gaps[1], equilibrium(r1, r2, kc_pair(m1, m2), 0.0))))
        elif vt == 0.0:
            e = [abs(s[i + 1][3] - s[i][3]) / vn for s in (t, l)]
            print("%20s apart, restitution: tumble %.5f LIGGGHTS %.5f (%.2f without cohesion)"
                  % ("", e[0], e[1], min(MATERIALS[m1][2], MATERIALS[m2][2])))
        else:
            print("%20s apart" % "")

    # The ground.
    sp = ground_spheres()
    v0 = impact_speed()
    print("%-20s %-9s %11s %11s %10s" % ("on the ground", "code", "z", "v_z", "|diff|/v0"))
    for g, (name, override) in enumerate(GROUNDS):
        tag = "ground%d" % g
        if not run_both(out, tag, tumble_scene(name, dt, steps, sp, True, override),
                        *liggghts_inputs(name, tag, dt, steps, sp, True, override), tumble, liggghts):
            return 1
        t, l = read_tumble_state(os.path.join(out, "tumble_%s.csv" % tag), sp), read_dump(os.path.join(out, "%s.dump" % tag))
        if len(t) != len(sp) or len(l) != len(sp):
            print("sjkr_collisions: %d spheres from tumble, %d from LIGGGHTS, %d written" % (len(t), len(l), len(sp)))
            return 1
        for i, (r, m, _, _) in enumerate(sp):
            diff = compare(sp[i:i + 1], t[i:i + 1], l[i:i + 1], v0)
            worst_v = max(worst_v, diff)
            failed |= not diff <= TOL
            label = "%s, %s" % (name, MATERIALS[m][0])
            for name_, s in (("tumble", t), ("LIGGGHTS", l)):
                print("%-20s %-9s %11.8f %11.3e %10s" % (label if name_ == "tumble" else "", name_, s[i][2], s[i][5],
                                                         "%.2e" % diff if name_ == "LIGGGHTS" else ""))
            rest = equilibrium(r, 0.0, kc_ground(m, override), mass(r) * GRAVITY)
            print("%20s %s" % ("", check_overlap(r - t[i][2], r - l[i][2], rest)))
    print("largest difference %.2e of the speed, %.2e of the overlap (tolerance %g): %s"
          % (worst_v, worst_d, TOL, "FAIL" if failed else "PASS"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
