"""Argument checks shared by the package: a wrong type or value raises
SceneError naming the argument and what is allowed (never a TypeError from
deep inside the extension)."""

from __future__ import annotations

import math
import numbers

from ._signorini import SceneError


def integer(name: str, v, lo: int, hi: int | None = None) -> int:
    if isinstance(v, bool) or not isinstance(v, numbers.Integral):
        raise SceneError(f"{name}: {v!r} is a {type(v).__name__}: an integer is expected")
    v = int(v)
    if v < lo or (hi is not None and v > hi):
        raise SceneError(f"{name}: {v} is out of range: an integer in [{lo}, {hi if hi is not None else 'inf'}]")
    return v


def number(name: str, v, *, positive: bool = False) -> float:
    if isinstance(v, bool) or not isinstance(v, numbers.Real):
        raise SceneError(f"{name}: {v!r} is a {type(v).__name__}: a number is expected")
    v = float(v)
    if not math.isfinite(v) or (positive and v <= 0):
        raise SceneError(f"{name}: {v} is out of range: finite{' and > 0' if positive else ''}")
    return v


def string(name: str, v, allowed=None) -> str:
    if not isinstance(v, str):
        raise SceneError(f"{name}: {v!r} is a {type(v).__name__}: a string is expected" + (f" (one of {', '.join(allowed)})" if allowed else ""))
    if allowed is not None and v not in allowed:
        raise SceneError(f"{name}: {v!r} is not one of {', '.join(allowed)}")
    return v


def sequence(name: str, v, item):
    """A list/tuple (or a single value) checked item by item with ``item(name[i], x)``."""
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        v = [v]
    return [item(f"{name}[{i}]", x) for i, x in enumerate(v)]
