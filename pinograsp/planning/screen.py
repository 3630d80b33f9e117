"""A cheap necessary condition for an ``"auto"`` preload, checked before designing one.

``pg.equilibrium_preload`` (the ``"auto"`` preload) looks for actuator commands under which every
contact presses and the object is in equilibrium; when there are none it also diagnoses why —
both are conic programs, and on a large hand most sampled approaches end there (the fingers
touch but cannot squeeze against each other). Without the actuators, the joints and the
stiffness, the design keeps only: contact forces ``c = D beta`` in the model's friction
pyramids (``beta >= 0``), balancing each other on the object (``G c = 0``), every normal force
``E beta`` positive. :func:`internal_force` solves that relaxation as one small linear program
(HiGHS); when even it has no positive solution, no preload exists, and the planner records
the approach as ``no_grasp (no_preload)`` without the design (docs/planning.md, "Speed").
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

#: Smallest normal force of the relaxation (the beta sum normalised to 1) below which no
#: preload can press every contact.
PRESSED = 1e-9


def internal_force(model: Any) -> float:
    """The largest smallest normal force of balanced contact forces in the friction pyramids,
    with the pyramid weights summing to 1 (dimensionless; 0 when no such forces exist)."""
    from scipy.optimize import linprog

    D, E, G = np.asarray(model.D), np.asarray(model.E), np.asarray(model.G)
    nb = D.shape[1]
    cost = np.zeros(nb + 1)
    cost[-1] = -1.0  # maximise t
    a_eq = np.vstack([np.c_[G @ D, np.zeros(G.shape[0])], np.r_[np.ones(nb), 0.0]])
    b_eq = np.r_[np.zeros(G.shape[0]), 1.0]
    a_ub = np.c_[-E, np.ones(E.shape[0])]  # t <= every normal force
    bounds = [(0.0, None)] * nb + [(None, 1.0)]
    r = linprog(
        cost, A_ub=a_ub, b_ub=np.zeros(E.shape[0]), A_eq=a_eq, b_eq=b_eq, bounds=bounds, method="highs"
    )
    return max(0.0, float(-r.fun)) if r.status == 0 else 0.0


@dataclass(frozen=True)
class PreloadScreen:
    """The batch score of the screen: ``pressed`` = :func:`internal_force` of the closed grasp
    (the command is ignored)."""

    @property
    def columns(self) -> tuple[str, ...]:
        """The table's score columns."""
        return ("score", "pressed")

    @property
    def no_grasp(self) -> dict[str, float]:
        """The values of a record that is not a grasp."""
        return {"score": 0.0, "pressed": 0.0}

    def __call__(self, model: Any, command: Mapping[str, float]) -> dict[str, float]:
        t = internal_force(model)
        return {"score": t, "pressed": t}
