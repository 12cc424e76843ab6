# SPDX-License-Identifier: MIT
"""The state of a Simulation between steps: per-particle velocities against finite differences,
shape names against the scene, set_bodies and set_parameters against runs that started with (or
resumed into) those values, bit for bit, and the forces against Newton's laws."""
import os

import numpy as np
import pytest

import tumble

SRC = os.environ["TUMBLE_SOURCE_DIR"]
MOLECULES = os.path.join(SRC, "scenes", "molecules.toml")
SPHERES = os.path.join(SRC, "scenes", "spheres.toml")
HERTZ = os.path.join(SRC, "scenes", "heap-hertz.toml")


def same_bits(a, b):
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def same_state(a, b):
    return all(same_bits(a.bodies()[k], b.bodies()[k]) for k in ("x", "v", "q", "l"))


def balls(velocities=None, positions=None, extra=None):
    """Three balls above the ground (report law): a small scene built in Python."""
    positions = positions or [[0.0, 0.0, 0.5], [0.5, 0.0, 0.3], [1.0, 0.0, 0.1]]
    velocities = velocities or [[0.0, 0.0, 0.0]] * len(positions)
    tables = {
        "scene": {"name": "balls", "dt": 1e-4, "steps": 1000},
        "ground": {"height": 0.0, "friction": 0.4},
        "shape": [{"name": "ball", "sphere": [{"radius": 0.1, "mass": 1.0, "elasticity": 0.5}]},
                  {"name": "pair", "sphere": [{"offset": [-0.05, 0.0, 0.0], "radius": 0.06, "mass": 0.5, "elasticity": 0.5},
                                              {"offset": [0.05, 0.0, 0.0], "radius": 0.06, "mass": 0.5, "elasticity": 0.5}]}],
        "body": [{"shape": "ball", "position": p, "velocity": v} for p, v in zip(positions, velocities)],
    }
    if extra:
        tables.update(extra)
    return tumble.scene_from_dict(tables)


# --- per-particle velocities, shape names -------------------------------------------------------

def test_particle_velocities_are_the_rigid_motion():
    """v = V + omega x (x - X) of each particle's body: a step of dt moves the particles by v dt
    (to first order), and spinning bodies give their particles other velocities than their centre."""
    sim = tumble.Simulation(tumble.Scene.load(MOLECULES))
    sim.step(20)  # falling and spinning, before the first contact
    p0, b = sim.particles(), sim.bodies()
    sim.step(1)
    p1 = sim.particles()
    dt = tumble.Scene.load(MOLECULES).dt
    # Kick-drift: the step moves the centres by V dt with the new V, and turns the bodies by the new
    # Omega. What is left is the rounding of x (two ulps of 2 m over dt: 1.6e-3 m/s) and the arcs
    # (|Omega|^2 |arm| dt, 1.6e-3 m/s at 6 rad/s).
    moved = (p1["x"].astype(np.float64) - p0["x"]) / dt
    assert p1["v"].shape == p1["x"].shape and p1["v"].dtype == np.float32
    assert np.abs(moved - p1["v"]).max() < 4e-3
    spin = np.abs(p0["v"] - b["v"][p0["body"]]).max()
    assert spin > 0.3  # the molecules' random spins move their spheres: V alone would be that far off
    arm = p0["x"].astype(np.float64) - b["x"][p0["body"]]
    want = b["v"][p0["body"]] + np.cross(b["omega"][p0["body"]].astype(np.float64), arm)
    assert np.abs(want - p0["v"]).max() < 1e-4


def test_every_body_has_its_shape_name(tmp_path):
    scene = balls(extra={"body": [{"shape": "ball", "position": [0.0, 0.0, 0.5]},
                                  {"shape": "pair", "position": [0.5, 0.0, 0.3]},
                                  {"shape": "ball", "position": [1.0, 0.0, 0.3]}],
                         "pour": [{"shape": "pair", "count": 2, "rate": 1000, "start": 0.0, "interval": 0.001,
                                   "region": "box",
                                   "min": [2.0, 2.0, 0.5], "max": [3.0, 3.0, 1.0]}]})
    sim = tumble.Simulation(scene)
    sim.step(50)
    assert sim.num_bodies == 5
    b = sim.bodies()
    assert b["shape"].shape == (5,)
    assert [sim.shape_names[s] for s in b["shape"]] == ["ball", "pair", "ball", "pair", "pair"]


# --- setting bodies and pulls between steps -------------------------------------------------------

