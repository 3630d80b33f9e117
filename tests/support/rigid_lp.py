"""A toy method added by the recipe of docs/design.md, "Adding a method": its row (:data:`SPEC`)
and this module, nothing else. Registered by the tests only (tests/test_method_recipe.py).

``rigid_lp``: rigid contacts and a rigid hand, one LP over the friction-edge weights ``beta``,
the actuator forces ``f`` and the coupling forces ``nu``: the largest ``lam`` with

    G D beta + lam w = 0          (the object balances the load lam w)
    J^T D beta = R f + C^T nu     (the hand balances the contact forces)
    beta >= 0,  0 <= f <= f_c     (forces in the friction pyramids, actuators up to their commands)

A load ``w`` is resisted when ``lam = 1`` is feasible. No preload stage (preload and load are
one problem: the variant ``"single-step"``), and the limit is exact (``upper``/``steps`` do not
apply).
"""

from __future__ import annotations

import time

import numpy as np
from scipy.optimize import linprog

from pinograsp.analysis.method_base import MethodBase
from pinograsp.analysis.protocols import LimitQuery, SessionLike
from pinograsp.core.methods import MethodSpec
from pinograsp.core.model import GraspModel
from pinograsp.core.results import MaxWrench, PassiveResponse
from pinograsp.core.settings import Search, Variant

SPEC = MethodSpec(
    name="rigid_lp",
    searches=(Search.DIRECT,),
    implementation="support.rigid_lp:RigidLpMethod",
    help="rigid contacts and hand, one LP over the contact forces",
    bounded=False,
    limit_text="the largest load of one LP over the contact forces (exact; upper and steps do not apply)",
    variants=(Variant.SINGLE_STEP,),
    default_variant=Variant.SINGLE_STEP,
    preload_stage=False,
)


def solve_lp(
    m: GraspModel, fc: np.ndarray, w: np.ndarray, fixed: float | None
) -> tuple[str, float, np.ndarray]:
    """``("optimal", lam, x)``, ``("unbounded", inf, x)`` or ``("infeasible", nan, x)`` of the LP
    above for the reduced load ``w`` (nw,); ``fixed``: ``lam`` held at that value (feasibility)."""
    nb, na, ncp = m.nb, m.na, m.ncp
    n = nb + na + ncp + 1
    a_obj = np.hstack([m.G @ m.D, np.zeros((m.nw, na + ncp)), w[:, None]])
    a_hand = np.hstack([m.J.T @ m.D, -m.R, -m.C.T, np.zeros((m.nq, 1))])
    bounds = [(0.0, None)] * nb + [(0.0, float(f)) for f in fc] + [(None, None)] * ncp
    bounds.append((fixed, fixed) if fixed is not None else (0.0, None))
    cost = np.zeros(n)
    cost[-1] = -1.0
    res = linprog(
        cost, A_eq=np.vstack([a_obj, a_hand]), b_eq=np.zeros(m.nw + m.nq), bounds=bounds, method="highs"
    )
    if res.status == 3:
        return "unbounded", float("inf"), np.zeros(n)
    if res.status != 0:
        return "infeasible", float("nan"), np.full(n, np.nan)
    return "optimal", float(res.x[-1]), res.x


class RigidLpMethod(MethodBase):
    """``method="rigid_lp"``: differs from the base in its response and its largest load only."""

    def response(self, session: SessionLike, fc: np.ndarray, w6: np.ndarray) -> PassiveResponse:
        """The LP's forces at ``w6`` (``"resisted"``) or NaN (``"not_resisted"``)."""
        m = session.model
        status, _, x = solve_lp(m, fc, m.reduce_wrench(np.asarray(w6, float)), 1.0)
        ok = status == "optimal"
        c = m.D @ x[: m.nb]
        cf = np.zeros((m.nc, 3))
        cf[:, : m.d] = c.reshape(m.nc, m.d)
        zero = np.zeros
        return PassiveResponse.of_model(
            m,
            resistible=ok,
            status="resisted" if ok else "not_resisted",
            method=self.name,
            variant=self.default_variant.value,
            wrench=np.asarray(w6, float),
            command=np.asarray(fc, float),
            contact_forces=cf,
            contact_forces_world=m.world_forces(c),
            joint_torques=m.J.T @ c,
            actuator_forces=x[m.nb : m.nb + m.na],
            coupling_forces=x[m.nb + m.na : m.nb + m.na + m.ncp],
            object_displacement=zero(6),
            joint_displacements=zero(m.nq),
            actuator_displacements=zero(m.na),
            contact_modes=tuple("touching" if v > 0 else "separated" for v in cf[:, 0]),
            actuator_modes=("holding",) * m.na,
            net_wrench=m.expand_wrench(m.G @ c + m.reduce_wrench(np.asarray(w6, float))),
            audit=None,
            solver="highs",
            n_solves=1,
        )

    def max_load(self, session: SessionLike, query: LimitQuery) -> MaxWrench:
        """The LP's largest ``lam`` along ``query.direction`` (one solve, exact)."""
        m = session.model
        fc = m.command_vector(query.command)
        status, lam, _ = solve_lp(m, fc, m.reduce_wrench(query.direction), None)
        kind = "unbounded" if status == "unbounded" else ("finite" if lam > 0 else "below_resolution")
        magnitude = lam if kind == "finite" else (float("inf") if kind == "unbounded" else 0.0)
        finite = np.isfinite(magnitude) and magnitude > 0
        response = self.response(session, fc, magnitude * query.direction) if finite else None
        return MaxWrench(
            direction=query.direction,
            magnitude=magnitude,
            unbounded=kind == "unbounded",
            status=kind,
            floor=query.floor,
            upper=float("inf"),
            resolution=0.0,
            evidence=((magnitude, True),),
            method=self.name,
            solve_time=0.0,
            wall_time=time.perf_counter() - query.t0,
            n_solves=query.tally.n_solves + 1,
            response=response,
            search=query.search.value,
        )
