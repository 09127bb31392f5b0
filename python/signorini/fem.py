"""Finite-element matrices of the bar and the beam.

``bar(elements, mass=...)`` (P1, every mass treatment of the literature) and
``beam(elements)`` (clamped Hermite cubics) return a :class:`Matrices`:
``mass_band``/``stiffness_band`` in LAPACK's upper symmetric band storage,
shape ``(p + 1, n)`` with ``ab[p + i - j, j] = A[i, j]`` (what
``scipy.linalg.eig_banded`` and ``solveh_banded`` take), the dense ``M``
and ``K`` built from them on demand, and ``kappa_h()``, the largest
generalized eigenvalue of ``(K, M)``.
"""

import warnings as _warnings
from typing import Optional as _Optional

import numpy as _np

from . import _signorini
from . import _check

__all__ = ["Matrices", "bar", "beam", "MASSES", "dense"]

#: The bar's mass treatments: consistent, row-sum lumped, the redistributed
#: masses of the papers (mod = mod1, mod2, mod3), GetFEM's two singular masses.
MASSES = ("std", "lumped", "mod", "mod1", "mod2", "mod3", "transfer", "singular")


def dense(ab: _np.ndarray) -> _np.ndarray:
    """The dense symmetric matrix of an upper band array ``ab`` (shape ``(p + 1, n)``)."""
    p, n = ab.shape[0] - 1, ab.shape[1]
    a = _np.zeros((n, n))
    for k in range(p + 1):
        d = ab[p - k, k:]
        idx = _np.arange(n - k)
        a[idx, idx + k] = d
        a[idx + k, idx] = d
    return a


class Matrices:
    """A discretisation's mass and stiffness matrices; see :func:`bar` and :func:`beam`."""

    def __init__(self, inner):
        self._inner = inner
        self._kappa = None

    def __repr__(self) -> str:
        return f"<signorini.fem.Matrices: {self.kind}, n = {self.n}, p = {self.half_bandwidth}>"

    @property
    def kind(self) -> str:
        """What was discretised, e.g. ``'bar, 10 elements, mass mod'``."""
        return self._inner.kind

    @property
    def n(self) -> int:
        """The number of unknowns."""
        return self._inner.n

    @property
    def h(self) -> float:
        """The element size."""
        return self._inner.h

    @property
    def x(self) -> _np.ndarray:
        """The position of each unknown (the beam's value and slope share their node's)."""
        return _np.asarray(self._inner.x, dtype=_np.float64)

    @property
    def half_bandwidth(self) -> int:
        """The half-bandwidth ``p`` (1 for the bar, 3 for the beam)."""
        return self._inner.half_bandwidth

    @property
    def mass_band(self) -> _np.ndarray:
        """M in upper band storage, shape ``(p + 1, n)``."""
        return self._inner.mass_band

    @property
    def stiffness_band(self) -> _np.ndarray:
        """K in upper band storage, shape ``(p + 1, n)``."""
        return self._inner.stiffness_band

    @property
    def M(self) -> _np.ndarray:
        """The dense mass matrix, ``(n, n)``."""
        return dense(self.mass_band)

    @property
    def K(self) -> _np.ndarray:
        """The dense stiffness matrix, ``(n, n)``."""
        return dense(self.stiffness_band)

    @property
    def massless(self) -> list:
        """The unknowns without mass (a zero row of M: the contact node of mod, transfer, singular)."""
        return self._inner.massless

    def kappa_h(self) -> float:
        """The largest generalized eigenvalue of ``(K, M)``, with the massless
        unknowns held fixed (their rows and columns removed): the central
        difference is stable for ``dt < 2/sqrt(kappa_h)``. Computed once (shifted
        inverse iteration certified by a factorisation), then cached."""
        if self._kappa is None:
            self._kappa = self._inner.kappa_h()
        return self._kappa


def bar(elements: int, mass: str = "std", *, length: float = 1.0, wave_speed: float = 1.0, far_end: _Optional[str] = None, contacts=(0,), degree: int = 1, right_end: _Optional[str] = None) -> Matrices:
    """The P1 bar on ``[0, length]`` with ``elements`` elements (>= 2), density 1
    and wave speed ``wave_speed``; ``far_end`` (the scene key ``bar.far_end``)
    ``'clamped'`` (the default: node m is not an unknown) or ``'free'``
    (``right_end=`` is its deprecated former name); ``mass`` one of :data:`MASSES`, built for contacts at
    the nodes ``contacts`` (the redistributed masses empty their element);
    ``degree`` 1, 2 or 3 (Lagrange P1, P2, P3; unknowns ordered by position,
    half-bandwidth ``degree``; std, lumped and mod at degrees 2 and 3)."""
    # The ranges are the Rust side's (python/src/fem.rs): a wrongly typed
    # value is refused with the range that side states (_check.allowed).
    elements = _check.integer("elements", elements, probe=lambda v: _signorini.bar_matrices(v))
    mass = _check.string("mass", mass, MASSES)
    if right_end is not None:
        if far_end is not None:
            raise _signorini.SceneError("right_end: give far_end only (right_end is its deprecated former name)")
        far_end = _check.string("right_end", right_end, ("clamped", "free"))
        _warnings.warn("fem.bar(right_end=...) is deprecated: far_end=... (the scene key bar.far_end)", DeprecationWarning, stacklevel=2)
    far_end = _check.string("far_end", far_end if far_end is not None else "clamped", ("clamped", "free"))
    length = _check.real("length", length, probe=lambda v: _signorini.bar_matrices(2, length=v))
    wave_speed = _check.real("wave_speed", wave_speed, probe=lambda v: _signorini.bar_matrices(2, wave_speed=v))
    degree = _check.integer("degree", degree, probe=lambda v: _signorini.bar_matrices(2, degree=v))
    nodes = _check.sequence("contacts", contacts, lambda n, v: _check.integer(n, v, probe=lambda x: _signorini.bar_matrices(elements, right_end=far_end, contacts=[x], degree=degree), prefix="contacts[0]"))
    return Matrices(_signorini.bar_matrices(elements, mass, length, wave_speed, far_end, nodes, degree))


def beam(elements: int, *, length: float = 1.0, k2: float = 1.0) -> Matrices:
    """The Hermite-cubic beam ``u_tt + k2 u_xxxx = 0`` on ``[0, length]``, clamped at
    0, with ``elements`` elements: unknown ``2(j - 1)`` is node j's value,
    ``2(j - 1) + 1`` its slope (unit ρS)."""
    elements = _check.integer("elements", elements, probe=lambda v: _signorini.beam_matrices(v))
    length = _check.real("length", length, probe=lambda v: _signorini.beam_matrices(1, length=v))
    k2 = _check.real("k2", k2, probe=lambda v: _signorini.beam_matrices(1, k2=v))
    return Matrices(_signorini.beam_matrices(elements, length, k2))
