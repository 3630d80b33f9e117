"""The backends that answer a complementarity problem, and their registry (docs/solvers.md).

Every solve of pinograsp — a stage, an iterative step, a subspace jump, a load factor, an
optimal-preload program — is one :class:`~pinograsp.solvers.problem.Problem` handed to the
:class:`SolverBackend` that ``Settings.backend`` names, through one caller: the session
(:meth:`pinograsp.analysis.response.Session.solve`). A backend is a small object with a
name, whether it is installed, what it can do (:class:`Capabilities`), and two calls: solve a
problem (the global optimum) and solve it in a fixed mode (one convex QP).

* ``"bnb"`` (default, :class:`BranchAndBoundBackend`): pinograsp's exact branch-and-bound
  (:mod:`.bnb`), deterministic, no time limits, canonical (least-norm) optimum; the only holder
  of the node limit (``Settings.max_nodes``).
* ``"miqp"`` (:class:`MiqpBackend`): the reference mixed-integer QP through cvxpy (:mod:`.miqp`;
  SCIP, or Gurobi when installed), with big-M audit and enlargement; its mode is then re-solved
  exactly by the same fixed-mode QP as the branch-and-bound, so both backends report points of
  the same kind.

A new backend is one class with this shape and one row of :data:`BACKENDS` (plus its name in
:class:`~pinograsp.core.settings.Backend`); see docs/design.md, "Adding a backend".
"""

from __future__ import annotations

import importlib.util
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Protocol

from ..core.settings import Settings
from ..errors import BigMWarning, SolverNotAvailableError, UnknownChoiceError
from .base import OPTIMAL, Mode, RawSolution
from .bnb import BranchAndBound
from .formulation import Formulation
from .problem import Problem
from .threads import single_threaded, single_threaded_blas  # noqa: F401  (their old home)

if TYPE_CHECKING:
    from .miqp import CvxpyMIQP

#: A solution whose big-M-bounded quantities reach this fraction of M is re-solved with a
#: larger M (the bound may be cutting off the true optimum).
BIGM_TRIGGER = 0.1


@dataclass(frozen=True)
class Capabilities:
    """What a backend offers.

    Attributes:
        exact: Proves global optimality of the complementarity problem (within its node limit).
        deterministic: The same problem gives the same bits on every machine.
        node_limit: Honours ``Settings.max_nodes`` (a count).
        time_limit: Honours ``Settings.time_limit`` (wall clock: answers may depend on the
            machine's speed).
        guess: Uses an incumbent mode to speed up a search.
    """

    exact: bool
    deterministic: bool
    node_limit: bool
    time_limit: bool
    guess: bool


class SolverBackend(Protocol):
    """A backend: a name, whether it is installed, what it can do, and two solves."""

    name: str
    capabilities: Capabilities

    def is_installed(self) -> bool:
        """Whether the packages it needs are importable."""
        ...

    def solve(self, problem: Problem, guess: Mode | None = None) -> RawSolution:
        """The global optimum of ``problem`` (``guess``: an incumbent mode, speed only)."""
        ...

    def solve_fixed_mode(self, problem: Problem, mode: Mode) -> RawSolution:
        """The canonical optimum of ``problem`` with every pair fixed by ``mode`` (a QP)."""
        ...


class BranchAndBoundBackend:
    """pinograsp's exact, deterministic branch-and-bound over the complementarity pairs."""

    name = "bnb"
    capabilities = Capabilities(exact=True, deterministic=True, node_limit=True, time_limit=False, guess=True)

    def __init__(self, settings: Settings, form: Formulation) -> None:
        self.settings = settings

    def is_installed(self) -> bool:
        """Always (NumPy and DAQP are dependencies of pinograsp)."""
        return True

    def solve(self, problem: Problem, guess: Mode | None = None) -> RawSolution:
        """The canonical global optimum, within ``Settings.max_nodes`` nodes."""
        return BranchAndBound(problem, int(self.settings.max_nodes)).solve(guess)

    def solve_fixed_mode(self, problem: Problem, mode: Mode) -> RawSolution:
        """The canonical optimum of one mode (one QP; no node limit applies)."""
        return BranchAndBound(problem, int(self.settings.max_nodes)).solve_mode(mode)


