"""signorini: 1D dynamic contact (impact) from Python.

Runs of scenes (:func:`run`), exact benchmark solutions (:mod:`signorini.exact`),
the finite-element matrices (:mod:`signorini.fem`), the studies and sweeps. Errors are typed: :class:`SceneError` (a
``ValueError`` naming the field and the allowed range), :class:`BlowUp`, and
:class:`InternalError` for a bug inside the Rust core (never an abort).
"""

import math as _math
import os as _os
import warnings as _warnings
from typing import Optional as _Optional, Union as _Union

import numpy as _np

from ._signorini import BlowUp, InternalError, SceneError, __version__
from . import _check, _signorini, exact, fem, studies
from .studies import convergence
from .sweep import SweepResult, sweep
from .orbits import BasinsResult, ContinuationResult, ModesResult, basins, continuation, modes

__all__ = ["BasinsResult", "BlowUp", "CheckResult", "ContinuationResult", "ModesResult", "basins", "continuation", "modes", "EnergyGrowthWarning", "InternalError", "RunResult", "SceneError", "SweepResult", "check", "convergence", "exact", "fem", "run", "studies", "sweep", "__version__"]

_Scene = _Union[dict, str, "_os.PathLike[str]"]


class EnergyGrowthWarning(UserWarning):
    """A run's discrete energy exceeded its budget (the initial energy plus
    the work of the loads and supports, minus what damping dissipates, as
    the scheme's energy identity defines it) by more than ``energy_warn``
    (default 2): the contact created energy, which no energy identity bounds
    for this scheme, mass and dt (docs/theory.md §7). Emitted once per run
    through :mod:`warnings`, with the factor and the time; the run itself
    completes (its result has ``energy_max_ratio`` and ``energy_exceeded``).
    ``warnings.simplefilter("error", signorini.EnergyGrowthWarning)`` makes
    it an exception."""


class RunResult:
    """What :func:`run` recorded: numpy arrays and a few numbers (see
    :func:`run` for each attribute). Plain Python data: it pickles, so it
    comes back from a dask or multiprocessing worker."""

    __slots__ = ("t", "tip", "lam_t", "lam", "energy_t", "energy", "contact_dofs", "contact_lo", "contact_hi", "contact_u", "forces", "active", "fields_t", "fields", "norms", "steps", "contact_steps", "dt", "status", "energy_max_ratio", "energy_exceeded", "energy_warning", "events")

    t: _np.ndarray
    tip: _np.ndarray
    lam_t: _np.ndarray
    lam: _np.ndarray
    energy_t: _np.ndarray
    energy: _np.ndarray
    contact_dofs: list
    contact_lo: _np.ndarray
    contact_hi: _np.ndarray
    contact_u: _np.ndarray
    forces: _np.ndarray
    active: _np.ndarray
    fields_t: _np.ndarray
    fields: _np.ndarray
    norms: _Optional[dict]
    steps: int
    contact_steps: int
    dt: float
    status: str
    energy_max_ratio: float
    energy_exceeded: _Optional[dict]
    energy_warning: _Optional[str]
    events: _Optional[dict]

    def __init__(self, arrays=None, **values):
        for k in self.__slots__:
            setattr(self, k, getattr(arrays, k) if arrays is not None else values[k])

    def __reduce__(self):
        return (_rebuild, ({k: getattr(self, k) for k in self.__slots__},))

    def __repr__(self) -> str:
        return f"<signorini.RunResult: {self.steps} steps, {len(self.contact_dofs)} contact(s), status {self.status!r}>"


def _rebuild(values):
    return RunResult(**values)


class CheckResult(str):
    """What :func:`check` found: the text of ``signorini check`` (this object
    is that str: print it, search it) and the numbers it states:

    * ``steps``: the number of time steps;
    * ``stability_limit``: the exact limit of dt of a conditionally stable
      scheme (dt is below it: a scene beyond it is refused), None for an
      unconditionally stable one;
    * ``memory_bytes``, ``output_bytes``: the memory and output estimates.
    """

    text: str
    steps: int
    stability_limit: _Optional[float]
    memory_bytes: int
    output_bytes: int

    def __new__(cls, d: dict) -> "CheckResult":
        self = super().__new__(cls, d["text"])
        self.text = d["text"]
        self.steps = d["steps"]
        self.stability_limit = d["stability_limit"]
        self.memory_bytes = d["memory_bytes"]
        self.output_bytes = d["output_bytes"]
        return self

    def __reduce__(self):
        return (CheckResult, ({k: getattr(self, k) for k in ("text", "steps", "stability_limit", "memory_bytes", "output_bytes")},))


