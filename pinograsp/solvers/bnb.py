"""pinograsp's exact solver: branch-and-bound over the complementarity pairs of a
:class:`~.problem.Problem`.

A node fixes some pairs to a side (that side's row at its lower bound) and leaves the others
*free* (both rows only bounded below): its convex QP (:class:`~.node_qp.NodeQP`) is a relaxation
of every mode below it, so its optimum is a lower bound. The search is depth first:

1. **incumbent** — the caller's guess (e.g. the previous iteration step's mode) is solved
   first as a fixed-mode QP; a feasible guess bounds the search from the start;
2. at a node whose optimum violates complementarity the **repair** QP fixes every free pair at
   the side its relaxed optimum sits closest to; a feasible repair is a new incumbent and very
   often the optimum, which then prunes the rest of the tree;
3. the node branches on one violated pair — actuators first (their choice decides which
   contacts can carry load), then contacts, then friction — and visits the child on the natural
   side first.

Energetic problems add a contact's friction pairs (edge weight / dissipation row). They are
branched per contact, as the disjunction of its complementary states: *sticking* (every
dissipation row at zero: no slip) or *sliding in sector k* (only the adjacent edges ``k, k+1``
may carry force; their own pairs are decided further down). The repair step tries every free
contact sticking first, then sliding on the edges most against its relaxed slip.

A node is pruned when its bound is not better than the incumbent by more than the relative
tolerance :data:`REL_GAP` (the objective is a squared net wrench or spring energy that shrinks
towards zero, so only a relative test is meaningful). Node counts are limited by a count, never
by time; hitting the limit returns status ``node_limit`` with the best point found.

The search is a pure function of its inputs: the same problem and guess give the same bits.

This module never imports Pinocchio or Coal.
"""

from __future__ import annotations

import heapq

import numpy as np

from ..core.settings import MAX_NODES
from .base import FAILED, INFEASIBLE, NODE_LIMIT, OPTIMAL, Mode, RawSolution, SolveStatus
from .node_qp import NodeQP, QPResult
from .problem import INF, PairKind, Problem, ProblemKind

#: Relative optimality tolerance on the objective (a squared force): a node whose bound is within
#: this fraction of the incumbent cannot improve it enough to matter (|r| within 5e-10).
REL_GAP = 1e-9
#: Absolute floor of the pruning tolerance (scaled force units squared).
ABS_GAP = 1e-24
#: Complementarity violation (scaled force units) below which a pair counts as satisfied.
COMP_TOL = 1e-9
#: Default node limit of one search.


class _Open:
    """The open nodes: a stack (depth first), or for energetic problems a priority queue on
    the parent's bound (best first: their many friction pairs make a depth-first dive into a
    poor subtree costly), ties depth first. Both orders are deterministic."""

    def __init__(self, best_first: bool) -> None:
        self.best_first = best_first
        self._items: list = []
        self._count = 0

    def __bool__(self) -> bool:
        return bool(self._items)

    def append(self, fixed: np.ndarray, bound: float) -> None:
        self._count += 1
        if self.best_first:
            heapq.heappush(self._items, (bound, -self._count, fixed))
        else:
            self._items.append((bound, fixed))

    def pop(self) -> tuple[np.ndarray, float]:
        if self.best_first:
            bound, _, fixed = heapq.heappop(self._items)
            return fixed, bound
        bound, fixed = self._items.pop()
        return fixed, bound


