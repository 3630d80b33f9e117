"""The seed paper's polar resistance profile (``docs/plots.md``).

:func:`plot_profile` draws finite magnitudes as a curve and directions resisted without bound as
hatched wedges reaching the plot edge (marked ``∞``, ``gid``
:data:`~pinograsp.viz.figures.GID_UNBOUNDED`), optionally normalised by the ``+b2`` (``+Y``)
value; several profiles of one plane are overlaid. It returns the matplotlib ``Axes`` it drew
on; pass ``ax=`` to draw into your own figure.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..core.axes import axis_index, wrench_unit
from ..core.results import ResistanceProfile
from ..errors import InvalidInputError, UnknownNameError
from .figures import GID_UNBOUNDED, polar_axes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes

_HATCHES = ("//", "\\\\", "xx", "..", "++", "--", "oo", "||")
#: Unit text of a magnitude along a direction with both force and torque parts.
MIXED_UNIT = "N, N·m mixed"


# ----------------------------------------------------------------------------- units
def _axis_unit(label: str) -> str | None:
    """Unit of a wrench axis name (``fx`` … ``mz``; ``tx`` … accepted), ``None`` for other labels."""
    try:
        return "N" if axis_index(label) < 3 else "N·m"
    except UnknownNameError:
        return None


def direction_unit(direction: np.ndarray) -> str:
    """Unit of a magnitude along a wrench direction (6,): ``"N"``, ``"N·m"`` or :data:`MIXED_UNIT`."""
    unit = wrench_unit(np.asarray(direction, dtype=float).reshape(-1))
    return unit if unit in ("N", "N·m") else MIXED_UNIT


def _plane_unit(plane: Sequence[str], basis: np.ndarray) -> str:
    """Unit of the plane's axis names if they share one, else of its basis directions (2, 6)."""
    units = {_axis_unit(p) for p in plane}
    if len(units) == 1 and None not in units:
        return units.pop()  # type: ignore[return-value]
    kinds = {direction_unit(b) for b in np.atleast_2d(basis)}
    return kinds.pop() if len(kinds) == 1 else MIXED_UNIT


# ----------------------------------------------------------------------------- input
def _profile_list(profile_or_list: object) -> tuple[list[ResistanceProfile], list[str | None]]:
    """The profiles and their names (dict keys, else ``None``); each a non-empty profile."""
    names: list[str | None]
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
    return profiles, names


def _legend_names(
    profiles: list[ResistanceProfile], names: list[str | None], labels: Sequence[str] | None
) -> list[str]:
    """One distinct legend label per profile: ``labels``, the dict keys, the method or ``profile i``."""
    if labels is not None:
        if isinstance(labels, (str, bytes)) or not isinstance(labels, (Sequence, np.ndarray)):
            raise InvalidInputError("labels", f"expected a list of {len(profiles)} labels, got {labels!r}")
        labels = [str(s) for s in labels]
        if len(labels) != len(profiles):
            raise InvalidInputError("labels", f"expected {len(profiles)} labels, got {len(labels)}")
        names = list(labels)
    out = [
        n if n is not None else (p.results[0].method if p.results else f"profile {i}")
        for i, (n, p) in enumerate(zip(names, profiles))
    ]
    if len(set(out)) < len(out):  # e.g. two profiles of the same method
        out = [f"{n} ({i})" for i, n in enumerate(out)]
    return out


def _as_profiles(
    profile_or_list: object, labels: Sequence[str] | None
) -> tuple[list[ResistanceProfile], list[str]]:
    """The profiles to overlay (all of one plane) and their legend labels."""
    profiles, names = _profile_list(profile_or_list)
    legend = _legend_names(profiles, names, labels)
    base = profiles[0]
    for i, p in enumerate(profiles[1:], start=1):
        if p.basis.shape != base.basis.shape or not np.allclose(p.basis, base.basis, atol=1e-9):
            raise InvalidInputError(
                f"profile[{i}]",
                f"spans the plane {p.plane}, profile 0 spans {base.plane}: overlay one plane only",
            )
    return profiles, legend


