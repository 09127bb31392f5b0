"""signorini: 1D dynamic contact (impact) from Python.

Exact benchmark solutions (:mod:`signorini.exact`) today; runs, studies and
sweeps join as the package grows. Errors are typed: :class:`SceneError` (a
``ValueError`` naming the field and the allowed range), :class:`BlowUp`, and
:class:`InternalError` for a bug inside the Rust core (never an abort).
"""

from ._signorini import BlowUp, InternalError, SceneError, __version__
from . import exact

__all__ = ["BlowUp", "InternalError", "SceneError", "exact", "__version__"]
