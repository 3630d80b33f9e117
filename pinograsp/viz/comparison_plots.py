"""Comparison plots (``docs/plots.md``).

* :func:`plot_preload_comparison` — max resistible wrench per named preload as bars (unbounded:
  hatched bar labelled ``∞``, ``gid`` :data:`~pinograsp.viz.figures.GID_UNBOUNDED`), or
  overlaid profiles.
* :func:`plot_force_comparison` — the seed paper's Fig. 1: normal vs tangential force per
  contact for the passive analysis and the linear-compliance baseline, with the friction-cone
  boundary ``|c_t| = mu c_n``; contacts outside their cone are circled in red (``gid``
  :data:`GID_OUTSIDE_CONE`).

Both return the matplotlib ``Axes`` they drew on; pass ``ax=`` to draw into your own figure.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.axes import direction_label
from ..core.model import GraspModel
from ..core.results import MaxWrench, PassiveResponse, ResistanceProfile
from ..errors import InvalidInputError
from .figures import GID_UNBOUNDED, cartesian_axes
from .profile_plots import direction_unit, plot_profile

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes

    from ..analysis.baseline import LinearComplianceResult

#: ``gid`` of the markers of contacts outside their friction cone.
GID_OUTSIDE_CONE = "pinograsp-outside-cone"


# ----------------------------------------------------------------------------- preloads
def _check_results(results: object) -> bool:
    """Whether ``results`` holds profiles (``True``) or max wrenches (``False``), never a mix."""
    if not isinstance(results, Mapping) or not results:
        raise InvalidInputError(
            "results", "expected a non-empty dict {preload name: MaxWrench | ResistanceProfile}"
        )
    values = list(results.values())
    if all(isinstance(v, ResistanceProfile) for v in values):
        return True
    if not all(isinstance(v, MaxWrench) for v in values):
        kinds = sorted({type(v).__name__ for v in values})
        raise InvalidInputError(
            "results", f"expected only MaxWrench or only ResistanceProfile values, got {', '.join(kinds)}"
        )
    return False


def _bar_unit(dirs: np.ndarray) -> str:
    """Unit of the bars' magnitudes along the directions (k, 6)."""
    units = {direction_unit(d) for d in dirs}
    return units.pop() if len(units) == 1 else "N, N·m"


def _bars_title(
    names: list[str], dirs: np.ndarray, same_dir: bool, mags: np.ndarray, unb: np.ndarray, ratio: bool
) -> str:
    """Default title: the direction (or "per direction"), and the ratio of two finite results if ``ratio``."""
    where = f"along {direction_label(dirs[0])}" if same_dir else "per direction"
    title = f"max resistible wrench {where}"
    if ratio and len(names) == 2 and not unb.any() and mags[1] > 0:
        title += f"\n{names[0]} / {names[1]} = {mags[0] / mags[1]:.3g}"
    return title


