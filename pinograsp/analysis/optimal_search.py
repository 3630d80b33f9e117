"""The two engines of :func:`pinograsp.optimal_preload` (docs/optimal_preload.md).

:func:`exact_prp` solves the PRP's program with the commands as variables
(:mod:`pinograsp.solvers.preload_problem`); :func:`search` is the deterministic search over
command directions for the iterative scheme. Both return the fields of
:class:`~pinograsp.analysis.optimal.OptimalPreload` except ``method`` and ``wall_time``.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..core.settings import Method
from ..errors import PinograspError, PreloadNotInEquilibriumError, SolverError
from ..solvers.base import INFEASIBLE, OPTIMAL
from .response import Session

Status = Literal["optimal", "bound_hit", "infeasible"]
OBJECTIVES = ("max", "sum")
RESISTANCES = ("min", "sum")
#: Grid divisions of the command simplex by the number of chosen actuators (about 9-20 points).
GRID = {1: 1, 2: 8, 3: 4, 4: 3}
#: Relative margin of the PRP's exact answer: commands x (1 + MARGIN) (smallest), loads x
#: (1 - MARGIN) (split), so that the verification is not on the boundary.
MARGIN = 1e-6


@dataclass(frozen=True)
class DisturbanceCheck:
    """One disturbance at the answer.

    Attributes:
        index: Position in the given list.
        wrench: The wrench checked (6,) [N, N·m] (split: the disturbance x the factor reached).
        resisted: Whether ``passive_response`` resists it under the answer.
        status: That response's status.
        needs_preload: False if it is resisted with zero commands.
        limit: Largest resistible multiple of the given disturbance under the answer
            (``inf``: unbounded; NaN: not computed).
        margin: ``limit - 1`` for the smallest-preload task (how much larger the disturbance
            could be), ``limit / factor - 1`` for the split.
    """

    index: int
    wrench: np.ndarray
    resisted: bool
    status: str
    needs_preload: bool
    limit: float
    margin: float

    def to_dict(self) -> dict:
        """Plain JSON-able dictionary (``None`` for inf/NaN)."""

        def num(v: float) -> float | None:
            return float(v) if np.isfinite(v) else None

        return {
            "index": self.index,
            "wrench": self.wrench.tolist(),
            "resisted": self.resisted,
            "status": self.status,
            "needs_preload": self.needs_preload,
            "limit": num(self.limit),
            "margin": num(self.margin),
        }


def simplex_grid(n: int, divisions: int) -> list[np.ndarray]:
    """Points of the simplex ``{v >= 0, sum v = 1}`` in ``n`` dimensions with coordinates
    ``i / divisions``, in a fixed (lexicographic, descending) order."""
    pts = []
    for comb in itertools.product(range(divisions, -1, -1), repeat=n - 1):
        if sum(comb) <= divisions:
            pts.append(np.array([*comb, divisions - sum(comb)], float) / divisions)
    return pts


#: A command at or above ``bound * (1 - BOUND_TOL)`` is at its bound.
BOUND_TOL = 1e-9


class _Count:
    """Solves spent by one call."""

    def __init__(self) -> None:
        self.n = 0


def _phi(u: np.ndarray, cost: np.ndarray, objective: str) -> float:
    v = cost * u
    return float(v.max(initial=0.0) if objective == "max" else v.sum())


def _command_dict(solver: Session, f: np.ndarray) -> dict[str, float]:
    m = solver.model
    out = {n: 0.0 for n in m.all_actuator_names}
    out.update({n: float(v) for n, v in zip(m.actuator_names, f)})
    return out


def _needs_preload(solver: Session, method: str, loads: np.ndarray, count: _Count) -> np.ndarray:
    """Whether each disturbance needs a preload (not resisted with zero commands)."""
    zero = np.zeros(solver.model.na)
    out = []
    for w in loads:
        r = solver.response(zero, w, method)
        count.n += r.n_solves
        out.append(not r.resistible)
    return np.array(out, bool)


def _checks(
    solver: Session,
    method: str,
    f: np.ndarray,
    loads: np.ndarray,
    needs: np.ndarray,
    factors: np.ndarray,
    limits: np.ndarray,
    count: _Count,
) -> tuple[DisturbanceCheck, ...]:
    """Each disturbance ``factors_k w_k`` under ``f``, with its limit (multiples of ``w_k``)."""
    out = []
    for k, w in enumerate(loads):
        r = solver.response(f, factors[k] * w, method)
        count.n += r.n_solves
        margin = limits[k] / factors[k] - 1.0 if factors[k] > 0 else float("nan")
        out.append(
            DisturbanceCheck(
                k, factors[k] * w, bool(r.resistible), r.status, bool(needs[k]), limits[k], margin
            )
        )
    return tuple(out)


def _at_bound(solver: Session, f: np.ndarray, bound: np.ndarray, free: np.ndarray) -> tuple[str, ...]:
    hit = free & (f >= bound * (1.0 - BOUND_TOL))
    return tuple(n for n, h in zip(solver.model.actuator_names, hit) if h)


def _zero_answer(
    solver: Session, method: str, loads: np.ndarray, needs: np.ndarray, spec: dict, count: _Count
) -> dict:
    f = np.zeros(solver.model.na)
    ones = np.ones(len(loads))
    checks = _checks(solver, method, f, loads, needs, ones, np.full(len(loads), np.inf), count)
    return dict(
        status="optimal", task="smallest", command=_command_dict(solver, f), value=0.0,
        objective=spec["objective"], resistance=None, bound=(), infeasible=(), checks=checks,
        reason="every disturbance is resisted without preload (passively)",
    )  # fmt: skip


# ------------------------------------------------------------------------------ exact (PRP)
def _solve_program(solver: Session, loads: np.ndarray, spec: dict, task: str, upper: float):
    """Solve the program; returns (status, commands (na,) [N·m or N], factors) in physical units."""
    from ..solvers.preload_problem import build_preload_program

    m, form = solver.model, solver.form
    lw = np.array([m.reduce_wrench(w) * form.wscale for w in loads])
    F = max(
        float(np.abs(lw).max(initial=0.0)) if task == "smallest" else 0.0,
        float((spec["bound"] * form.rho).max()),
    )
    budget = np.inf if spec["budget"] is None else spec["budget"] / F
    prog = build_preload_program(
        form, lw / F, task=task, objective=spec["objective"], cost=spec["cost"] / form.rho,
        bound=spec["bound"] * form.rho / F, budget=min(budget, 1e30), t_max=upper, weights=spec["dw"],
    )  # fmt: skip
    raw = solver.solve_problem(prog.problem)  # the settings' backend
    if raw.status not in (OPTIMAL, INFEASIBLE):
        raise SolverError(
            f"optimal-preload program: {raw.status.value} ({raw.message})",
            solver=solver.backend.name,
            status=raw.status.value,
        )
    if raw.status == INFEASIBLE or raw.z is None:
        return False, None, None
    f = np.maximum(raw.z[prog.command], 0.0) * F / form.rho
    return True, f, raw.z[prog.factors]


def _limits(solver: Session, f: np.ndarray, loads: np.ndarray, upper: float, count: _Count) -> np.ndarray:
    """Largest resistible multiple of each load under ``f`` (PRP, one load-factor solve each)."""
    out = []
    for w in loads:
        size = float(np.linalg.norm(w))
        lf = solver.max_load_factor(f, w / size, upper * size)
        count.n += 1
        out.append(lf.magnitude / size if lf.status == OPTIMAL else float("nan"))
    return np.array(out)


def _infeasible(bad: list, why: str, n_solves: int, common: dict) -> dict:
    """The fields of an infeasible :class:`~pinograsp.analysis.optimal.OptimalPreload`."""
    return dict(
        status="infeasible",
        command=None,
        value=float("nan"),
        bound=(),
        infeasible=tuple(bad),
        checks=(),
        reason=why,
        n_solves=n_solves,
        **common,
    )


def exact_prp(solver: Session, loads: np.ndarray, free: np.ndarray, spec: dict, upper: float) -> dict:
    """The PRP's exact answer (module docstring of :mod:`pinograsp.solvers.preload_problem`)."""
    count = _Count()
    needs = _needs_preload(solver, Method.PRP, loads, count)
    split = spec["budget"] is not None
    if not split and not needs.any():
        return {
            **_zero_answer(solver, "prp", loads, needs, spec, count),
            "exact": True,
            "evaluations": 0,
            "n_solves": count.n,
        }
    task = spec["resistance"] if split else "smallest"
    use = np.ones(len(loads), bool) if split else needs
    ok, f, t = _solve_program(solver, loads[use], spec, task, upper)
    count.n += 1
    common = dict(
        task="split" if split else "smallest",
        objective=spec["objective"],
        resistance=spec["resistance"] if split else None,
        exact=True,
        evaluations=0,
    )
    if ok and split and spec["resistance"] == "min" and t[0] <= 0:
        ok = False
    if not ok:
        bad = []
        for k in np.flatnonzero(use):  # which disturbance no preload within the bounds resists alone
            alone, _, tk = _solve_program(
                solver, loads[k : k + 1], spec, "min" if split else "smallest", upper
            )
            count.n += 1
            if not alone or (split and tk[0] <= 0):
                bad.append(int(k))
        # by homogeneity, "at any preload" = with the bounds 1e6 times larger
        wide = {**spec, "bound": spec["bound"] * 1e6}
        never = [k for k in bad if not _solve_program(solver, loads[k : k + 1], wide, "smallest", upper)[0]]
        count.n += len(bad)
        why = (
            f"no preload within the bounds resists disturbance(s) {bad}"
            + (f" ({never} not even as the preload grows large relative to them)" if never else "")
            if bad
            else "each disturbance is resisted within the bounds, but not all under one preload"
        )
        return _infeasible(bad, why, count.n, common)
    if split:
        factors = np.full(len(loads), t[0]) if spec["resistance"] == "min" else t.copy()
        value = float(t[0] if spec["resistance"] == "min" else spec["dw"] @ t)
        limits = _limits(solver, f, loads, upper, count)
        checks = _checks(solver, Method.PRP, f, loads, needs, factors * (1.0 - MARGIN), limits, count)
    else:
        f = np.minimum(f * (1.0 + MARGIN), spec["bound"])
        value = _phi(f, spec["cost"], spec["objective"])
        limits = _limits(solver, f, loads, upper, count)
        checks = _checks(solver, Method.PRP, f, loads, needs, np.ones(len(loads)), limits, count)
    return _finish(solver, f, value, free, spec, checks, common, count, "exact program")