@pytest.mark.parametrize("pipeline", ["cpu", "cuda-host"])
@pytest.mark.parametrize("path, sets", [(MOLECULES, []), (HERTZ, ["scene.steps=300"])])
def test_setting_the_state_it_has_changes_no_bit(path, sets, pipeline):
    """set_bodies reloads the pipeline with the state as it integrates it (the contact history of
    hertz-mindlin too): setting the values the run has gives the uninterrupted run's bits, on the
    CPU pipeline and on the CUDA pipeline's code (its host backend)."""
    scene = tumble.Scene.load(path, set=sets)
    whole, split = tumble.Simulation(scene, pipeline), tumble.Simulation(scene, pipeline)
    whole.step(120)
    split.step(60)
    b = split.bodies()
    split.set_bodies(x=b["x"], v=b["v"], q=b["q"], l=b["l"])
    assert split.step_count == 60
    split.step(60)
    assert same_state(whole, split)


def test_a_state_set_at_the_start_is_the_scene_that_starts_with_it():
    v = [[1.0, 0.0, 2.0], [0.0, -1.0, 0.0], [0.5, 0.5, 0.0]]
    later = tumble.Simulation(balls())
    later.set_bodies(v=np.array(v, dtype=np.float32))
    x = later.bodies()["x"]
    x[1] = [0.5, 0.0, 0.4]
    later.set_bodies(bodies=[1], x=x[1:2])
    given = tumble.Simulation(balls(velocities=v, positions=[[0.0, 0.0, 0.5], [0.5, 0.0, 0.4], [1.0, 0.0, 0.1]]))
    for sim in (given, later):
        sim.step(3000)  # falls, bounces and rolls
    assert same_state(given, later)


def test_a_body_moved_during_the_run_falls_from_there():
    sim = tumble.Simulation(balls())
    sim.step(500)
    sim.set_bodies(bodies=[0], x=[[3.0, 0.0, 2.0]], v=[[0.0, 0.0, 0.0]])
    assert same_bits(sim.bodies()["x"][0], np.array([3.0, 0.0, 2.0], np.float32))
    t0 = sim.time
    sim.step(1000)
    t = sim.time - t0
    assert sim.bodies()["x"][0, 2] == pytest.approx(2.0 - 0.5 * 9.81 * t * t, abs=2e-3)


def test_setting_a_spin():
    """omega sets L = R I0 R^T omega; bodies() hands the same omega back."""
    scene = tumble.Scene.load(MOLECULES)
    sim = tumble.Simulation(scene)
    w = np.tile(np.array([[0.0, 0.0, 5.0]], np.float32), (sim.num_bodies, 1))
    sim.set_bodies(omega=w)
    assert np.abs(sim.bodies()["omega"] - w).max() < 1e-4
    ref = tumble.Simulation(scene)
    sim.step(10)
    ref.step(10)
    assert not same_bits(sim.bodies()["q"], ref.bodies()["q"])


def test_bad_changes_raise_and_change_nothing():
    sim, ref = tumble.Simulation(balls()), tumble.Simulation(balls())
    sim.step(10)
    ref.step(10)
    cases = [
        (dict(x=np.zeros((2, 3))), r"x must have shape \(3, 3\)"),
        (dict(bodies=[3], v=[[0, 0, 0]]), "body 3 is not one of the 3 bodies"),
        (dict(bodies=[0, 0], v=[[0, 0, 0], [1, 0, 0]]), "body 0 is named twice"),
        (dict(bodies=[0], v=[[np.nan, 0, 0]]), "not finite"),
        (dict(bodies=[0], q=[[1, 0, 0, 0.1]]), "not a unit quaternion"),
        (dict(bodies=[0], omega=[[0, 0, 1]]), "does not rotate"),
        (dict(bodies=[0], l=[[0, 0, 0]], omega=[[0, 0, 0]]), "l or omega, not both"),
        (dict(bodies=[0.5]), "whole numbers"),
        # Beyond the range whose contacts single precision decides right (issue 34, item 7).
        (dict(bodies=[0], x=[[3e38, 0, 0]]), r"beyond \+-2\^60 m"),
        (dict(bodies=[0], x=[[0, 2e18, 0]]), r"beyond \+-2\^60 m"),
    ]
    for kwargs, message in cases:
        with pytest.raises(tumble.Error, match=message):
            sim.set_bodies(**kwargs)
    sim.step(100)
    ref.step(100)
    assert same_state(sim, ref)


