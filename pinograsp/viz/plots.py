"""Matplotlib plots of pinograsp results.

* :func:`plot_profile` — the seed paper's polar resistance profile: finite magnitudes as a
  curve, directions resisted without bound as hatched wedges reaching the plot edge (marked
  ``∞``), optionally normalised by the ``+b2`` (``+Y``) value; several profiles overlaid.
* :func:`plot_preload_comparison` — max resistible wrench per named preload as bars (unbounded:
  hatched bar labelled ``∞``), or overlaid profiles.
* :func:`plot_force_comparison` — the seed paper's Fig. 1: normal vs tangential force per
  contact for the passive analysis and the linear-compliance baseline, with the friction-cone
  boundary ``|c_t| = mu c_n``; contacts outside their cone are circled in red.
* :func:`save_figure` — write a figure (or an Axes' figure), creating parent folders.

matplotlib is imported lazily. Without a display (headless Linux, no ``MPLBACKEND``, not in
Jupyter) the non-interactive ``Agg`` backend is selected before ``pyplot`` is first imported, so
the functions work in scripts, CI and notebooks alike. Every function returns the matplotlib
``Axes`` it drew on; pass ``ax=`` to draw into your own figure.

Artists that tests (and users) may look up carry a ``gid``: :data:`GID_UNBOUNDED` (unbounded
wedges and bars), :data:`GID_OUTSIDE_CONE` (the red markers of contacts outside their cone).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.axes import direction_label
from ..core.model import GraspModel
from ..core.results import MaxWrench, PassiveResponse, ResistanceProfile
from ..core.validate import writing
from ..errors import InvalidInputError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.baseline import LinearComplianceResult
    from ..core.model import GraspModel

#: ``gid`` of the artists that mark directions resisted without bound.
GID_UNBOUNDED = "pinograsp-unbounded"
#: ``gid`` of the markers of contacts outside their friction cone.
GID_OUTSIDE_CONE = "pinograsp-outside-cone"

_HATCHES = ("//", "\\\\", "xx", "..", "++", "--", "oo", "||")
_FORCE_AXES = {"fx", "fy", "fz"}
_TORQUE_AXES = {"mx", "my", "mz", "tx", "ty", "tz"}


# ----------------------------------------------------------------------------- matplotlib
def _headless() -> bool:
    """No display to open windows on (and nobody chose a backend)."""
    if os.environ.get("MPLBACKEND") or "ipykernel" in sys.modules:
        return False
    if sys.platform.startswith(("win", "darwin")):
        return False
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def pyplot() -> Any:
    """``matplotlib.pyplot``, selecting the ``Agg`` backend first when there is no display."""
    import matplotlib

    if "matplotlib.pyplot" not in sys.modules and _headless():
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _polar_axes(ax: Axes | None, figsize: tuple[float, float] = (5.5, 5.5)) -> Axes:
    if ax is None:
        _, ax = pyplot().subplots(subplot_kw={"projection": "polar"}, figsize=figsize)
        return ax
    if getattr(ax, "name", None) != "polar":
        raise InvalidInputError(
            "ax", "a polar profile needs a polar Axes (e.g. plt.subplots(subplot_kw={'projection': 'polar'}))"
        )
    return ax


def _cartesian_axes(ax: Axes | None, figsize: tuple[float, float]) -> Axes:
    if ax is None:
        _, ax = pyplot().subplots(figsize=figsize)
        return ax
    if getattr(ax, "name", None) != "rectilinear":
        raise InvalidInputError(
            "ax", f"expected a rectilinear (x-y) Axes, got a {getattr(ax, 'name', ax)!r} Axes"
        )
    return ax


def save_figure(
    fig: Figure | Axes, path: str | os.PathLike[str], *, dpi: int = 120, close: bool = False
) -> Path:
    """Save a figure (or the figure of an Axes) and return the written path.

    Parent folders are created. The format follows the suffix (``.png``, ``.pdf``, ``.svg``, ...).

    Args:
        fig: A matplotlib ``Figure`` or ``Axes``.
        path: Output file.
        dpi: Resolution of raster formats.
        close: Close the figure afterwards (frees memory in loops; pyplot figures only).
    """
    figure = getattr(fig, "figure", None) if not hasattr(fig, "savefig") else fig
    if figure is None or not hasattr(figure, "savefig"):
        raise InvalidInputError("fig", f"expected a matplotlib Figure or Axes, got {type(fig).__name__}")
    if isinstance(path, (str, os.PathLike)) and not isinstance(path, bytes) and not Path(path).suffix:
        raise InvalidInputError("path", f"{str(path)!r} has no suffix (e.g. '.png') to pick the format")
    p = writing(path, lambda f: figure.savefig(f, dpi=dpi, bbox_inches="tight"))
    if close:
        pyplot().close(figure)
    return p


# ----------------------------------------------------------------------------- profiles
def _axis_unit(label: str) -> str | None:
    key = str(label).lower()
    if key in _FORCE_AXES:
        return "N"
    if key in _TORQUE_AXES:
        return "N·m"
    return None


def _direction_unit(direction: np.ndarray) -> str:
    """Unit of a magnitude along a 6-D wrench direction."""
    d = np.abs(np.asarray(direction, dtype=float).reshape(-1))
    if d.shape != (6,):
        return "wrench units"
    force, torque = d[:3].max() > 1e-12, d[3:].max() > 1e-12
    if force and not torque:
        return "N"
    if torque and not force:
        return "N·m"
    return "N, N·m mixed"


def _plane_unit(plane: Sequence[str], basis: np.ndarray) -> str:
    units = {_axis_unit(p) for p in plane}
    if len(units) == 1 and None not in units:
        return units.pop()  # type: ignore[return-value]
    kinds = {_direction_unit(b) for b in np.atleast_2d(basis)}
    return kinds.pop() if len(kinds) == 1 else "N, N·m mixed"


def _as_profiles(
    profile_or_list: object, labels: Sequence[str] | None
) -> tuple[list[ResistanceProfile], list[str]]:
    if isinstance(profile_or_list, ResistanceProfile):
        profiles, names = [profile_or_list], [None]
    elif isinstance(profile_or_list, Mapping):
        profiles, names = list(profile_or_list.values()), [str(k) for k in profile_or_list]
    elif isinstance(profile_or_list, Sequence) and not isinstance(profile_or_list, str):
        profiles, names = list(profile_or_list), [None] * len(profile_or_list)
    else:
        raise InvalidInputError(
            "profile",
            f"expected a ResistanceProfile, a list or a dict of them, got {type(profile_or_list).__name__}",
        )
    if not profiles:
        raise InvalidInputError("profile", "no profile to plot")
    for i, p in enumerate(profiles):
        if not isinstance(p, ResistanceProfile):
            raise InvalidInputError(f"profile[{i}]", f"expected a ResistanceProfile, got {type(p).__name__}")
        if p.magnitudes.size == 0:
            raise InvalidInputError(f"profile[{i}]", "has no directions")
    if labels is not None:
        if isinstance(labels, (str, bytes)) or not isinstance(labels, (Sequence, np.ndarray)):
            raise InvalidInputError("labels", f"expected a list of {len(profiles)} labels, got {labels!r}")
        labels = [str(s) for s in labels]
        if len(labels) != len(profiles):
            raise InvalidInputError("labels", f"expected {len(profiles)} labels, got {len(labels)}")
        names = labels
    names = [
        n if n is not None else (p.results[0].method if p.results else f"profile {i}")
        for i, (n, p) in enumerate(zip(names, profiles))
    ]
    if len(set(names)) < len(names):  # e.g. two profiles of the same method
        names = [f"{n} ({i})" for i, n in enumerate(names)]
    base = profiles[0]
    for i, p in enumerate(profiles[1:], start=1):
        if p.basis.shape != base.basis.shape or not np.allclose(p.basis, base.basis, atol=1e-9):
            raise InvalidInputError(
                f"profile[{i}]",
                f"spans the plane {p.plane}, profile 0 spans {base.plane}: overlay one plane only",
            )
    return profiles, names


def _circular_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Runs ``(first, last)`` of True in a circular boolean array (``last < first``: wraps)."""
    n = mask.size
    if mask.all():
        return [(0, n - 1)]
    runs = []
    start = int(np.argmin(mask))  # a False entry: no run crosses it
    i = 0
    while i < n:
        k = (start + i) % n
        if mask[k]:
            j = i
            while j + 1 < n and mask[(start + j + 1) % n]:
                j += 1
            runs.append((k, (start + j) % n))
            i = j + 1
        else:
            i += 1
    return runs


