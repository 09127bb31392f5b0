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


#: Out-of-range stand-ins handed to the Rust side to learn a range: an int
#: keyword gets 0, then -1, then the largest 64-bit int; a real one NaN.
INT_STAND_INS = (0, -1, (1 << 63) - 1)
REAL_STAND_INS = (float("nan"),)
_ALLOWED_WORDS = ("is not allowed:", "is out of range:", "allowed:", "allowed")


def allowed(name: str, probe, stand_ins, prefix: _Optional[str] = None) -> _Optional[str]:
    """The allowed range of the argument ``name`` in the Rust side's own
    words: ``probe(v)`` calls the Rust function that checks the argument,
    with the stand-in ``v`` in its place; the first SceneError that names
    the argument (its message starts with ``prefix``, default ``name``)
    gives the range (the text after "is not allowed:", "is out of range:"
    or "allowed"). So a range is written once, where it is checked, and a
    wrongly typed value is refused with that range. None if no stand-in is
    refused naming the argument."""
    if probe is None:
        return None
    prefix = name if prefix is None else prefix
    for v in stand_ins:
        try:
            probe(v)
        except SceneError as e:
            m = str(e)
            if not (m.startswith(prefix + ":") or m.startswith(prefix + " ")):
                continue
            for word in _ALLOWED_WORDS:
                at = m.find(word)
                if at >= 0 and m[at + len(word):].strip(" :"):
                    return m[at + len(word):].strip(" :")
        except Exception:  # OverflowError for a negative usize: the next stand-in
            continue
    return None


def integer(name: str, v, lo: _Optional[int] = None, hi: _Optional[int] = None, *, probe=None, prefix: _Optional[str] = None) -> int:
    """An int (a numpy integer, a 0-d array, a float with an integral value);
    a bool is not an integer. With ``probe`` (see :func:`allowed`) the Rust
    side checks the range and states it, and this checks only that the
    value is an int that fits 64 bits (``lo`` default 0); without, the range
    is ``[lo, hi]`` and is checked here."""
    x = scalar(v)

    def rng():
        r = allowed(name, probe, INT_STAND_INS, prefix)
        return r if r is not None else f"an int in [{lo if lo is not None else 0}, {hi if hi is not None else 'inf'}]"

    if isinstance(x, bool) or not isinstance(x, (_numbers.Integral, _numbers.Real)):
        raise SceneError(f"{name}: {_what(v)} is not allowed: {rng()}")
    if not isinstance(x, _numbers.Integral):
        if not (_math.isfinite(x) and float(x).is_integer()):
            raise SceneError(f"{name}: {_what(v)} is not a whole number: {rng()}")
    x = int(x)
    low = lo if lo is not None else 0
    high = hi if hi is not None else ((1 << 63) - 1 if probe is not None else None)
    if x < low or (high is not None and x > high):
        raise SceneError(f"{name}: {x} is out of range: {rng()}")
    return x


def real(name: str, v, *, probe=None, prefix: _Optional[str] = None) -> float:
    """A number (int, float, numpy scalar or 0-d array; not a bool) as a
    float, any value: the range is the callee's to check. A wrong type is
    refused with the range ``probe`` finds (:func:`allowed`), else as "a
    number"."""
    x = scalar(v)
    if isinstance(x, bool) or not isinstance(x, _numbers.Real):
        r = allowed(name, probe, REAL_STAND_INS, prefix)
        raise SceneError(f"{name}: {_what(v)} is not allowed: {r if r is not None else 'a number (int or float)'}")
    return float(x)


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