def test_pulls_set_between_steps():
    """The pulls act from the next step: on at the start is the scene with them on, and switching
    them during the run changes the motion from then on."""
    on = tumble.Simulation(tumble.Scene.load(MOLECULES, set=['pulls.on=["x", "swirl"]']))
    late = tumble.Simulation(tumble.Scene.load(MOLECULES))
    late.pulls = tumble.PULL_X | tumble.PULL_SWIRL
    off = tumble.Simulation(tumble.Scene.load(MOLECULES))
    for sim in (on, late, off):
        sim.step(100)
    assert same_state(on, late) and not same_state(on, off)
    late.pulls = 0
    on.step(1)
    late.step(1)
    assert not same_bits(on.bodies()["v"], late.bodies()["v"])


# --- forces ------------------------------------------------------------------------------------------

def test_forces_of_a_resting_ball_and_of_contacts():
    sim = tumble.Simulation(balls(positions=[[0.0, 0.0, 0.1]]))
    with pytest.raises(tumble.Error, match="capture_forces = True"):
        sim.forces()
    sim.capture_forces = True
    with pytest.raises(tumble.Error, match="step first"):
        sim.forces()
    sim.step(5000)  # settled on the ground
    f = sim.forces()
    assert sorted(f) == sorted(["repulsion", "damping", "shear", "ground", "friction"])
    assert f["ground"][0, 2] == pytest.approx(9.81, rel=1e-3)  # carries m g, m = 1 kg
    assert np.abs(f["repulsion"]).max() == 0.0

    spheres = tumble.Simulation(tumble.Scene.load(SPHERES))
    spheres.capture_forces = True
    spheres.step(300)
    f = spheres.forces()
    contact = f["repulsion"].astype(np.float64) + f["damping"] + f["shear"]
    assert np.abs(contact).max() > 1.0
    assert np.abs(contact.sum(axis=0)).max() < 1e-3 * np.abs(contact).sum()  # action = reaction


def test_capturing_forces_changes_no_bit_and_survives_a_plain_recording(tmp_path):
    a, b = tumble.Simulation(tumble.Scene.load(SPHERES)), tumble.Simulation(tumble.Scene.load(SPHERES))
    a.capture_forces = True
    a.record(tmp_path / "plain.bin")  # a recording without forces keeps the capture on
    a.step(200)
    b.step(200)
    assert same_state(a, b)
    assert a.forces()["ground"].shape == (a.num_particles, 3)
    a.close_recording()
    a.step(1)
    assert a.capture_forces and a.forces()["ground"].shape == (a.num_particles, 3)


# --- contact parameters -----------------------------------------------------------------------------

@pytest.mark.parametrize("path, sets, changes", [
    (SPHERES, [], {"ground.friction": 0.1, "contact.damping": 5.0}),
    (HERTZ, ["scene.steps=300"], {"material.glass.youngs_modulus": 4e7, "material.glass.friction": 0.3,
                                  "ground.friction": 0.2}),
])
@pytest.mark.parametrize("pipeline", ["cpu", "cuda-host"])
def test_parameters_changed_between_steps_are_a_resumed_run_with_them(tmp_path, path, sets, changes, pipeline):
    """A change at step 100 goes on exactly as a run of the changed scene resumed from a checkpoint
    of step 100 (the documented warning about other parameters aside)."""
    scene = tumble.Scene.load(path, set=sets)
    changed = tumble.Scene.load(path, set=sets + [f"{k}={v}" for k, v in changes.items() if not k.startswith("material")])
    sim = tumble.Simulation(scene, pipeline)
    sim.step(100)
    sim.checkpoint(tmp_path / "c.ck")
    sim.set_parameters(changes)
    sim.step(100)
    if any(k.startswith("material") for k in changes):  # [[material]] tables take no --set: edit the text
        text = open(path).read().replace("youngs_modulus = 5.0e7", "youngs_modulus = 4e7")
        text = text.replace("friction = 0.5           # Coulomb", "friction = 0.3           # Coulomb")
        changed = tumble.Scene.parse(text, "heap-hertz.toml", sets + ["ground.friction=0.2"])
    resumed = tumble.Simulation(changed, pipeline, resume=tmp_path / "c.ck")
    assert "differ" in resumed.warning
    resumed.step(100)
    assert same_state(sim, resumed)
    plain = tumble.Simulation(scene, pipeline)
    plain.step(200)
    assert not same_state(sim, plain)


