# SPDX-License-Identifier: MIT
"""The Python module against independent references: the `tumble` command on the same scene
(bit for bit), NumPy brute force for the pairs, Python's tomllib for the scene writer.
Run by ctest (python_tests) with PYTHONPATH, TUMBLE_BIN and TUMBLE_SOURCE_DIR set."""
import csv
import os
import pathlib
import subprocess
import tomllib
import warnings

import numpy as np
import pytest

import tumble

BIN = os.environ["TUMBLE_BIN"]
SRC = os.environ["TUMBLE_SOURCE_DIR"]
MOLECULES = os.path.join(SRC, "scenes", "molecules.toml")
SPHERES = os.path.join(SRC, "scenes", "spheres.toml")
BOX = os.path.join(SRC, "scenes", "box.toml")
HOPPER_MESH = os.path.join(SRC, "scenes", "hopper-mesh.toml")


def cli_state(tmp_path, *args):
    """Body state after `tumble run ... --state-out` as float32 columns."""
    out = tmp_path / "state.csv"
    subprocess.run([BIN, "run", *args, "--state-out", str(out), "-q"], check=True, capture_output=True)
    with open(out) as f:
        rows = list(csv.DictReader(f))
    col = lambda *names: np.array([[float(r[n]) for n in names] for r in rows], dtype=np.float32)
    return {"x": col("x", "y", "z"), "v": col("vx", "vy", "vz"), "q": col("qw", "qx", "qy", "qz"),
            "l": col("lx", "ly", "lz")}


def same_bits(a, b):
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


@pytest.mark.parametrize("path", [MOLECULES, SPHERES, BOX])
def test_same_bits_as_tumble_run(tmp_path, path):
    sim = tumble.Simulation(tumble.Scene.load(path), threads=2)
    sim.step(150)
    got, want = sim.bodies(), cli_state(tmp_path, path, "--steps", "150")
    for k in ("x", "v", "q", "l"):
        assert same_bits(got[k], want[k]), k
    assert sim.step_count == 150 and sim.time > 0


def test_overrides_and_thread_counts(tmp_path):
    scene = tumble.Scene.load(MOLECULES, set=["ground.friction=0.2", "scene.steps=80"])
    assert scene.steps == 80
    a = tumble.Simulation(scene, threads=1)
    b = tumble.Simulation(scene, threads=2)
    a.step(80)
    b.step(40)
    b.step(40)  # steps in two calls: the same run
    assert same_bits(a.bodies()["x"], b.bodies()["x"])
    want = cli_state(tmp_path, MOLECULES, "--set", "ground.friction=0.2", "--steps", "80")
    assert same_bits(a.bodies()["x"], want["x"])


def brute_pairs(x, r, body):
    d2 = ((x[:, None, :].astype(np.float64) - x[None, :, :]) ** 2).sum(-1)
    reach = (r[:, None].astype(np.float64) + r[None, :]) ** 2
    i, j = np.nonzero((d2 < reach) & (body[:, None] != body[None, :]))
    keep = i < j
    return set(zip(i[keep].tolist(), j[keep].tolist()))


