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
