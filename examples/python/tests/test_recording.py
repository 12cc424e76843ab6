# SPDX-License-Identifier: MIT
"""tumble.Recording against the run that wrote the recording: every frame holds the bodies and
particles that Simulation handed out at that step, bit for bit."""
import os

import numpy as np
import pytest

import tumble

SRC = os.environ["TUMBLE_SOURCE_DIR"]
MOLECULES = os.path.join(SRC, "scenes", "molecules.toml")
SPHERES = os.path.join(SRC, "scenes", "spheres.toml")


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def test_frames_are_the_states_of_the_run(tmp_path):
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES))
    sim.record(tmp_path / "r.bin", steps_per_frame=10)
    seen = [(sim.step_count, sim.time, sim.bodies(), sim.particles())]
    for _ in range(6):
        sim.step(10)
        seen.append((sim.step_count, sim.time, sim.bodies(), sim.particles()))
    sim.close()
    with tumble.Recording(tmp_path / "r.bin") as rec:
        assert len(rec) == 7 and rec.steps_per_frame == 10 and not rec.debug and rec.version == 3
        assert rec.num_bodies == sim.num_bodies and rec.num_particles == sim.num_particles
        assert rec.scene_name == "molecules" and rec.dt == pytest.approx(tumble.Scene.load(MOLECULES).dt)
        assert rec.ground is not None and rec.gravity[2] < 0
        table = rec.table()
        assert same_bits(table["radius"], seen[0][3]["radius"]) and np.array_equal(table["body"], seen[0][3]["body"])
        frames = list(rec)  # iteration stops at the last frame
        assert len(frames) == 7
        for (step, time, bodies, particles), f in zip(seen, frames):
            assert f["step"] == step and f["time"] == time
            assert same_bits(f["x"], bodies["x"]) and same_bits(f["q"], bodies["q"])
            assert same_bits(f["particles"], particles["x"])  # the same x = X + R(Q) u
        assert rec[-1]["step"] == 60
        with pytest.raises(IndexError, match="frame 7 of a recording of 7 frames"):
            rec[7]
    with pytest.raises(tumble.Error, match="closed"):
        rec[0]


def test_a_debug_recording_has_velocities_forces_and_contacts(tmp_path):
    sim = tumble.Simulation(tumble.Scene.load(SPHERES))
    sim.step(290)  # the spheres touch by now
    sim.record(tmp_path / "d.bin", steps_per_frame=5, debug=True)
    contacts = []
    for _ in range(4):
        sim.step(5)
        contacts.append(sim.contacts())
    sim.close()
    rec = tumble.Recording(str(tmp_path / "d.bin"))
    assert rec.debug and len(rec) == 4  # no step-0 frame: forces exist once a step has run
    n = sim.num_particles
    for f, c in zip(rec, contacts):
        assert f["v"].shape == (n, 3)
        assert sorted(f["forces"]) == sorted(["repulsion", "damping", "shear", "ground", "friction"])
        assert all(v.shape == (n, 3) for v in f["forces"].values())
        assert f["step"] > 290 and len(c) > 0 and np.array_equal(f["contacts"], c)
        assert np.abs(f["forces"]["repulsion"]).max() > 0


