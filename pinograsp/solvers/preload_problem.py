"""Alg. 1 with the actuator commands as decision variables (``pg.optimal_preload``, PRP).

Under the PRP a load is resisted exactly when its complementarity system is feasible (the
PRP's objective only picks one equilibrium among several). So "the smallest commands under
which every load ``w_k`` is resisted" is one complementarity-constrained program: one copy of
the PRP's variables per load (block ``k``), the commands ``f̂_c`` (na) shared by every block,
and the objective on the commands::

    minimise    phi(f̂_c)^2                  (phi: "sum" = cost·f̂_c, "max" = max_a cost_a f̂_c,a)
    subject to  block k: the PRP rows of problems.build_problem with load w_k and the
                actuator rows  f̂_k - f̂_c >= 0 (non-backdrivable, complementary to û_k),
                               f̂_k - f̂_c  = 0 (backdrivable)
                0 <= f̂_c <= bound

Block 0 is the preload alone (``w = 0``): the answer's preload is itself an equilibrium, as
every analysis checks first. The *split* task keeps the commands free within a budget
(``cost·f̂_c <= B`` or ``cost_a f̂_c,a <= B``) and maximises load factors instead: one shared
factor ``t`` (loads ``t w_k``; the smallest resistance, ``"min"``) or one per load (a
weighted sum, ``"sum"``), each within ``[0, t_max]``, as the ``LOAD`` problem does.

The pairs are the blocks' own pairs, so :class:`~.bnb.BranchAndBound` solves the program
exactly (global optimum, a count limit, the same bits for the same inputs). This matches the
PRP's ``"single-step"`` variant (its default): the other variants start from the preload
stage's least-energy solution, a nested optimisation that this program cannot express.

This module never imports Pinocchio or Coal.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .formulation import Formulation, ScaledData
from .problem import INF, Problem, ProblemKind, build_problem


@dataclass(frozen=True, eq=False)
class PreloadProgram:
    """A built program and where its answer lives.

    Attributes:
        problem: The stacked :class:`~.problem.Problem`.
        command: Columns of the scaled commands ``f̂_c`` (na,).
        factors: Columns of the load factors (split task), else empty.
    """

    problem: Problem
    command: np.ndarray
    factors: np.ndarray


def build_preload_program(
    form: Formulation,
    loads: np.ndarray,
    *,
    task: str,
    objective: str,
    cost: np.ndarray,
    bound: np.ndarray,
    budget: float = INF,
    t_max: float = 1.0,
    weights: np.ndarray | None = None,
) -> PreloadProgram:
    """The program of the module docstring, in scaled units.

    Args:
        form: Scaled formulation of the model.
        loads: Scaled loads (K, nw) (``w * wscale / F``).
        task: ``"smallest"`` (fixed loads, minimise ``phi``), ``"min"`` or ``"sum"`` (split:
            maximise the shared factor, or the ``weights``-weighted sum of per-load factors).
        objective: ``"max"`` or ``"sum"``: the function ``phi`` of the commands.
        cost: Cost of each scaled command in ``phi`` (na,) (0 for commands not chosen).
        bound: Upper bound of each scaled command (na,) (0: held at zero).
        budget: ``phi(f̂_c) <= budget`` (split tasks).
        t_max: Largest load factor (split tasks).
        weights: Weights of the per-load factors (``"sum"``), (K,).
    """
    base = build_problem(form, ProblemKind.PRP, _zero_data(form))
    nl = len(loads)
    naux = {"smallest": 1 if objective == "max" else 0, "min": 1, "sum": nl}[task]
    fcol = (1 + nl) * base.n
    acol = fcol + form.na
    stacked = _stack_blocks(form, base, loads, task, fcol, acol, acol + naux)
    extra_C, extra_lo, extra_up, L, lvec = _command_rows(
        stacked.n, fcol, acol, naux, task, objective, cost, bound, budget, t_max, weights
    )
    problem = replace(
        stacked,
        L=L,
        l=lvec,
        C=np.vstack([stacked.C, *extra_C]) if extra_C else stacked.C,
        lo=np.concatenate([stacked.lo, extra_lo]),
        up=np.concatenate([stacked.up, extra_up]),
    )
    return PreloadProgram(
        problem, fcol + np.arange(form.na), acol + np.arange(naux) if task != "smallest" else np.zeros(0, int)
    )


def _stack_blocks(
    form: Formulation, base: Problem, loads: np.ndarray, task: str, fcol: int, acol: int, n: int
) -> Problem:
    """The preload block and one block per load, each a copy of ``base`` on its own columns,
    with its actuator rows ``f̂_k - f̂_c`` on the shared commands (columns from ``fcol``) and its
    load: fixed (``"smallest"``) or times a factor (columns from ``acol``). No objective yet."""
    nblock = 1 + len(loads)
    n0, me0, mi0 = base.n, base.A.shape[0], base.C.shape[0]
    na, nw = form.na, form.nw
    A = np.zeros((nblock * me0, n))
    b = np.zeros(nblock * me0)
    C = np.zeros((nblock * mi0, n))
    lo = np.zeros(nblock * mi0)
    up = np.zeros(nblock * mi0)
    pairs, kinds, owners, factor = [], [], [], []
    drive = np.flatnonzero(~form.lck)
    for k in range(nblock):
        cs, ra, rc = slice(k * n0, (k + 1) * n0), k * me0, k * mi0
        A[ra : ra + me0, cs] = base.A
        C[rc : rc + mi0, cs] = base.C
        lo[rc : rc + mi0], up[rc : rc + mi0] = base.lo, base.up
        if k and task == "smallest":
            b[ra : ra + nw] = -loads[k - 1]
        elif k:
            A[ra : ra + nw, acol + (0 if task == "min" else k - 1)] = loads[k - 1]
        C[rc + base.rows.f.start + drive, fcol + drive] = -1.0  # f̂_k - f̂_c
        pairs.append(base.pairs + rc)
        kinds += list(base.pair_kind)
        owners.append(base.pair_owner + np.where(np.arange(len(base.pairs)) < form.nc, form.nc, na) * k)
        factor.append(base.bigm_factor)
    return Problem(
        kind=ProblemKind.PRP,
        L=np.zeros((0, n)),
        l=np.zeros(0),
        A=A,
        b=b,
        C=C,
        lo=lo,
        up=up,
        pairs=np.vstack(pairs),
        pair_kind=tuple(kinds),
        pair_owner=np.concatenate(owners).astype(int),
        bigm_factor=np.vstack(factor),
        rows=base.rows,
        nc=form.nc * nblock,
        na=na * nblock,
        eq_names=tuple(
            f"load[{k - 1}].{nm}" if k else f"preload.{nm}" for k in range(nblock) for nm in base.eq_names
        ),
    )


def _command_rows(
    n: int,
    fcol: int,
    acol: int,
    naux: int,
    task: str,
    objective: str,
    cost: np.ndarray,
    bound: np.ndarray,
    budget: float,
    t_max: float,
    weights: np.ndarray | None,
) -> tuple[list, list, list, np.ndarray, np.ndarray]:
    """Rows on the commands (bounds, the max objective's epigraph, the budget), the factors'
    bounds, and the objective ``|L z + l|^2``."""
    na = len(cost)
    extra_C: list = []
    extra_lo: list = []
    extra_up: list = []

    def row(cols: dict[int, float], low: float, high: float) -> None:
        r = np.zeros(n)
        for c, v in cols.items():
            r[c] = v
        extra_C.append(r)
        extra_lo.append(low)
        extra_up.append(high)

    for a in range(na):
        row({fcol + a: 1.0}, 0.0, float(bound[a]))
    L = np.zeros((1, n))
    lvec = np.zeros(1)
    if task == "smallest" and objective == "max":
        for a in np.flatnonzero(cost > 0).tolist():
            row({fcol + a: float(cost[a]), acol: -1.0}, -INF, 0.0)
        L[0, acol] = 1.0
    elif task == "smallest":
        L[0, fcol : fcol + na] = cost
    else:
        if objective == "sum":
            row({fcol + a: float(cost[a]) for a in range(na)}, -INF, float(budget))
        else:
            for a in np.flatnonzero(cost > 0).tolist():
                row({fcol + a: float(cost[a])}, -INF, float(budget))
        wts = np.ones(naux) if weights is None or task == "min" else np.asarray(weights, float)
        for j in range(naux):
            row({acol + j: 1.0}, 0.0, float(t_max))
        L[0, acol:] = wts
        lvec[0] = -float(t_max) * float(wts.sum())
    return extra_C, extra_lo, extra_up, L, lvec


def _zero_data(form: Formulation) -> ScaledData:
    """Data of a PRP block with no load and zero commands (the commands become variables)."""
    return ScaledData(
        1.0, np.zeros(form.nw), np.zeros(form.na), np.zeros(form.nc), np.zeros(form.nx), np.zeros(form.nx)
    )
