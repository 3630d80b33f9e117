"""The quasi-static loading path as a load–displacement plot (``docs/plots.md``).

:func:`plot_loading_path` draws the load λ against the object's displacement along the load
direction, marks the breakpoints where something changes (events), ends the curve at the limit
load (or continues the last segment as a dashed ray when the path is unbounded), and shows the
state of every contact below it as coloured bands (sticking, sliding, separated).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.axes import wrench_unit
from ..errors import InvalidInputError
from .figures import GID_UNBOUNDED, pyplot

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

#: Band colours of the contact states.
STATE_COLORS = {"sticking": "#4c9a2a", "sliding": "#e08a1e", "separated": "#bbbbbb"}
#: ``gid`` of the event markers.
GID_EVENTS = "pinograsp-path-events"


def _check(lp: Any) -> None:
    from ..analysis.quasistatic.result import LoadingPath

    if not isinstance(lp, LoadingPath):
        raise InvalidInputError("lp", f"expected a pinograsp.LoadingPath, got {type(lp).__name__}")


def plot_loading_path(lp: Any, ax: Axes | None = None, *, bands: bool = True) -> Axes:
    """Load vs displacement along the direction, events marked, contact states as bands.

    Args:
        lp: A :class:`~pinograsp.LoadingPath`.
        ax: Axes to draw the curve on (default: a new figure; the bands then get their own
            Axes below it, sharing the displacement axis).
        bands: Draw the contact-state bands (only in a new figure).

    Returns:
        The Axes of the load–displacement curve.
    """
    _check(lp)
    plt = pyplot()
    s = lp.displacement_along
    loads = np.asarray(lp.loads, float)
    band_ax = None
    if ax is None:
        nc = len(lp.contact_names)
        if bands and nc:
            fig, (ax, band_ax) = plt.subplots(
                2, 1, sharex=True, figsize=(6.5, 4.5 + 0.18 * nc), height_ratios=[3.0, 0.4 + 0.25 * nc]
            )
        else:
            fig, ax = plt.subplots(figsize=(6.5, 4.5))
    assert ax is not None
    xs = list(s)
    if lp.ray is not None:
        along = float(lp.ray["object_displacements"] @ lp.direction)
        span = max(float(s.max() - s.min()), abs(along) * max(loads[-1], 1.0), 1e-300)
        extra = 0.3 * span / max(abs(along), 1e-300) if along != 0 else 0.3 * max(loads[-1], 1.0)
        ax.plot(
            [s[-1], s[-1] + along * extra],
            [loads[-1], loads[-1] + extra],
            "--",
            color="C0",
            gid=GID_UNBOUNDED,
        )
        ax.annotate("unbounded", (s[-1] + along * extra, loads[-1] + extra), fontsize=8, ha="right")
        xs.append(s[-1] + along * extra)
    ax.plot(s, loads, "-", color="C0", marker="o", markersize=3, label="load path")
    at = sorted({e.breakpoint for e in lp.events if e.kind in ("contact", "actuator")})
    if at:
        ax.plot(s[at], loads[at], "s", color="C3", markersize=5, gid=GID_EVENTS, label="events")
    if lp.status in ("finite", "below_resolution"):
        ax.axhline(lp.limit, color="C3", lw=0.8, ls=":")
        ax.annotate(f"limit {lp.limit:.4g}", (s[-1], lp.limit), fontsize=8, va="bottom", ha="right")
    unit = wrench_unit(lp.direction)
    ax.set_ylabel(f"load λ [{unit}]")
    ax.set_title(f"quasi-static loading path ({lp.status})", fontsize=10)
    ax.grid(True, alpha=0.3)
    target = band_ax if band_ax is not None else ax
    target.set_xlabel("displacement along the load (model units, scales as 1/k)")
    if band_ax is not None:
        _bands(band_ax, lp, s, xs)
    return ax


def _bands(ax: Axes, lp: Any, s: np.ndarray, xs: list[float]) -> None:
    """One band per contact, coloured by its state on each segment."""
    nc = len(lp.contact_names)
    ends = list(s[1:]) + ([xs[-1]] if lp.ray is not None else [])
    for i in range(nc):
        for j, x1 in enumerate(ends):
            state = lp.contact_states[j][i]
            x0 = s[j]
            ax.barh(i, x1 - x0, left=x0, height=0.7, color=STATE_COLORS.get(state, "white"), edgecolor="none")
    ax.set_yticks(range(nc))
    ax.set_yticklabels(lp.contact_names, fontsize=7)
    ax.invert_yaxis()
    handles = [pyplot().Rectangle((0, 0), 1, 1, color=c) for c in STATE_COLORS.values()]
    ax.legend(
        handles, list(STATE_COLORS), fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.45)
    )


__all__ = ["GID_EVENTS", "STATE_COLORS", "plot_loading_path"]