def test_contact_forces_in_a_recording_and_from_the_simulation(tmp_path):
    """record(contacts=True) keeps each frame's contacts with their forces: the arrays that
    contacts(forces=True) hands out after the same step, bit for bit; per particle they sum to the
    repulsion + damping + shear that forces() reports (float rounding apart)."""
    sim = tumble.Simulation(tumble.Scene.load(SPHERES))
    sim.step(290)  # the spheres touch by now
    sim.record(tmp_path / "c.bin", steps_per_frame=5, contacts=True)
    sim.capture_forces = True
    seen = []
    for _ in range(4):
        sim.step(5)
        seen.append((sim.contacts(forces=True), sim.forces()))
    sim.close()
    rec = tumble.Recording(str(tmp_path / "c.bin"))
    assert rec.contact_forces and not rec.debug and rec.version == 3 and len(rec) == 4
    n = sim.num_particles
    for f, (c, forces) in zip(rec, seen):
        got = f["contact_forces"]
        assert "v" not in f and len(c["pairs"]) > 0
        for key in ("pairs", "normal", "tangential", "overlap"):
            assert got[key].shape == c[key].shape and np.array_equal(got[key], c[key]), key
        assert np.all(c["pairs"][:, 0] < c["pairs"][:, 1]) and np.all(c["overlap"] > 0)
        assert np.array_equal(c["normal"], c["fn"][:, None] * c["n"]) and np.allclose(np.linalg.norm(c["n"], axis=1), 1)
        total = (c["normal"] + c["tangential"]).astype(np.float64)
        per_particle = np.zeros((n, 3))
        np.add.at(per_particle, c["pairs"][:, 0], total)
        np.add.at(per_particle, c["pairs"][:, 1], -total)
        want = sum(forces[k].astype(np.float64) for k in ("repulsion", "damping", "shear"))
        scale = np.zeros(n)
        np.add.at(scale, c["pairs"].ravel(), np.repeat(np.abs(total).sum(axis=1), 2))
        assert np.all(np.abs(per_particle - want).max(axis=1) <= 1e-5 * scale + 1e-30)
    with pytest.raises(tumble.Error, match="capture_forces"):
        tumble.Simulation(tumble.Scene.load(SPHERES)).contacts(forces=True)


def test_fields_equal_tumble_fields_and_hold_the_mass(tmp_path):
    """tumble.fields() is `tumble fields`: the CSV the command writes holds the same numbers (the
    shortest text of each double reads back to it); over a box that holds every kernel the density
    integrates to the particles' mass, and the momentum to theirs."""
    import subprocess
    sim = tumble.Simulation(tumble.Scene.load(SPHERES))
    sim.step(290)
    sim.record(tmp_path / "f.bin", steps_per_frame=5, debug=True, contacts=True)
    sim.step(20)
    mass = sim.particles()["mass"].astype(np.float64).sum()
    sim.close()
    x = tumble.Recording(str(tmp_path / "f.bin"))[-1]["particles"]
    lo, hi = x.min(axis=0) - 0.5, x.max(axis=0) + 0.5
    box = (*lo, *hi)
    f = tumble.fields(tmp_path / "f.bin", 0.05, grid=(40, 40, 40), box=box, first=-1)
    assert f["shape"] == (40, 40, 40) and f["frames"] == 1 and f["kinetic_stress"].shape == (40 ** 3, 3, 3)
    cell = np.prod((hi - lo) / 40)
    assert f["density"].sum() * cell == pytest.approx(mass, rel=1e-3)
    binary = os.environ.get("TUMBLE_BIN")  # the ctest's (test_tumble.py's too)
    if binary:
        out = tmp_path / "f.csv"
        subprocess.run([binary, "fields", str(tmp_path / "f.bin"), "-o", str(out), "--width", "0.05", "--grid", "40,40,40",
                        "--box", ",".join(repr(float(v)) for v in box), "--from", "-1", "-q"], check=True)
        rows = np.genfromtxt(out, delimiter=",", names=True)
        assert np.array_equal(rows["density"], f["density"]) and np.array_equal(rows["x"], f["points"][:, 0])
        assert np.array_equal(rows["contact_stress_xz"], f["contact_stress"][:, 0, 2])
    with pytest.raises(tumble.Error, match="width"):
        tumble.fields(tmp_path / "f.bin", 0.0)
    assert tumble.fields(tmp_path / "f.bin", 0.05, grid=(4, 4, 4), box=box, first=0, last=2, every=2 ** 64 - 10)["frames"] == 1


def test_bad_files_raise_input_errors(tmp_path):
    with pytest.raises(tumble.InputError, match="nope.bin"):
        tumble.Recording(tmp_path / "nope.bin")
    bad = tmp_path / "bad.bin"
    bad.write_bytes(b"not a recording at all, not at all")
    with pytest.raises(tumble.InputError, match="bad.bin"):
        tumble.Recording(bad)
