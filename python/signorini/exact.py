"""Exact benchmark solutions of the bar problems.

``solution(name, **params)`` returns an object whose methods take numpy
arrays (or numbers) and broadcast: ``u(x, t)``, ``u_x(x, t)``, ``u_t(x, t)``,
``lam(t)``, ``energy(t)``; results are float64 arrays of the broadcast shape.
Outside the solution's domain — a NaN or infinite ``t`` (for
bar-neumann-gravity, ``t`` outside ``[0, t_max]``), a point ``x`` off the
bar ``[0, length]`` by more than round-off — the values are NaN.
"""

from __future__ import annotations

import numpy as np

from . import _check, _signorini

__all__ = ["Solution", "solution", "NAMES"]

NAMES = ("bar-dirichlet", "bar-mirrored", "bar-neumann-gravity", "bar-neumann-gravity-0.11")

_PARAMS = {"g", "u0", "length", "t_max"}


def _pair(x, t):
    x, t = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(t, dtype=np.float64))
    return x.shape, np.ascontiguousarray(x).ravel(), np.ascontiguousarray(t).ravel()


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

    def u(self, x, t) -> np.ndarray:
        """Displacement u(x, t)."""
        shape, x, t = _pair(x, t)
        return self._inner.u(x, t).reshape(shape)

    def u_x(self, x, t) -> np.ndarray:
        """Strain u_x(x, t)."""
        shape, x, t = _pair(x, t)
        return self._inner.u_x(x, t).reshape(shape)

    def u_t(self, x, t) -> np.ndarray:
        """Velocity u_t(x, t)."""
        shape, x, t = _pair(x, t)
        return self._inner.u_t(x, t).reshape(shape)

    def lam(self, t) -> np.ndarray:
        """Contact force λ(t)."""
        t = np.asarray(t, dtype=np.float64)
        return self._inner.lam(np.ascontiguousarray(t).ravel()).reshape(t.shape)

    def energy(self, t) -> np.ndarray:
        """Energy E(t) (conserved: the same value at every t where the
        solution is defined; NaN at a NaN or infinite t, or beyond t_max)."""
        t = np.asarray(t, dtype=np.float64)
        return self._inner.energy_at(np.ascontiguousarray(t).ravel()).reshape(t.shape)

    def __repr__(self) -> str:
        return f"signorini.exact.Solution({self.name!r})"


def solution(name: str, **params) -> Solution:
    """The exact solution ``name``: 'bar-dirichlet', 'bar-mirrored',
    'bar-neumann-gravity' (g = 1/9; parameters g, u0, length, t_max) or
    'bar-neumann-gravity-0.11'. Raises SceneError naming a bad parameter."""
    unknown = sorted(set(params) - _PARAMS)
    if unknown:
        raise _signorini.SceneError(f"{unknown[0]}: not a parameter of solution(); allowed: {', '.join(sorted(_PARAMS))}")
    return Solution(_signorini.exact_solution(name, **{k: _check.real(k, v) for k, v in params.items()}))
