"""A grasp plan as a picture: the hand closed on the object with its contacts (left) and the
passive resistance along each disturbance (right; docs/planning.md)."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..planning.records import GraspPlan
from .figures import save_figure

#: The value axis's label (the cube's unit forces: newtons).
VALUE_LABEL = "largest resisted multiple of the disturbance [N for unit forces]"


def plot_plan(
    plan: GraspPlan, path: str | os.PathLike[str] | None = None, *, dpi: int = 110, ylabel: str | None = None
) -> Any:
    """Draw one plan: the scene (hand at ``plan.q``, object at ``plan.object_pose``, contacts)
    and a bar per disturbance of its value (unbounded bars drawn to 1.2 × the largest finite
    value, hatched; the worst one in red; an orange bar across a value past a snap marks the
    first snap's load, ``plan.snaps``). A verified plan (``plan.checks``) also shows each
    simulated load: a black dot where the simulation gave way, a black triangle on the bar
    where it held. ``ylabel`` names the values' unit (None: :data:`VALUE_LABEL`, newtons for
    the cube's unit forces; ``pinograsp plan --gravity``: weights).
    Returns the matplotlib ``Figure``; with ``path`` (``.png``, ``.pdf``, ...) also writes it.
    """
    from matplotlib.figure import Figure

    from ..batch.grasps import build_grasp, grasp_configuration
    from .scene_mpl import scene_axes

    fig = Figure(figsize=(11.0, 4.6))
    hand, obj, q = grasp_configuration(plan.spec)
    model, _, _ = build_grasp(plan.spec)
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    scene_axes(model, ax=ax3, hand=hand, q=q, obj=obj, title=f"plan #{plan.rank} ({plan.id})")
    ax = fig.add_subplot(1, 2, 2)
    labels = list(plan.values)
    v = np.array([plan.values[k] for k in labels])
    sims = {c.label: c.simulated for c in plan.checks if c.label in plan.values}
    finite = np.array([x for x in (*v, *sims.values(), *plan.snaps.values()) if math.isfinite(x)])
    cap = 1.2 * float(finite.max()) if finite.size and finite.max() > 0 else 1.0
    shown = np.where(np.isfinite(v), v, cap)
    colours = ["tab:red" if k == plan.worst else "tab:blue" for k in labels]
    bars = ax.bar(range(len(v)), shown, color=colours)
    for b, x in zip(bars, v):
        if not math.isfinite(x):
            b.set_hatch("//")
            b.set_alpha(0.5)
    title = f"score {plan.score:.3g} (worst {plan.worst}), epsilon {plan.epsilon:.3g}"
    snapped = [k for k in labels if k in plan.snaps]
    if snapped:
        ax.plot([labels.index(k) for k in snapped], [plan.snaps[k] for k in snapped], "_", color="tab:orange",
                ms=12, mew=2.5, label="first snap")  # fmt: skip
    if sims:
        x = [labels.index(k) for k in sims]
        gave = [(i, sims[k]) for i, k in zip(x, sims) if math.isfinite(sims[k])]
        held = [i for i, k in zip(x, sims) if not math.isfinite(sims[k])]
        ax.plot([i for i, _ in gave], [y for _, y in gave], "ko", ms=5, label="simulated: gave way")
        ax.plot(held, shown[held], "k^", ms=6, label="simulated: held")
        title += f"; simulated worst {min(sims.values()):.3g}"
    if sims or snapped:
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xticks(range(len(v)), labels, rotation=90, fontsize=7)
    ax.set_ylabel(VALUE_LABEL if ylabel is None else ylabel)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, Path(path), dpi=dpi)
    return fig
