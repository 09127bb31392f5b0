"""signorini: 1D dynamic contact (impact) from Python.

Exact benchmark solutions (:mod:`signorini.exact`) today; runs, studies and
sweeps join as the package grows. Errors are typed: :class:`SceneError` (a
``ValueError`` naming the field and the allowed range), :class:`BlowUp`, and
:class:`InternalError` for a bug inside the Rust core (never an abort).
"""

from ._signorini import BlowUp, InternalError, SceneError, __version__
from . import _signorini, exact

__all__ = ["BlowUp", "InternalError", "SceneError", "exact", "run", "__version__"]


def run(scene):
    """Runs a scene: a dict with the TOML schema (``{"bar": {"benchmark":
    "bar-dirichlet", "elements": 80, ...}}``), a path to a TOML file, or TOML
    text. Returns an object with float64 arrays ``t`` and ``tip`` (one value
    per time level: the contact dof of a bar, the beam's tip, the
    oscillator), ``lam_t``/``lam`` (the contact force and its time, per
    step), ``energy_t``/``energy``, and ``steps``, ``contact_steps``,
    ``status``. The stepping releases the GIL; Ctrl-C raises
    KeyboardInterrupt within 50 ms, a blow-up raises BlowUp — both with the
    partial result as their ``partial`` attribute. Bad input raises
    SceneError naming the field."""
    if hasattr(scene, "__fspath__"):
        scene = str(scene.__fspath__())
    return _signorini.run_scene(scene)