def run(scene: _Scene, *, energy: _Optional[bool] = None, fields_every: int = 0, energy_warn: _Optional[float] = None) -> RunResult:
    """Runs a scene: a dict with the TOML schema of ``signorini run``
    (``{"bar": {"benchmark": "bar-dirichlet", "elements": 80, ...}}``), a path
    to a TOML file, or TOML text. Returns a result whose arrays are float64
    numpy arrays (handed over without per-element Python objects):

    * ``t`` (levels), ``tip`` (the contact dof of a bar — contact 0 —, the
      beam's tip, the oscillator's x, one value per level);
    * ``contact_dofs`` and ``contact_u`` (levels × contacts: each contact
      dof's displacement), ``contact_lo``/``contact_hi`` (each contact's
      bounds ``lo <= u <= hi``, ±inf where there is none), ``forces`` (levels × contacts: each contact's
      force from the step that reached the level, zeros at the start levels),
      ``active`` (bool per level: some constraint active);
    * ``lam_t``/``lam`` (contact 0's force per step and its time);
    * ``energy_t``/``energy`` (the scheme's discrete energy; computed by
      default for bars and the oscillator as ``signorini run`` does,
      ``energy=True/False`` to choose; it costs one solve per step);
    * ``fields_t``/``fields`` (levels/k × unknowns) when ``fields_every=k``
      (k >= 1): the whole displacement every k steps (the beam's absolute
      displacement, lifting added back);
    * ``norms`` (a dict keyed like ``norms.csv``: ``linf_l2_u, l2_l2_u,
      linf_v_u, l2_v_u, l2_lambda, linf_energy, l2_energy,
      lambda_tv_ratio``) when the scene is a bar benchmark with an exact
      solution, else None;
    * ``steps``, ``contact_steps``, ``dt``, ``status`` ("ok" or why it stopped);
    * ``energy_max_ratio``: the largest E/budget over the run, the budget
      being the initial energy plus the work of the loads and supports minus
      the damping's dissipation as the scheme's identity defines it (NaN
      for a run that stopped early); ``energy_exceeded``: None, or the first
      level at which E/budget exceeded ``energy_warn`` (a dict ``step, t,
      ratio, energy, budget``); ``energy_warning``: that warning's text.
    * ``events``: with ``scheme = "event-driven"`` (the exact reference),
      the event log as a dict of arrays with the columns of ``events.csv``
      (``t``, ``kind`` — a list of ``"impact"``, ``"release"``,
      ``"accumulation"`` —, ``contact``, ``velocity_before``,
      ``velocity_after``, ``impulse``); None for a time-stepping scheme.

    ``energy_warn`` (finite and > 1; default the scene's ``[output]
    energy_warn``, else 2): when the energy exceeds this factor times its
    budget, one :class:`EnergyGrowthWarning` is emitted through
    :mod:`warnings` with the factor and the time (as ``signorini run``
    prints one warning on stderr). The energy is then computed at every
    level whatever ``energy`` says (``energy`` only chooses what is
    recorded).

    The stepping releases the GIL; Ctrl-C raises KeyboardInterrupt within
    50 ms, a blow-up raises BlowUp (step and time in its message) — both with
    the partial result as their ``partial`` attribute. Bad input raises
    SceneError naming the field."""
    scene = _check.scene(scene)
    if energy is not None:
        energy = _check.boolean("energy", energy)
    # The ranges are the Rust side's (python/src/run.rs), which checks these
    # arguments before the scene: a wrongly typed value is refused with them.
    fields_every = _check.integer("fields_every", fields_every, probe=lambda v: _signorini.run_scene({}, None, v, None))
    if energy_warn is not None:
        energy_warn = _check.real("energy_warn", energy_warn, probe=lambda v: _signorini.run_scene({}, None, 0, v))
    try:
        result = RunResult(_signorini.run_scene(scene, energy, fields_every, energy_warn))
    except (KeyboardInterrupt, BlowUp, SceneError) as e:
        part = getattr(e, "partial", None)
        if part is not None:
            e.partial = RunResult(part)
        raise
    if result.energy_warning is not None:
        _warnings.warn(result.energy_warning, EnergyGrowthWarning, stacklevel=2)
    return result


def check(scene: _Scene) -> CheckResult:
    """What :func:`run` would do with ``scene``, as ``signorini check``
    prints it: the scene validated and its integrator built (a bad scene
    raises SceneError, exactly as ``run`` would), the stability limit, the
    memory and output estimates, the number of steps. Nothing is run.
    Returns a :class:`CheckResult`: that text (a str) with the numbers as
    attributes (``steps``, ``stability_limit``, ``memory_bytes``,
    ``output_bytes``)."""
    return CheckResult(_signorini.check_scene_numbers(_check.scene(scene)))
