"""Plot of a :class:`~pinograsp.analysis.resistance_set.ResistanceSet` (``docs/metrics.md``).

:func:`plot_resistance_set` draws equal-area maps of the directions coloured by their scaled
limit ``sqrt(|f|² + |tau / length|²)`` [N] — unbounded directions as black crosses, directions not
resistible at all (below the resolution) as red rings, failed ones as grey dots — and the
empirical distribution of the limits with the 5/25/50 % quantiles.

* 6-D sets: two Mollweide maps, of the force part ``f / |f|`` (longitude ``atan2(fy, fx)``,
  latitude ``asin(fz / |f|)``) and of the torque part ``tau / |tau|``; marker size grows with
  the share of that part in the direction.
* planar sets (``fx, fy, mz``): one map of the whole sphere ``u = (fx, fy, mz / length)``,
  Lambert cylindrical equal-area (``x``: the force angle, ``y``: ``u_mz``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..analysis.resistance_set import QUANTILES, ResistanceSet
from ..errors import InvalidInputError
from .figures import GID_UNBOUNDED, pyplot

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

#: ``gid`` of the markers of directions that are not resistible at all.
GID_NOT_RESISTIBLE = "pinograsp-not-resistible"
#: ``gid`` of the map markers of ``above_limit`` directions (resisted at ``upper``: a lower bound).
GID_ABOVE_LIMIT = "pinograsp-above-limit"


def _colour_norm(values: np.ndarray) -> Any:
    from matplotlib.colors import LogNorm, Normalize

    v = values[np.isfinite(values) & (values > 0)]
    if v.size == 0:
        return Normalize(0.0, 1.0)
    lo, hi = float(v.min()), float(v.max())
    if hi > 10 * lo:
        return LogNorm(lo, hi)
    return Normalize(lo, hi if hi > lo else lo + 1.0)


def _draw_map(ax: Any, lon: np.ndarray, lat_or_y: np.ndarray, size: np.ndarray, rs: ResistanceSet, norm: Any):
    s = np.array(rs.statuses)
    fin = s == "finite"
    sc = ax.scatter(
        lon[fin], lat_or_y[fin], c=rs.scaled[fin], s=size[fin], cmap="viridis", norm=norm, edgecolors="none"
    )
    # above_limit: resisted at ``upper``, the limit lies above it (a lower bound, not a limit)
    m = s == "above_limit"
    ax.scatter(
        lon[m],
        lat_or_y[m],
        c=rs.scaled[m],
        s=np.maximum(size[m], 30.0),
        marker="^",
        cmap="viridis",
        norm=norm,
        edgecolors="k",
        linewidths=0.8,
        gid=GID_ABOVE_LIMIT,
    )
    m = s == "unbounded"
    big = np.maximum(size[m], 40.0)
    ax.scatter(lon[m], lat_or_y[m], marker="x", c="k", s=big, linewidths=1.0, gid=GID_UNBOUNDED)
    m = s == "below_resolution"
    ax.scatter(lon[m], lat_or_y[m], marker="o", facecolors="none", edgecolors="red", s=size[m] * 1.5)
    ax.collections[-1].set_gid(GID_NOT_RESISTIBLE)
    m = s == "failed"
    ax.scatter(lon[m], lat_or_y[m], marker=".", c="0.6", s=size[m])
    ax.grid(True, alpha=0.3)
    return sc


def _part(v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Longitude, latitude [rad] of the unit part ``v / |v|`` (n, 3), and ``|v|``."""
    r = np.linalg.norm(v, axis=1)
    w = v / np.where(r > 0, r, 1.0)[:, None]
    return np.arctan2(w[:, 1], w[:, 0]), np.arcsin(np.clip(w[:, 2], -1, 1)), r


def _ecdf(ax: Any, rs: ResistanceSet) -> None:
    ok = np.array(rs.statuses) != "failed"
    v = np.sort(rs.capped[ok])
    frac = np.arange(1, v.size + 1) / max(v.size, 1)
    ax.step(v, frac, where="post", color="C0", label="capped at upper where unbounded")
    for q in QUANTILES:
        x = rs.quantile(q)
        if np.isfinite(x):
            ax.axvline(x, color="0.5", ls=":", lw=1)
            ax.text(x, q, f" {q:.0%}: {x:.3g} N", fontsize=8, va="bottom")
    ax.set_xlabel("scaled limit sqrt(|f|² + |τ/L|²) [N]")
    ax.set_ylabel("fraction of directions")
    ax.set_ylim(0, 1.02)
    if v.size and v[0] > 0 and v[-1] > 20 * v[0]:
        ax.set_xscale("log")
    ax.grid(True, alpha=0.3)


def plot_resistance_set(rset: ResistanceSet, *, title: str | None = None) -> Figure:
    """Maps of a resistance set's directions coloured by the scaled limit [N], and the
    distribution of the limits. Returns the matplotlib ``Figure``.

    Args:
        rset: The set (:func:`pinograsp.resistance_set`).
        title: Figure title (default: counts per class and the length scale).
    """
    if not isinstance(rset, ResistanceSet):
        raise InvalidInputError("rset", f"expected a ResistanceSet, got {type(rset).__name__}")
    if rset.n == 0:
        raise InvalidInputError("rset", "has no directions")
    plt = pyplot()
    u = rset.sphere
    planar = bool(np.allclose(u[:, [2, 3, 4]], 0.0))
    norm = _colour_norm(rset.scaled)
    fig = plt.figure(figsize=(15, 5.2) if not planar else (11, 4.8))
    grid = fig.add_gridspec(1, 2 if planar else 3, width_ratios=[1, 1] if planar else [1.25, 1.25, 1])
    if planar:
        ax = fig.add_subplot(grid[0])
        lon = np.degrees(np.arctan2(u[:, 1], u[:, 0]))
        sc = _draw_map(ax, lon, u[:, 5], np.full(rset.n, 30.0), rset, norm)
        ax.set_xlim(-180, 180)
        ax.set_ylim(-1.05, 1.05)
        ax.set_xlabel("force angle atan2(fy, fx) [deg]")
        ax.set_ylabel("u_mz = (mz / L) share")
        ax.set_title("sphere (fx, fy, mz/L), equal-area")
        maps = [ax]
    else:
        maps = []
        for k, (part, name) in enumerate(((u[:, :3], "force"), (u[:, 3:], "torque"))):
            ax = fig.add_subplot(grid[k], projection="mollweide")
            lon, lat, r = _part(part)
            sc = _draw_map(ax, lon, lat, 6.0 + 40.0 * r**2, rset, norm)
            ax.set_title(f"{name} direction (marker size: {name} share)", fontsize=10)
            ax.set_xticklabels([])
            ax.tick_params(labelsize=7)
            maps.append(ax)
    cb = fig.colorbar(sc, ax=maps, orientation="horizontal", fraction=0.06, pad=0.18 if planar else 0.06)
    cb.set_label("scaled limit [N]  (×: unbounded, ▲: above upper, a lower bound, red ring: not resistible)")
    _ecdf(fig.add_subplot(grid[-1]), rset)
    c = rset.classes()
    fig.suptitle(
        title
        or f"resistance set: {rset.n} directions, L = {rset.length:.3g} m; finite {c['finite']}, "
        f"unbounded {c['unbounded']}, not resistible {c['not_resistible']}, failed {c['failed']}",
        fontsize=11,
    )
    return fig
