"""Analyses built on the passive response: max resistible wrench and resistance profiles."""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Callable, Sequence

import numpy as np

from ..core.audit import audit_message
from ..core.axes import WRENCH_AXES, circle_directions, plane_basis, wrench_direction
from ..core.model import GraspModel
from ..core.results import MaxWrench, PassiveResponse, ResistanceProfile
from ..core.settings import Search
from ..core.validate import choice, positive_number, whole_number
from ..errors import (
    AuditWarning,
    InvalidInputError,
    PreloadNotInEquilibriumError,
    SolverError,
    SolverTimeoutError,
)
from ..solvers.base import SolveStatus
from ..solvers.solve import single_threaded
from .response import METHODS, PassiveSolver, Settings, solver_for
from .search import bisection, secant


def _check(resp: PassiveResponse, magnitude: float) -> bool:
    if resp.status == "node_limit":
        raise SolverError(
            f"branch-and-bound node limit reached at magnitude {magnitude:.6g} (raise Settings.max_nodes)",
            solver=resp.solver,
            status="node_limit",
        )
    if resp.status == "timeout":
        raise SolverTimeoutError(
            f"solver timed out at magnitude {magnitude:.6g}", solver=resp.solver, status="timeout"
        )
    if resp.status == "failed":
        raise SolverError(
            f"solver failed at magnitude {magnitude:.6g} (no trustworthy verdict)",
            solver=resp.solver,
            status="failed",
        )
    return resp.resistible


def check_preload(solver: PassiveSolver, command: object, method: str) -> PassiveResponse:
    """Solve ``w = 0``; raise :class:`PreloadNotInEquilibriumError` if the preload alone has no
    passive equilibrium."""
    resp = solver.response(command, np.zeros(6), method)
    if not _check(resp, 0.0):
        detail = f"{method} solve at w = 0 returned {resp.status!r}"
        residual = None
        if np.all(np.isfinite(resp.net_wrench)):
            residual = resp.net_wrench
            shown = ", ".join(f"{a}={v:.3g}" for a, v in zip(WRENCH_AXES, residual) if abs(v) > 0)
            detail += f"; net wrench left on the object: {shown or '0'} [N, N·m]"
        elif resp.residual_history:
            detail += f" (net wrench {resp.residual_history[-1]:.3g} N)"
        raise PreloadNotInEquilibriumError(solver.model.command_vector(command).tolist(), detail, residual)
    return resp