def test_find_pairs_against_numpy_brute_force():
    seed = 20261202
    print("seed", seed)
    rng = np.random.default_rng(seed)
    n = 600
    x = rng.uniform(-1, 1, (n, 3)).astype(np.float32)
    r = rng.uniform(0.02, 0.12, n).astype(np.float32)
    body = (np.arange(n) // 3).astype(np.uint32)
    got = tumble.find_pairs(x, r, body)
    assert got.dtype == np.uint32 and got.shape[1] == 2
    # Pairs far from touching decide the same in float and double; the few within rounding of
    # |x_i - x_j| = r_i + r_j are left out of the comparison.
    d = np.linalg.norm(x[got[:, 0]].astype(np.float64) - x[got[:, 1]], axis=1)
    assert np.all(d <= (r[got[:, 0]].astype(np.float64) + r[got[:, 1]]) * (1 + 1e-6))
    want = brute_pairs(x, r, body)
    assert len(want) > 100
    assert set(map(tuple, got.tolist())) == want
    with pytest.raises(tumble.Error, match="radius"):
        tumble.find_pairs(x, r[:-1], body)


def test_contacts_are_the_touching_pairs_at_the_start_of_the_step():
    sim = tumble.Simulation(tumble.Scene.load(SPHERES), threads=2)
    sim.step(299)
    p = sim.particles()
    sim.step(1)
    c = sim.contacts()
    assert len(c) > 0
    assert set(map(tuple, c.tolist())) == set(map(tuple, tumble.find_pairs(p["x"], p["radius"], p["body"]).tolist()))
    assert sim.thermo()["contacts"] == len(c)


def test_checkpoint_and_resume(tmp_path):
    scene = tumble.Scene.load(MOLECULES)
    whole = tumble.Simulation(scene)
    whole.step(120)
    half = tumble.Simulation(scene)
    half.step(60)
    half.checkpoint(str(tmp_path / "c.ck"))
    resumed = tumble.Simulation(scene, resume=str(tmp_path / "c.ck"))
    assert resumed.step_count == 60
    resumed.step(60)
    for k in ("x", "v", "q", "l"):
        assert same_bits(resumed.bodies()[k], whole.bodies()[k]), k
    with pytest.raises(tumble.InputError, match="nope.ck"):
        tumble.Simulation(scene, resume=str(tmp_path / "nope.ck"))


def test_recording_and_time_series_equal_tumble_runs(tmp_path):
    with tumble.Simulation(tumble.Scene.load(MOLECULES)) as sim:
        sim.record(str(tmp_path / "py.bin"))
        sim.write_thermo(str(tmp_path / "py.csv"), every=20)
        sim.step(100)
    subprocess.run([BIN, "run", MOLECULES, "--steps", "100", "--record", str(tmp_path / "cli.bin"),
                    "--thermo", str(tmp_path / "cli.csv"), "--thermo-every", "20", "-q"], check=True)
    assert (tmp_path / "py.bin").read_bytes() == (tmp_path / "cli.bin").read_bytes()
    assert (tmp_path / "py.csv").read_text() == (tmp_path / "cli.csv").read_text()
    header = (tmp_path / "cli.csv").read_text().splitlines()[0].split(",")
    assert list(sim.thermo().keys()) == header


def test_energy_balance_equals_tumble_run(tmp_path):
    """write_thermo(energy_balance=True) writes the bytes of tumble run --energy-balance; thermo()
    has the tally's numbers while it writes and NaN without it."""
    with tumble.Simulation(tumble.Scene.load(MOLECULES)) as sim:
        assert np.isnan(sim.thermo()["balance"])
        sim.write_thermo(str(tmp_path / "py.csv"), every=50, energy_balance=True)
        sim.step(300)
        row = sim.thermo()
        assert row["dissipated_normal"] > 0 and row["balance"] == pytest.approx(
            row["energy"] + row["dissipated_normal"] + row["dissipated_tangential"] + row["dissipated_friction"]
            + row["dissipated_cohesion"] - row["wall_work"] - row["pull_work"])
        sim.close_thermo()
        assert np.isnan(sim.thermo()["balance"])
    subprocess.run([BIN, "run", MOLECULES, "--steps", "300", "--thermo", str(tmp_path / "cli.csv"), "--thermo-every",
                    "50", "--energy-balance", "-q"], check=True)
    assert (tmp_path / "py.csv").read_text() == (tmp_path / "cli.csv").read_text()


def test_energy_balance_counts_from_each_series(tmp_path):
    """A series that replaces another counts its tally from its first row; a write_thermo that
    fails leaves the series under way and its tally as they were; one opened again after
    close_thermo starts from 0 (the steps between were not tallied)."""
    with tumble.Simulation(tumble.Scene.load(MOLECULES)) as sim:
        sim.write_thermo(str(tmp_path / "a.csv"), every=100, energy_balance=True)
        sim.step(300)
        sim.write_thermo(str(tmp_path / "b.csv"), every=100, energy_balance=True)
        assert sim.thermo()["dissipated_normal"] == 0.0
        sim.step(300)
        with pytest.raises(Exception):
            sim.write_thermo(str(tmp_path / "no" / "x.csv"), energy_balance=False)
        sim.step(100)
        assert sim.thermo()["dissipated_normal"] > 0.0
        sim.close_thermo()
        sim.step(100)
        sim.write_thermo(str(tmp_path / "c.csv"), every=100, energy_balance=True)
        assert sim.thermo()["dissipated_normal"] == 0.0
    with open(tmp_path / "b.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["step"] for r in rows] == ["300", "400", "500", "600", "700"]
    assert rows[0]["dissipated_normal"] == "0" and all(float(r["balance"]) == float(r["balance"]) for r in rows)


@pytest.mark.parametrize("name, walls", [("box", 5), ("drum", 3)])
def test_recordings_carry_the_walls_as_tumble_run_writes_them(tmp_path, name, walls):
    """A recording written from Python holds the scene's walls (version 2), byte for byte those of
    `tumble run`: the writer takes them from the world, whoever writes."""
    scene = os.path.join(SRC, "scenes", name + ".toml")
    with tumble.Simulation(tumble.Scene.load(scene)) as sim:
        sim.record(str(tmp_path / "py.bin"))
        sim.step(400)
    subprocess.run([BIN, "run", scene, "--steps", "400", "--record", str(tmp_path / "cli.bin"), "-q"], check=True)
    data = (tmp_path / "py.bin").read_bytes()
    assert data == (tmp_path / "cli.bin").read_bytes()
    version, header = np.frombuffer(data, "<u4", 2, 8)
    particles = int(np.frombuffer(data, "<u4", 1, 16)[0])
    assert version == 3
    assert int(np.frombuffer(data, "<u4", 1, header + 28 * particles + 4)[0]) == walls  # W, the wall count


def test_scene_from_dict_equals_the_file(tmp_path):
    with open(MOLECULES, "rb") as f:
        tables = tomllib.load(f)
    tables.setdefault("output", {}).pop("record", None)
    text = tumble.to_toml(tables)
    assert tomllib.loads(text) == tables  # the writer is TOML that reads back to the same tables
    a = tumble.Simulation(tumble.scene_from_dict(tables))
    b = tumble.Simulation(tumble.Scene.load(MOLECULES))
    a.step(50)
    b.step(50)
    assert same_bits(a.bodies()["x"], b.bodies()["x"])


def test_set_reaches_the_entries_of_arrays_of_tables():
    """Issue 35, item 7: an entry by its index from 0 or its name, checked as the file is; the
    messages say set=, not the command line."""
    others = tumble.Scene.load(MOLECULES).num_bodies - 20 * 19 * 4  # the [[body]] tables; the group is 20 x 19 x 4
    assert tumble.Scene.load(MOLECULES, set=["group[0].count=[2, 3, 1]"]).num_bodies == others + 6
    with open(MOLECULES, "rb") as f:
        tables = tomllib.load(f)
    tables["shape"][0]["sphere"][1]["radius"] = 0.2
    a = tumble.Simulation(tumble.Scene.load(MOLECULES, set=["shape.dimer.sphere[1].radius=0.2"]))
    b = tumble.Simulation(tumble.scene_from_dict(tables))
    a.step(30)
    b.step(30)
    assert same_bits(a.bodies()["x"], b.bodies()["x"])
    for spec, message in [
            ("group[1].count=[1, 1, 1]", r"group\[1\]: the scene has 1 \[\[group\]\] table, group\[0\]$"),
            ("shape.dimer.sphere[0].radius=-1", r'shape "dimer", \[\[shape.sphere\]\] #1: radius must be > 0'),
            ("shape.dimr.name=1", r'shape.dimr: no \[\[shape\]\] is named "dimr"; the names: "dimer" \(shape\[0\]\), '),
            ("foo", r"expected SECTION.KEY=VALUE.*e.g. set=\['ground.friction=0.3'\]")]:
        with pytest.raises(tumble.InputError, match=r"^set=\['" + spec.replace("[", r"\[").replace("]", r"\]") +
                           r"'\]: " + message) as e:
            tumble.Scene.load(MOLECULES, set=[spec])
        assert "command line" not in str(e.value) and "--set" not in str(e.value)
    with pytest.raises(tumble.InputError, match=r"""^set=\["scene.name='x"\]: TOML syntax error"""):
        tumble.Scene.load(MOLECULES, set=["scene.name='x"])  # quoted as repr() quotes it

def test_scene_from_dict_finds_meshes_from_base(tmp_path, monkeypatch):
    """Issue 35, item 7: the tables of a scene with a relative mesh file load from Python with
    base= the scene's folder, and run as the file does."""
    with open(HOPPER_MESH, "rb") as f:
        tables = tomllib.load(f)
    assert tables["wall"][0]["file"] == "hopper-mesh.stl"
    monkeypatch.chdir(tmp_path)  # no mesh here
    with pytest.raises(tumble.InputError, match=r"cannot open the mesh file.*looked for at hopper-mesh.stl"):
        tumble.scene_from_dict(tables)
    with pytest.raises(tumble.InputError, match=r"a relative file is found from the base folder " + str(tmp_path)):
        tumble.scene_from_dict(tables, base=tmp_path)
    for base in (os.path.join(SRC, "scenes"), pathlib.Path(SRC) / "scenes"):
        a = tumble.Simulation(tumble.scene_from_dict(tables, base=base, set=["wall[0].friction=0.4"]))
        b = tumble.Simulation(tumble.Scene.load(HOPPER_MESH, set=["wall[0].friction=0.4"]))
        assert a.num_bodies == b.num_bodies == 400
        a.step(20)
        b.step(20)
        assert same_bits(a.bodies()["x"], b.bodies()["x"])


def test_a_small_scene_built_in_python():
    scene = tumble.scene_from_dict({
        "scene": {"name": "drop", "dt": 1e-4, "steps": 2000},
        "ground": {"height": 0.0},
        "shape": [{"name": "ball", "sphere": [{"offset": [0.0, 0.0, 0.0], "radius": 0.1, "mass": 1.0,
                                               "elasticity": 0.5}]}],
        "body": [{"shape": "ball", "position": [0.0, 0.0, 1.0]}],
    })
    sim = tumble.Simulation(scene)
    z0 = sim.bodies()["x"][0, 2]
    sim.step(1000)
    t = sim.time
    z = sim.bodies()["x"][0, 2]
    assert abs((z0 - z) - 0.5 * 9.81 * t * t) < 2e-3  # free fall, before it lands (t = 0.1 s)


def test_a_wall_built_in_python():
    """A ball thrown at a plane wall x = 1 (normal -x, no gravity) comes back at e times its speed."""
    scene = tumble.scene_from_dict({
        "scene": {"name": "wall", "dt": 1e-5, "steps": 4000, "gravity": [0.0, 0.0, 0.0]},
        "wall": [{"type": "plane", "point": [1.0, 0.0, 0.0], "normal": [-1.0, 0.0, 0.0], "stiffness": 1e5,
                  "friction": 0.0}],
        "shape": [{"name": "ball", "sphere": [{"radius": 0.1, "mass": 1.0, "elasticity": 0.5}]}],
        "body": [{"shape": "ball", "position": [0.85, 0.0, 0.0], "velocity": [2.0, 0.0, 0.0]}],
    })
    sim = tumble.Simulation(scene)
    sim.step(4000)
    b = sim.bodies()
    assert b["x"][0, 0] < 0.9
    assert abs(b["v"][0, 0] + 0.5 * 2.0) < 0.02


def test_a_pour_grows_the_run_as_tumble_run_does(tmp_path):
    """[[pour]] bodies enter during step() calls split anyhow: the bodies and their bits are the
    command's, and so is the recording (its frames hold the bodies present)."""
    tables = {
        "scene": {"name": "pour", "dt": 1e-4, "steps": 600},
        "ground": {"height": 0.0},
        "shape": [{"name": "ball", "sphere": [{"radius": 0.1, "mass": 1.0, "elasticity": 0.5}]}],
        "body": [{"shape": "ball", "position": [0.0, 0.0, 0.1]}],
        "pour": [{"shape": "ball", "count": 30, "rate": 1000, "start": 0.005, "interval": 0.001, "region": "box",
                  "min": [-0.3, -0.3, 0.5], "max": [0.9, 0.9, 1.1]}],
    }
    scene = tumble.scene_from_dict(tables)
    assert scene.num_bodies == 31 and scene.pour_bodies == 30, "the pour's bodies count (issue 35, item 8)"
    sim = tumble.Simulation(scene)
    assert sim.num_bodies == 1 and sim.bodies_to_come == 30
    sim.record(tmp_path / "py.bin")
    for n in (7, 93, 250, 250):
        sim.step(n)
    assert sim.num_bodies == 31 and sim.bodies()["x"].shape == (31, 3)
    assert sim.bodies_to_come == 0
    path = tmp_path / "pour.toml"
    path.write_text(tumble.to_toml(tables))
    want = cli_state(tmp_path, str(path), "--steps", "600")
    for k, v in sim.bodies().items():
        if k in want:
            assert same_bits(v, want[k]), k
    sim.close_recording()
    subprocess.run([BIN, "run", str(path), "--steps", "600", "--record", str(tmp_path / "cli.bin"), "-q"], check=True)
    assert (tmp_path / "py.bin").read_bytes() == (tmp_path / "cli.bin").read_bytes()


def test_a_nul_byte_in_name_or_set_is_shown_escaped():
    # A NUL in name= or set= is shown as \0; it used to end the message there (issue 34, item 12).
    with pytest.raises(tumble.InputError) as e:
        tumble.Scene.parse('[scene]\nname = "x"\ndt = -1\n', name="sce\0ne.toml")
    assert str(e.value).startswith("sce\\0ne.toml:3: "), str(e.value)
    assert "dt" in str(e.value)
    with pytest.raises(tumble.InputError) as e:
        tumble.Scene.load(MOLECULES, set=["ground.friction=-1\0 # x"])
    assert str(e.value).startswith("set=['ground.friction=-1\\0 # x']: "), str(e.value)
    assert "\0" not in str(e.value)


def test_errors_name_the_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[scene]\nname = "x"\ndt = -1\n')
    with pytest.raises(tumble.InputError, match=r"bad.toml:3"):
        tumble.Scene.load(str(bad))
    with pytest.raises(tumble.InputError, match=r"^set=\['ground.friction=-1'\]: \[ground\]: friction must be >= 0"):
        tumble.Scene.load(MOLECULES, set=["ground.friction=-1"])
    with pytest.raises(tumble.InputError, match=r"<python>:"):
        tumble.scene_from_dict({"scene": {"name": "x", "bogus": 1}})
    with pytest.raises(tumble.Error, match="pipeline|backend"):
        tumble.Simulation(tumble.Scene.load(MOLECULES), pipeline="quantum")
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES))
    with pytest.raises(tumble.Error, match="unknown bits"):
        sim.pulls = 8
    sim.pulls = tumble.PULL_X | tumble.PULL_SWIRL
    assert sim.pulls == 5


