"""signorini: 1D dynamic contact (impact) from Python.

Runs of scenes (:func:`run`), exact benchmark solutions (:mod:`signorini.exact`),
the finite-element matrices (:mod:`signorini.fem`), the studies and sweeps. Errors are typed: :class:`SceneError` (a
``ValueError`` naming the field and the allowed range), :class:`BlowUp`, and
:class:`InternalError` for a bug inside the Rust core (never an abort).
"""

from __future__ import annotations

import os
from typing import Optional, Union

import numpy as np

from ._signorini import BlowUp, InternalError, SceneError, __version__
from . import _check, _signorini, exact, fem, studies
from .studies import convergence
from .sweep import SweepResult, sweep

__all__ = ["BlowUp", "InternalError", "RunResult", "SceneError", "SweepResult", "check", "convergence", "exact", "fem", "run", "studies", "sweep", "__version__"]


def run(scene: Union[dict, str, "os.PathLike[str]"], *, energy: Optional[bool] = None, fields_every: int = 0) -> "RunResult":
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
    * ``steps``, ``contact_steps``, ``dt``, ``status`` ("ok" or why it stopped).

    The stepping releases the GIL; Ctrl-C raises KeyboardInterrupt within
    50 ms, a blow-up raises BlowUp (step and time in its message) — both with
    the partial result as their ``partial`` attribute. Bad input raises
    SceneError naming the field."""
    scene = _check.scene(scene)
    if energy is not None:
        energy = _check.boolean("energy", energy)
    fields_every = _check.integer("fields_every", fields_every, 0)
    try:
        return RunResult(_signorini.run_scene(scene, energy, fields_every))
    except (KeyboardInterrupt, BlowUp, SceneError) as e:
        part = getattr(e, "partial", None)
        if part is not None:
            e.partial = RunResult(part)
        raise


def check(scene: Union[dict, str, "os.PathLike[str]"]) -> str:
    """What :func:`run` would do with ``scene``, as ``signorini check``
    prints it: the scene validated and its integrator built (a bad scene
    raises SceneError, exactly as ``run`` would), the stability limit, the
    memory and output estimates, the number of steps. Nothing is run."""
    return _signorini.check_scene(_check.scene(scene))


class RunResult:
    """What :func:`run` recorded: numpy arrays and a few numbers (see
    :func:`run` for each attribute). Plain Python data: it pickles, so it
    comes back from a dask or multiprocessing worker."""

    __slots__ = ("t", "tip", "lam_t", "lam", "energy_t", "energy", "contact_dofs", "contact_lo", "contact_hi", "contact_u", "forces", "active", "fields_t", "fields", "norms", "steps", "contact_steps", "dt", "status")

    t: np.ndarray
    tip: np.ndarray
    lam_t: np.ndarray
    lam: np.ndarray
    energy_t: np.ndarray
    energy: np.ndarray
    contact_dofs: list
    contact_lo: np.ndarray
    contact_hi: np.ndarray
    contact_u: np.ndarray
    forces: np.ndarray
    active: np.ndarray
    fields_t: np.ndarray
    fields: np.ndarray
    norms: Optional[dict]
    steps: int
    contact_steps: int
    dt: float
    status: str

    def __init__(self, arrays=None, **values):
        for k in self.__slots__:
            setattr(self, k, getattr(arrays, k) if arrays is not None else values[k])

    def __reduce__(self):
        return (_rebuild, ({k: getattr(self, k) for k in self.__slots__},))

    def __repr__(self) -> str:
        return f"<signorini.RunResult: {self.steps} steps, {len(self.contact_dofs)} contact(s), status {self.status!r}>"


def _rebuild(values):
    return RunResult(**values)