@single_threaded
def max_resistible_wrench(
    model: GraspModel,
    command: object,
    direction: object,
    method: str = "iterative",
    upper: float = 1e3,
    steps: int = 20,
    *,
    settings: Settings | None = None,
    check_preload_first: bool = True,
    search: str = "auto",
    **overrides: object,
) -> MaxWrench:
    """Largest wrench magnitude along ``direction`` that the preloaded grasp resists passively.

    Bisection on ``[0, upper]`` (seed paper: 20 steps, upper 1e3 N). The preload alone is
    checked first (``w = 0``); a grasp whose preload is not in equilibrium raises
    :class:`PreloadNotInEquilibriumError` instead of "resisting 0 N". If ``upper`` itself is
    resisted the direction is reported ``unbounded`` with ``magnitude = inf``.

    Args:
        model: The grasp.
        command: Actuator commands (see :func:`pinograsp.passive_response`).
        direction: Wrench direction: axis name (``"fx"``, ``"-fy"``, ``"mz"``) or vector
            (normalised here).
        method: ``"iterative"`` (default; no wedging artefact) or ``"prp"``.
        upper: Upper limit of the search [N or N·m along the unit direction].
        steps: Bisection steps; resolution ``upper / 2**steps``.
        search: ``"auto"`` (default: ``"secant"`` for the iterative method, ``"bisection"``
            for the PRP), ``"bisection"`` (the paper's), ``"secant"`` (iterative only: the same
            grid cell as the bisection when resistibility is monotone along the ray, in fewer
            stages; :mod:`pinograsp.analysis.search`) or ``"direct"`` (PRP only): one complementarity
            problem maximising the load factor, exact instead of ``upper / 2**steps``; the
            response at the limit is then solved at ``magnitude * (1 - 1e-6)``.
        settings, overrides: Solver settings (see :class:`pinograsp.analysis.response.Settings`).

    Raises:
        PreloadNotInEquilibriumError, SolverTimeoutError, SolverError, InvalidInputError.
    """
    t0 = time.perf_counter()
    choice("method", method, METHODS)
    upper = positive_number("upper", upper)
    steps = whole_number("steps", steps)
    solver = solver_for(model, settings, **overrides)
    d = wrench_direction(model, direction)
    solve_time, n_solves = 0.0, 0
    if check_preload_first:
        pre = check_preload(solver, command, method)
        solve_time += pre.solve_time
        n_solves += pre.n_solves
    evidence: list[tuple[float, bool]] = []
    flagged: list[tuple[float, PassiveResponse]] = []  # resisted, but failing the audit

    def test(mag: float, by: PassiveSolver | None = None) -> tuple[bool, PassiveResponse]:
        """Verdict at ``mag`` (by this query's solver, or ``by`` another one), recorded."""
        nonlocal solve_time, n_solves
        with warnings.catch_warnings():  # summarised once, after the search
            warnings.simplefilter("ignore", AuditWarning)
            resp = (by or solver).response(command, mag * d, method)
        solve_time += resp.solve_time
        n_solves += resp.n_solves
        ok = _check(resp, mag)
        evidence.append((mag, ok))
        if ok and resp.audit is not None and not resp.audit.ok:
            flagged.append((mag, resp))
        return ok, resp

    search = Search(choice("search", search, [x.value for x in Search]))
    if search is Search.AUTO:
        search = Search.SECANT if method == "iterative" else Search.BISECTION
    if search is Search.DIRECT and method != "prp":
        raise InvalidInputError("search", "'direct' exists for method='prp' only (Alg. 3 is a trajectory)")
    if search is Search.SECANT and method != "iterative":
        raise InvalidInputError(
            "search", "'secant' exists for method='iterative' only (PRP stages carry no residual)"
        )

    floor = float(upper) / 2**steps  # smallest magnitude distinguishable from zero
    if method == "iterative":  # ... and the scheme's equilibrium tolerance along d
        floor = max(
            floor, solver.settings.eps / float(np.linalg.norm(model.reduce_wrench(d) * solver.form.wscale))
        )

    def result(magnitude: float, unbounded: bool, response: PassiveResponse | None) -> MaxWrench:
        if unbounded:  # resisted at upper: unbounded only if the model says so in the limit
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", AuditWarning)
                limit = _resisted_without_preload(solver, command, d, method)
            if limit.resistible and limit.audit is not None and not limit.audit.ok:
                flagged.append((float("inf"), limit))
            solve_time_add = limit.solve_time
            status = "unbounded" if limit.resistible else "above_limit"
            magnitude = float("inf") if limit.resistible else float(upper)
            unbounded = limit.resistible
        else:
            solve_time_add = 0.0
            status = "finite" if magnitude >= floor and magnitude > 0 else "below_resolution"
        failures = tuple(sorted(m for m, _ in flagged))
        if failures:
            at, bad = min(flagged, key=lambda mr: mr[0])
            e = bad.audit.energy
            why = (
                audit_message(method, e)
                if e is not None and not (e.energy_ok and e.displacement_ok)
                else "residuals above the audit tolerance"
            )
            warnings.warn(
                f"{len(failures)} resisted magnitude(s) from {at:.6g} rest on solutions that fail "
                f"the audit; at {at:.6g}: {why}",
                AuditWarning,
                stacklevel=4,
            )
        return MaxWrench(
            direction=d,
            magnitude=magnitude,
            unbounded=unbounded,
            status=status,
            floor=floor,
            upper=float(upper),
            resolution=float(upper) / 2**steps,
            evidence=tuple(evidence),
            method=method,
            solve_time=solve_time + solve_time_add,
            wall_time=time.perf_counter() - t0,
            n_solves=n_solves,
            response=response,
            search=search.value,
            audit_failures=failures,
        )

    if search is Search.DIRECT:
        # the upper limit first: an unbounded direction costs one (fast-path) solve, not a MILP
        ok, resp = test(float(upper))
        if ok:
            return result(float("inf"), True, resp)
        lf = solver.max_load_factor(command, d, float(upper))
        status, mag = lf.status, lf.magnitude
        solve_time += lf.solve_time
        n_solves += 1
        if status in (SolveStatus.TIMEOUT, SolveStatus.FAILED, SolveStatus.NODE_LIMIT):
            cls = SolverTimeoutError if status is SolveStatus.TIMEOUT else SolverError
            raise cls(
                f"load-factor problem: {status.value}", solver=solver.settings.backend, status=status.value
            )
        if status is not SolveStatus.OPTIMAL:
            raise PreloadNotInEquilibriumError(
                model.command_vector(command).tolist(), "load-factor problem infeasible"
            )
        if np.isinf(mag):
            raise SolverError(
                f"load-factor problem reached the upper limit {upper:g} that the PRP did not resist",
                solver=solver.settings.backend,
                status="failed",
            )
        at = mag * (1.0 - 1e-6)
        ok, resp = test(at)
        if not ok:
            raise SolverError(
                f"load-factor problem found magnitude {mag:.9g} but the PRP at {at:.9g} is not resisted",
                solver=solver.settings.backend,
                status="failed",
            )
        return result(mag, bool(np.isinf(mag)), resp)

    ok, resp = test(float(upper))
    if ok:
        return result(float("inf"), True, resp)
    if search is Search.SECANT:
        st = solver.settings
        lo, best = secant(test, float(upper), int(steps), resp, lambda m: st.eps + st.eps_rel * m)
    else:
        lo, best = bisection(test, float(upper), int(steps))
    return result(lo, False, best)