def _finish(solver, f, value, free, spec, checks, common, count, how) -> dict:  # noqa: ANN001
    bound = _at_bound(solver, f, spec["bound"], free)
    if spec["budget"] is not None and _phi(f, spec["cost"], spec["objective"]) >= spec["budget"] * (1 - 1e-6):
        bound = (*bound, "budget")
    binding = [b for b in bound if b != "budget"]
    status = "bound_hit" if binding else "optimal"
    what = f"{value:.6g}" + (
        " (phi of the commands)" if common["task"] == "smallest" else " (load factor reached)"
    )
    reason = f"{how}: {what}" + (f"; max_command binds for {binding}" if binding else "")
    if not all(c.resisted for c in checks):
        reason += f"; NOT verified for disturbance(s) {[c.index for c in checks if not c.resisted]}"
    return dict(
        status=status,
        command=_command_dict(solver, f),
        value=value,
        bound=bound,
        infeasible=(),
        checks=checks,
        reason=reason,
        n_solves=count.n,
        **common,
    )


# ------------------------------------------------------------------------------ search
def _evaluate(solver, method, loads, needs, spec, u, upper, steps, count) -> dict:  # noqa: ANN001
    """One command direction ``u`` (phi(u) = 1): the factors ``rho_k`` at the query scale."""
    from .max_wrench import max_resistible_wrench

    pos = u > 0
    s_b = float(np.min(spec["bound"][pos] / u[pos]))
    s_q = s_b if spec["budget"] is None else min(spec["budget"], s_b)
    rho = np.full(len(loads), np.inf)
    for k, w in enumerate(loads):
        if spec["budget"] is None and not needs[k]:
            continue
        size = float(np.linalg.norm(w))
        try:
            r = max_resistible_wrench(
                solver.model, s_q * u, w / size, method, upper * size, steps, settings=solver.settings
            )
        except PreloadNotInEquilibriumError:
            return dict(u=u, s_q=s_q, rho=None, key=(3, 0.0))
        count.n += r.n_solves
        rho[k] = {"unbounded": np.inf, "above_limit": upper, "below_resolution": 0.0}.get(
            r.status, r.magnitude / size
        )
    if spec["budget"] is not None:
        score = float(rho.min() if spec["resistance"] == "min" else spec["dw"] @ rho)
        return dict(u=u, s_q=s_q, rho=rho, score=score, key=(0, -score) if score > 0 else (2, 0.0))
    with np.errstate(divide="ignore"):
        s_k = np.where(rho > 0, s_q / np.where(rho > 0, rho, 1.0), np.inf)
    need = float(s_k.max())
    if need <= s_q * (1.0 + BOUND_TOL):
        return dict(u=u, s_q=s_q, rho=rho, need=max(need, s_q / upper), key=(0, need))
    return dict(u=u, s_q=s_q, rho=rho, need=need, key=(1, need / s_q if np.isfinite(need) else np.inf))