def test_a_diverging_run_raises(tmp_path):
    scene = tumble.Scene.load(MOLECULES, set=["scene.dt=0.05"])
    sim = tumble.Simulation(scene)
    with pytest.raises(tumble.SimulationError, match="use dt <="):
        sim.step(2000)


def test_splitting_the_steps_changes_nothing(tmp_path):
    """Guard checks, frames and rows fall on multiples of their intervals however step() is called
    (the swirl's work, which the checks integrate, is the sensitive column)."""
    scene = tumble.Scene.load(MOLECULES, set=['pulls.on=["swirl"]'])
    outs = []
    for k, calls in enumerate([[100], [37, 63], [7] * 14 + [2]]):
        with tumble.Simulation(scene) as sim:
            sim.record(tmp_path / f"r{k}.bin")
            sim.write_thermo(tmp_path / f"t{k}.csv", every=30)
            for n in calls:
                sim.step(n)
                sim.thermo()  # asking changes nothing either
        outs.append(((tmp_path / f"r{k}.bin").read_bytes(), (tmp_path / f"t{k}.csv").read_text()))
    assert outs[0] == outs[1] == outs[2]
    subprocess.run([BIN, "run", MOLECULES, "--set", 'pulls.on=["swirl"]', "--steps", "100", "--thermo",
                    str(tmp_path / "cli.csv"), "--thermo-every", "30", "-q"], check=True)
    cli = (tmp_path / "cli.csv").read_text().splitlines()
    assert outs[0][1].splitlines() == cli[:-1]  # tumble run adds the last step's row (100)