def _resisted_without_preload(
    solver: PassiveSolver, command: object, d: np.ndarray, method: str
) -> PassiveResponse:
    """The load ``d`` (unit) under a zero preload: the limit of ``t d`` under ``command`` as
    ``t -> inf`` (the model is positively homogeneous: ``t d`` under ``f_c`` is ``d`` under
    ``f_c / t``). Resisted means passively resisted without bound (docs/accuracy.md)."""
    zero = np.zeros(solver.model.na)
    resp = solver.response(zero, d, method)
    _check(resp, float("inf"))
    return resp


def _worker_count(workers: int | None, n: int) -> int:
    if workers is None:
        return 1
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 0:
        raise InvalidInputError("workers", f"must be an integer >= 0, got {workers!r}")
    w = int(workers) or (os.cpu_count() or 1)
    return max(1, min(w, n))


#: A direction whose query raised a :class:`~pinograsp.errors.SolverError` (``run_directions``
#: with ``catch=True``): ``(index, message, status)``.
DirectionFailure = tuple[int, str, str]


def _directions_block(
    args: tuple[GraspModel, object, np.ndarray, str, float, int, Settings, str, bool],
) -> list[MaxWrench | tuple[str, str]]:
    """Worker: max resistible wrench along each of a block of directions (with ``catch``, a
    direction whose query raises a SolverError gives ``(message, status)`` instead)."""
    model, command, dirs, method, upper, steps, settings, search, catch = args
    out: list[MaxWrench | tuple[str, str]] = []
    for d in dirs:
        try:
            out.append(
                max_resistible_wrench(
                    model,
                    command,
                    d,
                    method,
                    upper,
                    steps,
                    settings=settings,
                    check_preload_first=False,
                    search=search,
                )
            )
        except SolverError as exc:
            if not catch:
                raise
            out.append((" ".join(str(exc).split()), str(exc.status or "failed")))
    return out


