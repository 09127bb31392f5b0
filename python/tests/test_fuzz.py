"""Every shipped scene, as a dict, with one value replaced by something
wrong (a wrong type, NaN, infinity, a negative or huge size, a missing or
unknown key): signorini.check either accepts it or raises SceneError —
never another exception, never InternalError (a Rust panic), never a crash
of the interpreter."""

import math
import random

import pytest

import signorini
from conftest import ROOT

tomllib = pytest.importorskip("tomllib")

SCENES = sorted((ROOT / "data/scenes").glob("*.toml"))
BAD = [None, "text", [1, 2], {"a": 1}, math.nan, math.inf, -math.inf, -1, 0, 1e300, -1e300, 2**70, True, 1e-300, [], 0.5, 3, object(), 1 + 2j, b"bytes", [object()]]


def leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from leaves(v, path + (k,))
    elif isinstance(d, list) and d and all(isinstance(x, dict) for x in d):
        for i, v in enumerate(d):
            yield from leaves(v, path + (i,))
    else:
        yield path


def replaced(doc, path, value):
    d = doc
    for k in path[:-1]:
        d = d[k]
    if value is None:
        del d[path[-1]]
    else:
        d[path[-1]] = value


def test_every_scene_accepts_or_refuses_with_a_scene_error():
    rng = random.Random(20261123)
    seen = {"accepted": 0, "refused": 0}
    for scene in SCENES:
        base = tomllib.loads(scene.read_text())
        if any(isinstance(v, str) and v.endswith(".csv") for p in leaves(base) for v in [_get(base, p)]):
            continue  # series files are found next to the scene file, not in a dict
        signorini.check(base)  # the shipped scene itself is valid
        paths = list(leaves(base))
        for _ in range(60):
            doc = tomllib.loads(scene.read_text())
            path = rng.choice(paths)
            value = rng.choice(BAD + ["unknown-key"])
            if value == "unknown-key":
                path, value = path[:-1] + ("no_such_key",), 1.0
            replaced(doc, path, value)
            try:
                signorini.check(doc)
                seen["accepted"] += 1
            except signorini.SceneError:
                seen["refused"] += 1
    print(seen)
    assert seen["refused"] > 500 and seen["accepted"] > 100, seen


def _get(doc, path):
    for k in path:
        doc = doc[k]
    return doc

