"""Argument checks shared by the package: a wrong type or value raises
SceneError naming the argument and what is allowed (never a TypeError from
deep inside the extension). numpy scalars and 0-d arrays count as the
Python number (or bool) they hold."""

import errno as _errno
import math as _math
import numbers as _numbers
import os as _os
from typing import Optional as _Optional

from ._signorini import SceneError

_TYPE = {bool: "a bool", int: "an int", float: "a float", str: "a str", list: "a list", tuple: "a tuple", dict: "a dict", type(None): "None"}


def _what(v) -> str:
    """``v`` and its type, in Python's words: ``10.5 (a float)``."""
    t = type(v)
    return f"{v!r} ({_TYPE.get(t, 'a ' + t.__module__ + '.' + t.__name__ if t.__module__ not in ('builtins',) else 'a ' + t.__name__)})"


def scalar(v):
    """A numpy scalar or 0-d array as the Python value it holds (``.item()``);
    anything else unchanged."""
    if getattr(v, "ndim", None) == 0 and hasattr(v, "dtype") and hasattr(v, "item"):
        return v.item()
    return v


def integer(name: str, v, lo: int, hi: _Optional[int] = None) -> int:
    """An int (a numpy integer, a 0-d array, a float with an integral value)
    in ``[lo, hi]``; a bool is not an integer."""
    x = scalar(v)
    rng = f"an int in [{lo}, {hi if hi is not None else 'inf'}]"
    if isinstance(x, bool) or not isinstance(x, (_numbers.Integral, _numbers.Real)):
        raise SceneError(f"{name}: {_what(v)} is not allowed: {rng}")
    if not isinstance(x, _numbers.Integral):
        if not (_math.isfinite(x) and float(x).is_integer()):
            raise SceneError(f"{name}: {_what(v)} is not a whole number: {rng}")
    x = int(x)
    if x < lo or (hi is not None and x > hi):
        raise SceneError(f"{name}: {x} is out of range: {rng}")
    return x


def real(name: str, v) -> float:
    """A number (int, float, numpy scalar or 0-d array; not a bool) as a
    float, any value: the range is the callee's to check."""
    x = scalar(v)
    if isinstance(x, bool) or not isinstance(x, _numbers.Real):
        raise SceneError(f"{name}: {_what(v)} is not allowed: a number (int or float)")
    return float(x)


def number(name: str, v, *, positive: bool = False) -> float:
    x = real(name, v)
    if not _math.isfinite(x) or (positive and x <= 0):
        raise SceneError(f"{name}: {x} is out of range: a finite float{' > 0' if positive else ''}")
    return x


def boolean(name: str, v) -> bool:
    """True or False (a numpy bool, a 0-d bool array)."""
    x = scalar(v)
    if not isinstance(x, bool):
        raise SceneError(f"{name}: {_what(v)} is not allowed: True or False")
    return x


def string(name: str, v, allowed=None) -> str:
    if not isinstance(v, str):
        raise SceneError(f"{name}: {_what(v)} is not allowed: a str" + (f" (one of {', '.join(allowed)})" if allowed else ""))
    if allowed is not None and v not in allowed:
        raise SceneError(f"{name}: {v!r} is not one of {', '.join(allowed)}")
    return v


def sequence(name: str, v, item):
    """A list/tuple/array (or a single value) checked item by item with ``item(name[i], x)``."""
    v = scalar(v)
    if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
        v = [v]
    return [item(f"{name}[{i}]", x) for i, x in enumerate(v)]


def scene(v):
    """A scene argument: a dict, or a str — a path (``os.PathLike`` too) or
    TOML text. A path to a missing file raises FileNotFoundError: a
    ``PathLike``, or a one-line str without ``=`` that ends with ``.toml``
    or names a folder (TOML text has a ``key = value``)."""
    if isinstance(v, dict):
        return v
    if isinstance(v, _os.PathLike):
        p = _os.fsdecode(_os.fspath(v))
        if not _os.path.isfile(p):
            raise FileNotFoundError(_errno.ENOENT, f"scene: no such file ({'a folder' if _os.path.isdir(p) else 'it does not exist'})", p)
        return p
    if isinstance(v, str):
        if "\n" not in v and "=" not in v and not _os.path.isfile(v) and (v.strip().endswith(".toml") or _os.sep in v or "/" in v):
            raise FileNotFoundError(_errno.ENOENT, f"scene: no such file ({'a folder' if _os.path.isdir(v) else 'it does not exist'})", v)
        return v
    raise SceneError(f"scene: {_what(v)} is not allowed: a dict, a path (str or os.PathLike) or TOML text (str)")
