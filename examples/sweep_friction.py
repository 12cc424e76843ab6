#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A parameter sweep from Python (docs/python.md): the ground friction of molecules.toml from 0 to
1.2, each run's time series to thermo_mu*.csv (draw one with `tumble plot thermo_mu0.6.csv`) and
one line per run. usage: PYTHONPATH=build/python python3 examples/sweep_friction.py"""
import os
import tumble

scene_file = os.path.join(os.path.dirname(__file__), "..", "scenes", "molecules.toml")
for mu in [0.0, 0.3, 0.6, 0.9, 1.2]:
    scene = tumble.Scene.load(scene_file, set=[f"ground.friction={mu}"])
    with tumble.Simulation(scene) as sim:
        sim.write_thermo(f"thermo_mu{mu}.csv", every=50)
        sim.step(scene.steps)
        x = sim.particles()["x"]
        print(f"friction {mu}: spread {x[:, :2].std():.3f} m, kinetic energy "
              f"{sim.thermo()['kinetic_translation']:.2f} J, {len(sim.contacts())} contacts")