# ----------------------------------------------------------------------------- normalisation
def _reference_value(p: ResistanceProfile, index: int) -> float:
    """Magnitude along ``+b2`` (angle π/2), the paper's ``+Y`` normalisation
    (:meth:`~pinograsp.core.results.ResistanceProfile.index_along`)."""
    i = p.index_along(p.basis[1])
    if i is None:
        raise InvalidInputError(
            "normalize",
            f"profile {index} has no direction along +{p.plane[1]} (use n divisible by 4, or "
            "resistance_profile(..., normalize=True) which solves the reference direction)",
        )
    if p.unbounded[i] or not p.magnitudes[i] > 0:
        raise InvalidInputError(
            "normalize",
            f"profile {index} is {'unbounded' if p.unbounded[i] else 'not resisted'} along +{p.plane[1]}",
        )
    return float(p.magnitudes[i])


def _radii(
    profiles: list[ResistanceProfile], normalize: bool | float | None
) -> tuple[list[np.ndarray], bool]:
    """The radius per direction of every profile (``inf`` unbounded), and whether they are normalised."""
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
                scale = float(normalize)
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
    return radii, normalised[0]


# ----------------------------------------------------------------------------- geometry
def _plot_edge(radii: list[np.ndarray], rmax: float | None) -> float:
    """Radius of the plot edge: ``rmax``, or 1.15 × the largest finite radius (1 if none)."""
    finite = np.concatenate([r[np.isfinite(r)] for r in radii])
    if rmax is None:
        top = float(finite.max()) if finite.size and finite.max() > 0 else 1.0
        return 1.15 * top
    if not (np.isfinite(rmax) and rmax > 0):
        raise InvalidInputError("rmax", f"must be finite and > 0, got {rmax!r}")
    return rmax


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