def _reference_value(p: ResistanceProfile, index: int) -> float:
    """Magnitude along ``+b2`` (angle π/2), the paper's ``+Y`` normalisation."""
    hit = np.flatnonzero(np.isclose(np.mod(p.angles, 2 * np.pi), np.pi / 2, atol=1e-9))
    if hit.size == 0:
        raise InvalidInputError(
            "normalize",
            f"profile {index} has no direction along +{p.plane[1]} (use n divisible by 4, or "
            "resistance_profile(..., normalize=True) which solves the reference direction)",
        )
    i = int(hit[0])
    if p.unbounded[i] or not p.magnitudes[i] > 0:
        raise InvalidInputError(
            "normalize",
            f"profile {index} is {'unbounded' if p.unbounded[i] else 'not resisted'} along +{p.plane[1]}",
        )
    return float(p.magnitudes[i])


def rlabel_angle(avoid: np.ndarray) -> float:
    """The ray (22.5° + k 45° [deg]) for the radial tick labels farthest from the angles ``avoid`` [rad]."""
    candidates = np.radians(22.5 + 45.0 * np.arange(8))
    if np.size(avoid) == 0:
        return 22.5
    gap = np.abs(np.angle(np.exp(1j * (candidates[:, None] - np.asarray(avoid, float)[None, :]))))
    return float(np.degrees(candidates[int(np.argmax(gap.min(axis=1) + 1e-9 * -np.arange(8)))]))


