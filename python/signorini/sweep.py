"""Parameter sweeps and bifurcation diagrams: the engine of ``signorini
sweep`` from Python (see the guide's Sweeps page, docs/sweeps.md, for the
files and columns).

``sweep(scene, "forcing.omega", 1.6, 2.2, 61, transient=200, record=10)``
runs the scene at each value of the field (any numeric field of the scene,
by its dotted path: ``forcing.omega``, ``support.amplitude``, ``stop.0.hi``)
in parallel batches (beam runs that share a step matrix go through the
lockstep engine), and returns a :class:`SweepResult` whose ``sweep``,
``summary`` and ``impacts`` are the CSV files' columns as numpy arrays.
"""

import os as _os
import pathlib as _pathlib
import tempfile as _tempfile

from . import _check, _signorini
from ._signorini import SceneError as _SceneError

__all__ = ["SweepResult", "sweep"]


class SweepResult:
    """A sweep's files as columns: ``sweep`` (``param, run, t,
    displacement, velocity, phase``: the Poincaré points of every run, the
    bifurcation diagram), ``summary`` (one row per run: ``param, run``, the
    vibro-impact statistics, ``steps, status``; ``param2`` last for a map),
    ``impacts`` (``param, run, stop, t, phase, velocity, impulse,
    duration``; None with ``impacts=False``), ``id`` (the manifest's id),
    ``lines`` (what the command prints), ``out``."""

    def __init__(self, d):
        self.tables = d["tables"]
        self.sweep = self.tables.get("sweep.csv")
        self.summary = self.tables.get("summary.csv")
        self.impacts = self.tables.get("impacts.csv")
        self.id = d["id"]
        self.lines = list(d["lines"])
        self.out = d["out"]

    def __repr__(self) -> str:
        n = len(self.summary["run"]) if self.summary else 0
        return f"<signorini.SweepResult {self.id}: {n} runs>"


def _scene(scene):
    scene = _check.scene(scene)
    if isinstance(scene, dict):
        return _signorini.scene_text(scene), "scene", None
    if isinstance(scene, str):
        p = _pathlib.Path(scene)
        if "\n" not in scene and "=" not in scene and p.exists():
            return p.read_text(), p.name, str(p.parent)
        return scene, "scene", None
    raise _SceneError(f"scene: a {type(scene).__name__} is not allowed: a dict, a path or TOML text")


def _probe(**over):
    """A call of the Rust side's option check with every option valid but
    the one in ``over`` (None, or the None of a pair, marks where the
    stand-in goes): what :func:`signorini._check.allowed` asks for a range.
    The options are checked before anything else, so nothing runs."""
    ((key, where),) = over.items()

    def call(v):
        o = dict(start=0.0, stop=1.0, count=1, start2=0.0, stop2=1.0, count2=1, transient=100.0, record=10.0, phase=0.0, period_tol=1e-3, shard=None, threads=None)
        o[key] = v if where is None else tuple(v if x is None else x for x in where)
        second = ("p2", o["start2"], o["stop2"], o["count2"], False) if key in ("start2", "stop2", "count2") else None
        _signorini.run_sweep("", "scene", None, "", "p", o["start"], o["stop"], o["count"], False, second, o["transient"], o["record"], o["phase"], o["period_tol"], True, False, o["shard"], False, o["threads"])

    return call


def sweep(scene, param, start, stop, count, *, log=False, param2=None, start2=None, stop2=None, count2=None, log2=False, transient=100.0, record=10.0, phase=0.0, period_tol=1e-3, impacts=True, follow=False, shard=None, resume=False, threads=None, out=None) -> SweepResult:
    """Sweeps the scene's field ``param`` over ``count`` values from ``start``
    to ``stop`` (``--from``/``--to`` of ``signorini sweep``; ``log=True``:
    geometric spacing), with ``param2``/``start2``/``stop2``/``count2``/``log2``
    for a two-parameter map (run r takes value r mod count of the first axis
    and r div count of the second). Each run goes ``transient`` forcing
    periods before ``record`` recorded periods; ``phase`` is the Poincaré
    section's forcing phase; ``period_tol`` the period detector's relative
    tolerance; ``impacts=False`` skips ``impacts.csv``; ``follow=True``
    starts each run from the last one's state; ``shard=(i, n)`` runs block i
    of n (merge the folders with ``signorini merge``); ``resume=True``
    continues ``out``; ``threads`` (default all cores). ``out`` keeps the
    files (default: a temporary folder, removed afterwards).

    Ctrl-C stops after the current batch and raises KeyboardInterrupt whose
    ``partial`` is the SweepResult of the runs completed."""
    text, name, base = _scene(scene)
    param = _check.string("param", param)
    # The ranges are the sweep crate's (SweepOptions::validate, the options
    # of `signorini sweep`): the Rust side checks them, and a wrongly typed
    # value is refused with the range it states (_check.allowed).
    start = _check.real("start", start, probe=_probe(start=None))
    stop = _check.real("stop", stop, probe=_probe(stop=None))
    count = _check.integer("count", count, probe=_probe(count=None))
    second = None
    if param2 is not None:
        second = (
            _check.string("param2", param2),
            _check.real("start2", start2, probe=_probe(start2=None)),
            _check.real("stop2", stop2, probe=_probe(stop2=None)),
            _check.integer("count2", count2, probe=_probe(count2=None)),
            _check.boolean("log2", log2),
        )
    transient = _check.real("transient", transient, probe=_probe(transient=None))
    record = _check.real("record", record, probe=_probe(record=None))
    phase = _check.real("phase", phase, probe=_probe(phase=None))
    period_tol = _check.real("period_tol", period_tol, probe=_probe(period_tol=None))
    if shard is not None:
        if not isinstance(shard, (tuple, list)) or len(shard) != 2:
            raise _SceneError(f"shard: {shard!r} is not allowed: a pair (i, n) with 0 <= i < n")
        shard = (_check.integer("shard[0]", shard[0], probe=_probe(shard=(None, 1)), prefix="shard"), _check.integer("shard[1]", shard[1], probe=_probe(shard=(0, None)), prefix="shard"))
    if threads is not None:
        threads = _check.integer("threads", threads, probe=_probe(threads=None))
    log, impacts, follow, resume = (_check.boolean(k, v) for k, v in (("log", log), ("impacts", impacts), ("follow", follow), ("resume", resume)))

    def go(folder):
        try:
            return SweepResult(_signorini.run_sweep(text, name, base, folder, param, start, stop, count, log, second, transient, record, phase, period_tol, impacts, follow, shard, resume, threads))
        except BaseException as e:
            if isinstance(getattr(e, "partial", None), dict):
                e.partial = SweepResult(e.partial)
            raise

    if out is not None:
        return go(_os.fspath(out))
    if resume:
        raise _SceneError("resume: needs out, the folder to continue")
    with _tempfile.TemporaryDirectory(prefix="signorini-sweep-") as tmp:
        return go(_os.path.join(tmp, "sweep"))
