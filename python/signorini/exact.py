"""Exact benchmark solutions of the bar problems.

``solution(name, **params)`` returns an object whose methods take numpy
arrays (or numbers) and broadcast: ``u(x, t)``, ``u_x(x, t)``, ``u_t(x, t)``,
``lam(t)``, ``energy(t)``; results are float64 arrays of the broadcast shape
(a float when every argument is a scalar).
Outside the solution's domain — a NaN or infinite ``t`` (for
bar-neumann-gravity, ``t`` outside ``[0, t_max]``), a point ``x`` off the
bar ``[0, length]`` by more than round-off — the values are NaN.
"""

from typing import Union as _Union

import numpy as _np

from . import _check, _signorini

__all__ = ["Solution", "solution", "NAMES", "Value"]

NAMES = ("bar-dirichlet", "bar-mirrored", "bar-neumann-gravity", "bar-neumann-gravity-0.11")

_PARAMS = {"g", "u0", "length", "t_max"}


#: What the methods return: a float for scalar arguments, else a float64
#: array of the broadcast shape.
Value = _Union[float, _np.ndarray]


def _out(a, shape):
    """``a`` reshaped to ``shape``; a float when the arguments were scalars."""
    return float(a[0]) if shape == () else a.reshape(shape)


#: What ``x`` and ``t`` may be (the solutions are defined for every real
#: value; off the domain they are NaN, see the module's documentation).
_ALLOWED = "a number or an array of numbers (float64; any real value, NaN off the solution's domain)"


def _reals(name, v):
    """``v`` as a float64 array, or SceneError naming the argument (a str, a
    bool, None, a ragged list: what numpy would refuse, or silently read as
    a number)."""
    a = None
    if not isinstance(v, (str, bytes)):
        try:
            a = _np.asarray(v)
        except (TypeError, ValueError):
            a = None
    if a is None or a.dtype.kind not in "iuf":
        raise _signorini.SceneError(f"{name}: {_check._what(v)} is not allowed: {_ALLOWED}")
    return a.astype(_np.float64, copy=False)


def _pair(x, t):
    x, t = _reals("x", x), _reals("t", t)
    try:
        x, t = _np.broadcast_arrays(x, t)
    except ValueError:
        raise _signorini.SceneError(f"x and t: shapes {x.shape} and {t.shape} do not broadcast: {_ALLOWED}, of shapes that broadcast") from None
    return x.shape, _np.ascontiguousarray(x).ravel(), _np.ascontiguousarray(t).ravel()


class Solution:
    """An exact solution; see :func:`solution`."""

    def __init__(self, inner):
        self._inner = inner

    @property
    def name(self) -> str:
        return self._inner.name

    @property
    def length(self) -> float:
        return self._inner.length

    def u(self, x, t) -> Value:
        """Displacement u(x, t)."""
        shape, x, t = _pair(x, t)
        return _out(self._inner.u(x, t), shape)

    def u_x(self, x, t) -> Value:
        """Strain u_x(x, t)."""
        shape, x, t = _pair(x, t)
        return _out(self._inner.u_x(x, t), shape)

    def u_t(self, x, t) -> Value:
        """Velocity u_t(x, t)."""
        shape, x, t = _pair(x, t)
        return _out(self._inner.u_t(x, t), shape)

    def lam(self, t) -> Value:
        """Contact force λ(t)."""
        t = _reals("t", t)
        return _out(self._inner.lam(_np.ascontiguousarray(t).ravel()), t.shape)

    def energy(self, t) -> Value:
        """Energy E(t) (conserved: the same value at every t where the
        solution is defined; NaN at a NaN or infinite t, or beyond t_max)."""
        t = _reals("t", t)
        return _out(self._inner.energy_at(_np.ascontiguousarray(t).ravel()), t.shape)

    def __repr__(self) -> str:
        return f"signorini.exact.Solution({self.name!r})"


def solution(name: str, **params) -> Solution:
    """The exact solution ``name``: 'bar-dirichlet', 'bar-mirrored',
    'bar-neumann-gravity' (g = 1/9; parameters g, u0, length, t_max) or
    'bar-neumann-gravity-0.11'. Raises SceneError naming a bad parameter."""
    unknown = sorted(set(params) - _PARAMS)
    if unknown:
        raise _signorini.SceneError(f"{unknown[0]}: not a parameter of solution(); allowed: {', '.join(sorted(_PARAMS))}")
    # The ranges are the Rust side's (the exact crate's): a wrongly typed
    # value is refused with the range it states for that parameter.
    return Solution(_signorini.exact_solution(name, **{k: _check.real(k, v, probe=lambda x, k=k: _signorini.exact_solution(name, **{k: x})) for k, v in params.items()}))