def _candidates(solver: Session, method: str, free: np.ndarray, grid: int) -> list[np.ndarray]:
    """Grid points on the simplex of the chosen actuators, then the balanced equilibrium preload."""
    from .preload import equilibrium_preload

    idx = np.flatnonzero(free)
    pts = []
    for v in simplex_grid(len(idx), grid):
        u = np.zeros(solver.model.na)
        u[idx] = v
        pts.append(u)
    try:
        design = equilibrium_preload(solver.model, method, settings=solver.settings)
    except PinograspError:
        design = None
    if design is not None and design.in_equilibrium:  # a preload: one more start point
        f = solver.model.command_vector(design.command)
        if not np.any(f[~free] > 0) and f.sum() > 0:
            pts.append(np.round(f / f.sum(), 12))
    return pts


def search(solver, method, loads, free, spec, grid, refine, upper, steps) -> dict:  # noqa: ANN001
    """The deterministic search over command directions (module docstring of optimal_preload)."""
    count = _Count()
    needs = _needs_preload(solver, method, loads, count)
    split = spec["budget"] is not None
    common = dict(
        task="split" if split else "smallest",
        objective=spec["objective"],
        resistance=spec["resistance"] if split else None,
        exact=False,
    )
    if not split and not needs.any():
        return {
            **_zero_answer(solver, method, loads, needs, spec, count),
            "exact": False,
            "evaluations": 0,
            "n_solves": count.n,
        }
    seen: dict[tuple, dict] = {}

    def ev(v: np.ndarray) -> dict:
        key = tuple(np.round(v, 12).tolist())
        if key not in seen:
            phi = _phi(v, spec["cost"], spec["objective"])
            seen[key] = _evaluate(solver, method, loads, needs, spec, v / phi, upper, steps, count)
        return seen[key]

    best = min((ev(v) for v in _candidates(solver, method, free, grid)), key=lambda e: e["key"])
    h, idx = 0.5 / grid, np.flatnonzero(free)
    for _ in range(refine if len(idx) > 1 else 0):  # pattern search: move h between two commands
        base = best["u"] / best["u"].sum()
        moves = []
        for i, j in itertools.permutations(idx, 2):
            step = min(h, base[j])
            if step > 0:
                v = base.copy()
                v[i] += step
                v[j] -= step
                moves.append(ev(v))
        cand = min(moves, key=lambda e: e["key"], default=best)
        if cand["key"] < best["key"]:
            best = cand
        else:
            h /= 2.0
    common["evaluations"] = len(seen)
    return _search_answer(solver, method, loads, needs, spec, free, best, list(seen.values()), common, count)


