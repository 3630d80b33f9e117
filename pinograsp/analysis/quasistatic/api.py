"""The loading path of a prepared grasp: :func:`loading_path` (public) and :func:`run_path`
(what the method's answers run on a prepared grasp)."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ...core.axes import wrench_direction
from ...core.giveway import DEFAULT_CONTACT_STIFFNESS
from ...core.model import GraspModel
from ...core.settings import Settings
from ...core.validate import MAX_FORCE, MAX_PATH_SEGMENTS, count, load_within, number_in
from ...errors import InvalidInputError
from ...solvers.threads import single_threaded
from .continuation import continue_past_limit
from .geometry import GEOMETRY_MAX, GeometryUpdates
from .path import MAX_SEGMENTS, StageRun, follow
from .prepared import Prepared, checked_settings, path_of_variant, prepare
from .records import build_path, continuation_record
from .result import LoadingPath
from .state import StageSpec
from .statuses import RunStatus


@single_threaded
def loading_path(
    model: GraspModel,
    command: object,
    direction: object,
    *,
    variant: str | None = None,
    settings: Settings | None = None,
    max_segments: int = MAX_SEGMENTS,
    up_to: float | None = None,
    continuation: bool = True,
) -> LoadingPath:
    """Follow the equilibrium of the preloaded grasp as the load ``λ direction`` grows from 0
    (the quasi-static loading path, docs/methods.md).

    Args:
        model: The grasp.
        command: Actuator commands (as for :func:`pinograsp.passive_response`) [N·m or N].
        direction: Wrench direction: axis name (``"fy"``, ``"-mz"``) or vector (normalised).
        variant: Preload, in the variant vocabulary of every entry point: ``"preload-first"``
            (default, as the simulation's: object held, friction off while the commands ramp,
            then released; the path's name ``"held"``) or ``"settled-preload"`` (object free,
            friction on; ``"settled"``); None: ``Settings.variant``. ``"single-step"`` is
            refused, as by ``max_resistible_wrench(method="quasistatic")``.
        settings: :class:`~pinograsp.Settings`: ``tangential_ratio`` (tangential / normal
            contact stiffness, default 1) and ``normal_uncertainty`` apply.
        max_segments: Segment-count limit of each stage (a count in [1, 1e6]; status
            ``"segment_limit"``).
        up_to: Stop at this load [N or N·m] (status ``"reached"`` when the path gets there),
            in [0, 1e12] and within 1e6 times the grasp's force scale (docs/errors.md).
        continuation: At a softening limit, also follow the path past it to the snap's
            landing and on (:attr:`LoadingPath.continuation`).

    Returns:
        The :class:`LoadingPath`.

    Raises:
        PreloadNotInEquilibriumError: The preload path reaches a limit before its end.
        InvalidInputError: Bad model, command, direction, variant or settings.
    """
    t0 = time.perf_counter()
    s = checked_settings(settings)
    v = path_of_variant(variant, s)
    max_segments = count("max_segments", max_segments, MAX_PATH_SEGMENTS, what="each segment one LCP")
    if not isinstance(continuation, (bool, np.bool_)):  # "no" is truthy: docs/errors.md
        raise InvalidInputError("continuation", f"expected True or False, got {continuation!r}")
    p = prepare(model, command, s, v, int(max_segments))
    d6 = wrench_direction(model, direction)
    if up_to is not None:  # a load: the domains of every load (docs/errors.md, "Input domains")
        up_to = number_in("up_to", up_to, 0.0, MAX_FORCE, "N or N·m")
        load_within(model, model.command_vector(command), "up_to", up_to * d6)
    return run_path(p, d6, int(max_segments), up_to, continuation, t0, stiffness=s.contact_stiffness)


def unit_again(d6: np.ndarray) -> np.ndarray:
    """:func:`~pinograsp.core.axes.wrench_direction`'s arithmetic on a direction (6,) it has
    already validated and normalised (the same bits, without validating it again)."""
    d = d6 / float(np.abs(d6).max())
    return d / float(np.linalg.norm(d))


def run_path(
    p: Prepared,
    d6: np.ndarray,
    max_segments: int,
    up_to: float | None,
    continuation: bool,
    t0: float,
    lean: bool = False,
    until: float = float("inf"),
    stiffness: float = DEFAULT_CONTACT_STIFFNESS,
    reach: tuple[float, float] = (float("inf"), float("inf")),
) -> LoadingPath:
    """The load stage of a prepared grasp along the unit direction ``d6`` (6,) as a
    :class:`LoadingPath` (see :func:`loading_path`); ``lean``: without its events, stiffness
    and energy balance (see :func:`build_path`); ``until``: no geometry update above this load,
    ``stiffness``: the contact stiffness [N/m] at which the object turns, ``reach``: no update
    past this rotation [rad] and translation [m] of the object (the give-way thresholds)
    (``geometry.GeometryUpdates``)."""
    d_red = p.model.reduce_wrench(d6)
    t_end = float("inf") if up_to is None else float(up_to)
    spec = StageSpec(np.zeros(p.qm.nx), d_red, p.fc, np.zeros(p.qm.na), t_end, held=False, friction=True)
    geo = GeometryUpdates(
        scale=float(np.max(p.model.k)) / float(stiffness),
        until=until,
        max_rotation=min(GEOMETRY_MAX, reach[0]),
        max_translation=reach[1],
    )
    run = (
        follow(p.qm, p.start, spec, max_segments, geo)
        if t_end > 0
        else StageRun(states=[p.start.copy()], status=RunStatus.END)
    )
    cont = None
    if run.status == RunStatus.LIMIT and up_to is None and continuation:
        more = continue_past_limit(p.qm, run, spec, max_segments, geo)
        if more is not None:
            cont = continuation_record(p, d6, more, spec, lean)
    lp = build_path(p, d6, run, spec, time.perf_counter() - t0, lean)
    return replace(lp, continuation=cont) if cont is not None else lp


__all__ = ["loading_path", "run_path", "unit_again"]
