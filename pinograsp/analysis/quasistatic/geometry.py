"""Geometry updates along the load stage: the object's finite rotation (docs/quasistatic.md,
"Large rotations").

The model's grasp map ``G`` holds the lever arms ``a_i`` of the contacts at rest. When the
object turns by ``R``, its material contact points move by ``(R - I) a_i`` — to first order
``theta x a_i`` (what ``G^T`` gives), to second order also ``-|theta|^2 a_perp / 2`` towards the
rotation axis — and the contact forces act at ``R a_i``. The simulation
(:func:`~pinograsp.simulate_max_wrench`) turns the object exactly, with the hand linearised and
the contact normals fixed in the world; at the give-way rotations of a loosely held object
(2–29 degrees) the second-order motion (millimetres) dwarfs the springs' deflections (microns)
and the linear path holds loads the turned grasp does not.

So the load stage re-linearises about the turned object every :data:`GEOMETRY_STEP` of
rotation: a new :class:`~.model.QSModel` whose ``A`` has the arms ``R_mid a_i`` (``R_mid``:
the rotation half a step ahead along the last segment's spin, a midpoint rule, so that the
second-order motion over a step is captured), and the **geometric stiffness** of the current
forces, ``d(sum_i R a_i x f_i)/dtheta = sum_i [f_i]x [R a_i]x`` (the moment of the contact
forces about the turning object changes as their arms turn: a squeezed object destabilised as
it turns), which enters the tangent stiffness as ``A k A^T - K_G``. Rates within a step are
those of that linear model; its equilibrium invariant ``G c + K_G (x - x_ref) + w`` is what
the audit checks per state (``e_ref``: its value at the update). Hand kinematics stay linear,
as in the simulation. Paths whose object turns less than one step are unchanged.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ...core.axes import PLANAR_AXES
from ...core.giveway import LINEAR_ROTATION
from .model import Constraints, QSModel, evolved, lazy_products
from .state import State

#: Object rotation [rad] between two geometry updates of the load stage (chosen by measurement:
#: docs/quasistatic.md, "Large rotations").
GEOMETRY_STEP = 0.005
#: Total object rotation [rad] beyond which the geometry is no longer updated (the path then
#: ends its resisted range there: :data:`~pinograsp.core.giveway.LINEAR_ROTATION`).
GEOMETRY_MAX = LINEAR_ROTATION


@dataclass(frozen=True)
class GeometryUpdates:
    """When the load stage re-linearises about the turned object.

    Attributes:
        scale: Physical displacement per model displacement (``max(k) / contact_stiffness``:
            the path's displacements are those of the model's own ``k``; the object turns by
            ``scale`` times its model rotation at the chosen contact stiffness).
        step: Object rotation between updates [rad].
        max_rotation: No update beyond this total rotation [rad].
        until: No update above this load [N or N·m] (the largest load of interest).
        max_translation: No update beyond this translation of the object [m] (with
            ``max_rotation``: the give-way thresholds, past which the path's answer is decided).
        min_step, max_step: Bounds of the adapted step [rad] (:meth:`adapted`).
    """

    scale: float = 1.0
    step: float = GEOMETRY_STEP
    max_rotation: float = GEOMETRY_MAX
    until: float = float("inf")
    max_translation: float = float("inf")
    min_step: float = GEOMETRY_STEP / 20
    max_step: float = GEOMETRY_STEP

    def adapted(self, step: float, before: float, after: float) -> float:
        """The next step [rad] after one of ``step``, from the compliance along the load
        ``before`` and ``after`` the update ([m/N] in any positive scale): where the grasp
        softens, a quarter of the rotation left to the limit that the stiffness ``1 /
        compliance`` falling at this rate predicts, at most :attr:`step` (the steps shrink as a
        limit comes near, so that it is located within a small step); where it does not (an
        object turning steadily as it holds), twice the step, at most ``max_step``."""
        if not (np.isfinite(before) and np.isfinite(after)) or before <= 0.0 or after <= 0.0:
            return self.min_step
        s0, s1 = 1.0 / before, 1.0 / after
        if s1 >= s0:  # not softening: the step may grow
            return float(min(self.max_step, 2.0 * step))
        return float(min(self.step, max(self.min_step, 0.25 * step * s1 / (s0 - s1))))


def _axes6(qm: QSModel) -> list[int]:
    """The 6D axis of each of the model's object coordinates."""
    return list(PLANAR_AXES) if qm.model.planar else list(range(qm.nx))


@dataclass(frozen=True, eq=False)
class _Constants:
    """What a geometry update reads of the model and never changes along a path (kept once per
    model on :attr:`QSModel.geometry_constants`; speed only).

    Attributes:
        arms0: Contact points less the reference point (nc, 3) [m] (the arms at rest).
        F: The contact frames' first ``d`` columns (nc, 3, d).
        force_rows: The rows of the grasp map on the force axes (nx, nc*d), zero elsewhere.
        moment: The object coordinates on the moment axes (m,) (a slice when contiguous) and,
            for each, the two arm components ``i1``, ``i2`` (m,) and the frame rows
            ``F[:, i2]``, ``F[:, i1]`` (nc, m, d) of its cross product: its row is
            ``a[i1] F[i2] - a[i2] F[i1]``.
        rows, axes: The rotation coordinates (k,) and their world axes (k,) (slices when
            contiguous).
        S_rot: ``S`` of the rotation coordinates (k,); S_col: ``S[:nx, None]``;
            S_outer: ``outer(S[:nx], S[:nx])``.
        full_spin: Whether the rotation coordinates are the three world axes in order.
    """

    arms0: np.ndarray
    F: np.ndarray
    force_rows: np.ndarray
    moment: tuple[np.ndarray | slice, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    rows: np.ndarray | slice
    axes: np.ndarray | slice
    S_rot: np.ndarray
    S_col: np.ndarray
    S_outer: np.ndarray
    full_spin: bool


def _constants(qm: QSModel) -> _Constants:
    """The model's :class:`_Constants` (computed on the first update, then shared by every
    model re-linearised from it: :func:`~.model.evolved` copies the field)."""
    got = qm.geometry_constants
    if isinstance(got, _Constants):
        return got
    m = qm.model
    F = np.asarray(m.frames, float)[:, :, : qm.d]
    axes6 = list(PLANAR_AXES) if m.planar else list(range(qm.nx))  # _axes6 (no call: the call budget)
    force_rows = np.zeros((qm.nx, qm.ncd))
    mom_at, i1, i2 = [], [], []
    for i, axis in enumerate(axes6):
        if axis < 3:
            force_rows[i] = F[:, axis].reshape(-1)
        else:
            mom_at.append(i)
            i1.append((axis - 2) % 3)
            i2.append((axis - 1) % 3)
    rows, axes = _rows_of(bool(m.planar), qm.nx)
    at, r, a = (  # contiguous increasing index ranges as slices (the same elements)
        slice(int(i[0]), int(i[-1]) + 1) if len(i) and bool(np.all(np.diff(i) == 1)) else i
        for i in (np.array(mom_at, int), rows, axes)
    )
    S = qm.S
    out = _Constants(
        arms0=np.asarray(m.points, float) - np.asarray(m.reference_point, float),
        F=F,
        force_rows=force_rows,
        moment=(at, np.array(i1, int), np.array(i2, int), F[:, i2], F[:, i1]),
        rows=r,
        axes=a,
        S_rot=S[rows],
        S_col=S[: qm.nx, None],
        S_outer=np.outer(S[: qm.nx], S[: qm.nx]),
        full_spin=len(axes) == 3 and bool(np.all(axes == np.arange(3))),
    )
    object.__setattr__(qm, "geometry_constants", out)
    return out


@functools.cache
def _rows_of(planar: bool, nx: int) -> tuple[np.ndarray, np.ndarray]:
    axes = np.array(list(PLANAR_AXES) if planar else list(range(nx)))
    rows = (axes >= 3).nonzero()[0]
    rows.setflags(write=False)
    out = axes[rows] - 3
    out.setflags(write=False)
    return rows, out


def _rotation_rows(qm: QSModel) -> tuple[np.ndarray, np.ndarray]:
    """The model's object coordinates that are rotations (k,) and their world axes (k,)
    (read-only: two shapes of model, planar or not, so kept once)."""
    return _rows_of(bool(qm.model.planar), qm.nx)


def _spin(k: _Constants, dvs: np.ndarray) -> np.ndarray:
    """:func:`spin` with the model's constants."""
    if k.full_spin:
        return dvs[k.rows] / k.S_rot
    out = np.zeros(3)
    out[k.axes] = dvs[k.rows] / k.S_rot
    return out


def spin(qm: QSModel, dvs: np.ndarray) -> np.ndarray:
    """The object rotation (3,) [rad], world frame, of a scaled displacement (change) ``dvs``."""
    return _spin(_constants(qm), dvs)


#: The identity (3, 3), read-only.
_I3 = np.eye(3)
_I3.setflags(write=False)


def rotation_matrix(theta: np.ndarray) -> np.ndarray:
    """``exp([theta]x)`` (3, 3) of a rotation vector ``theta`` (3,) [rad] (Rodrigues)."""
    theta = np.asarray(theta, float).ravel()
    angle = math.sqrt(theta.dot(theta))  # np.linalg.norm's own arithmetic
    if angle == 0.0:
        return np.eye(3)
    k0, k1, k2 = (theta / angle).tolist()
    K = np.array([[0.0, -k2, k1], [k2, 0.0, -k0], [-k1, k0, 0.0]])
    return _I3 + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def _turned(qm: QSModel, k: _Constants, vs: np.ndarray, scale: float) -> np.ndarray:
    """:func:`turned` with the model's constants."""
    if qm.vs_ref is None:  # vs - 0 is vs, bit for bit
        theta = scale * _spin(k, vs)
    else:
        theta = scale * _spin(k, vs - qm.vs_ref)
    base = qm.rot if qm.rot is not None else np.eye(3)
    return rotation_matrix(theta) @ base


def turned(qm: QSModel, vs: np.ndarray, scale: float) -> np.ndarray:
    """The object's physical rotation (3, 3) at the scaled displacements ``vs`` (nv,) of a
    path on ``qm``: the rotation at its last update composed with the spin since (``scale``:
    :attr:`GeometryUpdates.scale`)."""
    return _turned(qm, _constants(qm), vs, scale)


def _arms(qm: QSModel, R: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The contact arms turned by ``R`` (nc, 3) [m] and the contact frames (nc, 3, d)."""
    k = _constants(qm)
    return k.arms0 @ R.T, k.F


def _grasp_map(qm: QSModel, arms: np.ndarray, F: np.ndarray) -> np.ndarray:
    """The grasp map (nx, nc*d): the constant force rows, and on each moment axis the rows of
    ``a_i x`` each column of ``F_i`` (``F``: the model's frames, :attr:`_Constants.F`)."""
    k = _constants(qm)
    out = k.force_rows.copy()
    at, i1, i2, F2, F1 = k.moment
    if len(i1):
        if F is not k.F:  # other frames than the model's
            F2, F1 = F[:, i2], F[:, i1]
        cross = arms[:, i1, None] * F2 - arms[:, i2, None] * F1  # (nc, m, d)
        out[at] = cross.transpose(1, 0, 2).reshape(len(i1), -1)
    return out


def _geometric_stiffness(qm: QSModel, arms: np.ndarray, F: np.ndarray, c: np.ndarray) -> np.ndarray:
    f = np.einsum("iad,id->ia", F, c.reshape(qm.nc, qm.d))
    K3 = np.einsum("ia,ib->ab", arms, f) - float(np.einsum("ia,ia->", arms, f)) * _I3
    k = _constants(qm)
    out = np.zeros((qm.nx, qm.nx))
    if isinstance(k.rows, slice) and isinstance(k.axes, slice):
        out[k.rows, k.rows] = K3[k.axes, k.axes]
    else:
        rows, axes = _rotation_rows(qm)
        out[rows[:, None], rows] = K3[axes[:, None], axes]
    return out


def grasp_map(qm: QSModel, R: np.ndarray) -> np.ndarray:
    """The grasp map (nx, nc*d) [1, m] with the contact arms turned by ``R`` (3, 3) (normals
    fixed in the world, as in the simulation)."""
    return _grasp_map(qm, *_arms(qm, R))


def geometric_stiffness(qm: QSModel, R: np.ndarray, c: np.ndarray) -> np.ndarray:
    """``d(G(R) c)/dtheta`` (nx, nx) [N·m/rad on the rotation block, 0 elsewhere] of contact forces
    ``c`` (nc*d,) [N] at arms turned by ``R``: ``sum_i [f_i]x [R a_i]x`` (``f_i`` world)."""
    return _geometric_stiffness(qm, *_arms(qm, R), c)


def _with_arms(con: Constraints, A: np.ndarray) -> Constraints:
    """``con`` for the re-linearised ``A`` (nv, nc*d): the constraint columns, their basis and
    pseudo-inverses do not depend on the contact geometry, only their products with ``A``."""
    return evolved(con, AZ=A.T @ con.Z, AtBt=A.T @ con.Bt_pinv, BpA=con.B_pinv @ A)


def moved(
    qm: QSModel, st: State, w: np.ndarray, ahead: np.ndarray, scale: float, dc: np.ndarray | None = None
) -> QSModel:
    """The model re-linearised at the state ``st`` of a path on ``qm`` under the reduced load
    ``w`` (nx,): arms turned half of ``ahead`` (3,) [rad] beyond the current rotation
    (:func:`turned`), the geometric stiffness there of the contact forces half-way along the
    predicted force change ``dc`` (nc*d,) over the step (per model radian: ``scale`` times the
    physical one), and the references of the incremental gaps and of the equilibrium
    invariant at ``st``."""
    k = _constants(qm)
    R = _turned(qm, k, st.vs, scale)
    R_mid = rotation_matrix(0.5 * ahead) @ R
    arms = k.arms0 @ R_mid.T
    G = _grasp_map(qm, arms, k.F)
    nx = qm.nx
    A = qm.A.copy()
    A[:nx] = G / k.S_col
    c_mid = st.c if dc is None else st.c + 0.5 * dc
    KGp = scale * _geometric_stiffness(qm, arms, k.F, c_mid)
    KG = np.zeros((qm.nv, qm.nv))
    KG[:nx, :nx] = KGp / k.S_outer
    return evolved(
        qm,
        A=A,
        free=_with_arms(qm.free, A),
        held=lazy_products(qm.held, A),
        KG=KG,
        KGp=KGp,
        rot=R,
        turn=float(np.arccos(min(max((R[0, 0] + R[1, 1] + R[2, 2] - 1.0) / 2.0, -1.0), 1.0))),
        vs_ref=st.vs.copy(),
        gap_ref=qm.gaps(st.vs),
        e_ref=G @ st.c + w,
    )


def _may_update(qm: QSModel, st: State, geo: GeometryUpdates) -> bool:
    """Whether ``geo`` allows an update at ``st`` (below ``until``, within the rotation and
    translation bounds)."""
    if st.t > geo.until:
        return False
    x = st.vs[:3]
    return not (qm.turn >= geo.max_rotation or geo.scale * math.sqrt(x.dot(x)) >= geo.max_translation)


def step_to_update(
    qm: QSModel, st: State, dvs: np.ndarray, geo: GeometryUpdates, load_rate: float, step: float
) -> float:
    """The step along a segment with rates ``dvs`` from ``st`` at which the object has turned
    ``step`` [rad] since the last update (``inf``: never, or not within ``geo``'s limits)."""
    k = _constants(qm)
    b = geo.scale * _spin(k, dvs)
    bb = float(b @ b)
    if bb == 0.0:
        return float("inf")
    if not _may_update(qm, st, geo):
        return float("inf")
    a = geo.scale * _spin(k, st.vs if qm.vs_ref is None else st.vs - qm.vs_ref)  # vs - 0 is vs
    ab, aa = float(a @ b), float(a @ a)
    disc = ab * ab - bb * (aa - step**2)
    t = (-ab + math.sqrt(max(disc, 0.0))) / bb
    if load_rate > 0 and math.isfinite(geo.until):
        t = t if st.t + t * load_rate <= geo.until else float("inf")
    return max(float(t), 0.0)


__all__ = [
    "GEOMETRY_MAX",
    "GEOMETRY_STEP",
    "GeometryUpdates",
    "geometric_stiffness",
    "grasp_map",
    "moved",
    "rotation_matrix",
    "spin",
    "step_to_update",
    "turned",
]