def test_one_simulation_is_not_shared_between_threads():
    import threading
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES), threads=2, guard=False)
    errors, done = [], []

    def run():
        try:
            sim.step(400)
            done.append(1)
        except tumble.Error as e:
            errors.append(str(e))

    ts = [threading.Thread(target=run) for _ in range(3)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert sim.step_count == 400 * len(done)
    assert all("in use by another thread" in e for e in errors)


def test_find_pairs_refuses_bad_body_ids_and_values():
    x = np.zeros((3, 3), dtype=np.float32)
    x[:, 0] = [0.0, 0.1, 5.0]
    r = np.full(3, 0.1, dtype=np.float32)
    for bad in ([2**32, 0, 1], [-1, 0, 1], [0.5, 1.7, 2.2]):
        with pytest.raises(tumble.InputError, match="body"):
            tumble.find_pairs(x, r, np.array(bad))
    x[2, 1] = np.nan
    with pytest.raises(tumble.InputError, match="not finite"):
        tumble.find_pairs(x, r, np.arange(3))
    with pytest.raises(tumble.InputError, match="radius"):
        tumble.find_pairs(x[:2], np.array([0.1, -1.0]), np.arange(2))
    # Outside the range whose pairs single precision decides right (issue 34, item 7): both
    # pairs were missed, with no error.
    with pytest.raises(tumble.InputError, match=r"particle 0: its radius 1e-23 m is outside \[2\^-60, 2\^60\] m"):
        tumble.find_pairs(np.zeros((2, 3)), np.full(2, 1e-23), np.arange(2))
    with pytest.raises(tumble.InputError, match=r"particle 1: its radius 1\.5e\+19 m is outside"):
        tumble.find_pairs(np.array([[0, 0, 0], [2e19, 0, 0]]), np.array([1e-3, 1.5e19]), np.arange(2))
    with pytest.raises(tumble.InputError, match=r"particle 1: it reaches beyond \+-2\^60 m \(1.15e18\) along y"):
        tumble.find_pairs(np.array([[0, 0, 0], [0, 1.2e18, 0]]), np.full(2, 1.0), np.arange(2))


def test_to_toml_quotes_keys_and_escapes_strings():
    tables = {"output": {"thermo_every = 5\nx": 1, "a.b": "q\"uote\\ \r\x00\x7f\b é"}, "t a": {"k]": True}}
    assert tomllib.loads(tumble.to_toml(tables)) == tables
    with pytest.raises(tumble.Error, match="key must be a string"):
        tumble.to_toml({"scene": {1: 2}})
    with open(MOLECULES, "rb") as f:
        scene = tomllib.load(f)
    scene.setdefault("output", {})["thermo_every = 5\nx"] = 1  # one odd key, not two lines
    with pytest.raises(tumble.InputError, match="unknown key"):
        tumble.scene_from_dict(scene)


def test_outputs_are_not_clobbered(tmp_path):
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES))
    sim.record(tmp_path / "same.out")
    with pytest.raises(tumble.Error, match="recording's file"):
        sim.write_thermo(tmp_path / "same.out")
    with pytest.raises(tumble.Error, match="writing"):
        sim.checkpoint(tmp_path / "same.out")
    with pytest.raises(tumble.Error):
        sim.record(tmp_path / "no" / "such" / "dir" / "x.bin")
    sim.step(20)  # the recording under way goes on
    sim.close()
    assert len((tmp_path / "same.out").read_bytes()) > 0
    subprocess.run([BIN, "export", str(tmp_path / "same.out"), str(tmp_path / "ex"), "-q"], check=True)
    assert len(list((tmp_path / "ex").glob("same_0*.vtp"))) == 3  # frames 0, 10, 20


