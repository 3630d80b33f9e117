"""The quasi-static state-space model of a :class:`~pinograsp.GraspModel` (docs/quasistatic.md).

Everything the path follower needs, precomputed once per model, in *scaled* coordinates so
that rank decisions and tolerances do not depend on units:

* displacements ``v_s = S v`` with ``S`` = 1 for object translations, the model's length scale
  ``ℓ`` for object rotations and each joint's lever (its largest Jacobian entry [m/rad]) for
  joints — every component is a length [m];
* equilibrium rows multiplied by ``S^-1`` — every row is a force [N];
* contact forces in [N] (contact frames), as in the model.

The relative displacement of the object over the hand at contact ``i`` (contact frame) is
``g_i = A_i^T v_s`` with ``A = S^-1 [G; -J^T]`` (nv, nc*d); equilibrium of the object and the
joints is ``A c + S^-1 [w; R f + C^T lam_C] = 0``. The friction polygon of each contact (the
pyramid's cross-section per unit normal force, refined cones and normal uncertainty included
since they live in ``D``) is stored as its faces: outward unit normals ``nu_j`` in the tangent
plane and support values ``h_j`` (``nu_j . c_t <= h_j c_n``), so each face's slack is
``h_j c_n - nu_j . c_t``, one row of :attr:`QSModel.Phi`.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field, replace
from typing import TypeVar

import numpy as np

from ...core.actuation import BACKDRIVABLE, LOCKED, NON_BACKDRIVABLE
from ...core.model import GraspModel
from ...errors import ModelError

T = TypeVar("T")

#: Relative singular-value cut-off of the rate system (its rank, relative to its scale).
RANK_RTOL = 1e-11


@dataclass(frozen=True, eq=False)
class Constraints:
    """The rigid constraints of a stage (actuators that are not backdrivable or are locked,
    couplings and, when the object is held, the holder): columns ``B`` (nv, ncon), the owner of
    each (actuator index; -1 coupling; -2 holder), a basis ``Z`` of the motions they allow,
    ``pinv(B)`` and ``pinv(B^T)``, the column of each actuator (``col_of``, ``col_arr``; -1:
    none) and the products with ``A`` the rate problem reads (``A^T Z``, ``A^T pinv(B^T)``,
    ``pinv(B) A``)."""

    B: np.ndarray
    owner: np.ndarray
    Z: np.ndarray
    B_pinv: np.ndarray
    Bt_pinv: np.ndarray
    col_of: dict
    col_arr: np.ndarray
    AZ: np.ndarray
    AtBt: np.ndarray
    BpA: np.ndarray


def evolved(obj: T, **changes: object) -> T:
    """A copy of the frozen dataclass ``obj`` with ``changes`` set, without running its
    ``__init__`` or ``__post_init__``: for the per-update copies of :class:`QSModel`,
    :class:`Constraints` and the stage cache, whose derived fields do not depend on what
    changes (speed only: ``dataclasses.replace`` costs ~15 µs a call, ``copy.copy`` ~1.5 µs;
    this is ``copy.copy`` of an object whose state is its ``__dict__``)."""
    state = getattr(obj, "__dict__", None)
    if state is None or hasattr(type(obj), "__copy__") or hasattr(type(obj), "__setstate__"):
        out = copy.copy(obj)
    else:
        out = object.__new__(type(obj))
        out.__dict__.update(state)
        out.__dict__.update(changes)  # the fields of a dataclass without slots live there
        return out
    for name, value in changes.items():
        object.__setattr__(out, name, value)
    return out


#: The fields of :class:`Constraints` that depend on ``A`` (:func:`lazy_products`).
_PRODUCTS = ("AZ", "AtBt", "BpA")


class _LazyProducts(Constraints):
    """:class:`Constraints` whose products with ``A`` are computed on their first read (the
    same products, on the same arrays: :func:`lazy_products`)."""

    def __getattr__(self, name: str) -> object:  # only for attributes not set yet
        A = self.__dict__.get("_lazy_A")
        if name not in _PRODUCTS or A is None:
            raise AttributeError(name)
        object.__setattr__(self, "AZ", A.T @ self.Z)
        object.__setattr__(self, "AtBt", A.T @ self.Bt_pinv)
        object.__setattr__(self, "BpA", self.B_pinv @ A)
        return self.__dict__[name]


def lazy_products(con: Constraints, A: np.ndarray) -> Constraints:
    """``con`` for a re-linearised ``A`` (nv, nc*d) whose products with ``A`` (``A^T Z``,
    ``A^T pinv(B^T)``, ``pinv(B) A``) are computed only when first read (speed only: a geometry
    update re-linearises the constraints of both stages, and a path reads those of one; ``A``
    must not change afterwards)."""
    out = object.__new__(_LazyProducts)
    out.__dict__.update({k: v for k, v in con.__dict__.items() if k not in _PRODUCTS})
    out.__dict__["_lazy_A"] = A
    return out


def constraints_of(
    A: np.ndarray, Rn: np.ndarray, Cn: np.ndarray, rigid: np.ndarray, nx: int, held: bool
) -> Constraints:
    """The :class:`Constraints` of a model's scaled arrays (``rigid``: the actuators whose
    displacement is constrained, (na,) bool) with the object free or ``held``."""
    nv = A.shape[0]
    cols, owner = [], []
    for a in np.flatnonzero(rigid):
        col = np.zeros(nv)
        col[nx:] = Rn[:, a]
        cols.append(col)
        owner.append(int(a))
    for k in range(Cn.shape[0]):
        col = np.zeros(nv)
        col[nx:] = Cn[k]
        cols.append(col)
        owner.append(-1)
    if held:
        for j in range(nx):
            col = np.zeros(nv)
            col[j] = 1.0
            cols.append(col)
            owner.append(-2)
    B = np.column_stack(cols) if cols else np.zeros((nv, 0))
    if B.shape[1]:
        u, sv, _ = np.linalg.svd(B, full_matrices=True)
        rank = int(np.sum(sv > RANK_RTOL * sv[0]))
        Z = u[:, rank:]
        B_pinv = np.linalg.pinv(B, rcond=RANK_RTOL)
    else:
        Z, B_pinv = np.eye(nv), np.zeros((0, nv))
    col_of = {a: j for j, a in enumerate(owner) if a >= 0}
    Bt_pinv = B_pinv.T.copy()
    col_arr = np.array([col_of.get(a, -1) for a in range(Rn.shape[1])], int)
    return Constraints(
        B, np.array(owner, int), Z, B_pinv, Bt_pinv, col_of, col_arr, A.T @ Z, A.T @ Bt_pinv, B_pinv @ A
    )


def _polygon_faces(block: np.ndarray, d: int) -> tuple[np.ndarray, np.ndarray]:
    """Faces ``(nu (m, d-1), h (m,))`` of the friction polygon of one contact's pyramid block
    (d, m_i); empty for a frictionless contact."""
    V = (block[1:] / block[0]).T  # (m_i, d-1) tangential vertices per unit normal force
    if V.size == 0 or float(np.abs(V).max()) == 0.0:
        return np.zeros((0, d - 1)), np.zeros(0)
    if d == 2:
        v = V[:, 0]
        v = v[v != 0.0]
        nu = np.sign(v)[:, None]
        return nu, np.abs(v)
    ang = np.arctan2(V[:, 1], V[:, 0])
    V = V[np.argsort(ang, kind="stable")]
    E = np.roll(V, -1, axis=0) - V
    length = np.linalg.norm(E, axis=1)
    keep = length > 1e-12 * float(np.abs(V).max())
    V, E, length = V[keep], E[keep], length[keep]
    nu = np.column_stack([E[:, 1], -E[:, 0]]) / length[:, None]  # outward for counter-clockwise
    h = np.einsum("ij,ij->i", nu, V)
    if np.any(h <= 0.0):
        raise ModelError("a friction pyramid does not contain its normal (the polygon misses the origin)")
    return nu, h


@dataclass(frozen=True, eq=False)
class QSModel:
    """Precomputed arrays of one model (shapes: ``nv = nx + nq``, ``nf`` faces in all).

    Attributes:
        model: The :class:`GraspModel`.
        nx, nq, na, ncp, nc, d: Sizes.
        S: Displacement scaling (nv,) [m per unit of the model's coordinate].
        A: ``S^-1 [G; -J^T]``, (nv, nc*d).
        kn: Normal stiffness (nc,) [N/m]; kt: tangential stiffness (nc,) (0 without friction).
        Phi: Face rows (nf, nc*d): slack of face f = ``Phi[f] @ c``.
        face_contact: Contact of each face (nf,); face_index: its index on that contact (nf,).
        Rn: Scaled, unit-column transmission ``S_q^-1 R / r_norm`` (nq, na); r_norm (na,).
        Cn: Scaled, unit-row couplings (ncp, nq); c_norm (ncp,).
        nbd, bd, locked: Actuator kinds as boolean masks (na,).
        k_ref: Largest contact stiffness [N/m] (the balancing factor of constraint rows).
        lever: Joint levers (nq,) [m/rad].
    """

    model: GraspModel
    nx: int
    nq: int
    na: int
    ncp: int
    nc: int
    d: int
    S: np.ndarray
    A: np.ndarray
    kn: np.ndarray
    kt: np.ndarray
    Phi: np.ndarray
    face_contact: np.ndarray
    face_index: np.ndarray
    Rn: np.ndarray
    r_norm: np.ndarray
    Cn: np.ndarray
    c_norm: np.ndarray
    nbd: np.ndarray
    bd: np.ndarray
    locked: np.ndarray
    k_ref: float
    lever: np.ndarray
    row_contact: np.ndarray
    kn_rows: np.ndarray
    kt_rows: np.ndarray
    PhiT_t: np.ndarray
    slip_rows: np.ndarray
    #: The stage constraints with the object free and held (:class:`Constraints`).
    free: Constraints
    held: Constraints

    #: Scaled displacement unknowns ``nx + nq``, polygon faces of all contacts, contact force
    #: components ``nc * d`` (sizes, kept as fields: read in every segment).
    nv: int = 0
    nf: int = 0
    ncd: int = 0
    #: The model's wrench metric (``GraspModel.wrench_weights``: ``1 / S`` on the object rows).
    weights: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: Geometry updated at a turned object (``geometry.moved``; None: the model's own rest
    #: geometry): the scaled geometric stiffness ``K_G`` (nv, nv) and its physical object block
    #: (nx, nx) [N·m/rad], the object's rotation at the update (3, 3) and its angle, the scaled displacements
    #: there (nv,), the contacts' normal gaps there (nc,) [m] and the equilibrium invariant
    #: ``G c + w`` there (nx,) [N, N·m].
    KG: np.ndarray | None = None
    KGp: np.ndarray | None = None
    rot: np.ndarray | None = None
    #: The angle of ``rot`` [rad] (0 at the rest geometry).
    turn: float = 0.0
    vs_ref: np.ndarray | None = None
    gap_ref: np.ndarray | None = None
    e_ref: np.ndarray | None = None
    #: What a geometry update reads of the model and never changes (``geometry._constants``,
    #: set on the first update; speed only).
    geometry_constants: object = field(default=None, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "nv", self.nx + self.nq)
        object.__setattr__(self, "nf", int(self.Phi.shape[0]))
        object.__setattr__(self, "ncd", self.nc * self.d)
        object.__setattr__(self, "weights", 1.0 / self.S[: self.nx])

    def w_scaled(self, w: np.ndarray) -> np.ndarray:
        """A reduced wrench (nx,) [N, N·m] as scaled equilibrium rows (nx,) [N]."""
        return np.asarray(w, float) / self.S[: self.nx]

    def gaps(self, vs: np.ndarray) -> np.ndarray:
        """Normal gap of each contact (nc,) [m] (``-delta``) at the scaled displacements ``vs``
        (nv,): ``g_n = A_n^T vs``, incrementally from the last geometry update when there is one."""
        An = self.A[:, :: self.d]
        if self.vs_ref is None or self.gap_ref is None:
            return An.T @ vs
        return An.T @ (vs - self.vs_ref) + self.gap_ref


def _faces(
    model: GraspModel, kn: np.ndarray, kt: np.ndarray, ratio: float
) -> tuple[np.ndarray, list[int], list[int]]:
    """The face rows of every contact's friction polygon, ``Phi`` (nf, nc*d), with the contact
    and index of each face; ``kt`` (nc,) is filled in place: ``ratio * kn`` where a contact has
    a polygon (0 without friction)."""
    nc, d = model.nc, model.d
    rows, owner, index = [], [], []
    D = np.asarray(model.D, float)
    bc = np.asarray(model.beta_contact)
    for i in range(nc):
        nu, h = _polygon_faces(D[i * d : (i + 1) * d, bc == i], d)
        if len(h):
            kt[i] = ratio * kn[i]
        for j in range(len(h)):
            row = np.zeros(nc * d)
            row[i * d] = h[j]
            row[i * d + 1 : (i + 1) * d] = -nu[j]
            rows.append(row)
            owner.append(i)
            index.append(j)
    Phi = np.array(rows) if rows else np.zeros((0, nc * d))
    return Phi, owner, index


def build_qs_model(model: GraspModel, tangential_ratio: float = 1.0) -> QSModel:
    """The :class:`QSModel` of ``model`` with tangential springs ``tangential_ratio * k``."""
    nx, nq, na, ncp, nc, d = model.nw, model.nq, model.na, model.ncp, model.nc, model.d
    ell = float(model.length_scale)
    absJ = np.abs(np.asarray(model.J, float))
    lever = absJ.max(axis=0) if nq else np.zeros(0)
    lever = np.where(lever > 0, lever, ell)
    sx = np.ones(nx)
    sx[d:] = ell
    S = np.concatenate([sx, lever])
    A = np.vstack([np.asarray(model.G, float), -np.asarray(model.J, float).T]) / S[:, None]
    kn = np.asarray(model.k, float).copy()
    kt = np.zeros(nc)
    Phi, owner, index = _faces(model, kn, kt, float(tangential_ratio))
    Rs = np.asarray(model.R, float) / lever[:, None] if na else np.zeros((nq, 0))
    r_norm = np.linalg.norm(Rs, axis=0) if na else np.zeros(0)
    if na and np.any(r_norm == 0):
        raise ModelError("an actuator reaches no joint of the model")
    Rn = Rs / r_norm[None, :] if na else Rs
    Cs = np.asarray(model.C, float) / lever[None, :] if ncp else np.zeros((0, nq))
    c_norm = np.linalg.norm(Cs, axis=1) if ncp else np.zeros(0)
    Cn = Cs / np.where(c_norm > 0, c_norm, 1.0)[:, None] if ncp else Cs
    kinds = tuple(model.kinds)
    nbd = np.array([k == NON_BACKDRIVABLE for k in kinds], bool)
    locked = np.array([k == LOCKED for k in kinds], bool)
    rigid = nbd | locked
    row_contact = np.repeat(np.arange(nc), d)
    kn_rows = np.zeros(nc * d)
    kn_rows[::d] = kn
    kt_rows = np.repeat(kt, d)
    kt_rows[::d] = 0.0
    PhiT_t = Phi.T.copy()
    PhiT_t[::d] = 0.0  # tangential part only: the force rate of a unit slip flow on a face
    owner_kt = kt[np.array(owner, int)] if owner else np.zeros(0)
    # slip rate da = -nu / kt per unit flow (flows are in force units: kt * slip rate)
    slip_rows = PhiT_t.T / np.where(owner_kt > 0, owner_kt, 1.0)[:, None] * (owner_kt > 0)[:, None]
    return QSModel(
        model=model,
        nx=nx,
        nq=nq,
        na=na,
        ncp=ncp,
        nc=nc,
        d=d,
        S=S,
        A=A,
        kn=kn,
        kt=kt,
        Phi=Phi,
        face_contact=np.array(owner, int),
        face_index=np.array(index, int),
        Rn=Rn,
        r_norm=r_norm,
        Cn=Cn,
        c_norm=c_norm,
        nbd=nbd,
        bd=np.array([k == BACKDRIVABLE for k in kinds], bool),
        locked=locked,
        k_ref=float(kn.max()),
        lever=lever,
        row_contact=row_contact,
        kn_rows=kn_rows,
        kt_rows=kt_rows,
        PhiT_t=PhiT_t,
        slip_rows=slip_rows,
        free=constraints_of(A, Rn, Cn, rigid, nx, held=False),
        held=constraints_of(A, Rn, Cn, rigid, nx, held=True),
    )


def invariant_rows(
    c: np.ndarray,
    x: np.ndarray,
    w: np.ndarray,
    terms: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
    S: np.ndarray,
) -> np.ndarray:
    """The equilibrium invariant of a geometry update, ``G c + K_G (x - x_ref) + w - e_ref``,
    one row per state (k, nx) [N, N·m]: ``c`` (k, nc*d), ``x`` (k, nx), ``w`` (k, nx) of the
    states on one updated geometry of :func:`invariant_terms` ``terms``, or a stack of such (a
    leading axis on every array: one geometry each); ``S`` (nx,): the object rows' scaling."""
    A, KGp, vs_ref, e_ref = terms
    x_ref = vs_ref / S
    G = A * S[:, None]
    Gt, Kt = np.swapaxes(G, -1, -2), np.swapaxes(KGp, -1, -2)
    return c @ Gt + (x - x_ref[..., None, :]) @ Kt + w - e_ref[..., None, :]


def invariant_terms(qm: QSModel) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The object rows of ``A`` (nx, nc*d), ``KGp`` (nx, nx), the object rows of ``vs_ref``
    and ``e_ref`` (nx,) of a geometry update (``geometry.moved``), for :func:`invariant_rows`."""
    assert qm.KGp is not None and qm.vs_ref is not None and qm.e_ref is not None
    return qm.A[: qm.nx], qm.KGp, qm.vs_ref[: qm.nx], qm.e_ref


def balance_residuals(
    qm: QSModel, c: np.ndarray, f: np.ndarray, lam: np.ndarray, w: np.ndarray, x: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The balance of states, one row each (the one place the path's residuals are written):
    the object's ``G c + w`` (k, nx) [N, N·m] (weight it with ``model.wrench_weights``), the
    joints' ``J^T c - R f - C^T lam`` over their levers (k, nq) [N], and the slack of every
    polygon face ``Phi c`` (k, nf) [N] (negative: outside its polygon). ``c`` (k, nc*d),
    ``f`` (k, na), ``lam`` (k, ncp), ``w`` (k, nx) reduced loads; ``x`` (k, nx) the object
    displacements [m, rad], read by a model with updated geometry (its linear invariant)."""
    m = qm.model
    k = len(c)
    if qm.KGp is None or qm.vs_ref is None or qm.e_ref is None or x is None:
        obj = c @ np.asarray(m.G).T + w
    else:  # the invariant of a geometry update (``geometry.moved``)
        obj = invariant_rows(c, x, w, invariant_terms(qm), qm.S[: qm.nx])
    if qm.nq:
        joints = (c @ np.asarray(m.J) - f @ np.asarray(m.R).T - lam @ np.asarray(m.C)) / qm.lever
    else:
        joints = np.zeros((k, 0))
    slack = c @ qm.Phi.T if qm.nf else np.zeros((k, 0))
    return obj, joints, slack


def with_friction_on(qm: QSModel, mask: np.ndarray) -> QSModel:
    """``qm`` with friction (tangential springs and polygon faces) only at the contacts of
    ``mask`` (nc,) bool; the others are frictionless. States are interchangeable with ``qm``'s
    (same unknowns), so a stage followed on one continues on the other."""
    mask = np.asarray(mask, bool)
    keep = mask[qm.face_contact] if qm.nf else np.zeros(0, bool)
    kt = np.where(mask, qm.kt, 0.0)
    kt_rows = np.repeat(kt, qm.d)
    kt_rows[:: qm.d] = 0.0
    return replace(
        qm,
        kt=kt,
        kt_rows=kt_rows,
        Phi=qm.Phi[keep],
        face_contact=qm.face_contact[keep],
        face_index=qm.face_index[keep],
        PhiT_t=qm.PhiT_t[:, keep],
        slip_rows=qm.slip_rows[keep],
    )


def finger_groups(qm: QSModel) -> list[np.ndarray]:
    """The contacts of each group of the hand that moves independently of the others while the
    object is held still (joints linked through a contact, an actuator or a coupling; in
    practice one finger each), as boolean masks (nc,), in order of their first contact.
    Contacts on no joint (the palm) form no group: with the object held they carry no force."""
    model = qm.model
    nq, nc, d = qm.nq, qm.nc, qm.d
    parent = list(range(nq))

    def root(j: int) -> int:
        while parent[j] != j:
            parent[j] = parent[parent[j]]
            j = parent[j]
        return j

    def link(js: np.ndarray) -> None:
        for j in js[1:]:
            parent[root(int(j))] = root(int(js[0]))

    J = np.abs(np.asarray(model.J, float)).reshape(nc, d, nq).max(axis=1)  # (nc, nq)
    for i in range(nc):
        link(np.flatnonzero(J[i] > 0))
    for a in range(qm.na):
        link(np.flatnonzero(np.asarray(model.R, float)[:, a] != 0))
    for k in range(qm.ncp):
        link(np.flatnonzero(np.asarray(model.C, float)[k] != 0))
    groups: dict[int, np.ndarray] = {}
    for i in range(nc):
        js = np.flatnonzero(J[i] > 0)
        if len(js):
            groups.setdefault(root(int(js[0])), np.zeros(nc, bool))[i] = True
    return list(groups.values())
