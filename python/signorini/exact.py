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

__all__ = ["Backbone", "Solution", "backbone", "solution", "NAMES", "Value"]

NAMES = ("bar-dirichlet", "bar-mirrored", "bar-neumann-gravity", "bar-neumann-gravity-0.11", "nonsmooth-mode")

_PARAMS = {"g", "u0", "length", "t_max", "energy", "wave_speed", "gap", "family"}


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
    'bar-neumann-gravity' (g = 1/9; parameters g, u0, length, t_max),
    'bar-neumann-gravity-0.11', or 'nonsmooth-mode' (the periodic motion of
    the clamped bar with a contact at x = 0 at a given energy,
    docs/theory.md §11; parameters energy (required), length, wave_speed,
    gap, family; t = 0 at the top of the flight). Raises SceneError naming a
    bad parameter."""
    unknown = sorted(set(params) - _PARAMS)
    if unknown:
        raise _signorini.SceneError(f"{unknown[0]}: not a parameter of solution(); allowed: {', '.join(sorted(_PARAMS))}")
    # The ranges are the Rust side's (the exact crate's): a wrongly typed
    # value is refused with the range it states for that parameter.
    return Solution(_signorini.exact_solution(name, **{k: _check.real(k, v, probe=lambda x, k=k: _signorini.exact_solution(name, **{k: x})) for k, v in params.items()}))


class Backbone:
    """The backbone of a family of nonsmooth modes; see :func:`backbone`."""

    def __init__(self, inner):
        self._inner = inner

    @property
    def family(self) -> int:
        """The family index k (1: through the first linear period 4L/c)."""
        return self._inner.family

    @property
    def threshold(self) -> float:
        """The least energy with contact: (2k-1)² c² g²/(2L) for a clearance
        (g < 0), the static state's energy c² g²/(2L) for g > 0, 0 for g = 0."""
        return self._inner.threshold

    @property
    def linear_period(self) -> float:
        """The period below the threshold, 4L/((2k-1)c)."""
        return self._inner.linear_period

    @property
    def limit_period(self) -> float:
        """The period at g = 0 (every energy) and as the energy grows
        without bound (any g): (2k+1)L/(k² c)."""
        return self._inner.limit_period

    def __call__(self, energy) -> dict:
        """The family at each energy (a number or an array): a dict of
        ``period``, ``contact_time``, ``flight_time``, ``impacts_per_period``
        (int64), ``impact_velocity`` (the end's speed Q = √(2E/L)) and
        ``contact_force`` (−cQ, 0 without contact), each a float (int) for
        a scalar energy, else an array of its shape. A negative or
        non-finite energy, or one below the static energy when g > 0, raises
        SceneError naming ``energy``."""
        e = _reals("energy", energy)
        got = self._inner.at(_np.ascontiguousarray(e).ravel())
        if e.shape == ():
            return {k: (int(v[0]) if v.dtype.kind == "i" else float(v[0])) for k, v in got.items()}
        return {k: v.reshape(e.shape) for k, v in got.items()}

    def __repr__(self) -> str:
        return f"signorini.exact.Backbone(family={self.family})"


def backbone(length: float = 1.0, wave_speed: float = 1.0, gap: float = 0.0, far_end: str = "clamped", family: int = 1) -> Backbone:
    """The exact backbone of the nonsmooth modes of the bar (docs/theory.md
    §11): the ``[bar]`` scene's ``length``, ``wave_speed``, ``gap`` (the
    obstacle's position: < 0 a clearance, > 0 a prestress) and ``far_end``,
    and the family ``family`` (1: the one through the first linear period
    4L/c, the family of ``bar-dirichlet``). ``backbone(...)(energy)`` gives
    the period, contact time and impacts per period. A free far end has no
    periodic motion with contact: SceneError naming ``far_end``, as for
    every bad value."""
    probe = lambda **kw: _signorini.exact_backbone(**kw)  # noqa: E731
    args = {k: _check.real(k, v, probe=lambda x, k=k: probe(**{k: x})) for k, v in (("length", length), ("wave_speed", wave_speed), ("gap", gap))}
    k = _check.integer("family", family, 1, (1 << 32) - 1)
    return Backbone(_signorini.exact_backbone(far_end=_check.string("far_end", far_end, ("clamped", "free")), family=k, **args))