def test_warnings_and_names():
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES, set=["scene.dt=0.01"]))
    assert "use dt <=" in sim.warning
    assert tumble.SimulationError.__module__ == "tumble"
    assert "dt 1e-07 s" in repr(tumble.Scene.load(MOLECULES, set=["scene.dt=1e-7"]))


def test_a_pour_that_falls_behind_warns_once():
    """A pour faster than its region takes bodies says so (issue 35, item 8): a RuntimeWarning
    naming the bodies that wait, and bodies_to_come counts them."""
    tables = {
        "scene": {"name": "behind", "dt": 1e-4, "steps": 400},
        "ground": {"height": 0.0},
        "shape": [{"name": "ball", "sphere": [{"radius": 0.1, "mass": 1.0, "elasticity": 0.5}]}],
        "pour": [{"shape": "ball", "count": 40, "rate": 1e5, "region": "box",
                  "min": [0.0, 0.0, 0.5], "max": [0.5, 0.5, 0.9]}],
    }
    sim = tumble.Simulation(tumble.scene_from_dict(tables))
    with pytest.warns(RuntimeWarning, match=r"the \[\[pour\]\] fell behind: \d+ bodies due by now found no place"):
        sim.step(200)
    assert 0 < sim.bodies_to_come < 40
    assert sim.num_bodies + sim.bodies_to_come == 40
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sim.step(100)  # said once


def test_paths_may_be_bytes(tmp_path):
    """A bytes path is the file system's name (os.fsdecode), not the text "b'...'"."""
    sim = tumble.Simulation(tumble.Scene.load(os.fsencode(SPHERES)))
    sim.step(2)
    sim.checkpoint(os.fsencode(str(tmp_path / "b.ck")))
    assert (tmp_path / "b.ck").is_file()
    assert not any(p.name.startswith("b'") for p in tmp_path.iterdir())
