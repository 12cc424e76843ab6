# SPDX-License-Identifier: MIT
"""examples/heap_angle.py against cones of known slope (no tumble needed)."""
import importlib.util
import math
import os
import random

import pytest

_spec = importlib.util.spec_from_file_location(
    "heap_angle", os.path.join(os.environ.get("TUMBLE_SOURCE_DIR", "."), "examples", "heap_angle.py"))
heap_angle = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(heap_angle)


def cone(deg, n=20000, radius=0.5, seed=3):
    rng = random.Random(seed)
    h = radius * math.tan(math.radians(deg))
    rows = []
    for _ in range(n):
        r = radius * math.sqrt(rng.random())
        a = 2 * math.pi * rng.random()
        z = rng.random() * max(0.0, h * (1 - r / radius))
        rows.append({"x": str(r * math.cos(a)), "y": str(r * math.sin(a)), "z": str(z)})
    return rows


@pytest.mark.parametrize("deg", [10, 25, 40])
def test_the_slope_of_a_cone(deg):
    angle, rmax, height, _ = heap_angle.heap_angle(cone(deg))
    print("cone of %d deg: measured %.2f" % (deg, angle))
    assert abs(angle - deg) < 1.5


def test_too_few_bodies():
    with pytest.raises(ValueError):
        heap_angle.heap_angle(cone(20, n=5))
