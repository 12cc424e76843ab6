# SPDX-License-Identifier: MIT
"""tumble: rigid bodies made of spheres, from Python (docs/python.md).

    import tumble
    scene = tumble.Scene.load("scenes/molecules.toml", set=["ground.friction=0.3"])
    with tumble.Simulation(scene, threads=2) as sim:
        sim.record("run.bin")             # a frame every steps_per_frame steps
        sim.step(1000)
        print(sim.time, sim.thermo()["energy"], len(sim.contacts()))
        x = sim.particles()["x"]          # (N, 3) NumPy array
    for frame in tumble.Recording("run.bin"):   # a recording, frame by frame
        print(frame["step"], frame["x"].shape)

A scene can also be built from Python objects: scene_from_dict({...}) takes the tables of a
scene file as dicts and lists (the layout of docs/scenes.md) and checks them as the file is.
"""
from ._tumble import (PULL_SWIRL, PULL_X, PULL_Y, Error, InputError, Recording, Scene, Simulation,
                      SimulationError, __version__, fields, find_pairs)

for _e in (Error, InputError, SimulationError):
    _e.__module__ = "tumble"

__all__ = ["Scene", "Simulation", "Recording", "fields", "find_pairs", "scene_from_dict", "to_toml", "Error", "InputError",
           "SimulationError", "PULL_X", "PULL_Y", "PULL_SWIRL", "__version__"]


def _value(v, where):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        r = repr(v)
        if r in ("inf", "-inf", "nan"):
            raise Error(f"{where}: {r} is not a value a scene takes")
        return r
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, where) for x in v) + "]"
    if hasattr(v, "tolist"):  # a NumPy scalar or array
        return _value(v.tolist(), where)
    raise Error(f"{where}: cannot write a {type(v).__name__} into a scene")


def _string(v):
    """A TOML basic string: backslash, quote and every control character escaped."""
    out = []
    for c in v:
        if c == "\\" or c == '"':
            out.append("\\" + c)
        elif ord(c) < 0x20 or ord(c) == 0x7f:
            out.append({"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(c, f"\\u{ord(c):04x}"))
        else:
            out.append(c)
    return '"' + "".join(out) + '"'


def _key(k, where):
    """A TOML key: bare when it can be (A-Z a-z 0-9 _ -), else quoted."""
    if not isinstance(k, str):
        raise Error(f"{where}: a key must be a string, got {k!r}")
    if k and all(c.isascii() and (c.isalnum() or c in "_-") for c in k):
        return k
    return _string(k)


def _table(lines, path, table):
    subs = []
    for key, v in table.items():
        if isinstance(v, dict):
            subs.append(("table", key, v))
        elif isinstance(v, (list, tuple)) and v and all(isinstance(x, dict) for x in v):
            subs.append(("array", key, v))
        else:
            lines.append(f"{_key(key, '.'.join(path))} = {_value(v, '.'.join(path + [str(key)]))}")
    for kind, key, v in subs:
        name = ".".join(path + [_key(key, ".".join(path))])
        if kind == "table":
            lines.append(f"\n[{name}]")
            _table(lines, path + [_key(key, "")], v)
        else:
            for item in v:
                lines.append(f"\n[[{name}]]")
                _table(lines, path + [_key(key, "")], item)


def to_toml(scene):
    """The TOML text of a scene given as dicts and lists (the tables of docs/scenes.md)."""
    if not isinstance(scene, dict):
        raise Error("a scene is a dict of tables, e.g. {'scene': {...}, 'shape': [...], 'group': [...]}")
    lines = []
    _table(lines, [], scene)
    return "\n".join(lines).lstrip("\n") + "\n"


def scene_from_dict(scene, name="<python>", set=(), base=None):
    """A Scene from dicts and lists laid out as a scene file (docs/scenes.md), checked as the file
    is: errors name `name` and the line of the generated TOML (to_toml(scene) shows it). `set`
    takes the overrides of Scene.load; `base` is the folder a relative mesh file is found from
    (the scene file's folder, for the tables of a file; default: the working directory)."""
    return Scene.parse(to_toml(scene), name, [set] if isinstance(set, str) else list(set), base)