def test_what_cannot_change_is_named():
    sim = tumble.Simulation(tumble.Scene.load(SPHERES))
    sim.step(10)
    ref = tumble.Simulation(tumble.Scene.load(SPHERES))
    ref.step(10)
    for changes, message in [
        ({"contact.law": 1.0}, "contact.law: the law cannot change during a run"),
        ({"ground.height": 1.0}, "ground.height: the ground's place"),
        ({"scene.dt": 1e-4}, "scene.dt: dt cannot change"),
        ({"contact.friction": 0.3}, r"contact.friction: not a contact parameter .* these can: contact.stiffness, "
                                    r"contact.damping, contact.shear, ground.stiffness"),
        ({"ground.friction": -1.0}, "ground.friction = -1.* must be a finite number >= 0"),
        ({"ground.friction": 0.2, "contact.stiffness": 0.0}, "contact.stiffness = 0.* > 0"),
        ({"contact.stiffness": True}, r"contact.stiffness = True: expected a number"),
        ({"ground.friction": -1e300}, r"ground.friction = -1e\+300: must be"),
    ]:
        with pytest.raises(tumble.Error, match=message):
            sim.set_parameters(changes)
    sim.step(100)
    ref.step(100)
    assert same_state(sim, ref)  # nothing changed, not even ground.friction of the refused pair


@pytest.mark.parametrize("pipeline", ["cpu", "cuda-host"])
def test_cohesion_changed_between_steps_is_a_resumed_run_with_it(tmp_path, pipeline):
    """The cohesion's coefficient (docs/model.md#cohesion) changes as the other contact parameters:
    scenes/heap-cohesive.toml with k_c lowered at step 100 goes on as the changed scene resumed."""
    path = os.path.join(SRC, "scenes", "heap-cohesive.toml")
    sim = tumble.Simulation(tumble.Scene.load(path), pipeline)
    sim.step(100)
    sim.checkpoint(tmp_path / "c.ck")
    sim.set_parameters({"material.glass.cohesion_energy_density": 5e5, "ground.cohesion_energy_density": 2e5})
    sim.step(100)
    text = open(path).read()
    assert "cohesion_energy_density = 7e5" in text
    text = text.replace("cohesion_energy_density = 7e5", "cohesion_energy_density = 5e5")
    changed = tumble.Scene.parse(text, "heap-cohesive.toml", ["ground.cohesion_energy_density=2e5"])
    resumed = tumble.Simulation(changed, pipeline, resume=tmp_path / "c.ck")
    assert "differ" in resumed.warning
    resumed.step(100)
    assert same_state(sim, resumed)
    with pytest.raises(tumble.Error, match="contact.cohesion: the cohesion model cannot change"):
        sim.set_parameters({"contact.cohesion": 0.0})
    with pytest.raises(tumble.Error, match='surface_energy: the scene\'s cohesion is "sjkr", whose coefficient is '
                                           'cohesion_energy_density'):
        sim.set_parameters({"material.glass.surface_energy": 0.1})


def test_a_cohesion_refused_for_bodies_still_to_pour_changes_nothing():
    """Under hooke-history sjkr a k_c must stay below k / (2 pi R*) for every contact the scene can
    have, the pour's bodies included: one that suits the spheres present but not the large ones to
    come is refused, and the run goes on as if it had not been asked."""
    text = "\n".join([
        '[scene]', 'name = "pour-cohesion"', 'dt = 5e-5', 'steps = 400', 'gravity = [0, 0, -9.81]',
        '[contact]', 'law = "hooke-history"', 'stiffness = 2e4', 'gamma_n = 1500', 'cohesion = "sjkr"',
        'cohesion_energy_density = 5e4',
        '[ground]', 'stiffness = 2e4',
        '[[shape]]', 'name = "small"', '[[shape.sphere]]', 'radius = 0.01', 'density = 2500',
        '[[shape]]', 'name = "big"', '[[shape.sphere]]', 'radius = 0.05', 'density = 2500',
        '[[body]]', 'shape = "small"', 'position = [0, 0, 0.01]',
        '[[body]]', 'shape = "small"', 'position = [0.1, 0, 0.01]',
        '[[pour]]', 'shape = "big"', 'count = 2', 'rate = 200', 'start = 0.01', 'region = "box"',
        'min = [-0.3, -0.3, 0.2]', 'max = [0.3, 0.3, 0.6]', ''])
    sim = tumble.Simulation(tumble.Scene.parse(text, "pour-cohesion.toml"))
    ref = tumble.Simulation(tumble.Scene.parse(text, "pour-cohesion.toml"))
    sim.step(100)
    ref.step(100)
    # 2 pi 7e4 * 0.05 = 2.2e4 N/m against the ground's 2e4 for a big sphere (a small one: 4.4e3).
    with pytest.raises(tumble.Error, match=r"setParameters: \[ground\]: cohesion_energy_density 7e\+04 \(\[contact\]'s\)"):
        sim.set_parameters({"contact.cohesion_energy_density": 7e4})
    sim.step(300)  # the pour enters: the run goes on with k_c 5e4, as the reference
    ref.step(300)
    assert len(sim.bodies()["x"]) == 4  # the two big ones are in
    assert same_state(sim, ref)
