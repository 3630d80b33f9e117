"""The quasi-static loading path (docs/methods.md, "Quasi-static loading path"): follow the
equilibrium of the preloaded grasp exactly, event by event, as the load grows — tangential
contact springs with Coulomb slip on the model's friction polygon, ratchets, couplings — with
each segment's rates from a small LCP solved by Lemke's method.

Public: :func:`loading_path` (the :class:`LoadingPath`), :func:`quasistatic_max_wrench` and
:func:`quasistatic_response`.
"""

from .answers import quasistatic_max_wrench, quasistatic_response
from .api import loading_path
from .events import PathEvent
from .result import LoadingPath

__all__ = ["LoadingPath", "PathEvent", "loading_path", "quasistatic_max_wrench", "quasistatic_response"]
