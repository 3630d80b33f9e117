"""Proof in simulation: a plan's disturbances ramped in MuJoCo (``pg.simulate_max_wrench``),
predicted against simulated (docs/planning.md, "Verification")."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..batch.disturbances import DisturbanceScore
from .records import PlanCheck

if TYPE_CHECKING:
    from .records import GraspPlan


def verify_plan(plan: GraspPlan, model: Any, score: DisturbanceScore) -> tuple[PlanCheck, ...]:
    """Each disturbance of ``plan`` simulated on its grasp ``model`` with its preload.

    The simulation ramps the load up to twice the prediction (``score.upper`` when the
    prediction is unbounded or 0); the simulated value is its largest resisted load divided by
    the disturbance's norm (``inf`` when it held at the upper load).

    Raises:
        MissingDependencyError: MuJoCo is not installed (``pip install "pinograsp[mujoco]"``).
    """
    from ..sim.simulate import simulate_max_wrench

    out = []
    for label, w in zip(score.labels, score.wrenches):
        if label not in plan.values:
            continue
        norm = float(np.linalg.norm(w))
        predicted = plan.values[label]
        upper = 2.0 * predicted * norm if 0 < predicted < math.inf else score.upper
        r = simulate_max_wrench(model, w, plan.command, upper=upper)
        simulated = math.inf if r.load is None else float(r.load) / norm
        ratio = simulated / predicted if 0 < predicted < math.inf else math.nan
        out.append(PlanCheck(label, predicted, simulated, str(r.status), ratio))
    return tuple(out)
