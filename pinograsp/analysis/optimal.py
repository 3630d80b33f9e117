"""Optimal preloads: the smallest commands that resist given disturbances, or the best split of
a preload budget (docs/optimal_preload.md).

The model is positively homogeneous: a load ``w`` under commands ``f`` is resisted exactly when
``s w`` is under ``s f`` (``s > 0``). Along a command direction ``u`` (``phi(u) = 1``) the
disturbance ``w_k`` is therefore resisted from the scale ``s_k(u) = |w_k| / lambda_k(u)`` on,
where ``lambda_k(u)`` is the largest resistible magnitude along ``w_k`` under ``u``; the smallest
preload is ``min_u max_k s_k(u)`` and the best split of a budget ``B`` is
``max_u min_k lambda_k(B u) / |w_k|`` (the same search, inverted).

* ``method="prp"`` (variant ``"single-step"``, its default): exact, one complementarity program
  with the commands as variables (:mod:`pinograsp.solvers.preload_problem`).
* ``method="iterative"`` (and the PRP's other variants): a deterministic search over the
  command directions: a grid on the simplex of the chosen actuators, the balanced equilibrium
  preload as one more candidate, then a pattern search of ``refine`` halvings; each point costs
  one max-wrench search per disturbance. Counts, never time.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..core.methods import bounded as limits_bound
from ..core.methods import preload_method
from ..core.model import GraspModel
from ..core.settings import DEFAULT_METHOD, Settings, Variant
from ..core.validate import choice, count, finite_array, force, positive_number
from ..core.validate import steps as n_steps
from ..errors import AuditWarning, InvalidInputError
from ..solvers.problem import ProblemKind
from .optimal_search import GRID, OBJECTIVES, RESISTANCES, DisturbanceCheck, Status, simplex_grid
from .preload import command_bounds
from .registry import get_method
from .response import Session
from .staged import variant_of


@dataclass(frozen=True)
class OptimalPreload:
    """Result of :func:`optimal_preload`.

    Attributes:
        status: ``"optimal"``; ``"bound_hit"`` (a bound of ``max_command`` binds: ``bound``
            names it); ``"unverified"`` (an answer was found, but the verification at it does
            not resist every disturbance: ``checks`` says which; never ``"optimal"``);
            ``"infeasible"`` (``infeasible`` names the disturbances that no preload
            within the bounds resists).
        task: ``"smallest"`` (the least preload resisting every disturbance) or ``"split"``
            (the best use of ``budget``).
        command: ``{actuator: command}`` [N·m or N] (None when infeasible).
        value: Smallest task: ``phi(command)`` [N·m or N]; split: the resistance reached
            (``"min"``: the factor every disturbance can be scaled by; ``"sum"``: the weighted
            sum of the factors; ``inf``: unbounded).
        objective: ``"max"`` or ``"sum"``: the function ``phi`` of the commands.
        resistance: Split: ``"min"`` or ``"sum"``; else None.
        bound: Actuators whose bound binds (``"budget"`` too when the budget is used up).
        infeasible: Indices of the disturbances that cannot be resisted.
        checks: Each disturbance verified at the answer.
        method: ``"prp"`` or ``"iterative"``.
        exact: True for the PRP's program, False for the search.
        evaluations: Command directions evaluated by the search (0 when exact).
        n_solves: Solves (search queries and verification).
        wall_time: [s].
        reason: One sentence on the outcome.
    """

    status: Status | Literal["unverified"]
    task: Literal["smallest", "split"]
    command: dict[str, float] | None
    value: float
    objective: str
    resistance: str | None
    bound: tuple[str, ...]
    infeasible: tuple[int, ...]
    checks: tuple[DisturbanceCheck, ...]
    method: str
    exact: bool
    evaluations: int
    n_solves: int
    wall_time: float
    reason: str

    @property
    def verified(self) -> bool:
        """Every disturbance resisted at the answer."""
        return self.command is not None and all(c.resisted for c in self.checks)

    def to_dict(self) -> dict:
        """Plain JSON-able dictionary (the CLI's ``--json``)."""
        return {
            "status": self.status,
            "task": self.task,
            "command": self.command,
            "value": float(self.value) if np.isfinite(self.value) else None,
            "objective": self.objective,
            "resistance": self.resistance,
            "bound": list(self.bound),
            "infeasible": list(self.infeasible),
            "verified": self.verified,
            "checks": [c.to_dict() for c in self.checks],
            "method": self.method,
            "exact": self.exact,
            "evaluations": self.evaluations,
            "n_solves": self.n_solves,
            "wall_time": self.wall_time,
            "reason": self.reason,
        }

    def summary(self) -> str:
        """What ``print`` shows."""
        how = "exact program" if self.exact else f"search, {self.evaluations} command directions"
        lines = [f"optimal preload ({self.task}, {self.method}, {how}): {self.status}: {self.reason}"]
        if self.command is not None:
            lines += [f"  {k:<24s} {v:12.6g}" for k, v in self.command.items()]
        for c in self.checks:
            lim = "unbounded" if np.isinf(c.limit) else f"x{c.limit:.4g}"
            lines.append(
                f"  disturbance {c.index}: {'resisted' if c.resisted else c.status}, limit {lim}"
                + ("" if c.needs_preload else " (no preload needed)")
            )
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def _disturbances(model: GraspModel, disturbances: object) -> np.ndarray:
    """(K, 6) wrenches from vectors, axis names (unit) or ``(direction, magnitude)`` pairs."""
    from ..core.axes import wrench_direction

    if isinstance(disturbances, (str, bytes)) or not isinstance(disturbances, (Sequence, np.ndarray)):
        disturbances = [disturbances]
    out = []
    for i, item in enumerate(disturbances):
        name = f"disturbances[{i}]"
        if isinstance(item, str):
            w = wrench_direction(model, item, name)
        elif (
            isinstance(item, tuple) and len(item) == 2 and (isinstance(item[0], str) or np.ndim(item[0]) == 1)
        ):
            w = wrench_direction(model, item[0], name) * force(f"{name} magnitude", item[1], "N or N·m")
        else:
            w = model.wrench_vector(item, name)
        if not np.any(w != 0):
            raise InvalidInputError(name, "zero wrench (the preload alone is always checked)")
        out.append(w)
    if not out:
        raise InvalidInputError("disturbances", "expected at least one wrench")
    return np.array(out)


def _cost(model: GraspModel, weights: object, free: np.ndarray) -> np.ndarray:
    """Cost of each command in ``phi`` (na,): ``weights`` for the chosen actuators, else 0."""
    w = np.ones(model.na)
    if weights is not None:
        if not isinstance(weights, dict):
            raise InvalidInputError("weights", f"expected {{actuator: weight}}, got {weights!r}")
        for key, value in weights.items():
            if key not in model.actuator_names:
                raise InvalidInputError("weights", f"unknown actuator {key!r}; valid: {model.actuator_names}")
            w[model.actuator_names.index(key)] = positive_number(f"weights[{key!r}]", value)
    return np.where(free, w, 0.0)


#: Largest number of pattern-search halvings (2**-30 of the grid step is below the design accuracy).
MAX_REFINE = 30
#: Largest simplex grid: at most this many candidate points looped over ((grid + 1)**(n - 1)).
MAX_GRID_LOOP = 1_000_000


def _grid(grid: object, nfree: int) -> int:
    """Divisions of the simplex (default by the number of actuators), refused before any work
    when the grid's loop ``(grid + 1)**(nfree - 1)`` exceeds :data:`MAX_GRID_LOOP`."""
    if grid is None:
        return GRID.get(nfree, 2)
    g = count("grid", grid, MAX_GRID_LOOP, what="divisions of the command simplex")
    if nfree > 1 and (g + 1) ** (nfree - 1) > MAX_GRID_LOOP:
        raise InvalidInputError(
            "grid",
            f"{g} divisions for {nfree} actuators is a grid of (grid + 1)**{nfree - 1} > "
            f"{MAX_GRID_LOOP:g} points: choose grid <= {int(MAX_GRID_LOOP ** (1 / (nfree - 1))) - 1}",
        )
    return g


def _free(model: GraspModel, actuators: object) -> np.ndarray:
    """Which kept actuators get a command (driving ones among ``actuators``; None: all)."""
    drive = np.array([k != "locked" for k in model.kinds], bool)
    if actuators is None:
        return drive
    if isinstance(actuators, str) or not isinstance(actuators, Sequence):
        raise InvalidInputError("actuators", f"expected a list of actuator names, got {actuators!r}")
    for a in actuators:
        if a not in model.actuator_names:
            raise InvalidInputError("actuators", f"unknown actuator {a!r}; valid: {model.actuator_names}")
    chosen = np.array([n in actuators for n in model.actuator_names], bool) & drive
    if not chosen.any():
        raise InvalidInputError("actuators", "no driving actuator chosen")
    return chosen


def _direction_weights(direction_weights: Sequence[float] | None, k: int) -> np.ndarray:
    """The (k,) weights of ``resistance="sum"`` (default 1), each > 0."""
    if direction_weights is None:
        return np.ones(k)
    dw = finite_array("direction_weights", direction_weights, (k,))
    if np.any(dw <= 0):
        raise InvalidInputError("direction_weights", "every weight must be > 0")
    return dw


def optimal_preload(
    model: GraspModel,
    disturbances: object,
    method: str = DEFAULT_METHOD,
    *,
    objective: str = "max",
    budget: float | None = None,
    resistance: str = "min",
    max_command: float | dict[str, float] = 1.0,
    weights: dict[str, float] | None = None,
    direction_weights: Sequence[float] | None = None,
    actuators: Sequence[str] | None = None,
    grid: int | None = None,
    refine: int = 3,
    upper: float = 1e3,
    steps: int = 20,
    settings: Settings | None = None,
) -> OptimalPreload:
    """The smallest preload resisting every disturbance, or the best split of a budget.

    Args:
        model: The grasp.
        disturbances: Wrenches (K, 6) or (K, 3) planar [N, N·m]; items may also be axis names
            (``"fy"``: a unit force) or ``(direction, magnitude)`` pairs.
        method: ``"quasistatic"`` (default: the search, with the limit loads of the loading
            path), ``"iterative"`` (the search) or ``"prp"`` (exact program for the
            ``"single-step"`` variant, else the search); ``"energetic"`` runs the search.
        objective: ``phi(f) = max_a weights_a f_a`` (``"max"``, default) or
            ``sum_a weights_a f_a`` (``"sum"``) [N·m or N].
        budget: None: minimise ``phi`` (task "smallest"). A number: ``phi(f) <= budget`` and
            maximise the ``resistance`` (task "split").
        resistance: Split: ``"min"`` (the largest factor ``r`` with every ``r w_k`` resisted)
            or ``"sum"`` (``sum_k direction_weights_k r_k``, each ``r_k`` on its own).
        max_command: Upper bound of every command, or ``{actuator: bound}`` (others 1).
        weights: ``{actuator: weight > 0}`` of ``phi`` (default 1).
        direction_weights: (K,) weights of ``resistance="sum"`` (default 1).
        actuators: The actuators whose commands are chosen (default: every driving one);
            the others are held at zero. Commands are never negative.
        grid: Search: divisions of the simplex (default by the number of actuators, ``GRID``).
        refine: Search: pattern-search halvings after the grid.
        upper: Largest load factor searched (``r``, or ``lambda_k / |w_k|``).
        steps: Bisection steps of each max-wrench search (resolution ``upper / 2**steps``).
        settings: Solver settings (the PRP program needs ``variant`` "single-step").

    Returns:
        An :class:`OptimalPreload`; ``result.command`` goes straight into every analysis.
    """
    from .optimal_search import exact_prp, search

    t0 = time.perf_counter()
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    preload_method(method, "optimal_preload")
    choice("objective", objective, OBJECTIVES)
    choice("resistance", resistance, RESISTANCES)
    loads = _disturbances(model, disturbances)
    free = _free(model, actuators)
    cost = _cost(model, weights, free)
    bound = np.where(free, command_bounds(model, max_command), 0.0)
    if budget is not None:
        budget = force("budget", budget, "N·m or N")
    dw = _direction_weights(direction_weights, len(loads))
    nfree = int(free.sum())
    grid = _grid(grid, nfree)
    refine = count("refine", refine, MAX_REFINE, minimum=0, what="each halves the pattern step")
    upper = force("upper", upper, "(a load factor)")
    steps = n_steps(steps, bounded=limits_bound(method))  # an exact limit does not bisect
    solver = Session(model, settings)
    spec = dict(objective=objective, budget=budget, resistance=resistance, cost=cost, bound=bound, dw=dw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AuditWarning)
        rules = get_method(method)  # the exact program writes Alg. 1's single-step problem
        if rules.load_kind is ProblemKind.PRP and variant_of(solver.settings, rules) is Variant.SINGLE_STEP:
            out = exact_prp(solver, loads, free, spec, upper)
        else:
            out = search(solver, method, loads, free, spec, grid, refine, upper, steps)
    if out["command"] is not None and not all(c.resisted for c in out["checks"]):
        out["status"] = "unverified"  # its own verification failed: never "optimal"/"bound_hit"
    return OptimalPreload(**out, method=method, wall_time=time.perf_counter() - t0)


__all__ = ["DisturbanceCheck", "OptimalPreload", "optimal_preload", "simplex_grid"]