def plot_profile(
    profile_or_list: ResistanceProfile | Sequence[ResistanceProfile] | Mapping[str, ResistanceProfile],
    ax: Axes | None = None,
    labels: Sequence[str] | None = None,
    normalize: bool | float | None = None,
    title: str | None = None,
    *,
    rmax: float | None = None,
    colors: Sequence[str] | None = None,
) -> Axes:
    """Polar resistance profile(s), as in the seed paper.

    The angle is the direction in the profile's plane, measured from its first spanning
    direction ``+b1`` towards ``+b2`` (``+fx`` towards ``+fy`` for the XY plane); the radius is
    the max resistible magnitude. Directions resisted without bound are drawn as hatched
    wedges (``gid`` :data:`GID_UNBOUNDED`) reaching the plot edge and marked with ``∞``; the
    finite magnitudes form a curve with points at the sampled directions (broken where the
    profile is unbounded). A magnitude of 0 (not resisted at all) is a point at the centre.

    Args:
        profile_or_list: A :class:`~pinograsp.ResistanceProfile`, a list of them, or a dict
            ``{label: profile}``; all in the same plane.
        ax: A polar Axes to draw on (default: a new figure).
        labels: Legend labels (default: the dict keys, the method names, or ``profile i``).
        normalize: ``True``: divide every profile by its own value along ``+b2`` (the paper's
            ``+Y`` normalisation; a profile already normalised by
            :func:`~pinograsp.resistance_profile` is left as it is); a number: divide by it.
            ``None``/``False``: plot as computed.
        title: Axes title (default: plane and unit).
        rmax: Radius of the plot edge (default 1.15 × the largest finite magnitude).
        colors: One matplotlib colour per profile (default the colour cycle).

    Returns:
        The polar Axes.

    Raises:
        InvalidInputError: Not profiles, profiles of different planes, mixed normalised and
            absolute profiles, a non-polar ``ax``, or a normalisation reference that is
            missing, unbounded or zero.
    """
    profiles, names = _as_profiles(profile_or_list, labels)
    ax = _polar_axes(ax)
    plane = profiles[0].plane
    radii: list[np.ndarray] = []
    normalised: list[bool] = []
    for i, p in enumerate(profiles):
        r = np.where(p.unbounded, np.inf, np.asarray(p.magnitudes, dtype=float))
        if normalize is None or normalize is False:
            normalised.append(p.normalized_by is not None)
        elif normalize is True:
            if p.normalized_by is None:
                r = r / _reference_value(p, i)
            normalised.append(True)
        else:
            try:
                scale = float(normalize)  # type: ignore[arg-type]
            except (TypeError, ValueError) as exc:
                raise InvalidInputError(
                    "normalize", f"expected True, None or a number, got {normalize!r}"
                ) from exc
            if not np.isfinite(scale) or scale <= 0:
                raise InvalidInputError("normalize", f"must be finite and > 0, got {normalize!r}")
            r = r / scale
            normalised.append(True)
        radii.append(r)
    if len(set(normalised)) > 1:
        raise InvalidInputError(
            "normalize",
            "some profiles are normalised and others are not; pass normalize=True to normalise all of them",
        )
    unit = "normalised" if normalised[0] else _plane_unit(plane, profiles[0].basis)
    finite = np.concatenate([r[np.isfinite(r)] for r in radii])
    if rmax is None:
        top = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
        rmax = 1.15 * top
    elif not (np.isfinite(rmax) and rmax > 0):
        raise InvalidInputError("rmax", f"must be finite and > 0, got {rmax!r}")
    if colors is not None and len(colors) < len(profiles):
        raise InvalidInputError("colors", f"expected {len(profiles)} colours, got {len(colors)}")

    from matplotlib.patches import Patch

    handles = []
    any_unbounded = False
    for i, (p, r, name) in enumerate(zip(profiles, radii, names)):
        color = colors[i] if colors is not None else f"C{i % 10}"
        a = np.mod(np.asarray(p.angles, dtype=float), 2 * np.pi)
        order = np.argsort(a)
        a, r = a[order], r[order]
        curve = np.where(np.isfinite(r), r, np.nan)
        closed_a, closed_r = np.append(a, a[0] + 2 * np.pi), np.append(curve, curve[0])
        (line,) = ax.plot(closed_a, closed_r, marker=".", color=color, lw=1.6, label=name)
        handles.append(line)
        unb = ~np.isfinite(r)
        if unb.any():
            any_unbounded = True
            # each unbounded sample owns the angular interval halfway to its neighbours
            prev = np.roll(a, 1)
            prev[0] -= 2 * np.pi
            nxt = np.roll(a, -1)
            nxt[-1] += 2 * np.pi
            lo = 0.5 * (a + prev) if a.size > 1 else a - np.pi
            hi = 0.5 * (a + nxt) if a.size > 1 else a + np.pi
            for k in np.flatnonzero(unb):
                ax.bar(
                    0.5 * (lo[k] + hi[k]),
                    rmax,
                    width=hi[k] - lo[k],
                    bottom=0.0,
                    color=color,
                    alpha=0.18,
                    hatch=_HATCHES[i % len(_HATCHES)],
                    edgecolor=color,
                    linewidth=0.0,
                    gid=GID_UNBOUNDED,
                    zorder=0.5,
                )
            # one ∞ mark per run of consecutive unbounded directions (circular), at its middle
            runs = _circular_runs(unb)
            mid = np.array(
                [
                    np.mod(0.5 * (lo[i0] + hi[i1] + (2 * np.pi if i1 < i0 else 0.0)), 2 * np.pi)
                    for i0, i1 in runs
                ]
            )
            ax.plot(
                mid,
                np.full(mid.size, 0.92 * rmax),
                linestyle="none",
                marker=r"$\infty$",
                markersize=11,
                color=color,
                gid=GID_UNBOUNDED,
                clip_on=False,
            )
    if any_unbounded:
        handles.append(Patch(facecolor="0.6", alpha=0.4, hatch="//", edgecolor="0.4", label="unbounded (∞)"))
    ax.set_ylim(0.0, rmax)
    b1, b2 = plane
    ax.set_thetagrids(
        np.arange(0, 360, 45),
        [f"+{b1}", "", f"+{b2}", "", f"−{b1}", "", f"−{b2}", ""],
    )
    # radial tick labels on the unlabelled grid ray farthest from every unbounded wedge
    unb_angles = np.concatenate(
        [np.mod(p.angles, 2 * np.pi)[~np.isfinite(r)] for p, r in zip(profiles, radii)]
    )
    ax.set_rlabel_position(rlabel_angle(unb_angles))
    ax.grid(True, alpha=0.4)
    if title is None:
        title = f"max resistible wrench in the {b1}–{b2} plane [{unit}]"
    ax.set_title(title, fontsize=10, pad=14)
    ax.legend(handles=handles, loc="lower left", bbox_to_anchor=(-0.12, -0.14), fontsize=8, framealpha=0.9)
    return ax


