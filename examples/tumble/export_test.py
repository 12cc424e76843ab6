#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""`tumble export` read back by independent readers (ctest export_vtk).

The recording is parsed here from its documented byte layout (docs/recording.md), not through
tumble; the .vtp files are read with VTK's own XML reader (Debian: python3-vtk9), the .pvd and
the CSV files with Python's standard library. Particle positions are recomputed in float32 with
the formula of kernels/integrate.hpp (x = X + R(Q) u, the same operations in the same order), so
they must match the exported ones bit for bit.

usage: export_test.py TUMBLE SOURCE_DIR WORK_DIR
"""
import csv
import os
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

SKIP = 77  # ctest SKIP_RETURN_CODE

try:
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
except ImportError as e:
    print(f"export_test: skipped, {e} (Debian: apt-get install python3-vtk9 python3-numpy)")
    sys.exit(SKIP)

tumble, source, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


def run(*args):
    p = subprocess.run([tumble, *args], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"tumble {' '.join(args)} failed ({p.returncode}):\n{p.stderr}")
    return p.stderr


def read_recording(path):
    """The recording per docs/recording.md, version 1, 2 or 3."""
    b = open(path, "rb").read()
    assert b[:8] == b"TUMBLREC", "magic"
    version, H, N, B, spf = struct.unpack_from("<5I", b, 8)
    dt, fps = struct.unpack_from("<2f", b, 28)
    flags, = struct.unpack_from("<I", b, 36)
    ground_h, = struct.unpack_from("<f", b, 40)
    assert version in (1, 2, 3)
    at = H
    f32 = lambda count: np.frombuffer(b, "<f4", count, at)
    table = {}
    for name in ("radius", "mass", "elasticity"):
        table[name] = f32(N).copy()
        at += 4 * N
    table["body"] = np.frombuffer(b, "<u4", N, at).copy()
    at += 4 * N
    for name in ("ux", "uy", "uz"):
        table[name] = f32(N).copy()
        at += 4 * N
    at += 4  # table checksum
    walls = []
    if version >= 2:  # the wall block: W, S, W records, a checksum
        W, S = struct.unpack_from("<2I", b, at)
        p = at + 8
        for _ in range(W):
            kind, = struct.unpack_from("<I", b, p)
            v = np.frombuffer(b, "<f4", 3, p + 4).copy()
            w = np.frombuffer(b, "<f4", 3, p + 16).copy()
            pivot = np.frombuffer(b, "<f4", 3, p + 28).copy()
            start, stop, T = struct.unpack_from("<ddI", b, p + 40)
            tri = np.frombuffer(b, "<f4", 9 * T, p + 60).reshape(T, 3, 3).copy()
            walls.append({"kind": kind, "v": v, "w": w, "pivot": pivot, "start": start, "stop": stop, "tri": tri})
            p += 60 + 36 * T
        assert p == at + 8 + S, "wall records fill S"
        at = p + 4
    debug = bool(flags & 1)
    contact_forces = bool(flags & 8)
    frames = []
    while at < len(b):
        S, = struct.unpack_from("<I", b, at)
        p = at + 4
        step, time, pulls = struct.unpack_from("<QdI", b, p)
        p += 20
        fr = {"step": step, "time": time}
        for name in ("px", "py", "pz", "qw", "qx", "qy", "qz"):
            fr[name] = np.frombuffer(b, "<f4", B, p).copy()
            p += 4 * B
        if debug:
            fr["v"] = np.frombuffer(b, "<f4", 3 * N, p).reshape(N, 3).copy()
            p += 12 * N
            fr["forces"] = []
            for _ in range(5):
                fr["forces"].append(np.frombuffer(b, "<f4", 3 * N, p).reshape(N, 3).copy())
                p += 12 * N
            C, = struct.unpack_from("<I", b, p)
            fr["contacts"] = np.frombuffer(b, "<u4", 2 * C, p + 4).reshape(C, 2).copy()
            p += 4 + 8 * C
        if contact_forces:  # C, then per contact i, j (u32), n (3 f32), fn, tangential (3 f32), overlap
            C, = struct.unpack_from("<I", b, p)
            rows = np.frombuffer(b, np.dtype([("ij", "<u4", 2), ("f", "<f4", 8)]), C, p + 4)
            fr["cf_pairs"] = rows["ij"].copy()
            fr["cf_n"], fr["cf_fn"] = rows["f"][:, 0:3].copy(), rows["f"][:, 3].copy()
            fr["cf_normal"] = fr["cf_fn"][:, None] * fr["cf_n"]  # float32: the C++ product's bits
            fr["cf_tangential"], fr["cf_overlap"] = rows["f"][:, 4:7].copy(), rows["f"][:, 7].copy()
        frames.append(fr)
        at += 4 + S + 4
    return {"N": N, "B": B, "ground": bool(flags & 2), "ground_h": ground_h, "debug": debug, "table": table,
            "walls": walls, "frames": frames, "contact_forces": contact_forces}


def positions(rec, fr):
    """x = X + R(Q) u in float32, kernels/integrate.hpp's operations in their order."""
    t = rec["table"]
    k = t["body"]
    one = np.float32(1)
    w, x, y, z = (fr[n][k] for n in ("qw", "qx", "qy", "qz"))
    x2, y2, z2 = x + x, y + y, z + z
    xx, yy, zz = x * x2, y * y2, z * z2
    xy, xz, yz = x * y2, x * z2, y * z2
    wx, wy, wz = w * x2, w * y2, w * z2
    R = [[one - (yy + zz), xy - wz, xz + wy], [xy + wz, one - (xx + zz), yz - wx], [xz - wy, yz + wx, one - (xx + yy)]]
    u = (t["ux"], t["uy"], t["uz"])
    X = (fr["px"][k], fr["py"][k], fr["pz"][k])
    return np.stack([X[r] + (R[r][0] * u[0] + R[r][1] * u[1] + R[r][2] * u[2]) for r in range(3)], axis=1)


