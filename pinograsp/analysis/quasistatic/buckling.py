"""Buckling on a ray: the load at which the grasp's tangent stiffness stops holding a motion.

A path whose last segment has no event ahead is a ray: it is "unbounded" when nothing ends it.
Its rates come from the tangent stiffness under load control, which gives finite rates as long
as that stiffness is invertible — also when it is no longer positive. The geometric stiffness
of the contact forces (:mod:`~.geometry`) grows with the load along the ray; where a motion has
no spring against it (an object pressed onto the single line of one jaw after the other jaw has
let go: it can turn about that line), the compressed forces make its stiffness negative and the
grasp tips over, however the load is aimed. The path's geometry updates see that only once the
object has turned a step; a load aimed exactly across the motion never turns it.

:func:`ray_buckling` finds the first load on a ray at which the symmetric part of the reduced
tangent stiffness has a negative eigenvalue, with every touching contact a spring (normal and
tangential; a contact at zero force only normal, since it carries no friction), every
non-backdrivable actuator held, and the geometric stiffness of the ray's contact forces. That
stiffness is at least the true one (sliding and moving actuators only soften the grasp), so a
negative eigenvalue there certifies a motion nothing holds: the path ends with a limit (status
``"unstable"``) at that load. A zero eigenvalue (a free motion the load does not drive, such as
a spin about the chord of two points) is not a buckling.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh

from .geometry import GeometryUpdates, geometric_stiffness, turned
from .model import QSModel
from .rates import Segment, StageCache, State, separated_on

#: A negative eigenvalue below this fraction of the largest spring stiffness on the free motions
#: (rounding of an exact mechanism stays above it).
BUCKLING_RTOL = 1e-8


def _reduced(qm: QSModel, sc: StageCache, K: np.ndarray) -> np.ndarray:
    """The symmetric part of ``Z^T K Z`` for an object-block matrix ``K`` (nx, nx) [N·m/rad
    on the rotations], in the scaled coordinates of the allowed motions ``Z``."""
    S = qm.S[: qm.nx]
    Zx = sc.Z[: qm.nx] / S[:, None]
    out = Zx.T @ K @ Zx
    return 0.5 * (out + out.T)


def ray_buckling(qm: QSModel, st: State, seg: Segment, sc: StageCache, geo: GeometryUpdates) -> float | None:
    """The step ``t >= 0`` along the ray ``seg`` from ``st`` (path parameter) at which the grasp
    buckles, or ``None`` (positive stiffness all along the ray)."""
    AZ = sc.AZ
    if AZ.shape[1] == 0:
        return None
    touching = ~separated_on(seg)
    zero = touching & (np.abs(st.c[:: qm.d]) <= 0.0)
    rc = qm.row_contact
    ks = touching[rc] * qm.kn_rows + (touching & ~zero)[rc] * qm.kt_rows
    springs = AZ.T @ (AZ * ks[:, None])
    scale = float(np.abs(np.diag(springs)).max(initial=0.0))
    if not scale > 0.0:
        return None
    R = turned(qm, st.vs, geo.scale)
    now = springs - geo.scale * _reduced(qm, sc, geometric_stiffness(qm, R, st.c))
    tol = BUCKLING_RTOL * scale
    if float(np.linalg.eigvalsh(now)[0]) < -tol:
        return 0.0
    rate = geo.scale * _reduced(qm, sc, geometric_stiffness(qm, R, seg.dc))
    # now - t rate loses positivity at t = 1 / nu for the largest nu of rate v = nu now v
    shift = now + tol * np.eye(len(now))  # positive definite: the pencil's metric
    nu = float(eigh(rate, shift, eigvals_only=True)[-1])
    if not nu > 0.0:
        return None
    return 1.0 / nu


__all__ = ["BUCKLING_RTOL", "ray_buckling"]
