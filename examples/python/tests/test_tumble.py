# SPDX-License-Identifier: MIT
"""The Python module against independent references: the `tumble` command on the same scene
(bit for bit), NumPy brute force for the pairs, Python's tomllib for the scene writer.
Run by ctest (python_tests) with PYTHONPATH, TUMBLE_BIN and TUMBLE_SOURCE_DIR set."""
import csv
import os
import subprocess
import tomllib

import numpy as np
import pytest

import tumble

BIN = os.environ["TUMBLE_BIN"]
SRC = os.environ["TUMBLE_SOURCE_DIR"]
MOLECULES = os.path.join(SRC, "scenes", "molecules.toml")
SPHERES = os.path.join(SRC, "scenes", "spheres.toml")


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


@pytest.mark.parametrize("path", [MOLECULES, SPHERES])
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


def test_errors_name_the_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[scene]\nname = "x"\ndt = -1\n')
    with pytest.raises(tumble.InputError, match=r"bad.toml:3"):
        tumble.Scene.load(str(bad))
    with pytest.raises(tumble.InputError, match=r"command line, --set ground.friction=-1"):
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