def read_vtp(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        raise RuntimeError(f"VTK could not read {path}")
    return r.GetOutput()


def point_array(pd, name):
    a = pd.GetPointData().GetArray(name)
    check(a is not None, f"array {name} present")
    return vtk_to_numpy(a) if a is not None else None


def posed(w, t):
    """A wall's corners at time t: the rotation about the pivot by |w| tau about w, then v tau,
    tau = clamp(t - start, 0, stop - start) (docs/recording.md), in float64."""
    tau = min(max(t - w["start"], 0.0), w["stop"] - w["start"])
    p = w["tri"].reshape(-1, 3).astype(np.float64)
    om = w["w"].astype(np.float64)
    speed = np.linalg.norm(om)
    if speed > 0 and tau > 0:
        k = om / speed
        a = speed * tau
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K  # Rodrigues
        p = (p - w["pivot"]) @ R.T + w["pivot"]
    return p + w["v"].astype(np.float64) * tau


def check_walls(rec, out, parts, want):
    """The walls part of every time step: the recording's triangles, posed at the frame's time."""
    walls = rec["walls"]
    ntri = sum(len(w["tri"]) for w in walls)
    part = "2" if rec["ground"] else "1"
    if ntri == 0:
        check(part not in parts or all("_contacts_" in s.get("file") for s in parts[part]),
              "no walls part without walls (the contacts' part, when exported, takes its number)")
        return
    check(len(parts.get(part, [])) == len(want), f"the walls are part {part} of every time step")
    moving = any((np.any(w["w"] != 0) or np.any(w["v"] != 0)) and w["stop"] > w["start"] for w in walls)
    files = [s.get("file") for s in parts.get(part, [])]
    check(len(set(files)) == (len(want) if moving else 1),
          f"{len(set(files))} walls files: one per frame when a wall moves, else one")
    ids = np.concatenate([np.full(len(w["tri"]), k) for k, w in enumerate(walls)])
    kinds = np.concatenate([np.full(len(w["tri"]), w["kind"]) for w in walls])
    size = max(np.max(np.abs(w["tri"])) for w in walls if len(w["tri"]))
    for s, fr in zip(parts.get(part, []), want):
        pd = read_vtp(os.path.join(out, s.get("file")))
        check(pd.GetNumberOfPolys() == ntri and pd.GetNumberOfPoints() == 3 * ntri, f"{s.get('file')}: {ntri} triangles")
        got = vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64)
        exp = np.concatenate([posed(w, fr["time"]) for w in walls])
        check(got.shape == exp.shape and np.max(np.abs(got - exp)) <= 1e-6 * size,
              f"{s.get('file')}: the walls posed at t = {fr['time']}")
        conn = vtk_to_numpy(pd.GetPolys().GetConnectivityArray())
        check(np.array_equal(conn, np.arange(3 * ntri)), "triangle k joins points 3k, 3k+1, 3k+2")
        for col, values in (("wall", ids), ("kind", kinds)):
            a = pd.GetCellData().GetArray(col)
            check(a is not None and np.array_equal(vtk_to_numpy(a), values), f"{s.get('file')}: cell array {col}")
    return files


