"""The linear part of the local rate problem: what is constant along a stage
(:class:`StageCache`) and the displacement and load rates as affine maps of the flows, through
the motions the constraints allow (Cholesky of the reduced tangent stiffness) or, for
mechanisms and redundant constraints, a least-norm SVD solve of the whole bordered system."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.linalg.lapack import dgetrf, dgetrs, dpotrf, dpotrs

from .model import RANK_RTOL, QSModel, evolved
from .state import StageSpec

#: Relative residual above which a linear solve is taken as having no solution (singular
#: system whose right-hand side is outside its range). The same size as the audit's allowance
#: for a load's rounding-level part along a free motion (``api.UNBALANCED_RTOL``, 1e-5): a
#: two-fingertip grasp of a ball whose contact chord passes microns from the centre (3.4e-6 N
#: per N along the free spin) answers instead of stopping at load 0 (1e-6 before).
RANGE_RTOL = 1e-5
#: Relative squared pivot of the Cholesky factor below which the stiffness is singular.
CHOL_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class StageCache:
    """What is constant along a stage: the constraint columns ``B`` (nv, ncon) (actuators
    that are not backdrivable, couplings, the holder), the owner of each column (actuator
    index; -1 coupling; -2 holder), a basis ``Z`` of the motions they allow, ``pinv(B^T)``
    and ``pinv(B)``, the load per unit parameter ``r0`` (nv,) and its direction ``crow``."""

    B: np.ndarray
    owner: np.ndarray
    Z: np.ndarray
    Bt_pinv: np.ndarray
    B_pinv: np.ndarray
    r0: np.ndarray
    crow: np.ndarray | None
    col_of: dict
    col_arr: np.ndarray
    act_cols: np.ndarray
    coupling_cols: np.ndarray
    holder_cols: np.ndarray
    AZ: np.ndarray
    AtBt: np.ndarray
    BpA: np.ndarray
    Bpr0: np.ndarray
    Ztr0: np.ndarray
    cz: np.ndarray | None
    r0max: float = 0.0  # largest |r0| (speed only)
    #: The stage's load and command rates as forces: the largest scaled load rate and command
    #: rate [N], the scaled load rate (nx,), its norm [N], whether the stage loads the object
    #: (what the segment loop reads of the spec; :func:`stage_rates`).
    rates: tuple[float, float, np.ndarray, float, bool] = (0.0, 0.0, np.zeros(0), 0.0, False)
    #: ``Z^T K_G Z`` of a model with a geometric stiffness (None without: speed only).
    ZtKGZ: np.ndarray | None = None
    #: The contacts' spring stiffness per force row (ncd,) [N/m]: normal, and tangential
    #: where the stage has friction (what a touching contact contributes; speed only).
    k_rows: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: Factors of the reduced tangent stiffness by spring rows ``ks.tobytes()`` (None: it is
    #: singular): the segments of one geometry with the same touching contacts share them
    #: (speed only; a new geometry starts an empty one, :meth:`rebased`).
    factors: dict | None = None
    #: The actuator owning each actuator column and its norm ``r_norm`` (speed only).
    act_owner: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    act_rnorm: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: ``pinv(B^T) / k_ref`` (nv, ncon) and the command rates as forces ``r_norm * dfc`` (na,)
    #: (speed only).
    Bt_pinv_k: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    rdfc: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: ``ks[:, None] * AtBt / k_ref`` by spring rows ``ks.tobytes()`` (:func:`spring_act`).
    springs: dict | None = None
    #: Per unit flow of each LCP item code (opening of contact ``i``: ``i``; face ``f``:
    #: ``nc + f``; actuator ``a``: ``nc + nf + a``), then one zero column for the load: the
    #: contact force rates before the springs' share of an actuator's motion (a unit normal
    #: rate for an opening, ``PhiT_t``, ``dc_t = -nu``, for a face, zero for an actuator)
    #: (ncd, nc + nf + na + 1) and the particular motion ``pinv(B^T) / k_ref`` of the
    #: actuator's column (zero else) (nv, nc + nf + na + 1) (speed only: one gather each).
    f_items: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    vp_items: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    #: The spring rows ``ks`` (ncd,) by touching contacts ``touch.tobytes()`` (speed only).
    ks_of: dict | None = None
    #: Per actuator its label on a segment where it does not move: ``"holding"`` if it is not
    #: backdrivable, else its kind; and ``spec.dfc`` of the backdrivable ones (speed only).
    act_still: tuple[str, ...] = ()
    dfc_bd: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: Per face row its contact and its index on the contact (speed only).
    face_owner_index: tuple[tuple[int, int], ...] = ()
    #: The load rates of load control, ``(1, 0, ...)`` (nc + nf + na + 1,) (read-only; speed only).
    e0: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @classmethod
    def of(cls, qm: QSModel, spec: StageSpec) -> StageCache:
        """The cache of ``spec`` on ``qm`` (its constraints: the model's, free or held)."""
        nv, nx = qm.nv, qm.nx
        con = qm.held if spec.held else qm.free
        r0 = np.zeros(nv)
        r0[:nx] = qm.w_scaled(spec.dw)
        if qm.na and np.any(qm.bd):
            r0[nx:] = qm.Rn[:, qm.bd] @ (qm.r_norm[qm.bd] * spec.dfc[qm.bd])
        size = float(np.linalg.norm(r0[:nx]))
        crow = r0[:nx] / size if size > 0 else None
        Z = con.Z
        act_owner = con.owner[con.owner >= 0]
        Bt_pinv_k = con.Bt_pinv / qm.k_ref
        nc, nf = qm.nc, qm.nf
        f_items = np.zeros((qm.ncd, nc + nf + qm.na + 1))
        f_items[np.arange(nc) * qm.d, np.arange(nc)] = 1.0
        f_items[:, nc : nc + nf] = qm.PhiT_t
        vp_items = np.zeros((nv, nc + nf + qm.na + 1))
        if con.B.shape[1]:
            vp_items[:, nc + nf : -1] = Bt_pinv_k[:, con.col_arr]
        e0 = np.zeros(nc + nf + qm.na + 1)
        e0[0] = 1.0
        e0.setflags(write=False)
        still = ["holding" if n else kind for n, kind in zip(qm.nbd.tolist(), qm.model.kinds)]
        return cls(
            con.B,
            con.owner,
            Z,
            con.Bt_pinv,
            con.B_pinv,
            r0,
            crow,
            con.col_of,
            col_arr=con.col_arr,
            act_cols=con.owner >= 0,
            coupling_cols=con.owner == -1,
            holder_cols=con.owner == -2,
            AZ=con.AZ,
            AtBt=con.AtBt,
            BpA=con.BpA,
            Bpr0=con.B_pinv @ r0,
            Ztr0=Z.T @ r0,
            cz=None if crow is None else Z[:nx].T @ crow,
            r0max=float(np.abs(r0).max(initial=0.0)),
            rates=stage_rates(qm, spec),
            ZtKGZ=None if qm.KG is None else Z.T @ qm.KG @ Z,
            k_rows=qm.kn_rows + qm.kt_rows if spec.friction else qm.kn_rows,
            factors={},
            act_owner=act_owner,
            act_rnorm=qm.r_norm[act_owner],
            Bt_pinv_k=Bt_pinv_k,
            rdfc=qm.r_norm * spec.dfc,
            springs={},
            f_items=f_items,
            vp_items=vp_items,
            ks_of={},
            act_still=tuple(still),
            dfc_bd=spec.dfc[qm.bd],
            face_owner_index=tuple(zip(qm.face_contact.tolist(), qm.face_index.tolist())),
            e0=e0,
        )

    def rebased(self, qm: QSModel, spec: StageSpec) -> StageCache:
        """This cache for ``qm``, the same model re-linearised at a turned object
        (``geometry.moved``): only the products with ``A`` and the geometric stiffness change."""
        con = qm.held if spec.held else qm.free
        return evolved(
            self,
            AZ=con.AZ,
            AtBt=con.AtBt,
            BpA=con.BpA,
            ZtKGZ=None if qm.KG is None else self.Z.T @ qm.KG @ self.Z,
            factors={},
            springs={},
        )


def stage_rates(qm: QSModel, spec: StageSpec) -> tuple[float, float, np.ndarray, float, bool]:
    """What the segment loop reads of ``spec`` and never changes along it: the largest scaled
    load rate and command rate [N], the scaled load rate (nx,), its norm [N], whether the stage
    loads the object (kept on :class:`StageCache`)."""
    r0 = qm.w_scaled(spec.dw)
    return (
        float(np.abs(r0).max(initial=0.0)),
        float(np.abs(spec.dfc * qm.r_norm).max(initial=0.0)),
        r0,
        float(np.linalg.norm(r0)),
        bool(np.any(spec.dw)),
    )


def affine_reduced(qm, sc, ks, Fm, Vp, control):
    """Displacement rates ``V`` (nv, 1+nz) and load rates ``lam`` (1+nz,) as affine maps of
    the flows, through the allowed motions ``Z`` and a Cholesky factor; None when the
    stiffness on them is (nearly) singular. ``Fm``: contact force rates per column before the
    motions (flows minus the springs' share of the actuator flows' particular motion)."""
    AZ = sc.AZ
    if AZ.shape[1] == 0:
        return None
    factor = _factor(qm, sc, ks)
    if factor is None:
        return None
    rhs = AZ.T @ Fm
    rhs[:, 0] += sc.Ztr0
    if qm.KG is None:
        Y, info = dpotrs(factor[0], rhs, lower=1)
    else:
        Y, info = dgetrs(factor[0], factor[1], rhs + sc.Z.T @ (qm.KG @ Vp))
    if info != 0:
        return None
    nz1 = Y.shape[1]
    if control == "load":
        lam = sc.e0[:nz1]
    else:
        lam = np.zeros(nz1)
        along = float(sc.cz @ Y[:, 0])  # the load column has no actuator flow
        if not abs(along) > 0:
            return None
        rest = sc.cz @ Y[:, 1:] + (Vp[: qm.nx, 1:].T @ sc.crow)
        lam[0] = 1.0 / along
        lam[1:] = -rest / along
        Y = np.outer(Y[:, 0], lam) + np.concatenate([np.zeros((Y.shape[0], 1)), Y[:, 1:]], axis=1)
        Vp = np.outer(Vp[:, 0], lam) + np.concatenate([np.zeros((Vp.shape[0], 1)), Vp[:, 1:]], axis=1)
    return sc.Z @ Y + Vp, lam, AZ @ Y


def spring_act(sc: StageCache, ks: np.ndarray, k: float) -> np.ndarray:
    """The contact springs' force rows per unit actuator flow, ``ks[:, None] * AtBt / k``
    (ncd, ncon), for the spring rows ``ks`` (ncd,) [N/m] and the reference stiffness ``k``
    [N/m]: kept on ``sc`` per ``ks``."""
    key = ks.tobytes()
    cache = sc.springs
    if cache is not None and key in cache:
        return cache[key]
    out = ks[:, None] * sc.AtBt / k
    if cache is not None:
        cache[key] = out
    return out


def _factor(qm: QSModel, sc: StageCache, ks: np.ndarray) -> tuple[np.ndarray, ...] | None:
    """The factor of the reduced tangent stiffness ``Z^T (A diag(ks) A^T - K_G) Z`` with the
    spring rows ``ks`` (ncd,): Cholesky ``(L,)`` without a geometric part, LU ``(lu, piv)``
    with one (not symmetric); None when it is (nearly) singular (relative pivot bar
    :data:`CHOL_RTOL`). Kept on ``sc`` per ``ks``."""
    key = ks.tobytes()
    cache = sc.factors
    if cache is not None and key in cache:
        return cache[key]
    AZ = sc.AZ
    Kr = AZ.T @ (AZ * ks[:, None])
    out: tuple[np.ndarray, ...] | None = None
    if qm.KG is None:
        L, info = dpotrf(Kr, lower=1, clean=0)
        if info == 0:
            diag = L.diagonal()
            if float(diag.min()) ** 2 > CHOL_RTOL * float(diag.max()) ** 2:
                out = (L,)
    else:
        ZtKGZ = sc.ZtKGZ if sc.ZtKGZ is not None else sc.Z.T @ qm.KG @ sc.Z
        lu, piv, info = dgetrf(Kr - ZtKGZ)
        if info == 0:
            diag = np.abs(lu.diagonal())
            if float(diag.min()) > CHOL_RTOL * float(diag.max()):
                out = (lu, piv)
    if cache is not None:
        cache[key] = out
    return out


def affine_full(qm, sc, K, rhs_top, con_rhs, control):
    """As :func:`_affine_reduced` from the whole bordered system by a least-norm SVD solve
    (mechanisms, redundant constraints); None when the load is outside its range."""
    nv = qm.nv
    k = qm.k_ref
    B = sc.B
    ncon = B.shape[1]
    n = nv + ncon + 1
    H = np.zeros((n, n))
    H[:nv, :nv] = K
    H[:nv, nv : nv + ncon] = -k * B
    H[nv : nv + ncon, :nv] = -k * B.T
    H[:nv, -1] = -sc.r0
    if control == "load":
        H[-1, -1] = 1.0
    else:
        H[-1, : qm.nx] = sc.crow
    rhs = np.zeros((n, rhs_top.shape[1]))
    rhs[:nv] = rhs_top
    rhs[:nv, 0] = 0.0
    rhs[nv : nv + ncon] = con_rhs
    rhs[-1, 0] = 1.0
    u, s, vt = np.linalg.svd(H)
    keep = s > RANK_RTOL * s[0]
    U = vt[keep].T @ ((u[:, keep].T @ rhs) / s[keep][:, None])
    res = np.abs(H @ U[:, 0] - rhs[:, 0]).max()
    if res > RANGE_RTOL * (np.abs(H).max() * np.abs(U[:, 0]).max() + 1.0):
        return None
    return U[:nv], U[-1]


__all__ = [
    "CHOL_RTOL",
    "RANGE_RTOL",
    "RANK_RTOL",
    "StageCache",
    "affine_full",
    "affine_reduced",
    "spring_act",
    "stage_rates",
]
