"""Resistance profiles: the max resistible magnitude over directions in a plane of wrench
space, as in the seed paper's polar plots, and the one home of their normalisation. A
direction whose query raises a :class:`~pinograsp.SolverError` (a node limit, a timeout) is
recorded as ``"failed"`` with its message (``ResistanceProfile.failures``); the others are kept.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..core.axes import circle_directions, plane_basis, wrench_direction
from ..core.model import GraspModel
from ..core.query import Query, make_query
from ..core.results import MaxWrench, ResistanceProfile
from ..core.settings import DEFAULT_METHOD, Settings
from ..core.validate import directions
from ..solvers.threads import single_threaded
from .directions import run_directions
from .max_wrench import check_preload, max_wrench_on, query_within
from .registry import get_method, resolve_search
from .response import Session, session_for


def reference_magnitude(
    model: GraspModel,
    command: object,
    profile: ResistanceProfile,
    reference: object,
    method: str,
    upper: float,
    steps: int,
    settings: Settings,
) -> float:
    """The magnitude [N or N·m] a profile is normalised by: its max resistible magnitude along
    ``reference``.

    Args:
        model, command: The grasp and its commands, as the profile was solved.
        profile: The (absolute) profile.
        reference: ``True``: the profile's second spanning direction ``+b2`` (the paper's
            ``+Y`` for the XY plane); else an axis name (``"fy"``) or a wrench vector.
        method, upper, steps, settings: As the profile was solved; used only when the
            reference is not among the profile's directions
            (:meth:`~pinograsp.core.results.ResistanceProfile.result_along`), which is then
            solved on its own (the preload is not checked again).

    Raises:
        InvalidInputError: ``"normalize"``: the reference direction is unbounded or not
            resisted, or not a direction.
    """
    session = session_for(model, None, settings, {})
    q = make_query(None, method, upper, steps)
    return _reference(session, session.model.command_vector(command), profile, reference, q)


def _reference(
    session: Session, fc: np.ndarray, profile: ResistanceProfile, reference: object, query: Query
) -> float:
    """:func:`reference_magnitude` on a session with validated commands ``fc`` (na,)."""
    model = session.source
    ref = profile.basis[1] if reference is True else wrench_direction(model, reference, "normalize")
    hit = profile.result_along(ref)
    if hit is None:
        hit = max_wrench_on(session, fc, wrench_direction(model, ref), query, check_preload_first=False)
    return hit.as_reference("normalize")


def _failed(model: GraspModel, direction: np.ndarray, query: Query) -> MaxWrench:
    """The record of a direction whose query raised: status ``"failed"``, magnitude NaN."""
    search = resolve_search(query.search, get_method(query.method))
    nan = float("nan")
    return MaxWrench(
        direction=wrench_direction(model, direction),
        magnitude=nan,
        unbounded=False,
        status="failed",
        floor=nan,
        upper=query.upper,
        resolution=query.resolution,
        evidence=(),
        method=str(query.method),
        solve_time=0.0,
        wall_time=0.0,
        n_solves=0,
        search=search.value,
    )


@single_threaded
def resistance_profile(
    model: GraspModel,
    command: object,
    plane: Sequence[object] = ("fx", "fy"),
    n: int = 72,
    method: str = DEFAULT_METHOD,
    upper: float = 1e3,
    steps: int = 20,
    *,
    normalize: bool | str | None = None,
    settings: Settings | None = None,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
    search: str = "auto",
    session: Session | None = None,
    query: Query | None = None,
    **overrides: object,
) -> ResistanceProfile:
    """Max resistible magnitude over ``n`` directions in a plane of wrench space.

    Directions are ``cos(a) b1 + sin(a) b2`` for ``a = 2πi/n`` with ``(b1, b2)`` the plane's
    spanning directions (axis names like ``("fx", "fy")``, ``("fx", "fz")``, ``("mx", "my")``,
    or any two wrench vectors, orthonormalised).

    Args:
        normalize: Divide magnitudes by the value along a reference direction, as the paper
            does (``True``: along ``+b2``, i.e. ``+Y`` for the XY plane; or an axis name like
            ``"fy"``, or a vector; :func:`reference_magnitude`). A reference direction that is
            unbounded, not resisted or failed raises ``InvalidInputError``.
        progress: Called as ``progress(done, total)`` after each direction (after each chunk
            of directions with ``workers``).
        workers: Solve directions in a process pool of this many workers (``0``: one per CPU;
            ``None``/``1``: in this process, on one session). Each worker takes a contiguous
            block of directions on one session of its own (the preload stage solved once).
        session: A :class:`~pinograsp.Session` of ``model`` the caller owns (its settings
            rule): the directions solved in this process share its preload stages.
        query: A :class:`~pinograsp.Query` instead of ``method``, ``upper``, ``steps``,
            ``search``.
        Other arguments: as :func:`max_resistible_wrench`.

    Returns:
        A :class:`~pinograsp.ResistanceProfile`; a direction whose query raised a
        :class:`~pinograsp.SolverError` has a result of status ``"failed"`` (magnitude NaN, no
        evidence) and its ``(index, message, status)`` in ``failures``.
    """
    t0 = time.perf_counter()
    q = make_query(query, method, upper, steps, search)
    n = directions(n)
    basis, labels = plane_basis(model, plane)
    solver = session_for(model, session, settings, overrides)
    fc = query_within(solver, command, q, eps=False)  # before any work (docs/errors.md)
    check_preload(solver, fc, str(q.method))
    angles, dirs = circle_directions(basis, n)
    found, failures = run_directions(solver, fc, dirs, q, workers=workers, progress=progress, catch=True)
    results = [_failed(model, d, q) if r is None else r for r, d in zip(found, dirs)]
    profile = ResistanceProfile(
        plane=labels,
        basis=basis,
        angles=angles,
        directions=dirs,
        magnitudes=np.array([r.magnitude for r in results]),
        unbounded=np.array([r.unbounded for r in results]),
        normalized_by=None,
        results=tuple(results),
        failures=tuple(failures),
    )
    if normalize:
        by = _reference(solver, fc, profile, normalize, q)
        profile = replace(profile, magnitudes=profile.magnitudes / by, normalized_by=by)
    return replace(profile, wall_time=time.perf_counter() - t0)


__all__ = ["reference_magnitude", "resistance_profile"]