def check_vtk(rec, out, name, every=1):
    pvd = ET.parse(os.path.join(out, name + ".pvd")).getroot()
    sets = pvd.find("Collection").findall("DataSet")
    parts = {}
    for s in sets:
        parts.setdefault(s.get("part"), []).append(s)
    want = rec["frames"][::every]
    check(len(parts["0"]) == len(want), f"{name}.pvd lists {len(parts['0'])} frames, the recording has {len(want)}")
    if rec["ground"]:
        check(len(parts.get("1", [])) == len(want), "the ground is part 1 of every time step")
        g = read_vtp(os.path.join(out, parts["1"][0].get("file")))
        gp = vtk_to_numpy(g.GetPoints().GetData())
        check(g.GetNumberOfPolys() == 1 and np.all(gp[:, 2] == rec["ground_h"]), "ground square at its height")
    check_walls(rec, out, parts, want)
    t = rec["table"]
    for s, fr in zip(parts["0"], want):
        check(float(s.get("timestep")) == fr["time"], f"time of {s.get('file')}")
        pd = read_vtp(os.path.join(out, s.get("file")))
        check(pd.GetNumberOfPoints() == rec["N"], "number of points")
        check(pd.GetNumberOfVerts() == rec["N"], "one vertex cell per particle")
        got = vtk_to_numpy(pd.GetPoints().GetData())
        exp = positions(rec, fr)
        check(np.array_equal(got, exp), f"{s.get('file')}: positions equal the recomputed ones bit for bit "
              f"(largest difference {np.max(np.abs(got - exp)) if got.shape == exp.shape else 'shape'})")
        for col in ("radius", "mass", "elasticity", "body"):
            a = point_array(pd, col)
            check(a is not None and np.array_equal(a, t[col]), f"{s.get('file')}: {col}")
        check(pd.GetFieldData().GetArray("TimeValue").GetValue(0) == fr["time"], "TimeValue field")
        check(int(pd.GetFieldData().GetArray("step").GetValue(0)) == fr["step"], "step field")
        if rec["debug"]:
            v = point_array(pd, "velocity")
            check(v is not None and np.array_equal(v, fr["v"]), "velocity")
            for kname, f in zip(("repulsion", "damping", "shear", "ground", "friction"), fr["forces"]):
                a = point_array(pd, kname)
                check(a is not None and np.array_equal(a, f), kname)
            lines = pd.GetLines()
            check(pd.GetNumberOfLines() == len(fr["contacts"]), "one line per contact")
            if len(fr["contacts"]):
                conn = vtk_to_numpy(lines.GetConnectivityArray()).reshape(-1, 2)
                check(np.array_equal(conn, fr["contacts"]), "lines join the contact pairs")
        else:
            check(pd.GetPointData().GetArray("velocity") is None, "no velocity without a debug recording")