def _sample_intervals(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each sorted angle's interval [rad] reaching halfway to its neighbours (circular): lo, hi."""
    prev = np.roll(a, 1)
    prev[0] -= 2 * np.pi
    nxt = np.roll(a, -1)
    nxt[-1] += 2 * np.pi
    lo = 0.5 * (a + prev) if a.size > 1 else a - np.pi
    hi = 0.5 * (a + nxt) if a.size > 1 else a + np.pi
    return lo, hi


#: ``gid`` of the markers of ``above_limit`` directions in a profile plot.
GID_ABOVE_LIMIT = "pinograsp-above-limit"
#: ``gid`` of the markers of failed directions (no verdict: the query raised) in a profile plot.
GID_FAILED = "pinograsp-failed"


def _run_middles(unbounded: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Angle [rad] at the middle of each circular run of unbounded samples."""
    return np.array(
        [
            np.mod(0.5 * (lo[i0] + hi[i1] + (2 * np.pi if i1 < i0 else 0.0)), 2 * np.pi)
            for i0, i1 in _circular_runs(unbounded)
        ]
    )


def _rlabel_angle(avoid: np.ndarray) -> float:
    """The ray (22.5° + k 45° [deg]) for the radial tick labels farthest from the angles ``avoid`` [rad]."""
    candidates = np.radians(22.5 + 45.0 * np.arange(8))
    if np.size(avoid) == 0:
        return 22.5
    gap = np.abs(np.angle(np.exp(1j * (candidates[:, None] - np.asarray(avoid, float)[None, :]))))
    return float(np.degrees(candidates[int(np.argmax(gap.min(axis=1) + 1e-9 * -np.arange(8)))]))


# ----------------------------------------------------------------------------- drawing
def _draw_unbounded(ax: Axes, a: np.ndarray, unb: np.ndarray, color: str, hatch: str, rmax: float) -> None:
    """Hatched wedges of the unbounded samples (sorted angles ``a``), one ∞ mark per run."""
    lo, hi = _sample_intervals(a)
    for k in np.flatnonzero(unb):
        ax.bar(
            0.5 * (lo[k] + hi[k]),
            rmax,
            width=hi[k] - lo[k],
            bottom=0.0,
            color=color,
            alpha=0.18,
            hatch=hatch,
            edgecolor=color,
            linewidth=0.0,
            gid=GID_UNBOUNDED,
            zorder=0.5,
        )
    mid = _run_middles(unb, lo, hi)
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
    wedges (``gid`` :data:`~pinograsp.viz.figures.GID_UNBOUNDED`) reaching the plot edge and
    marked with ``∞``; the finite magnitudes form a curve with points at the sampled directions
    (broken where the profile is unbounded). A magnitude of 0 (not resisted at all) is a point
    at the centre.

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
    ax = polar_axes(ax)
    plane = profiles[0].plane
    radii, normalised = _radii(profiles, normalize)
    unit = "normalised" if normalised else _plane_unit(plane, profiles[0].basis)
    rmax = _plot_edge(radii, rmax)
    if colors is not None and len(colors) < len(profiles):
        raise InvalidInputError("colors", f"expected {len(profiles)} colours, got {len(colors)}")

    from matplotlib.patches import Patch

    handles: list[Artist] = []
    any_unbounded = any_above = any_failed = False
    for i, (p, r, name) in enumerate(zip(profiles, radii, names)):
        color = colors[i] if colors is not None else f"C{i % 10}"
        a = np.mod(np.asarray(p.angles, dtype=float), 2 * np.pi)
        order = np.argsort(a)
        a, r = a[order], r[order]
        curve = np.where(np.isfinite(r), r, np.nan)
        closed_a, closed_r = np.append(a, a[0] + 2 * np.pi), np.append(curve, curve[0])
        (line,) = ax.plot(closed_a, closed_r, marker=".", color=color, lw=1.6, label=name)
        handles.append(line)
        # above_limit: resisted at ``upper`` (a lower bound, the limit lies beyond): a hollow
        # triangle at ``upper`` instead of a point that reads as a limit
        above = np.array([st == "above_limit" for st in p.statuses], bool)[order] if p.results else None
        if above is not None and above.any():
            ax.plot(
                a[above], r[above], ls="none", marker="^", ms=7, mfc="none", mec=color, gid=GID_ABOVE_LIMIT
            )
            any_above = True
        failed = np.isnan(r)  # no verdict (the direction's query raised): marked, never a wedge
        if failed.any():
            ax.plot(a[failed], np.full(int(failed.sum()), rmax), ls="none", marker="x", ms=8, mew=2,
                    color="crimson", gid=GID_FAILED, clip_on=False)  # fmt: skip
            any_failed = True
        unb = np.isinf(r)
        if unb.any():
            any_unbounded = True
            _draw_unbounded(ax, a, unb, color, _HATCHES[i % len(_HATCHES)], rmax)
    if any_unbounded:
        handles.append(Patch(facecolor="0.6", alpha=0.4, hatch="//", edgecolor="0.4", label="unbounded (∞)"))
    if any_above:
        from matplotlib.lines import Line2D

        handles.append(
            Line2D(
                [], [], ls="none", marker="^", mfc="none", mec="0.3", label="above upper (≥, a lower bound)"
            )
        )
    if any_failed:
        from matplotlib.lines import Line2D

        handles.append(
            Line2D([], [], ls="none", marker="x", mew=2, color="crimson", label="no verdict (failed)")
        )
    ax.set_ylim(0.0, rmax)
    b1, b2 = plane
    ax.set_thetagrids(
        np.arange(0, 360, 45),
        [f"+{b1}", "", f"+{b2}", "", f"−{b1}", "", f"−{b2}", ""],
    )
    # radial tick labels on the unlabelled grid ray farthest from every unbounded wedge
    unb_angles = np.concatenate([np.mod(p.angles, 2 * np.pi)[np.isinf(r)] for p, r in zip(profiles, radii)])
    ax.set_rlabel_position(_rlabel_angle(unb_angles))
    ax.grid(True, alpha=0.4)
    if title is None:
        title = f"max resistible wrench in the {b1}–{b2} plane [{unit}]"
    ax.set_title(title, fontsize=10, pad=14)
    ax.legend(handles=handles, loc="lower left", bbox_to_anchor=(-0.12, -0.14), fontsize=8, framealpha=0.9)
    return ax


__all__ = ["GID_ABOVE_LIMIT", "GID_FAILED", "MIXED_UNIT", "direction_unit", "plot_profile"]