def _search_answer(solver, method, loads, needs, spec, free, best, evaluated, common, count) -> dict:  # noqa: ANN001
    valid = [e for e in evaluated if e["rho"] is not None]
    if best["key"][0] >= 1:
        if spec["budget"] is None:  # never within bounds at any direction tried
            bad = [
                k
                for k in range(len(loads))
                if needs[k]
                and not any(
                    e["s_q"] / e["rho"][k] <= e["s_q"] * (1 + BOUND_TOL) if e["rho"][k] > 0 else False
                    for e in valid
                )
            ]
        else:
            bad = [k for k in range(len(loads)) if not any(e["rho"][k] > 0 for e in valid)]
        never = [k for k in bad if not any(e["rho"][k] > 0 for e in valid)]
        why = "no command direction tried has the preload in equilibrium" if not valid else (
            f"disturbance(s) {bad} not resisted within the bounds at any command direction tried"
            + (f" ({never} not even as the preload grows large relative to them)" if never else "")
        )  # fmt: skip
        return _infeasible(bad, why, count.n, common)
    u = best["u"]
    if spec["budget"] is None:
        f = best["need"] * u
        limits = best["rho"] * best["need"] / best["s_q"]
        limits = np.where(needs, limits, np.nan)
        checks = _checks(solver, method, f, loads, needs, np.ones(len(loads)), limits, count)
        value = _phi(f, spec["cost"], spec["objective"])
    else:
        f = best["s_q"] * u
        rho = best["rho"]
        factors = np.full(len(loads), best["score"]) if spec["resistance"] == "min" else rho.copy()
        factors = np.where(np.isfinite(factors), factors, 1.0)  # unbounded: check the disturbance itself
        checks = _checks(solver, method, f, loads, needs, factors, rho, count)
        value = best["score"]
    return _finish(
        solver,
        f,
        value,
        free,
        spec,
        checks,
        common,
        count,
        f"search over {common['evaluations']} command directions",
    )
