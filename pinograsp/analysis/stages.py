"""The stages of a passive response, in scaled coordinates (docs/solvers.md).

A *stage* is one solve of the grasp from a given state: the preload alone (``w = 0``) or the
load on top of a pre-compression ``p``. Two kinds:

* :func:`prp_stage` — seed Alg. 1: one mixed-integer problem (:attr:`ProblemKind.PRP`);
* :func:`iterative_stage` — seed Alg. 2 inside Alg. 3: movement-constrained steps
  (:attr:`ProblemKind.MOVE`) along the current net wrench until it falls below the tolerance
  (resisted) or stops improving (not resisted), with the subspace :func:`jump` of
  ``Settings.accelerate`` in slow valleys.

:mod:`pinograsp.analysis.staged` chains the stages of a variant and
:mod:`pinograsp.analysis.assemble` turns them into a
:class:`~pinograsp.core.results.PassiveResponse`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..core.results import ResponseStatus
from ..solvers.base import INFEASIBLE, OPTIMAL, Mode, RawSolution, SolveStatus
from ..solvers.formulation import ScaledData
from ..solvers.problem import INF, ProblemKind, build_problem
from .context import SolveContext

#: Subspace jump of the iterative scheme: tried after this many real steps in one mode ...
JUMP_AFTER = 3
#: ... when the last step shrank the net wrench by less than this factor (slow convergence).
JUMP_RATIO = 0.5


@dataclass(frozen=True, eq=False)
class Stage:
    """One solved stage in scaled coordinates.

    Attributes:
        raw: The solution kept (the last real step of a trajectory); None when nothing solved.
        data: The scaled data of that solution.
        xh: Scaled object displacement of the stage's solution (the increment over the state
            the stage started from), (nx,).
        status: ``"resisted"``, ``"not_resisted"``, ``"not_converged"`` or a solver status.
        converged: The stage reached an equilibrium.
        iterations: Steps kept in ``history`` (1 for the PRP).
        history: Net-wrench norm after each step [N] (empty for the PRP).
        solve_time: Wall time of the solver calls [s].
        n_solves: Complementarity problems solved (steps and jumps).
    """

    raw: RawSolution | None
    data: ScaledData
    xh: np.ndarray
    status: ResponseStatus
    converged: bool
    iterations: int
    history: tuple[float, ...]
    solve_time: float
    n_solves: int


def _failed_status(raw: RawSolution) -> ResponseStatus:
    """The verdict of a solve without an optimum (infeasible: the load is not resisted)."""
    verdicts: dict[SolveStatus, ResponseStatus] = {
        INFEASIBLE: "not_resisted",
        SolveStatus.TIMEOUT: "timeout",
        SolveStatus.NODE_LIMIT: "node_limit",
    }
    return verdicts.get(raw.status, "failed")


def prp_stage(
    solver: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, kind: ProblemKind = ProblemKind.PRP
) -> Stage:
    """Alg. 1 for the (reduced) wrench ``w`` [N, N·m], commands ``fc`` (na,) and
    pre-compression ``p`` (nc,) [N]; ``kind=ProblemKind.ENERGETIC`` adds slip and maximum
    dissipation (the energetic method)."""
    form = solver.form
    data = form.scale_data(w, fc, p)
    raw = solver.solve(kind, data)
    ok = raw.status == OPTIMAL
    xh = raw.z[form.layout(kind).obj] if ok and raw.z is not None else np.zeros(form.nx)
    status = "resisted" if ok else _failed_status(raw)
    return Stage(raw, data, xh, status, ok, 1, (), raw.solve_time, 1)


def iterative_stage(
    solver: SolveContext, w: np.ndarray, fc: np.ndarray, p: np.ndarray, start: Mode | None = None
) -> Stage:
    """Alg. 3 from the (pre)loaded state (arguments as :func:`prp_stage`); ``start`` is the mode
    the grasp is in before the first step (the preload's), the first step's incumbent."""
    s = solver.settings
    f = solver.form
    lay = f.layout(ProblemKind.MOVE)
    base = f.scale_data(w, fc, p)
    tol = s.eps + s.eps_rel * base.F
    xh = np.zeros(f.nx)
    direction = np.zeros(f.nx)
    history: list[float] = []
    total, n = 0.0, 0
    status: ResponseStatus = "not_converged"
    converged, raw_best = False, None
    prev, guess = None, start
    streak: list[np.ndarray] = []  # net wrenches of the current mode's real steps
    for _ in range(int(s.max_iterations)):
        data = ScaledData(base.F, base.w, base.fc, base.p, xh, direction)
        raw = solver.solve(ProblemKind.MOVE, data, guess)
        total += raw.solve_time
        n += 1
        if raw.status != OPTIMAL or raw.z is None or raw.mode is None:
            status = _failed_status(raw)
            break
        if raw.mode != guess:
            streak = []
        guess = raw.mode
        r = base.w + f.Gb @ raw.z[lay.beta]
        norm = float(np.linalg.norm(r) * base.F)
        history.append(norm)
        xh_next = xh + raw.z[lay.obj][0] * direction
        raw_best = (raw, xh_next, data)
        if norm <= tol:
            status, converged = "resisted", True
            break
        if prev is not None and prev - norm < s.improvement * prev:
            status = "not_resisted"
            break
        streak.append(r)
        if s.accelerate and prev is not None and norm > JUMP_RATIO * prev and len(streak) >= JUMP_AFTER:
            x_jump, r_jump, dt = jump(solver, base, xh_next, streak, raw.mode)
            total += dt
            n += 1
            if x_jump is not None and np.linalg.norm(r_jump) * base.F < (1.0 - s.improvement) * norm:
                xh_next, r = x_jump, r_jump
                streak = []
        prev = norm
        xh, direction = xh_next, r
    if raw_best is None:
        return Stage(None, base, xh, status, False, n, tuple(history), total, n)
    raw, xh_sol, data = raw_best
    return Stage(raw, data, xh_sol, status, converged, len(history), tuple(history), total, n)


def jump(
    solver: SolveContext, base: ScaledData, xh: np.ndarray, streak: list[np.ndarray], mode: Mode
) -> tuple[np.ndarray | None, np.ndarray, float]:
    """Subspace jump of the iterative scheme (``Settings.accelerate``, docs/solvers.md).

    In a mode that has held for several slow steps, the object moves to the best point of
    ``x + D a`` (``a >= 0``, ``D`` the mode's recent net wrenches, unit length): where the
    step-by-step scheme would creep along a narrow valley. Returns the new displacement,
    the net wrench there (None, ... when the mode admits no such point) and the time [s].
    """
    f = solver.form
    recent = streak[-min(len(streak), f.nx) :]
    D = np.column_stack([v / np.linalg.norm(v) for v in recent])
    data = ScaledData(base.F, base.w, base.fc, base.p, xh, D)
    t0 = time.perf_counter()
    problem = build_problem(f, ProblemKind.MOVE, data, INF)
    sol = solver.solve_fixed_mode(problem, mode)
    dt = time.perf_counter() - t0
    if sol.status != OPTIMAL or sol.z is None:
        return None, np.zeros(f.nx), dt
    a = problem.step_lengths(sol.z)
    r = base.w + f.Gb @ sol.z[f.layout(ProblemKind.MOVE).beta]
    return xh + D @ a, r, dt