def check_contacts_vtk(rec, out, name):
    """The contacts part of every time step (after the ground and the walls): a line per contact
    from particle i's centre along its branch n (r_i + r_j - overlap) (in double, rounded to float),
    the recorded forces as cell data, bit for bit."""
    pvd = ET.parse(os.path.join(out, name + ".pvd")).getroot()
    part = str(1 + rec["ground"] + (sum(len(w["tri"]) for w in rec["walls"]) > 0))
    sets = [s for s in pvd.find("Collection").findall("DataSet") if s.get("part") == part]
    check(len(sets) == len(rec["frames"]), f"the contacts are part {part} of every time step")
    for s, fr in zip(sets, rec["frames"]):
        pd = read_vtp(os.path.join(out, s.get("file")))
        C = len(fr["cf_pairs"])
        check(pd.GetNumberOfLines() == C and pd.GetNumberOfPoints() == 2 * C, f"{s.get('file')}: {C} lines")
        x = positions(rec, fr)
        if C == 0:
            continue
        got = vtk_to_numpy(pd.GetPoints().GetData()).reshape(C, 2, 3)
        xi = x[fr["cf_pairs"][:, 0]]
        r = rec["table"]["radius"].astype(np.float64)
        length = (r[fr["cf_pairs"][:, 0]] + r[fr["cf_pairs"][:, 1]]) - fr["cf_overlap"].astype(np.float64)
        end = (xi.astype(np.float64) - fr["cf_n"].astype(np.float64) * length[:, None]).astype(np.float32)
        check(np.array_equal(got[:, 0], xi) and np.array_equal(got[:, 1], end),
              f"{s.get('file')}: each line runs from i's centre along its branch")
        gap = np.abs(got[:, 1] - x[fr["cf_pairs"][:, 1]]).max()
        check(gap < 0.05 * r.min(), f"the branch ends at j's centre (a step before the frame): {gap}")
        cell = lambda n: vtk_to_numpy(pd.GetCellData().GetArray(n))
        check(np.array_equal(cell("normal_force"), fr["cf_normal"]), "normal_force")
        check(np.array_equal(cell("tangential_force"), fr["cf_tangential"]), "tangential_force")
        check(np.array_equal(cell("overlap"), fr["cf_overlap"]), "overlap")
        check(np.array_equal(cell("particle_i"), fr["cf_pairs"][:, 0]) and
              np.array_equal(cell("particle_j"), fr["cf_pairs"][:, 1]), "particle_i, particle_j")
        check(np.array_equal(cell("unit_normal"), fr["cf_n"]) and np.array_equal(cell("fn"), fr["cf_fn"]), "unit_normal, fn")
        check(np.array_equal(cell("normal_magnitude"), np.abs(fr["cf_fn"])), "normal_magnitude")


def check_contacts_csv(rec, out, name):
    with open(os.path.join(out, name + "_frames.csv")) as f:
        index = list(csv.DictReader(f))
    check(len(index) == len(rec["frames"]), "the CSV index lists every frame")
    for row, fr in zip(index, rec["frames"]):
        with open(os.path.join(out, row["contacts_file"])) as f:
            rows = list(csv.DictReader(f))
        check(len(rows) == len(fr["cf_pairs"]), f"{row['contacts_file']}: a row per contact")
        if not rows:
            continue
        col = lambda *names: np.array([[float(r[n]) for n in names] for r in rows], dtype=np.float32)
        check(np.array_equal(np.array([[int(r["i"]), int(r["j"])] for r in rows]), fr["cf_pairs"]), "i, j")
        check(np.array_equal(col("normal_x", "normal_y", "normal_z"), fr["cf_normal"]), "normal_x,y,z")
        check(np.array_equal(col("nx", "ny", "nz"), fr["cf_n"]) and np.array_equal(col("fn")[:, 0], fr["cf_fn"]), "nx,ny,nz, fn")
        check(np.array_equal(col("tangential_x", "tangential_y", "tangential_z"), fr["cf_tangential"]),
              "tangential_x,y,z")
        check(np.array_equal(col("overlap")[:, 0], fr["cf_overlap"]), "overlap")
        x = positions(rec, fr)
        check(np.array_equal(col("xi", "yi", "zi"), x[fr["cf_pairs"][:, 0]]), "xi, yi, zi")


def check_csv(rec, out, name):
    with open(os.path.join(out, name + "_frames.csv")) as f:
        index = list(csv.DictReader(f))
    check(len(index) == len(rec["frames"]), "the CSV index lists every frame")
    t = rec["table"]
    for row, fr in zip(index, rec["frames"]):
        check(int(row["step"]) == fr["step"] and float(row["time"]) == fr["time"], "index step and time")
        with open(os.path.join(out, row["file"])) as f:
            rows = list(csv.DictReader(f))
        check(len(rows) == rec["N"], "one row per particle")
        exp = positions(rec, fr)
        got = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows], dtype=np.float32)
        check(np.array_equal(got, exp), f"{row['file']}: positions (the shortest text of each float reads back to it)")
        check(np.array_equal(np.array([float(r["r"]) for r in rows], dtype=np.float32), t["radius"]), "r")
        check(np.array_equal(np.array([int(r["body"]) for r in rows]), t["body"]), "body")
        if rec["debug"]:
            got = np.array([[float(r["vx"]), float(r["vy"]), float(r["vz"])] for r in rows], dtype=np.float32)
            check(np.array_equal(got, fr["v"]), "vx,vy,vz")


