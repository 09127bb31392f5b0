"""Periodic orbits and their continuation: ``signorini continue`` from
Python (see the guide's Periodic orbits page, docs/orbits.md, for the files
and columns).

``continuation(scene, "forcing.omega", 2.2, 3.0)`` finds the periodic orbit
the scene's motion settles on at the first value (its exact event-driven
flow: ``scheme = "event-driven(e)"``), then follows it by pseudo-arclength
continuation in the field, stable and unstable alike, and locates folds,
period doublings, Neimark-Sacker pairs, grazing and sticking on the way.
The result's ``branch`` and ``bifurcations`` are the CSV files' columns as
numpy arrays.
"""

import csv as _csv
import pathlib as _pathlib

from . import _check, _signorini
from ._signorini import SceneError as _SceneError
from .sweep import SweepResult as _SweepResult
from .sweep import _scene

__all__ = ["ContinuationResult", "ModesResult", "continuation", "modes"]


class ContinuationResult:
    """A continuation's files as columns: ``branch`` (``param, period,
    stable, mu_max, impact_velocity, impact_phase, impacts_per_period,
    releases_per_period, displacement, branch, residual`` and the state on
    the section, ``q<dof>`` then ``v<dof>``), ``bifurcations`` (``param,
    kind, mu_re, mu_im, impacts_before, impacts_after, releases_before,
    releases_after, displacement, branch``), ``svg`` (branch.svg's text),
    ``lines`` (what the command prints), ``out``."""

    def __init__(self, d, out):
        self.tables = d["tables"]
        self.branch = self.tables.get("branch.csv")
        self.bifurcations = self.tables.get("bifurcations.csv")
        self.svg = d["svg"]
        self.lines = list(d["lines"])
        self.out = out

    def __repr__(self) -> str:
        n = len(self.branch["param"]) if self.branch else 0
        k = len(self.bifurcations["param"]) if self.bifurcations else 0
        return f"<signorini.ContinuationResult: {n} points, {k} bifurcations>"


def _sweep_points(sweep):
    if sweep is None:
        return []
    if isinstance(sweep, _SweepResult):
        s = sweep.sweep
        return list(zip(map(float, s["param"]), map(float, s["displacement"])))
    p = _pathlib.Path(sweep) / "sweep.csv"
    if not p.exists():
        raise _SceneError(f"sweep: {sweep!r} is not allowed: a SweepResult or a sweep folder (with sweep.csv)")
    with open(p, newline="") as f:
        return [(float(r["param"]), float(r["displacement"])) for r in _csv.DictReader(f)]


def continuation(scene, param, start, stop, *, period=1, transient=100.0, max_points=400, switch=False, sweep=None, out=None) -> ContinuationResult:
    """Continues the scene's periodic orbits of ``period`` forcing periods in
    its numeric field ``param`` (a dotted path written in the scene, e.g.
    ``forcing.omega``) from ``start`` to ``stop`` (``--from``/``--to`` of
    ``signorini continue``). The first orbit is found by Newton from the
    scene's own initial state after ``transient`` forcing periods; at most
    ``max_points`` points; ``switch=True`` also continues the period-doubled
    branch born at each period doubling; ``sweep`` (a :class:`SweepResult`
    or a sweep folder) is drawn under the branch in ``svg``; ``out`` keeps
    the files. A start with no periodic orbit nearby raises RuntimeError
    with Newton's residual; bad input raises SceneError naming it."""
    text, _name, _base = _scene(scene)
    param = _check.string("param", param)
    start = _check.real("start", start)
    stop = _check.real("stop", stop)
    period = _check.integer("period", period)
    if period < 1:
        raise _SceneError(f"period: {period} is not allowed: forcing periods per orbit, an integer >= 1")
    transient = _check.real("transient", transient)
    max_points = _check.integer("max_points", max_points)
    if max_points < 2:
        raise _SceneError(f"max_points: {max_points} is not allowed: >= 2")
    switch = _check.boolean("switch", switch)
    points = _sweep_points(sweep)
    d = _signorini.run_continuation(text, param, start, stop, period, transient, max_points, switch, points, None if out is None else str(out))
    return ContinuationResult(d, out)


class ModesResult:
    """A backbone's file as columns: ``backbone`` (``energy, period,
    contact_time, impacts_per_period, exact_period``, then
    ``exact_contact_time, mu_max, residual``; the exact columns NaN where no
    closed form is known), ``svg`` (backbone.svg's text), ``lines``,
    ``out``."""

    def __init__(self, d, out):
        self.tables = d["tables"]
        self.backbone = self.tables.get("backbone.csv")
        self.svg = d["svg"]
        self.lines = list(d["lines"])
        self.out = out

    def __repr__(self) -> str:
        n = len(self.backbone["energy"]) if self.backbone else 0
        return f"<signorini.ModesResult: {n} energies>"


def modes(scene, start, stop, *, points=40, out=None) -> ModesResult:
    """The nonsmooth modes of an unforced ``[bar]`` scene (``scheme =
    "event-driven"``, far end clamped): its periodic motions continued in
    the energy from ``start`` to ``stop`` over ``points`` energies
    (``signorini modes``), with the exact backbone of the continuous bar
    beside them. A start with no periodic motion nearby raises RuntimeError
    with Newton's residual; bad input raises SceneError naming it."""
    text, _name, _base = _scene(scene)
    start = _check.real("start", start)
    stop = _check.real("stop", stop)
    points = _check.integer("points", points)
    d = _signorini.run_modes(text, start, stop, points, None if out is None else str(out))
    return ModesResult(d, out)