class MiqpBackend:
    """The reference mixed-integer QP through cvxpy, polished by the exact fixed-mode QP."""

    name = "miqp"
    capabilities = Capabilities(
        exact=True, deterministic=False, node_limit=False, time_limit=True, guess=False
    )

    def __init__(self, settings: Settings, form: Formulation) -> None:
        self.settings = settings
        self.form = form
        self._cache: dict[str, CvxpyMIQP] = {}

    def is_installed(self) -> bool:
        """Whether cvxpy is importable (the MIQP solver itself is checked by name when used)."""
        return importlib.util.find_spec("cvxpy") is not None

    def _miqp(self, problem: Problem) -> CvxpyMIQP:
        from .miqp import CvxpyMIQP  # cvxpy: loaded only for this backend

        key = problem.kind.value
        if key not in self._cache:
            s = self.settings
            self._cache[key] = CvxpyMIQP(
                self.form,
                key,
                solver=s.solver,
                time_limit=s.time_limit,
                complementarity=s.complementarity,
                verify_infeasible=s.verify_infeasible,
            )
        return self._cache[key]

    def solve(self, problem: Problem, guess: Mode | None = None) -> RawSolution:
        """Big-M MIQP (enlarged up to ``Settings.bigm_retries`` times while the solution uses
        10 % of the bound), then the exact QP of its mode. A load-factor problem starts from
        ``bigm * max(1, 10 t_max)`` (its forces grow with the factor) and is answered by the MIQP
        alone."""
        miqp, s = self._miqp(problem), self.settings
        if problem.kind.load:
            t_max = float(problem.up[problem.rows.step][0])
            return miqp.solve_problem(problem, s.bigm * max(1.0, 10.0 * t_max))
        M, retries = float(s.bigm), 0
        while True:
            sol = miqp.solve_problem(problem, M)
            if sol.status != OPTIMAL or sol.bigm_ratio < BIGM_TRIGGER or retries >= s.bigm_retries:
                break
            M *= 100.0
            retries += 1
        if sol.status != OPTIMAL or sol.mode is None:
            return replace(sol, bigm_retries=retries)
        if sol.bigm_ratio >= BIGM_TRIGGER:
            warnings.warn(
                f"MIQP solution uses {sol.bigm_ratio:.0%} of the big-M bound after {retries} enlargements "
                f"(M = {M:.3g} in scaled force units): the answer may be cut off by the bound",
                BigMWarning,
                stacklevel=4,
            )
        pol = BranchAndBound(problem).solve_mode(sol.mode)
        if pol.status != OPTIMAL:
            return replace(sol, bigm_retries=retries)
        return replace(
            pol,
            backend=f"{sol.backend}+polish",
            bigm_ratio=sol.bigm_ratio,
            bigm_retries=retries,
            message=sol.message,
        )

    def solve_fixed_mode(self, problem: Problem, mode: Mode) -> RawSolution:
        """The exact fixed-mode QP (the same one that polishes the MIQP's answers)."""
        return BranchAndBound(problem).solve_mode(mode)


#: The registered backends: name -> constructor ``(settings, formulation) -> SolverBackend``.
BACKENDS: dict[str, Callable[[Settings, Formulation], SolverBackend]] = {
    BranchAndBoundBackend.name: BranchAndBoundBackend,
    MiqpBackend.name: MiqpBackend,
}


def available_backends() -> tuple[str, ...]:
    """Names of the registered backends whose packages are installed."""
    return tuple(n for n in BACKENDS if _installed(n))


def _installed(name: str) -> bool:
    return name == BranchAndBoundBackend.name or importlib.util.find_spec("cvxpy") is not None


def make_backend(settings: Settings, form: Formulation) -> SolverBackend:
    """The backend ``settings.backend`` names, for the formulation ``form``.

    Raises:
        UnknownChoiceError: The name is not registered.
        SolverNotAvailableError: Its packages are not installed.
    """
    name = str(settings.backend)
    if name not in BACKENDS:
        raise UnknownChoiceError("backend", settings.backend, tuple(BACKENDS))
    backend = BACKENDS[name](settings, form)
    if not backend.is_installed():
        raise SolverNotAvailableError(f"backend {name!r} is not installed (pip install cvxpy)", solver=name)
    if name == MiqpBackend.name:
        from .miqp import resolve_solver

        resolve_solver(settings.solver)  # installed? (the name was checked by Settings)
    return backend


__all__ = [
    "BACKENDS",
    "BranchAndBoundBackend",
    "Capabilities",
    "MiqpBackend",
    "SolverBackend",
    "available_backends",
    "make_backend",
]
