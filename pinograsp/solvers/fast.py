"""The mode-guess fast path: a fixed-mode ProxSuite QP first, the exact MIQP only when needed.

Consecutive solves of a bisection or an iteration almost always share their complementarity
mode (SOLVER_NOTES: the previous step's optimal mode stays optimal in 97–99 % of iteration
steps). :class:`ModeGuessSolver` therefore solves the convex QP of a *guessed* mode (the mode of
the previous accepted solution) and accepts it only when

1. ProxSuite converged within a small iteration cap with primal residual < 1e-7 (the guessed
   mode is feasible: a complementarity-satisfying point exists — for Alg. 1 this alone proves the
   wrench resistible), and
2. the point is a local optimum of the full complementarity problem
   (:meth:`FixedModeQP.check_local_optimality`): no biactive contact or actuator wants to
   switch (strong stationarity, or the relaxed QP over all switched modes is not better).

Otherwise it falls back to :class:`~pinograsp.solvers.engine.ExactSolver` (MIQP + polish) and
counts the fallback. Strong stationarity certifies a *local* optimum of the mixed-integer
problem; a guessed mode that is feasible and locally optimal but not globally optimal is the one
way the fast path can differ from the exact path, and ``benchmarks/error_vs_runtime.py``
measures how often and by how much.

This module never imports Pinocchio or Coal.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from .base import OPTIMAL, Mode, RawSolution
from .engine import ExactSolver
from .fixed_mode import FixedModeQP
from .formulation import ScaledData

#: ProxSuite iteration cap for a guessed mode (a feasible mode converges in ~10–30).
GUESS_MAX_ITER = 60
#: Largest wrong-signed multiplier accepted at a biactive pair (scaled units).
STATIONARITY_TOL = 1e-7
#: Rounds of mode descent (move to a better switched mode and re-check) before falling back.
DESCENT_ROUNDS = 3
#: Recently accepted modes (distinct) tried after the guess before falling back: trajectories
#: that cross a mode boundary often come back to a mode they had.
RECENT_MODES = 3


@dataclass
class FastStats:
    """Counters of the fast path (per solver, cumulative).

    Attributes:
        guesses: Solves that tried a guessed mode.
        accepted: Guesses accepted (feasible and strongly stationary).
        infeasible: Guesses whose QP did not converge (mode infeasible or too slow).
        not_stationary: Guesses rejected by the stationarity check.
        exact: Exact (MIQP) solves, with or without a guess before.
    """

    guesses: int = 0
    accepted: int = 0
    infeasible: int = 0
    not_stationary: int = 0
    exact: int = 0

    @property
    def fallbacks(self) -> int:
        """Guesses that failed and were answered by the MIQP."""
        return self.infeasible + self.not_stationary


class ModeGuessSolver:
    """Fast path for one problem kind of one model, with the exact solver as fallback.

    Args:
        exact: The exact solver of the same formulation and kind (used for fallbacks).
        qp: The fixed-mode QP of the same formulation and kind.
    """

    def __init__(self, exact: ExactSolver, qp: FixedModeQP) -> None:
        if exact.kind != qp.kind:
            raise ValueError("exact solver and fixed-mode QP must be of the same kind")
        self.exact, self.qp, self.kind = exact, qp, qp.kind
        self.stats = FastStats()
        self.recent: list[Mode] = []

    def try_guess(self, data: ScaledData, guess: Mode) -> tuple[RawSolution | None, float]:
        """The guessed mode's QP solution if it passes both checks (else None), and the time
        spent [s]."""
        st = self.stats
        st.guesses += 1
        sol = self.qp.solve(data, guess, max_iter=GUESS_MAX_ITER, precondition=False)
        if sol.status != OPTIMAL:
            st.infeasible += 1
            return None, sol.solve_time
        spent = sol.solve_time
        for _ in range(DESCENT_ROUNDS):
            ok, extra, better = self.qp.check_local_optimality(
                data, sol, dual_tol=STATIONARITY_TOL, precondition=False
            )
            spent += extra
            if ok:
                st.accepted += 1
                return replace(sol, backend="proxsuite", path="guess", solve_time=spent), spent
            if better is None:
                break
            sol = better  # a switched mode is better: continue the local search from there
        st.not_stationary += 1
        return None, spent

    def solve(self, data: ScaledData, guess: Mode | None = None) -> RawSolution:
        """Solve with ``guess`` first (if given), else / on failure exactly."""
        tried, spent = guess is not None, 0.0
        if tried:
            # Alg. 1 beyond its limit has no feasible mode at all: recent modes would only add
            # failing QPs before the MIQP, so they are tried for movement steps only
            others = [m for m in self.recent if m != guess][:RECENT_MODES] if self.kind == "move" else []
            for g in [guess] + others:
                sol, dt = self.try_guess(data, g)
                spent += dt
                if sol is not None:
                    self._remember(sol.mode)
                    return replace(sol, solve_time=spent)
        self.stats.exact += 1
        raw = self.exact.solve(data)
        if raw.status == OPTIMAL and raw.mode is not None:
            self._remember(raw.mode)
        return replace(raw, path="fallback" if tried else "miqp", solve_time=raw.solve_time + spent)

    def _remember(self, mode: Mode) -> None:
        if mode in self.recent:
            self.recent.remove(mode)
        self.recent.insert(0, mode)
        del self.recent[RECENT_MODES + 1 :]
