"""A certified end of the quasi-static path: no continuation at all (a friction-induced snap).

When Lemke's method ray-terminates on the local rate problem under load control and under
displacement control, the LCP may still have a solution (Lemke's method decides only for
copositive-plus ``M``, and ``M`` is not with friction). For a small problem the question is
settled exactly by enumerating every complementary index set: if none of the ``2^n`` linear
systems gives ``z >= 0`` and ``w >= 0`` (by a margin, with every principal block well
conditioned), the LCP has no solution. Under both controls this means that no equilibrium path
leaves the state, neither with a growing nor with a falling load: typically a sliding contact
whose slip sheds its normal force faster than its friction polygon shrinks (the normal–
tangential coupling through the hand makes ``M`` lose positivity). The grasp then moves
dynamically — it gives way, as a softening limit does — so the path ends there with a limit,
status ``"unstable"`` (docs/hands.md, "When the quasi-static path has no continuation").
Anything short of a certificate (a larger problem, a nearly singular block, a candidate within
the tolerance) leaves the stop without a verdict, as before.
"""

from __future__ import annotations

import itertools

import numpy as np

from .model import QSModel
from .rates import FULL, Classes, Segment, StageCache, _items, _linear
from .state import StageSpec
from .statuses import SegmentStatus

#: Largest LCP whose complementary index sets are enumerated (2^n small solves).
MAX_ENUMERATED = 12
#: Condition number above which a principal block is taken as singular (no certificate).
BLOCK_COND = 1e10
#: Relative margin by which every candidate must fail for the certificate.
MARGIN_RTOL = 1e-9


def _lcp(qm: QSModel, spec: StageSpec, cls: Classes, sc: StageCache, control: str):
    """``(M, q)`` of the local rate problem at a state without zero-force contacts; None when
    its linear part is singular."""
    plan = np.full(qm.nc, FULL)
    sep = np.zeros(qm.nc, bool)
    rc = qm.row_contact
    ks = cls.pressed[rc] * (qm.kn_rows + qm.kt_rows) if spec.friction else cls.pressed[rc] * qm.kn_rows
    lin = _linear(qm, sc, spec, ks, _items(qm, cls, plan, sep, None), control)
    if isinstance(lin, Segment):
        return None
    _, _, _, W, M, _ = lin
    return M, W[:, 0]


def lcp_has_no_solution(M: np.ndarray, q: np.ndarray) -> bool:
    """True only when ``w = M z + q, 0 <= z ⟂ w >= 0`` provably has no solution: every
    complementary index set fails by a margin, every principal block well conditioned
    (``n <= MAX_ENUMERATED``). False means "not certified", not "solvable"."""
    n = q.size
    if n == 0 or n > MAX_ENUMERATED:
        return False
    mscale = max(float(np.abs(M).max(initial=0.0)), 1e-300)
    qscale = max(float(np.abs(q).max(initial=0.0)), 1e-300)
    for size in range(n + 1):
        for subset in itertools.combinations(range(n), size):
            B = np.array(subset, int)
            z = np.zeros(n)
            if size:
                Mbb = M[np.ix_(B, B)]
                if np.linalg.cond(Mbb) > BLOCK_COND:
                    return False
                z[B] = np.linalg.solve(Mbb, -q[B])
            w = M @ z + q
            w[B] = 0.0
            tol = MARGIN_RTOL * max(qscale, mscale * float(np.abs(z).max(initial=0.0)))
            if z.min(initial=0.0) >= -tol and w.min(initial=0.0) >= -tol:
                return False
    return True


def no_continuation(qm: QSModel, spec: StageSpec, cls: Classes, sc: StageCache) -> bool:
    """Whether the state has provably no quasi-static continuation: no zero-force contact
    (their plans would multiply the problems) and no solution of the local rate problem
    under load control nor under displacement control."""
    if cls.zero.any() or not np.any(spec.dw):
        return False
    for control in ("load", "displacement"):
        lcp = _lcp(qm, spec, cls, sc, control)
        if lcp is None or not lcp_has_no_solution(*lcp):
            return False
    return True


def unstable_segment() -> Segment:
    """The segment record of a certified end (status ``"unstable"``)."""
    return Segment(status=SegmentStatus.UNSTABLE, control="displacement", lam_rate=0.0)


__all__ = ["MAX_ENUMERATED", "lcp_has_no_solution", "no_continuation", "unstable_segment"]
