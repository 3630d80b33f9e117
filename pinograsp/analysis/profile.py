"""Resistance profiles: the max resistible magnitude over directions in a plane of wrench
space, as in the seed paper's polar plots, and the one home of their normalisation."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..core.axes import circle_directions, plane_basis, wrench_direction
from ..core.model import GraspModel
from ..core.results import ResistanceProfile
from ..core.settings import METHODS, Settings
from ..core.validate import choice, directions, search_bounds
from ..solvers.solve import single_threaded
from .directions import run_directions
from .max_wrench import check_preload, max_resistible_wrench
from .response import solver_for


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
    ref = profile.basis[1] if reference is True else wrench_direction(model, reference, "normalize")
    hit = profile.result_along(ref)
    if hit is None:
        hit = max_resistible_wrench(
            model, command, ref, method, upper, steps, settings=settings, check_preload_first=False
        )
    return hit.as_reference("normalize")


@single_threaded
def resistance_profile(
    model: GraspModel,
    command: object,
    plane: Sequence[object] = ("fx", "fy"),
    n: int = 72,
    method: str = "iterative",
    upper: float = 1e3,
    steps: int = 20,
    *,
    normalize: bool | str | None = None,
    settings: Settings | None = None,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
    search: str = "auto",
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
            unbounded or not resisted raises ``InvalidInputError``.
        progress: Called as ``progress(done, total)`` after each direction (after each chunk
            of directions with ``workers``).
        workers: Solve directions in a process pool of this many workers (``0``: one per CPU;
            ``None``/``1``: in this process). Each worker takes a contiguous block of
            directions, so neighbouring directions still warm-start each other.
        Other arguments: as :func:`max_resistible_wrench`.
    """
    t0 = time.perf_counter()
    n = directions(n)
    basis, labels = plane_basis(model, plane)
    solver = solver_for(model, settings, **overrides)
    search_bounds(model, command, upper, steps)  # before any work (docs/errors.md)
    check_preload(solver, command, choice("method", method, METHODS))
    angles, dirs = circle_directions(basis, n)
    results, _ = run_directions(
        model,
        command,
        dirs,
        method,
        upper,
        steps,
        solver.settings,
        workers=workers,
        progress=progress,
        search=search,
    )
    profile = ResistanceProfile(
        plane=labels,
        basis=basis,
        angles=angles,
        directions=dirs,
        magnitudes=np.array([r.magnitude for r in results]),
        unbounded=np.array([r.unbounded for r in results]),
        normalized_by=None,
        results=tuple(results),
    )
    if normalize:
        by = reference_magnitude(model, command, profile, normalize, method, upper, steps, solver.settings)
        profile = replace(profile, magnitudes=profile.magnitudes / by, normalized_by=by)
    return replace(profile, wall_time=time.perf_counter() - t0)


__all__ = ["reference_magnitude", "resistance_profile"]