scene = os.path.join(source, "scenes", "molecules.toml")
plain = os.path.join(work, "mol.bin")
debug = os.path.join(work, "dbg.bin")
run("run", scene, "--steps", "200", "--record", plain, "-q")
run("run", scene, "--steps", "200", "--record", debug, "--debug-record", "-q")
rec, drec = read_recording(plain), read_recording(debug)
check(len(rec["frames"]) == 21 and len(drec["frames"]) == 20, "frame counts")

run("export", plain, os.path.join(work, "vtk"), "-q")
check_vtk(rec, os.path.join(work, "vtk"), "mol")
run("export", plain, os.path.join(work, "vtk5"), "--every", "5", "--name", "m", "-q")
check_vtk(rec, os.path.join(work, "vtk5"), "m", every=5)
run("export", debug, os.path.join(work, "dvtk"), "-q")
check_vtk(drec, os.path.join(work, "dvtk"), "dbg")
check(any(len(f["contacts"]) for f in drec["frames"]), "the debug recording has contacts to export")
run("export", plain, os.path.join(work, "csv"), "--format", "csv", "-q")
check_csv(rec, os.path.join(work, "csv"), "mol")
run("export", debug, os.path.join(work, "dcsv"), "--format", "csv", "-q")
check_csv(drec, os.path.join(work, "dcsv"), "dbg")

# Contact forces (version 3): with the debug block (the same pairs) and the forces exported.
forces = os.path.join(work, "cf.bin")
run("run", scene, "--steps", "200", "--record", forces, "--debug-record", "--record-contacts", "-q")
crec = read_recording(forces)
check(crec["contact_forces"] and all(np.array_equal(f["cf_pairs"], f["contacts"]) for f in crec["frames"]),
      "the contact forces' pairs are the debug block's")
check(sum(len(f["cf_pairs"]) for f in crec["frames"]) > 0, "the recording has contact forces to export")
run("export", forces, os.path.join(work, "cvtk"), "--contacts", "-q")
check_vtk(crec, os.path.join(work, "cvtk"), "cf")
check_contacts_vtk(crec, os.path.join(work, "cvtk"), "cf")
run("export", forces, os.path.join(work, "ccsv"), "--format", "csv", "--contacts", "-q")
check_contacts_csv(crec, os.path.join(work, "ccsv"), "cf")
# tumble fields: the .vti read by VTK holds what the CSV holds (tensors in VTK's order xx yy zz xy yz xz).
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
run("fields", forces, "-o", os.path.join(work, "f.vti"), "--width", "0.2", "--grid", "6,5,4", "--from", "-3", "-q")
run("fields", forces, "-o", os.path.join(work, "f.csv"), "--width", "0.2", "--grid", "6,5,4", "--from", "-3", "-q")
p = subprocess.run([tumble, "fields", forces, "-o", os.path.join(work, "f.txt"), "--width", "0.2"], capture_output=True,
                   text=True)
check(p.returncode == 2 and ".vti" in p.stderr and not os.path.exists(os.path.join(work, "f.txt")),
      f"fields: an output neither .vti nor .csv is refused first: {p.stderr.strip()}")
r = vtkXMLImageDataReader()
r.SetFileName(os.path.join(work, "f.vti"))
r.Update()
img = r.GetOutput()
rows = np.genfromtxt(os.path.join(work, "f.csv"), delimiter=",", names=True)
check(img.GetDimensions() == (6, 5, 4) and img.GetNumberOfPoints() == len(rows), "fields: a 6 x 5 x 4 image")
pts = np.array([img.GetPoint(k) for k in range(img.GetNumberOfPoints())])
check(np.allclose(pts, np.stack([rows["x"], rows["y"], rows["z"]], axis=1), rtol=1e-12, atol=1e-12),
      "fields: the image's points are the CSV's")
