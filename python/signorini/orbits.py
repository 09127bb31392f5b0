"""Periodic orbits and their continuation: ``signorini continue`` from
Python (see the guide's Periodic orbits page, docs/orbits.md, for the files
and columns).

``continuation(scene, "forcing.omega", 2.2, 3.0)`` finds the periodic orbit
the scene's motion settles on at the first value (its exact event-driven
flow: ``scheme = "event-driven(e)"``), then follows it by pseudo-arclength
continuation in the field, stable and unstable alike, and locates folds,
branch points, period doublings, Neimark-Sacker pairs, grazing and sticking
on the way.
The result's ``branch`` and ``bifurcations`` are the CSV files' columns as
numpy arrays.
"""

import csv as _csv
import pathlib as _pathlib

from . import _check, _signorini
from ._signorini import SceneError as _SceneError
from .sweep import SweepResult as _SweepResult
from .sweep import _scene

__all__ = ["BasinsResult", "ContinuationResult", "ModesResult", "basins", "continuation", "modes"]


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
        self._files = d.get("files", {})
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


def continuation(scene, param, start, stop, *, period=1, transient=100.0, max_points=400, switch=False, sweep=None, out=None, param_scale=None) -> ContinuationResult:
    """Continues the scene's periodic orbits of ``period`` forcing periods in
    its numeric field ``param`` (a dotted path written in the scene, e.g.
    ``forcing.omega``) from ``start`` to ``stop`` (``--from``/``--to`` of
    ``signorini continue``). The first orbit is found by Newton from the
    scene's own initial state after ``transient`` forcing periods; at most
    ``max_points`` points; ``switch=True`` also continues the period-doubled
    branch born at each period doubling, and the doubled branches' own (a
    cascade p → 2p → 4p → 8p: the doublings of orbits of 8p periods are
    listed, not followed, a line of ``lines`` saying so), and at each
    branch point the branch crossing there (at most 24 branches in all);
    ``sweep`` (a :class:`SweepResult`
    or a sweep folder) is drawn under the branch in ``svg``; ``out`` keeps
    the files. ``param_scale`` (``--param-scale``) is the parameter's scale
    of which the steps and the searches' offsets are fractions (default:
    the range ``|stop - start|``): runs from one start with the same
    ``param_scale`` take the same steps where their ranges overlap. A start with no periodic orbit nearby raises RuntimeError
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
    if param_scale is not None:
        param_scale = _check.real("param_scale", param_scale)
    d = _signorini.run_continuation(text, param, start, stop, period, transient, max_points, switch, points, None if out is None else str(out), param_scale)
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


class BasinsResult:
    """A grid of basins (``signorini basins``), cell ``c = j*nx + i`` of the
    cells run (a shard's block, or the whole rows before a Ctrl-C):

    * per cell (numpy arrays): ``i``, ``j``, ``x``, ``v`` (the cell's values
      of the two keys), ``attractor`` (int64: the attractor's id, numbered
      in the order the cells first reach them; -1 non-periodic, -2 failed),
      ``period`` (forcing periods; 0 non-periodic or failed),
      ``impacts_per_period``, ``sticking`` (bool), ``label`` (list of str:
      ``branch<B>:<N>`` of a known orbit, else ``p<k>-i<n>[-sticking]``,
      ``non-periodic`` or ``failed``), ``state`` (cells x ``2·dofs``: the
      attractor's point on the section, columns ``state_columns``, NaN for
      a failed cell);
    * ``attractors``: a dict of arrays by attractor id — ``id``,
      ``period``, ``label`` (its first cell's), ``state`` (attractors x
      ``2·dofs``), ``cells`` (how many), ``first_cell``;
    * ``map``: ``attractor`` as a (ny, nx) array for a whole grid (None
      otherwise); ``grid`` ``(nx, ny)``; ``cells`` ``(first, end)``;
      ``complete``; ``id`` (the grid's, as ``basins.toml`` states it);
      ``files`` (name -> text of ``basins.csv``, ``basins.toml`` and, for a
      whole grid, ``basins.svg``: byte for byte the command's); ``svg``;
      ``lines``; ``out``. ``write(folder)`` writes the files."""

    def __init__(self, d, out=None):
        import numpy as _np

        self.i, self.j, self.x, self.v = d["i"], d["j"], d["x"], d["v"]
        self.attractor, self.period = d["attractor"], d["period"]
        self.impacts_per_period, self.sticking = d["impacts_per_period"], d["sticking"]
        self.label = list(d["label"])
        w = int(d["width"])
        self.state = _np.asarray(d["state"]).reshape(-1, w) if w else _np.zeros((len(self.attractor), 0))
        self.state_columns = list(d["state_columns"])
        a = dict(d["attractors"])
        a["label"] = list(a["label"])
        a["state"] = _np.asarray(a["state"]).reshape(-1, w) if w else _np.zeros((len(a["id"]), 0))
        self.attractors = a
        self.grid = tuple(d["grid"])
        self.cells = tuple(d["cells"])
        self.complete = bool(d["complete"])
        self.id = d["id"]
        self.files = dict(d["files"])
        self.svg = self.files.get("basins.svg")
        self.lines = list(d["lines"])
        nx, ny = self.grid
        whole = self.complete and self.cells == (0, nx * ny)
        self.map = self.attractor.reshape(ny, nx) if whole else None
        self.out = out

    def write(self, folder):
        """Writes ``files`` into ``folder`` (created if absent): the files
        ``signorini basins`` writes, byte for byte. Returns the folder."""
        folder = _pathlib.Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        for name, text in self.files.items():
            (folder / name).write_bytes(text.encode("utf-8"))
        return folder

    def __repr__(self) -> str:
        nx, ny = self.grid
        return f"<signorini.BasinsResult: {len(self.attractor)} of {nx}x{ny} cells, {len(self.attractors['id'])} attractors>"


def _pair(name, v, item):
    if not isinstance(v, (tuple, list)) or len(v) != 2:
        raise _SceneError(f"{name}: {v!r} is not allowed: a pair ({'nx, ny' if name == 'grid' else 'first, last'})")
    return (item(f"{name}[0]", v[0]), item(f"{name}[1]", v[1]))


def _orbits_text(orbits):
    if orbits is None:
        return None
    if isinstance(orbits, ContinuationResult):
        text = orbits._files.get("branch.csv")
        if text is None and orbits.out is not None:
            text = (_pathlib.Path(orbits.out) / "branch.csv").read_text()
        if text is None:
            raise _SceneError("orbits: a ContinuationResult without its branch.csv is not allowed: a ContinuationResult, a branch.csv or its folder")
        return text
    if not isinstance(orbits, (str, _pathlib.PurePath)):
        raise _SceneError(f"orbits: {orbits!r} is not allowed: a ContinuationResult, a branch.csv or its folder")
    p = _pathlib.Path(orbits)
    if p.is_dir():
        p = p / "branch.csv"
    try:
        return p.read_text()
    except OSError as e:
        raise _SceneError(f"orbits: {p}: {e.strerror or e} (a branch.csv of signorini continue)") from None


def basins(scene, x, v, grid, x_range, v_range, *, transient=200, max_period=16, tol=1e-6, match_tol=1e-3, orbits=None, shard=None, threads=None, out=None) -> BasinsResult:
    """The basins of attraction of an event-driven scene (``scheme =
    "event-driven(e)"``, a periodic forcing) over a grid of initial states
    (``signorini basins``): ``x`` and ``v`` are dotted paths of numeric keys
    written in the scene (``oscillator.initial_displacement``), ``grid =
    (nx, ny)`` the cells along each, ``x_range``/``v_range`` their first and
    last values. Each cell runs ``transient`` forcing periods, then its
    period (the smallest k <= ``max_period`` with ``|P^k(x) - x| <= tol *
    max(1, |x|)`` on the stroboscopic map P), impacts per period and
    sticking are read; cells within ``match_tol`` of one attractor share
    its id. ``orbits`` (a :class:`ContinuationResult`, a ``branch.csv`` or
    its folder) labels the cells that reach a known orbit, and its stable
    orbits at the scene's value stop the cells' transients as the seeds'
    attractors do (as ``signorini basins --orbits``); ``shard=(i, n)``
    runs the i-th of n blocks of cells (``signorini merge`` joins the
    folders); ``threads`` (default: all cores) changes nothing in the
    result; ``out`` writes the files (as :meth:`BasinsResult.write`).
    Ctrl-C stops between cells and raises KeyboardInterrupt whose
    ``partial`` is the BasinsResult of the whole rows so far (written to
    ``out`` too). Bad input raises SceneError naming the argument."""
    text, _name, _base = _scene(scene)
    x = _check.string("x", x)
    v = _check.string("v", v)
    grid = _pair("grid", grid, lambda n, k: _check.integer(n, k, 0, (1 << 63) - 1))
    x_range = _pair("x_range", x_range, _check.real)
    v_range = _pair("v_range", v_range, _check.real)
    transient = _check.integer("transient", transient, 0, (1 << 63) - 1)
    max_period = _check.integer("max_period", max_period, 0, (1 << 63) - 1)
    tol = _check.real("tol", tol)
    match_tol = _check.real("match_tol", match_tol)
    if shard is not None:
        shard = _pair("shard", shard, lambda n, k: _check.integer(n, k, 0, (1 << 63) - 1))
    if threads is not None:
        threads = _check.integer("threads", threads, 0, (1 << 63) - 1)
    orbits = _orbits_text(orbits)
    try:
        d = _signorini.run_basins(text, x, v, grid, x_range, v_range, transient, max_period, tol, match_tol, orbits, shard, threads)
    except KeyboardInterrupt as e:
        part = getattr(e, "partial", None)
        if isinstance(part, dict):
            e.partial = BasinsResult(part, out)
            if out is not None:
                e.partial.write(out)
        raise
    r = BasinsResult(d, out)
    if out is not None:
        r.write(out)
    return r