# ----------------------------------------------------------------------------- preloads
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
            labelled ``∞``, ``gid`` :data:`GID_UNBOUNDED`), or ``{preload name:
            ResistanceProfile}`` (overlaid polar profiles, see :func:`plot_profile`).
        ax: Axes to draw on (rectilinear for bars, polar for profiles; default a new figure).
        title: Axes title (default: the direction and unit).
        normalize: Profiles only, as in :func:`plot_profile`.
        show_ratio: Bars only: with exactly two finite results, write their ratio (first /
            second) in the title — the number the seed paper reports for its case 2.

    Returns:
        The Axes.

    Raises:
        InvalidInputError: Empty input, or a mix of MaxWrench and ResistanceProfile values.
    """
    if not isinstance(results, Mapping) or not results:
        raise InvalidInputError(
            "results", "expected a non-empty dict {preload name: MaxWrench | ResistanceProfile}"
        )
    values = list(results.values())
    if all(isinstance(v, ResistanceProfile) for v in values):
        return plot_profile(dict(results), ax=ax, normalize=normalize, title=title)
    if not all(isinstance(v, MaxWrench) for v in values):
        kinds = sorted({type(v).__name__ for v in values})
        raise InvalidInputError(
            "results", f"expected only MaxWrench or only ResistanceProfile values, got {', '.join(kinds)}"
        )
    ax = _cartesian_axes(ax, (max(4.0, 1.2 * len(values) + 2.0), 4.0))
    names = [str(k) for k in results]
    dirs = np.array([np.asarray(v.direction, dtype=float).reshape(-1) for v in values])
    same_dir = all(np.allclose(d, dirs[0], atol=1e-9) for d in dirs)
    units = {_direction_unit(d) for d in dirs}
    unit = units.pop() if len(units) == 1 else "N, N·m"
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
    ax.set_ylabel(f"max resistible magnitude [{unit}]")
    ax.grid(True, axis="y", alpha=0.4)
    if title is None:
        where = f"along {direction_label(dirs[0])}" if same_dir else "per direction"
        title = f"max resistible wrench {where}"
        if show_ratio and len(values) == 2 and not unb.any() and mags[1] > 0:
            title += f"\n{names[0]} / {names[1]} = {mags[0] / mags[1]:.3g}"
    ax.set_title(title, fontsize=10)
    return ax


# ----------------------------------------------------------------------------- Fig. 1
def _contact_forces(obj: object, name: str, nc: int) -> np.ndarray:
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
        renderer = ax.figure.canvas.get_renderer()
    except AttributeError:  # pragma: no cover - backends without a renderer: first position
        renderer = None
    box = ax.get_window_extent(renderer) if renderer is not None else None
    placed: list[Any] = [] if renderer is None else [a.get_window_extent(renderer) for a in avoid]

    def area(a: Any, b: Any) -> float:
        w = min(a.x1, b.x1) - max(a.x0, b.x0)
        h = min(a.y1, b.y1) - max(a.y0, b.y0)
        return max(w, 0.0) * max(h, 0.0)

    for point, text, color in labels:
        best, best_cost = None, np.inf
        for offset, ha, va in candidates:
            t = ax.annotate(
                text, point, xytext=offset, textcoords="offset points", ha=ha, va=va, fontsize=7, color=color
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
    ax = _cartesian_axes(ax, (6.0, 4.5))
    mu = np.asarray(model.mu, dtype=float)
    pts = []
    for c in (cp, cl):
        pts.append(np.column_stack([c[:, 0], np.linalg.norm(c[:, 1:], axis=1)]))
    finite = np.concatenate([p[np.all(np.isfinite(p), axis=1)] for p in pts])
    xmax = max(float(finite[:, 0].max()) if finite.size else 1.0, 1e-9)
    xmin = min(float(finite[:, 0].min()) if finite.size else 0.0, 0.0)
    ymax = max(float(finite[:, 1].max()) if finite.size else 1.0, 1e-9)
    span_x = 1.15 * xmax - (1.15 * xmin if xmin < 0 else 0.0)
    x_lo = 1.15 * xmin - 0.05 * span_x if xmin < 0 else -0.05 * span_x
    x_hi = 1.15 * xmax
    y_hi = 1.2 * max(ymax, float(mu.max()) * xmax if mu.size else ymax)
    if x_lo < 0:
        ax.axvspan(x_lo, 0.0, color="0.85", alpha=0.6, lw=0, label="pull (c_n < 0)")
    xs = np.array([0.0, x_hi])
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
    # one label per group of coincident points (mirror-symmetric contacts, or both models
    # agreeing); in the right quarter of the plot below-left of its point, so that it stays inside
    close = 1e-6 * max(xmax, ymax)
    groups: list[tuple[np.ndarray, list[str], bool]] = []
    for j in (0, 1):
        for k, name in enumerate(model.contact_names):
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
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(0.0, y_hi)
    ax.set_xlabel("normal force c_n [N]")
    ax.set_ylabel("tangential force |c_t| [N]")
    ax.grid(True, alpha=0.3)
    if title is None:
        w = getattr(passive, "wrench", None)
        what = (
            f"wrench {np.round(np.asarray(w, dtype=float), 4).tolist()}"
            if w is not None
            else "contact forces"
        )
        n_bad = int(bad[1].sum())
        verdict = getattr(passive, "status", "")
        title = f"{what}\n{labels[0]}: {verdict}; {labels[1]}: {n_bad} of {nc} contacts outside their cone"
    ax.set_title(title, fontsize=9)
    legend = ax.legend(fontsize=7, loc="upper left")
    _place_labels(
        ax, [(p, "\n".join(names), "red" if red else "0.2") for p, names, red in groups], avoid=[legend]
    )
    return ax


__all__ = [
    "GID_OUTSIDE_CONE",
    "GID_UNBOUNDED",
    "direction_label",
    "outside_cone",
    "plot_force_comparison",
    "plot_preload_comparison",
    "plot_profile",
    "pyplot",
    "rlabel_angle",
    "save_figure",
]