def _parallel_directions(
    model: GraspModel,
    command: object,
    dirs: np.ndarray,
    method: str,
    upper: float,
    steps: int,
    settings: Settings,
    workers: int,
    progress: Callable[[int, int], None] | None,
    search: str = "bisection",
    catch: bool = False,
) -> list[MaxWrench | tuple[str, str]]:
    """Directions in a process pool, in contiguous blocks (warm starts within a block)."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    nblocks = min(len(dirs), 4 * workers)
    blocks = [b for b in np.array_split(np.arange(len(dirs)), nblocks) if len(b)]
    ctx = mp.get_context("fork" if "fork" in mp.get_all_start_methods() else "spawn")
    out: list[MaxWrench | tuple[str, str] | None] = [None] * len(dirs)
    done = 0
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
        futures = {
            pool.submit(
                _directions_block, (model, command, dirs[b], method, upper, steps, settings, search, catch)
            ): b
            for b in blocks
        }
        for fut in as_completed(futures):
            b = futures[fut]
            for i, r in zip(b, fut.result()):
                out[i] = r
            done += len(b)
            if progress is not None:
                progress(done, len(dirs))
    return out  # type: ignore[return-value]


def run_directions(
    model: GraspModel,
    command: object,
    dirs: np.ndarray,
    method: str,
    upper: float,
    steps: int,
    settings: Settings,
    *,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    search: str = "auto",
    catch: bool = False,
) -> tuple[list[MaxWrench | None], list[DirectionFailure]]:
    """Max resistible wrench along many directions: the machinery of :func:`resistance_profile`
    and :func:`pinograsp.resistance_set` (the preload is *not* checked here).

    Args:
        dirs: Wrench directions, (k, 6) (each normalised by :func:`max_resistible_wrench`).
        workers: Process-pool size (``0``: one per CPU; ``None``/``1``: in this process).
        catch: Record a direction whose query raises a :class:`SolverError` as a failure
            (its result is ``None``) instead of raising.
        Other arguments: as :func:`max_resistible_wrench`.

    Returns:
        ``(results, failures)``: one :class:`MaxWrench` (or ``None`` for a failure) per
        direction, in order, and the failures as ``(index, message, status)``.
    """
    nw = _worker_count(workers, len(dirs))
    if nw > 1:
        raw = _parallel_directions(
            model, command, dirs, method, upper, steps, settings, nw, progress, search, catch
        )
    else:
        raw = []
        for i, d in enumerate(dirs):
            raw += _directions_block(
                (model, command, d[None, :], method, upper, steps, settings, search, catch)
            )
            if progress is not None:
                progress(i + 1, len(dirs))
    results = [r if isinstance(r, MaxWrench) else None for r in raw]
    failures = [(i, r[0], r[1]) for i, r in enumerate(raw) if not isinstance(r, MaxWrench)]
    return results, failures


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
            ``"fy"``). A reference direction that is unbounded raises ``InvalidInputError``.
        progress: Called as ``progress(done, total)`` after each direction (after each chunk
            of directions with ``workers``).
        workers: Solve directions in a process pool of this many workers (``0``: one per CPU;
            ``None``/``1``: in this process). Each worker takes a contiguous block of
            directions, so neighbouring directions still warm-start each other.
        Other arguments: as :func:`max_resistible_wrench`.
    """
    t0 = time.perf_counter()
    n = whole_number("n", n)
    basis, labels = plane_basis(model, plane)
    solver = solver_for(model, settings, **overrides)
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
    mags = np.array([r.magnitude for r in results])
    unb = np.array([r.unbounded for r in results])
    norm_by = None
    if normalize:
        ref = basis[1] if normalize is True else wrench_direction(model, normalize, "normalize")
        hit = [r for r, d in zip(results, dirs) if np.allclose(d, ref, atol=1e-12)]
        ref_res = (
            hit[0]
            if hit
            else max_resistible_wrench(
                model, command, ref, method, upper, steps, settings=solver.settings, check_preload_first=False
            )
        )
        if ref_res.unbounded or not ref_res.magnitude > 0:
            raise InvalidInputError(
                "normalize",
                f"the reference direction is {'unbounded' if ref_res.unbounded else 'not resisted'}",
            )
        norm_by = ref_res.magnitude
        mags = mags / norm_by
    return ResistanceProfile(
        plane=labels,
        basis=basis,
        angles=angles,
        directions=dirs,
        magnitudes=mags,
        unbounded=unb,
        normalized_by=norm_by,
        results=tuple(results),
        wall_time=time.perf_counter() - t0,
    )