def plot_preload_comparison(
    results: Mapping[str, MaxWrench | ResistanceProfile],
    ax: Axes | None = None,
    title: str | None = None,
    *,
    normalize: bool | float | None = None,
    show_ratio: bool = True,
) -> Axes:
    """Compare preloads: max resistible wrench per named preload.

    Args:
        results: ``{preload name: MaxWrench}`` (bar chart: finite magnitudes as bars labelled
            with their value, unbounded ones as hatched bars reaching above the finite ones,
            labelled ``∞``, ``gid`` :data:`~pinograsp.viz.figures.GID_UNBOUNDED`), or
            ``{preload name: ResistanceProfile}`` (overlaid polar profiles, see
            :func:`~pinograsp.viz.profile_plots.plot_profile`).
        ax: Axes to draw on (rectilinear for bars, polar for profiles; default a new figure).
        title: Axes title (default: the direction and unit).
        normalize: Profiles only, as in :func:`~pinograsp.viz.profile_plots.plot_profile`.
        show_ratio: Bars only: with exactly two finite results, write their ratio (first /
            second) in the title — the number the seed paper reports for its case 2.

    Returns:
        The Axes.

    Raises:
        InvalidInputError: Empty input, or a mix of MaxWrench and ResistanceProfile values.
    """
    if _check_results(results):
        profiles = {k: v for k, v in results.items() if isinstance(v, ResistanceProfile)}  # all (checked)
        return plot_profile(profiles, ax=ax, normalize=normalize, title=title)
    values = [v for v in results.values() if isinstance(v, MaxWrench)]  # all of them (checked)
    ax = cartesian_axes(ax, (max(4.0, 1.2 * len(values) + 2.0), 4.0))
    names = [str(k) for k in results]
    dirs = np.array([np.asarray(v.direction, dtype=float).reshape(-1) for v in values])
    same_dir = all(np.allclose(d, dirs[0], atol=1e-9) for d in dirs)
    mags = np.array([v.magnitude for v in values], dtype=float)
    unb = np.array([bool(v.unbounded) or not np.isfinite(v.magnitude) for v in values])
    finite = mags[~unb]
    top = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
    inf_height = 1.25 * top
    x = np.arange(len(values))
    for i in range(len(values)):
        if unb[i]:
            ax.bar(
                x[i],
                inf_height,
                width=0.6,
                color="C2",
                alpha=0.35,
                hatch="//",
                edgecolor="C2",
                gid=GID_UNBOUNDED,
            )
            ax.text(x[i], inf_height, "∞", ha="center", va="bottom", fontsize=16, color="C2")
        else:
            ax.bar(x[i], mags[i], width=0.6, color=f"C{i % 10}")
            ax.text(x[i], mags[i], f"{mags[i]:.4g}", ha="center", va="bottom", fontsize=9)
    ticks = names if same_dir else [f"{n}\n{direction_label(d)}" for n, d in zip(names, dirs)]
    ax.set_xticks(x, ticks)
    ax.set_ylim(0.0, 1.15 * inf_height if unb.any() else 1.15 * top)
    ax.set_ylabel(f"max resistible magnitude [{_bar_unit(dirs)}]")
    ax.grid(True, axis="y", alpha=0.4)
    if title is None:
        title = _bars_title(names, dirs, same_dir, mags, unb, show_ratio)
    ax.set_title(title, fontsize=10)
    return ax


# ----------------------------------------------------------------------------- Fig. 1
def _contact_forces(obj: object, name: str, nc: int) -> np.ndarray:
    """The contact forces (nc, >= 2) [N] of a result, checked against the model's ``nc``."""
    c = getattr(obj, "contact_forces", None)
    if c is None:
        raise InvalidInputError(name, f"expected a result with contact_forces, got {type(obj).__name__}")
    c = np.asarray(c, dtype=float)
    if c.ndim != 2 or c.shape[0] != nc or c.shape[1] < 2:
        raise InvalidInputError(name, f"has contact forces of shape {c.shape}, the model has {nc} contacts")
    return c


def outside_cone(model: GraspModel, contact_forces: np.ndarray, tol: float = 1e-6) -> np.ndarray:
    """Which contacts are outside their friction cone ``|c_t| <= mu c_n`` (or pull, ``c_n < 0``).

    Same test as :func:`~pinograsp.linear_compliance` (absolute tolerance ``tol`` [N]); (nc,) bool.
    """
    c = np.asarray(contact_forces, dtype=float)
    cn, ct = c[:, 0], np.linalg.norm(c[:, 1:], axis=1)
    return (ct > model.mu * np.maximum(cn, 0.0) + tol) | (cn < -tol)


@dataclass(frozen=True)
class _Frame:
    """Data limits of the force plot [N]: the x range, the top, and the largest finite x and y."""

    x_lo: float
    x_hi: float
    y_hi: float
    xmax: float
    ymax: float


def _frame(pts: list[np.ndarray], mu: np.ndarray) -> _Frame:
    """Limits that show every finite point ``(c_n, |c_t|)`` and the cone lines up to the right edge."""
    finite = np.concatenate([p[np.all(np.isfinite(p), axis=1)] for p in pts])
    xmax = max(float(finite[:, 0].max()) if finite.size else 1.0, 1e-9)
    xmin = min(float(finite[:, 0].min()) if finite.size else 0.0, 0.0)
    ymax = max(float(finite[:, 1].max()) if finite.size else 1.0, 1e-9)
    span_x = 1.15 * xmax - (1.15 * xmin if xmin < 0 else 0.0)
    x_lo = 1.15 * xmin - 0.05 * span_x if xmin < 0 else -0.05 * span_x
    x_hi = 1.15 * xmax
    y_hi = 1.2 * max(ymax, float(mu.max()) * xmax if mu.size else ymax)
    return _Frame(x_lo, x_hi, y_hi, xmax, ymax)


