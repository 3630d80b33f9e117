"""Max resistible wrench along many directions, in this process or a process pool: the
machinery of :func:`~pinograsp.analysis.profile.resistance_profile` and
:func:`~pinograsp.analysis.resistance_set.resistance_set` (docs/metrics.md).

Each block of directions runs on one session (:class:`~pinograsp.Session`): the caller's in
this process, a new one per block in a pool's worker, so the preload stage is solved once per
block. The commands, the query and the settings are validated once, before any block."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..core.axes import wrench_direction
from ..core.model import GraspModel
from ..core.processes import die_with_parent
from ..core.query import Query
from ..core.results import MaxWrench
from ..core.settings import Settings
from ..errors import InvalidInputError, SolverError
from .max_wrench import max_wrench_on
from .response import Session

#: A direction whose query raised a :class:`~pinograsp.errors.SolverError` (``run_directions``
#: with ``catch=True``): ``(index, message, status)``.
DirectionFailure = tuple[int, str, str]


def _worker_count(workers: int | None, n: int) -> int:
    """Processes for ``n`` directions (``workers``: ``0`` one per CPU, ``None`` this process)."""
    if workers is None:
        return 1
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 0:
        raise InvalidInputError("workers", f"must be an integer >= 0, got {workers!r}")
    w = int(workers) or (os.cpu_count() or 1)
    return max(1, min(w, n))


@dataclass(frozen=True)
class _Job:
    """What every direction of one run shares (sent to the pool's workers): the grasp, its
    validated commands (na,), the query, the validated settings and whether a
    :class:`SolverError` of one direction is recorded instead of raised."""

    model: GraspModel
    command: np.ndarray
    query: Query
    settings: Settings
    catch: bool


#: One direction's outcome in a block: its result, or ``(message, status)`` of its failure.
Outcome = MaxWrench | tuple[str, str]


def _directions_block(job: _Job, dirs: np.ndarray, session: Session | None = None) -> list[Outcome]:
    """Worker: max resistible wrench along each of a block of directions (k, 6) on one session
    (``session``, or a new one of the job's settings); with ``catch``, a direction whose query
    raises a SolverError gives ``(message, status)``."""
    session = session or Session(job.model, job.settings)
    out: list[Outcome] = []
    for d in dirs:
        try:
            u = wrench_direction(job.model, d)
            out.append(max_wrench_on(session, job.command, u, job.query, check_preload_first=False))
        except SolverError as exc:
            if not job.catch:
                raise
            out.append((" ".join(str(exc).split()), str(exc.status or "failed")))
    return out


def _parallel_directions(
    job: _Job, dirs: np.ndarray, workers: int, progress: Callable[[int, int], None] | None
) -> list[Outcome]:
    """Directions in a process pool, in contiguous blocks (one session per block)."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    nblocks = min(len(dirs), 4 * workers)
    blocks = [b for b in np.array_split(np.arange(len(dirs)), nblocks) if len(b)]
    ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    out: list[Outcome | None] = [None] * len(dirs)
    done = 0
    with ProcessPoolExecutor(workers, ctx, die_with_parent, (os.getpid(),)) as pool:  # no orphans
        futures = {pool.submit(_directions_block, job, dirs[b]): b for b in blocks}
        for fut in as_completed(futures):
            b = futures[fut]
            for i, r in zip(b, fut.result()):
                out[i] = r
            done += len(b)
            if progress is not None:
                progress(done, len(dirs))
    return out  # type: ignore[return-value]


def run_directions(
    session: Session,
    command: np.ndarray,
    dirs: np.ndarray,
    query: Query,
    *,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    catch: bool = False,
) -> tuple[list[MaxWrench | None], list[DirectionFailure]]:
    """Max resistible wrench along many directions: the machinery of
    :func:`~pinograsp.analysis.profile.resistance_profile` and :func:`pinograsp.resistance_set`
    (the preload is *not* checked here).

    Args:
        session: The session of the grasp (used for every direction in this process; a pool's
            workers build one of its model and settings per block).
        command: Validated actuator commands (na,).
        dirs: Wrench directions, (k, 6) (each normalised here).
        query: Method, upper limit, steps and search of every direction.
        workers: Process-pool size (``0``: one per CPU; ``None``/``1``: in this process).
        catch: Record a direction whose query raises a :class:`SolverError` as a failure
            (its result is ``None``) instead of raising.

    Returns:
        ``(results, failures)``: one :class:`MaxWrench` (or ``None`` for a failure) per
        direction, in order, and the failures as ``(index, message, status)``.
    """
    nw = _worker_count(workers, len(dirs))
    job = _Job(session.source, np.asarray(command, float), query, session.settings, catch)
    if nw > 1:
        raw = _parallel_directions(job, dirs, nw, progress)
    else:
        raw = []
        for i, d in enumerate(dirs):
            raw += _directions_block(job, d[None, :], session)
            if progress is not None:
                progress(i + 1, len(dirs))
    results = [r if isinstance(r, MaxWrench) else None for r in raw]
    failures = [(i, r[0], r[1]) for i, r in enumerate(raw) if not isinstance(r, MaxWrench)]
    return results, failures


__all__ = ["DirectionFailure", "run_directions"]
