"""A certified end of the quasi-static path: no continuation at all (a friction-induced snap).

When Lemke's method ray-terminates on the local rate problem under load control and under
displacement control, the LCP may still have a solution (Lemke's method decides only for
copositive-plus ``M``, and ``M`` is not with friction). The question is settled by
:func:`~pinograsp.solvers.lcp_certificates.provably_unsolvable`: a Farkas certificate at any size (no flows
keep every slack rate nonnegative) or, for a small problem, every complementary index set
enumerated — none of the ``2^n`` linear systems gives ``z >= 0`` and ``w >= 0`` (by a margin;
a singular block by a small linear program, at bounded flows) — and the LCP has no solution.
Under both controls this means that no equilibrium path
leaves the state, neither with a growing nor with a falling load: typically a sliding contact
whose slip sheds its normal force faster than its friction polygon shrinks (the normal–
tangential coupling through the hand makes ``M`` lose positivity). The grasp then moves
dynamically — it gives way, as a softening limit does — so the path ends there with a limit,
status ``"unstable"`` (docs/hands.md, "When the quasi-static path has no continuation").
Anything short of a certificate (a larger feasible problem, a candidate within the tolerance)
leaves the stop without a verdict, as before.
"""

from __future__ import annotations

import numpy as np

from ...solvers.lcp_certificates import provably_unsolvable
from .model import QSModel
from .rates import FULL, Classes, Segment, StageCache, lcp_items, linear_part
from .state import StageSpec
from .statuses import SegmentStatus


def _lcp(qm: QSModel, spec: StageSpec, cls: Classes, sc: StageCache, control: str):
    """``(M, q)`` of the local rate problem at a state with every zero-force contact in the
    LCP by both its pairs (the plan :data:`~.rates.FULL`: it may open, or stay and slide, so
    the one LCP holds every continuation of every plan); None when its linear part is
    singular."""
    plan = np.full(qm.nc, FULL)
    sep = np.zeros(qm.nc, bool)
    rc = qm.row_contact
    touch = cls.pressed | cls.zero
    ks = touch[rc] * (qm.kn_rows + qm.kt_rows) if spec.friction else touch[rc] * qm.kn_rows
    lin = linear_part(qm, sc, spec, ks, lcp_items(qm, cls, plan, sep, None), control)
    if lin is None:
        return None
    return lin.M, lin.W[:, 0]


def no_continuation(qm: QSModel, spec: StageSpec, cls: Classes, sc: StageCache) -> bool:
    """Whether the state has provably no quasi-static continuation: no solution of the local
    rate problem under load control nor under displacement control, zero-force contacts
    free to open or to stay (:func:`_lcp`)."""
    if not np.any(spec.dw):
        return False
    for control in ("load", "displacement"):
        lcp = _lcp(qm, spec, cls, sc, control)
        if lcp is None or not provably_unsolvable(*lcp):
            return False
    return True


def unstable_segment() -> Segment:
    """The segment record of a certified end (status ``"unstable"``)."""
    return Segment(status=SegmentStatus.UNSTABLE, control="displacement", lam_rate=0.0)


__all__ = ["no_continuation", "unstable_segment"]