def _label_groups(
    names: Sequence[str], pts: list[np.ndarray], bad: list[np.ndarray], close: float
) -> list[tuple[np.ndarray, list[str], bool]]:
    """One label per group of coincident points (mirror-symmetric contacts, or both models
    agreeing): ``(point, contact names, any outside its cone)``."""
    groups: list[tuple[np.ndarray, list[str], bool]] = []
    for j in (0, 1):
        for k, name in enumerate(names):
            if not np.all(np.isfinite(pts[j][k])):
                continue
            for i, g in enumerate(groups):
                if np.allclose(g[0], pts[j][k], atol=close):
                    if name not in g[1]:
                        g[1].append(name)
                    groups[i] = (g[0], g[1], g[2] or bool(bad[j][k]))
                    break
            else:
                groups.append((pts[j][k], [name], bool(bad[j][k])))
    return groups


def _forces_title(passive: object, labels: tuple[str, str], n_bad: int, nc: int) -> str:
    """Default title: the applied wrench, the passive verdict and the baseline's cone violations."""
    w = getattr(passive, "wrench", None)
    what = f"wrench {np.round(np.asarray(w, dtype=float), 4).tolist()}" if w is not None else "contact forces"
    verdict = getattr(passive, "status", "")
    return f"{what}\n{labels[0]}: {verdict}; {labels[1]}: {n_bad} of {nc} contacts outside their cone"


def _place_labels(ax: Axes, labels: list[tuple[np.ndarray, str, str]], avoid: Sequence[Any] = ()) -> None:
    """Annotate points without overlaps: each label takes, among eight positions around its
    point (right/left of it, above/below, near or farther), the first that overlaps no label
    placed before it nor the artists ``avoid`` (the legend) and stays inside the axes; when none
    does, the one with the least overlap."""
    candidates = [
        ((dx, dy), "left" if dx > 0 else "right", "bottom" if dy > 0 else "top")
        for dy in (4, -6, 16, -18)
        for dx in (6, -6)
    ]
    try:
        renderer = ax.figure.canvas.get_renderer()  # type: ignore[attr-defined]  # Agg-like canvases
    except AttributeError:  # pragma: no cover - backends without a renderer: first position
        renderer = None
    box = ax.get_window_extent(renderer) if renderer is not None else None
    placed: list[Any] = [] if renderer is None else [a.get_window_extent(renderer) for a in avoid]

    def area(a: Any, b: Any) -> float:
        w = min(a.x1, b.x1) - max(a.x0, b.x0)
        h = min(a.y1, b.y1) - max(a.y0, b.y0)
        return max(w, 0.0) * max(h, 0.0)

    for point, text, color in labels:
        best: tuple[Any, Any] | None = None
        best_cost = np.inf
        for offset, ha, va in candidates:
            t = ax.annotate(
                text,
                (point[0], point[1]),
                xytext=offset,
                textcoords="offset points",
                ha=ha,
                va=va,
                fontsize=7,
                color=color,
            )
            if renderer is None:
                best = (t, None)
                break
            ext = t.get_window_extent(renderer).expanded(1.15, 1.3)  # a margin: fonts render wider
            outside = ext.width * ext.height - area(ext, box)
            cost = sum(area(ext, e) for e in placed) + 10.0 * outside
            if cost < best_cost:
                if best is not None:
                    best[0].remove()
                best, best_cost = (t, ext), cost
            else:
                t.remove()
            if cost == 0.0:
                break
        if best is not None and best[1] is not None:
            placed.append(best[1])