pdata = img.GetPointData()
check(np.array_equal(vtk_to_numpy(pdata.GetArray("density")), rows["density"]), "fields: density")
cs = vtk_to_numpy(pdata.GetArray("contact_stress"))
check(np.array_equal(cs[:, [0, 1, 2, 3, 4, 5]],
                     np.stack([rows["contact_stress_" + c] for c in ("xx", "yy", "zz", "xy", "yz", "xz")], axis=1)),
      "fields: contact stress in VTK's component order")
check(np.abs(cs).max() > 0, "fields: the molecules press on each other")
p = subprocess.run([tumble, "export", debug, os.path.join(work, "none"), "--contacts"], capture_output=True, text=True)
check(p.returncode != 0 and "no contact forces" in p.stderr and not os.path.exists(os.path.join(work, "none")),
      f"--contacts of a recording without them is refused before anything is written: {p.stderr.strip()}")

# Walls (recording version 2): a box open at both ends around a cone that turns for a while and
# a tilted belt under them; then the box alone, whose walls stand still (one file for all).
walls_toml = """
[scene]
name = "walls"
dt = 1e-4
steps = 200
[ground]
height = -0.5
[[wall]]
type = "box"
min = [-0.4, -0.4, -0.2]
max = [0.4, 0.4, 0.6]
open = ["+z", "-z"]
[[wall]]
type = "cone"
point = [0.0, 0.0, -0.2]
axis = [0.0, 0.0, 0.3]
radius = [0.0, 0.3]
angular_velocity = 50.0
start = 0.004
stop = 0.015
[[wall]]
type = "plane"
point = [0.0, 0.0, -0.45]
normal = [0.0, 0.2, 1.0]
velocity = [1.0, 0.0, 0.0]
[[shape]]
name = "ball"
[[shape.sphere]]
radius = 0.05
mass = 0.1
elasticity = 0.5
[[group]]
shape = "ball"
count = [2, 2, 1]
spacing = 0.12
origin = [-0.06, -0.06, 0.3]
"""
with open(os.path.join(work, "walls.toml"), "w") as f:
    f.write(walls_toml)
box_only = walls_toml[:walls_toml.index("[[wall]]\ntype = \"cone\"")] + walls_toml[walls_toml.index("[[shape]]"):]
with open(os.path.join(work, "box.toml"), "w") as f:
    f.write(box_only)
for scene_name, moving in (("walls", True), ("box", False)):
    recfile = os.path.join(work, scene_name + ".bin")
    run("run", os.path.join(work, scene_name + ".toml"), "--record", recfile, "-q")
    wrec = read_recording(recfile)
    kinds = [w["kind"] for w in wrec["walls"]]
    check(kinds == ([0, 0, 0, 0, 2, 0] if moving else [0, 0, 0, 0]), f"{scene_name}: wall kinds {kinds}")
    outdir = os.path.join(work, scene_name + "_vtk")
    run("export", recfile, outdir, "-q")
    check_vtk(wrec, outdir, scene_name)
    stem = scene_name + "_walls"
    names = sorted(f for f in os.listdir(outdir) if f.startswith(stem))
    check(names == ([f"{stem}_{k:06d}.vtp" for k in range(len(wrec["frames"]))] if moving else [stem + ".vtp"]),
          f"{scene_name}: walls files {names[:3]}...")
    if moving:  # the cone has turned by the last frame: the test above would see a missing pose
        first, last = posed(wrec["walls"][4], 0.0), posed(wrec["walls"][4], wrec["frames"][-1]["time"])
        check(np.max(np.abs(first - last)) > 0.1, "the cone's drawing turned (0.55 rad)")
    run("export", recfile, os.path.join(work, scene_name + "_csv"), "--format", "csv", "-q")
    check(not any(f.startswith(stem) for f in os.listdir(os.path.join(work, scene_name + "_csv"))), "CSV: no walls")

if failures:
    sys.exit(f"export_test: {len(failures)} checks failed")
print(f"export_test: {rec['N']} particles, {len(rec['frames'])} + {len(drec['frames'])} frames read back by VTK "
      f"{__import__('vtkmodules').__version__ if hasattr(__import__('vtkmodules'), '__version__') else ''}: all equal")