class BranchAndBound:
    """Exact solver of one :class:`Problem`.

    Args:
        problem: The problem.
        max_nodes: Node limit (a count).
    """

    def __init__(self, problem: Problem, max_nodes: int = MAX_NODES) -> None:
        self.p = problem
        self.qp = NodeQP(problem)
        self.max_nodes = int(max_nodes)
        self._nodes = self._qps = self._attempts = 0
        npair = len(problem.pairs)
        # branching priority: actuator pairs first, then contacts, then friction
        self._actuator = np.array([k is PairKind.ACTUATOR for k in problem.pair_kind], bool).reshape(npair)
        self._contact = np.array([k is PairKind.CONTACT for k in problem.pair_kind], bool).reshape(npair)
        self._groups = [np.array(g, int) for g in problem.groups]
        self._group_pair = list(problem.group_owner)  # a contact's own pair index is its index

    # ---------------------------------------------------------------- helpers
    def _qp(self, fixed: np.ndarray, polish: bool = False) -> QPResult:
        _, up = self.p.bounds(fixed)
        res = self.qp.solve(up, polish=polish)
        self._qps += 1
        self._attempts += res.attempts
        return res

    def _violation(self, z: np.ndarray, fixed: np.ndarray) -> np.ndarray:
        comp = self.p.complementarity(z)
        comp[fixed >= 0] = 0.0
        return comp

    def _children(
        self, viol: np.ndarray, fixed: np.ndarray, natural: np.ndarray, z: np.ndarray
    ) -> list[np.ndarray]:
        """The children of a node, in push order (the last is explored first)."""
        bad = viol > COMP_TOL
        for cls in (self._actuator, self._contact):
            if (bad & cls).any():
                return self._pair_children(bad & cls, viol, fixed, natural)
        worst = max(self._groups, key=lambda g: viol[g].max()) if self._groups else None
        if worst is None or np.count_nonzero(fixed[worst] < 0) < 3:
            cand = bad if worst is None else bad & np.isin(np.arange(len(bad)), worst)
            return self._pair_children(cand, viol, fixed, natural)
        return self._group_children(worst, fixed, z)

    @staticmethod
    def _pair_children(
        cand: np.ndarray, viol: np.ndarray, fixed: np.ndarray, natural: np.ndarray
    ) -> list[np.ndarray]:
        idx = np.flatnonzero(cand)
        k = int(idx[np.argmax(viol[idx])])
        out = []
        for side in (1 - natural[k], natural[k]):  # natural side pushed last: explored first
            child = fixed.copy()
            child[k] = side
            out.append(child)
        return out

    def _group_children(self, g: np.ndarray, fixed: np.ndarray, z: np.ndarray) -> list[np.ndarray]:
        """One contact's states: sticking, or sliding in each sector of adjacent edges; the
        one closest to the relaxed point explored first."""
        P = self.p
        v = P.C @ z - P.lo
        weight, row = v[P.pairs[g, 0]], v[P.pairs[g, 1]]
        free = fixed[g] < 0
        stick = fixed.copy()
        stick[g[free]] = 1
        scored = [(float(np.abs(row[free]).sum()), 0, stick)]
        n = len(g)
        for k in range(n):
            keep = np.zeros(n, bool)
            keep[[k, (k + 1) % n]] = True
            off = free & ~keep
            child = fixed.copy()
            child[g[off]] = 0
            scored.append((float(np.abs(weight[off]).sum()), k + 1, child))
        scored.sort(key=lambda t: (-t[0], -t[1]))
        return [c for _, _, c in scored]

    def _repairs(self, z: np.ndarray, fixed: np.ndarray, natural: np.ndarray) -> list[np.ndarray]:
        """Complementary modes to try near the relaxed point ``z``: the natural sides; for
        energetic problems, every free friction contact sticking, then sliding on the edges
        most against its slip."""
        if not self._groups:
            return [natural]
        P = self.p
        v = P.C @ z - P.lo
        stick, slide = natural.copy(), natural.copy()
        for g, c in zip(self._groups, self._group_pair):
            free = g[fixed[g] < 0]
            if not len(free):
                continue
            if natural[c] == 0:  # separated: no friction force, any slip
                stick[free] = 0
                slide[free] = 0
                continue
            stick[free] = 1
            row = v[P.pairs[g, 1]]
            on = (row <= row.min() + COMP_TOL).astype(np.int8)
            slide[free] = on[fixed[g] < 0]
        return [stick, slide]

    # ------------------------------------------------------------------ solve
    def solve(self, guess: Mode | None = None) -> RawSolution:
        """The global optimum (canonical point of the optimal mode), or infeasibility.

        Args:
            guess: A mode tried first as incumbent (speed only: the answer does not depend on
                it except among exactly tied optima).
        """
        P = self.p
        self._nodes = self._qps = self._attempts = 0
        bad = P.empty_rows()
        if bad:
            msg = f"no contact force can produce the wrench component(s) {', '.join(bad)}"
            return RawSolution(status=INFEASIBLE, backend="bnb", message=msg)
        npair = len(P.pairs)
        best_obj, best_sides, best_z = INF, None, None
        if guess is not None:
            sides = P.sides_of(guess)
            res = self._qp(sides.astype(np.int8))
            if res.status is SolveStatus.OPTIMAL:
                best_obj, best_sides, best_z = res.objective, sides, res.z
        stack = _Open(P.kind.energetic)
        tried: set[bytes] = set()
        stack.append(np.full(npair, -1, np.int8), 0.0)
        limited = False
        while stack:
            if self._nodes >= self.max_nodes:
                limited = True
                break
            fixed, parent = stack.pop()
            if stack.best_first and self._pruned(parent, best_obj):
                continue
            res = self._qp(fixed)
            self._nodes += 1
            if res.status is SolveStatus.FAILED:
                # no verdict on this relaxation: its children cover every complementary point
                # of it, and fixing more pairs often makes the QP tractable; a leaf is a failure
                free = np.flatnonzero(fixed < 0)
                if not len(free):
                    return self._failed(f"a fixed-mode QP failed after {res.attempts} attempts")
                act = free[self._actuator[free]]
                k = int(act[0] if len(act) else free[0])
                for side in (0, 1):
                    child = fixed.copy()
                    child[k] = side
                    stack.append(child, parent)
                continue
            if res.status is SolveStatus.INFEASIBLE or self._pruned(res.objective, best_obj):
                continue
            viol = self._violation(res.point, fixed)
            natural = np.where(fixed >= 0, fixed, P.natural_sides(res.point)).astype(np.int8)
            if not np.any(viol > COMP_TOL):
                best_obj, best_sides, best_z = res.objective, natural, res.z
                continue
            for sides in self._repairs(res.point, fixed, natural):
                key = sides.tobytes()
                if key in tried:  # the same complete mode was solved before in this search
                    continue
                tried.add(key)
                rep = self._qp(sides)
                if rep.status is SolveStatus.OPTIMAL and rep.objective < best_obj:
                    best_obj, best_sides, best_z = rep.objective, sides, rep.z
                    break
            if self._pruned(res.objective, best_obj):
                continue
            for child in self._children(viol, fixed, natural, res.point):
                stack.append(child, res.objective)
        if best_sides is None:
            if limited:
                return RawSolution(
                    status=NODE_LIMIT, backend="bnb", message=f"node limit {self.max_nodes} reached"
                )
            return RawSolution(status=INFEASIBLE, backend="bnb", message=self._count_message())
        return self._final(best_sides, limited, best_z)

    def _pruned(self, bound: float, best: float) -> bool:
        return best < INF and bound >= best * (1.0 - REL_GAP) - ABS_GAP

    def _count_message(self) -> str:
        return f"{self._nodes} nodes, {self._qps} QPs, {self._attempts} DAQP calls"

    def _failed(self, why: str) -> RawSolution:
        return RawSolution(status=FAILED, backend="bnb", message=f"{why} ({self._count_message()})")

    def solve_mode(self, mode: Mode) -> RawSolution:
        """The canonical optimum of one fixed mode (``infeasible`` if the mode has no point).

        Used to polish a reference backend's answer: its mode is re-solved exactly here."""
        self._nodes = self._qps = self._attempts = 0
        return self._final(self.p.sides_of(mode), False, None)

    def _final(self, sides: np.ndarray, limited: bool, z_found: np.ndarray | None) -> RawSolution:
        """Canonical point of the optimal mode (``z_found``: the point the search found in it)."""
        P = self.p
        if z_found is None:
            res = self._qp(sides.astype(np.int8), polish=True)
            if res.status is SolveStatus.INFEASIBLE:
                return RawSolution(status=INFEASIBLE, backend="bnb", message="the mode has no feasible point")
            if res.status is not SolveStatus.OPTIMAL:
                return self._failed("the optimal mode's QP could not be re-solved")
            z_found = res.point
        else:
            _, up = P.bounds(sides.astype(np.int8))
            z_found = self.qp.polish(z_found, up)
        z = self._canonical(z_found, sides)
        mode = P.mode_of(sides)
        status = NODE_LIMIT if limited else OPTIMAL
        return RawSolution(
            status=status,
            z=z,
            mode=mode,
            objective=P.objective(z),
            backend="bnb",
            polished=True,
            message=self._count_message(),
            layout=P.layout,
        )

    def _canonical(self, z: np.ndarray, sides: np.ndarray) -> np.ndarray:
        """The canonical point of the optimal mode (docs/solvers.md, *The canonical optimum*).

        The optimal net wrench (or normal-force vector) ``L z + l`` is unique within a mode, but
        the point is not. Among the mode's points with ``L z = L z*`` the canonical one has the
        **largest step length** (single-direction movement steps: several step lengths often give
        the same optimal net wrench, and the smallest makes the scheme creep and stall under the
        1 % rule), then the **least spring energy** ``|c_n|^2`` (movement steps), then the
        **least norm** (a strictly convex QP, so ties between friction edges or joint null
        spaces are broken alike for mirror-symmetric grasps). Where those QPs fail the polished
        point is kept.
        """
        P = self.p
        _, up = P.bounds(sides.astype(np.int8))
        single = P.kind is ProblemKind.MOVE and P.rows.step.stop - P.rows.step.start == 1
        first = P.step_index if single else None
        cand = self.qp.least_norm(z, up, first, energy=P.kind is ProblemKind.MOVE)
        self._qps += 1
        return z if cand is None else cand