def plot_force_comparison(
    model: GraspModel,
    passive: PassiveResponse,
    compliance: LinearComplianceResult,
    ax: Axes | None = None,
    *,
    labels: tuple[str, str] = ("passive analysis", "linear compliance"),
    title: str | None = None,
    tol: float = 1e-6,
) -> Axes:
    """The seed paper's Fig. 1: contact forces of the passive analysis vs linear compliance.

    Each contact is a point ``(c_n, |c_t|)`` [N] per model (circles: passive, squares: linear
    compliance), joined by a grey line and labelled with the contact name. Dashed lines are the
    friction-cone boundaries ``|c_t| = mu c_n`` (one per distinct ``mu``); the region ``c_n < 0``
    (a contact that would have to pull) is shaded. Contacts outside their cone, or pulling, are
    circled in red (``gid`` :data:`GID_OUTSIDE_CONE`, one marker per violation, at the
    offending point), with the same test as the baseline's ``friction_violations``.

    Args:
        model: The grasp both results belong to.
        passive: :func:`~pinograsp.passive_response` result (contact forces, contact frames).
        compliance: :func:`~pinograsp.linear_compliance` result for the same wrench.
        ax: Axes to draw on (default: a new figure).
        labels: Legend labels of the two models.
        title: Axes title (default: applied wrench and verdicts).
        tol: Tolerance [N] of the cone test.

    Returns:
        The Axes.

    Raises:
        InvalidInputError: Not a model, or results whose contact count does not match it.
    """
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    nc = model.nc
    cp = _contact_forces(passive, "passive", nc)
    cl = _contact_forces(compliance, "compliance", nc)
    ax = cartesian_axes(ax, (6.0, 4.5))
    mu = np.asarray(model.mu, dtype=float)
    pts = [np.column_stack([c[:, 0], np.linalg.norm(c[:, 1:], axis=1)]) for c in (cp, cl)]
    fr = _frame(pts, mu)
    if fr.x_lo < 0:
        ax.axvspan(fr.x_lo, 0.0, color="0.85", alpha=0.6, lw=0, label="pull (c_n < 0)")
    xs = np.array([0.0, fr.x_hi])
    if mu.size:  # inside every contact's cone
        ax.fill_between(xs, 0.0, float(mu.min()) * xs, color="C2", alpha=0.08, lw=0)
    for j, m in enumerate(sorted(set(np.round(mu, 12).tolist()))):
        ax.plot(
            xs,
            m * xs,
            ls="--",
            color="0.3" if j == 0 else f"C{(j + 4) % 10}",
            lw=1.0,
            label=f"|c_t| = {m:g} c_n",
        )
    for k in range(nc):
        if np.all(np.isfinite(pts[0][k])) and np.all(np.isfinite(pts[1][k])):
            ax.plot([pts[0][k, 0], pts[1][k, 0]], [pts[0][k, 1], pts[1][k, 1]], color="0.6", lw=0.8, zorder=1)
    markers = ("o", "s")
    for j, (p, lab) in enumerate(zip(pts, labels)):
        ax.scatter(p[:, 0], p[:, 1], marker=markers[j], s=36, color=f"C{j}", label=lab, zorder=3)
    bad = [outside_cone(model, cp, tol), outside_cone(model, cl, tol)]
    out_pts = np.concatenate([pts[0][bad[0]], pts[1][bad[1]]])
    if out_pts.size:
        ax.scatter(
            out_pts[:, 0],
            out_pts[:, 1],
            s=180,
            facecolors="none",
            edgecolors="red",
            linewidths=1.8,
            label="outside friction cone",
            gid=GID_OUTSIDE_CONE,
            zorder=4,
        )
    groups = _label_groups(model.contact_names, pts, bad, 1e-6 * max(fr.xmax, fr.ymax))
    ax.set_xlim(fr.x_lo, fr.x_hi)
    ax.set_ylim(0.0, fr.y_hi)
    ax.set_xlabel("normal force c_n [N]")
    ax.set_ylabel("tangential force |c_t| [N]")
    ax.grid(True, alpha=0.3)
    if title is None:
        title = _forces_title(passive, labels, int(bad[1].sum()), nc)
    ax.set_title(title, fontsize=9)
    legend = ax.legend(fontsize=7, loc="upper left")
    _place_labels(
        ax, [(p, "\n".join(names), "red" if red else "0.2") for p, names, red in groups], avoid=[legend]
    )
    return ax


__all__ = ["GID_OUTSIDE_CONE", "outside_cone", "plot_force_comparison", "plot_preload_comparison"]
