"""One segment of the loading path: the local rate problem at a point of the path.

At a point (the :class:`State`), every contact and actuator is classified by the inequalities
that hold with zero slack (QUASISTATIC.md, "The local rate problem is an LCP"):

* a contact is *open* (gap ``delta < 0``), at *zero force* (touching with ``c_n = 0``: its
  opening rate and every face of its polygon are boundary items) or *pressed* (``c_n > 0``:
  the faces its tangential force lies on are boundary items);
* a non-backdrivable actuator is at its command (``f = f_c``: a boundary item, it may move or
  hold) or holds above it; backdrivable actuators keep ``f = f_c``; locked ones ``u = 0``.

Every boundary item carries one complementary pair *flow* ``>= 0`` ⟂ *force-rate slack*
``>= 0``: the slip rate on a face ⟂ the rate of that face's slack, the opening rate of a
zero-force contact ⟂ its normal force rate, the closing rate of an actuator ⟂ its over-force
rate. With the flows as unknowns the remaining relations are linear: the tangent stiffness of
the touching contacts (normal ``k``, tangential ``k_t``), the actuator and coupling constraints
and the object's equilibrium, plus one control row — the load rate ``dλ = 1`` (load control),
or unit displacement rate along the load (displacement control, which passes limit points and
returns ``dλ``). Eliminating them gives the LCP ``w = M ζ + q`` over exactly the boundary
items, solved by Lemke's method (:mod:`pinograsp.solvers.lcp`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...solvers.lcp import LCPStatus, lemke
from .model import QSModel

#: Relative tolerance (to the force scale of the state) under which a slack is zero.
EVENT_RTOL = 1e-9
#: Relative tolerance (to the rate scale of the segment) under which a rate is zero.
RATE_RTOL = 1e-10
#: Relative residual above which a linear solve is taken as having no solution (singular
#: system whose right-hand side is outside its range).
RANGE_RTOL = 1e-8
#: Diagonal regularisation of the faces of zero-force contacts in the LCP, relative to ``M``.
APEX_REG = 1e-12
#: Relative singular-value cut-off of the rate system (its rank, relative to its scale).
RANK_RTOL = 1e-11


@dataclass(frozen=True)
class StageSpec:
    """One stage of the path: object load ``w0 + t dw`` (reduced, [N, N·m]), commands
    ``fc0 + t dfc`` (na,), for ``t`` from its start to ``t_end``; ``held``: the object is
    held still (its holder takes any wrench); ``friction``: tangential springs and friction on."""

    w0: np.ndarray
    dw: np.ndarray
    fc0: np.ndarray
    dfc: np.ndarray
    t_end: float
    held: bool
    friction: bool

    def command(self, t: float) -> np.ndarray:
        """Commands at ``t`` (na,)."""
        return self.fc0 + t * self.dfc


@dataclass
class State:
    """A point of the path (scaled displacements, physical forces).

    Attributes:
        vs: Scaled displacements ``(x, q)`` (nv,) [m].
        c: Contact forces, contact frames (nc*d,) [N].
        f: Actuator forces (na,); lam_c: coupling reactions (ncp,); hold: holder wrench (nx,).
        slip: Accumulated tangential slip ``a`` (nc*d,; normal rows 0) [m].
        t: Path parameter of the stage (the load factor in the load stage).
    """

    vs: np.ndarray
    c: np.ndarray
    f: np.ndarray
    lam_c: np.ndarray
    hold: np.ndarray
    slip: np.ndarray
    t: float = 0.0

    def copy(self) -> State:
        """An independent copy."""
        return State(
            self.vs.copy(), self.c.copy(), self.f.copy(), self.lam_c.copy(), self.hold.copy(), self.slip.copy(), self.t
        )


@dataclass
class Segment:
    """Rates of one segment per unit of the path parameter, and its states.

    Attributes:
        status: ``"ok"``, ``"limit"`` (no continuation with growing load: ``dλ <= 0`` under
            displacement control), or the LCP's failure (``"ray_termination"``,
            ``"pivot_limit"``) / ``"singular"``.
        dvs, dc, df, dlam_c, dhold, dslip: Rates (as :class:`State`).
        contact: Per contact ``"separated"``, ``"sticking"`` or ``"sliding"``.
        detail: Per contact the sliding faces (indices) — one face, or two at a vertex.
        actuator: Per actuator ``"moving"``, ``"holding"``, ``"backdrivable"``, ``"locked"``.
        lcp_size, pivots: Size of the local LCP and Lemke pivots made.
        control: ``"load"`` or ``"displacement"``.
        stiffness_rate: ``dλ`` per unit scaled displacement along the load (displacement
            control only).
    """

    status: str
    dvs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dc: np.ndarray = field(default_factory=lambda: np.zeros(0))
    df: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dlam_c: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dhold: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dslip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    contact: tuple[str, ...] = ()
    detail: tuple[tuple[int, ...], ...] = ()
    actuator: tuple[str, ...] = ()
    lcp_size: int = 0
    pivots: int = 0
    control: str = "load"
    stiffness_rate: float = float("nan")
    lam_rate: float = 1.0
    flip: np.ndarray | None = None


@dataclass(frozen=True, eq=False)
class Classes:
    """Classification of a state (see the module docstring)."""

    open: np.ndarray  # (nc,) gap
    zero: np.ndarray  # (nc,) touching, zero force
    pressed: np.ndarray  # (nc,)
    faces: np.ndarray  # indices of boundary faces (of QSModel.Phi rows)
    act_lcp: np.ndarray  # (na,) non-backdrivable at its command
    tol: float  # force tolerance [N]
    fscale: float


def force_scale(qm: QSModel, st: State, spec: StageSpec) -> float:
    """Force scale of a state [N]: contact forces, load and commands (as forces)."""
    w = spec.w0 + st.t * spec.dw
    fc = spec.command(st.t)
    parts = [
        float(np.abs(st.c).max(initial=0.0)),
        float(np.abs(qm.w_scaled(w)).max(initial=0.0)),
        float(np.abs(qm.w_scaled(spec.dw)).max(initial=0.0)),
        float(np.abs(fc * qm.r_norm).max(initial=0.0)),
        float(np.abs(spec.dfc * qm.r_norm).max(initial=0.0)),
    ]
    return max(max(parts), 1e-300)


def classify(qm: QSModel, st: State, spec: StageSpec) -> Classes:
    """Classify contacts, faces and actuators of ``st`` (and zero the forces of contacts at
    zero force: their anchors are forgotten)."""
    fscale = force_scale(qm, st, spec)
    tol = EVENT_RTOL * fscale
    d = qm.d
    cn = st.c[::d]
    delta = -(qm.A[:, ::d].T @ st.vs)
    low = cn <= tol
    opened = low & (delta * qm.kn < -tol)
    zero = low & ~opened
    pressed = ~low
    for i in np.flatnonzero(low):
        st.c[i * d : (i + 1) * d] = 0.0
    if spec.friction and qm.nf:
        slack = qm.Phi @ st.c
        fc = qm.face_contact
        faces = np.flatnonzero((zero[fc]) | (pressed[fc] & (slack <= tol)))
    else:
        faces = np.zeros(0, int)
    phi = (st.f - spec.command(st.t)) * qm.r_norm
    act_lcp = qm.nbd & (phi <= tol)
    return Classes(opened, zero, pressed, faces, act_lcp, tol, fscale)


def _constraint_columns(qm: QSModel, spec: StageSpec) -> tuple[np.ndarray, np.ndarray]:
    """Constraint columns ``Bc`` (nv, ncon) and the actuator index of each column (-1 for
    couplings and the holder)."""
    nv, nx = qm.nv, qm.nx
    con = np.flatnonzero(qm.nbd | qm.locked)
    cols, owner = [], []
    for a in con:
        col = np.zeros(nv)
        col[nx:] = qm.Rn[:, a]
        cols.append(col)
        owner.append(a)
    for k in range(qm.ncp):
        col = np.zeros(nv)
        col[nx:] = qm.Cn[k]
        cols.append(col)
        owner.append(-1)
    if spec.held:
        for j in range(nx):
            col = np.zeros(nv)
            col[j] = 1.0
            cols.append(col)
            owner.append(-2)
    B = np.column_stack(cols) if cols else np.zeros((nv, 0))
    return B, np.array(owner, int)


def _solve(H: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Least-norm solution of ``H U = rhs`` (square ``H``; rank relative to its scale)."""
    u, s, vt = np.linalg.svd(H)
    keep = s > RANK_RTOL * s[0] if s.size and s[0] > 0 else np.zeros(s.size, bool)
    return vt[keep].T @ ((u[:, keep].T @ rhs) / s[keep][:, None])


#: Plans for a contact at zero force: both pairs in the LCP, pressed (touching, faces in the
#: LCP, no opening item) or separated (out of the rate problem).
FULL, PRESS, SEPARATE = 0, 1, 2


def rates(
    qm: QSModel, st: State, spec: StageSpec, cls: Classes, control: str = "load", plan: np.ndarray | None = None
) -> Segment:
    """The segment's rates at ``st`` under load (``dλ = 1``) or displacement control.

    ``plan`` (nc,) says how each zero-force contact enters (:data:`FULL`, :data:`PRESS`,
    :data:`SEPARATE`; default FULL); a PRESS or SEPARATE guess that its own rates contradict
    comes back in :attr:`Segment.flip` (status ``"guess"``).
    """
    d, nv, nx = qm.d, qm.nv, qm.nx
    plan = np.zeros(qm.nc, int) if plan is None else plan
    sep = cls.zero & (plan == SEPARATE)
    touch = (cls.zero & ~sep) | cls.pressed
    ks = np.zeros(qm.ncd)
    ks[::d] = np.where(touch, qm.kn, 0.0)
    if spec.friction and d > 1:
        for j in range(1, d):
            ks[j::d] = np.where(touch, qm.kt, 0.0)
    A = qm.A
    KT = (A * ks) @ A.T
    B, owner = _constraint_columns(qm, spec)
    ncon = B.shape[1]
    k = qm.k_ref
    # load per unit of the path parameter (scaled rows): object load and backdrivable commands
    r0 = np.zeros(nv)
    r0[:nx] = qm.w_scaled(spec.dw)
    if qm.na and np.any(qm.bd):
        r0[nx:] = qm.Rn[:, qm.bd] @ (qm.r_norm[qm.bd] * spec.dfc[qm.bd])
    n = nv + ncon + 1
    H = np.zeros((n, n))
    H[:nv, :nv] = KT
    H[:nv, nv : nv + ncon] = -k * B
    H[nv : nv + ncon, :nv] = -k * B.T
    H[:nv, -1] = -r0
    if control == "load":
        H[-1, -1] = 1.0
    else:
        crow = r0[:nx]
        H[-1, :nx] = crow / np.linalg.norm(crow)
    # flows: zero-force openings, boundary faces, actuators at their command
    zero = np.flatnonzero(cls.zero & (plan == FULL))
    faces = cls.faces[~sep[qm.face_contact[cls.faces]]] if len(cls.faces) else cls.faces
    acts = np.flatnonzero(cls.act_lcp)
    nz = len(zero) + len(faces) + len(acts)
    F = np.zeros((qm.ncd, nz))  # contact force rate per unit flow
    F[zero * d, np.arange(len(zero))] = 1.0
    if len(faces):
        F[:, len(zero) : len(zero) + len(faces)] = qm.Phi[faces].T  # dc_t = -nu per unit flow
        F[qm.face_contact[faces] * d, len(zero) + np.arange(len(faces))] = 0.0
    rhs = np.zeros((n, 1 + nz))
    rhs[-1, 0] = 1.0
    rhs[:nv, 1:] = A @ F
    act_row = {int(a): nv + int(np.flatnonzero(owner == a)[0]) for a in acts}
    for m, a in enumerate(acts):
        rhs[act_row[int(a)], 1 + len(zero) + len(faces) + m] = -1.0
    U = _solve(H, rhs)
    # contact force rates (ncd, 1 + nz) and the complementarity rows
    dC = -ks[:, None] * (A.T @ U[:nv])
    dC[:, 1:] += F
    Wrows = np.zeros((nz, 1 + nz))
    Wrows[: len(zero)] = dC[zero * d]
    if len(faces):
        Wrows[len(zero) : len(zero) + len(faces)] = qm.Phi[faces] @ dC
    for m, a in enumerate(acts):
        r = len(zero) + len(faces) + m
        Wrows[r] = k * U[act_row[int(a)]] - qm.r_norm[a] * spec.dfc[a] * U[-1]
    Mlcp = Wrows[:, 1:].copy()
    # faces of a contact at zero force: opposite faces' flows cancel (a null direction of M);
    # a relative 1e-12 on their diagonal picks the least flow
    apex = np.zeros(nz, bool)
    apex[len(zero) : len(zero) + len(faces)] = cls.zero[qm.face_contact[faces]]
    if apex.any():
        Mlcp[apex, apex] += APEX_REG * max(float(np.abs(Mlcp).max()), 1.0)
    res = lemke(Mlcp, Wrows[:, 0]) if nz else None
    if res is not None and not res.solved:
        return Segment(status=res.status.value, lcp_size=nz, pivots=res.pivots, control=control)
    zeta = res.z if res is not None else np.zeros(0)
    u = U[:, 0] + U[:, 1:] @ zeta
    resid = H @ u - (rhs[:, 0] + rhs[:, 1:] @ zeta)
    scale = np.abs(H).max() * np.abs(u).max(initial=0.0) + np.abs(rhs).max() * max(1.0, np.abs(zeta).max(initial=0.0))
    if np.abs(resid).max() > RANGE_RTOL * scale:
        return Segment(status="singular", lcp_size=nz, pivots=res.pivots if res else 0, control=control)
    dc = dC[:, 0] + dC[:, 1:] @ zeta
    seg = _segment(qm, spec, cls, u, dc, zeta, (zero, faces, acts), owner, nz, res, control, sep)
    # check the guesses: a pressed zero-force contact must not pull, a separated one not close
    rtol = RATE_RTOL * max(float(np.abs(dc).max(initial=0.0)), float(np.abs(r0).max()), 1e-300)
    pressed_guess = cls.zero & (plan == PRESS)
    bad = pressed_guess & (dc[::d] < -rtol)
    closing = -(A[:, ::d].T @ u[:nv]) * qm.kn
    bad |= sep & (closing > rtol)
    if bad.any():
        seg.status = "guess"
        seg.flip = bad
    return seg


def _segment(qm, spec, cls, u, dc, zeta, items, owner, nz, res, control, sep) -> Segment:
    """Assemble the :class:`Segment` of a solved rate problem."""
    zero, faces, acts = items
    d, nv, nx, nc = qm.d, qm.nv, qm.nx, qm.nc
    k = qm.k_ref
    lam_rate = float(u[-1])
    ncon = len(owner)
    rho = u[nv : nv + ncon]
    df = np.zeros(qm.na)
    if qm.na:
        df[qm.bd] = spec.dfc[qm.bd] * lam_rate
    for j, a in enumerate(owner):
        if a >= 0:
            df[a] = k * rho[j] / qm.r_norm[a]
    dlam = np.array([k * rho[j] / qm.c_norm[m] for m, j in enumerate(np.flatnonzero(owner == -1))])
    dhold = np.zeros(nx)
    if spec.held:
        dhold = qm.S[:nx] * k * rho[owner == -2]
    dslip = np.zeros(qm.ncd)
    nzero = len(zero)
    flows_f = zeta[nzero : nzero + len(faces)]
    for m, fidx in enumerate(faces):
        i = qm.face_contact[fidx]
        if qm.kt[i] > 0:
            dslip[i * d + 1 : (i + 1) * d] += qm.Phi[fidx, i * d + 1 : (i + 1) * d] * flows_f[m] / qm.kt[i]
    rscale = max(float(np.abs(dc).max(initial=0.0)), float(np.abs(qm.w_scaled(spec.dw)).max(initial=0.0)) * abs(lam_rate), 1e-300)
    ftol = RATE_RTOL * rscale
    opening = sep.copy()
    opening[zero] = (zeta[:nzero] > ftol) | (dc[zero * d] <= ftol)
    sliding: list[list[int]] = [[] for _ in range(nc)]
    for m, fidx in enumerate(faces):
        if flows_f[m] > ftol:
            sliding[qm.face_contact[fidx]].append(int(qm.face_index[fidx]))
    contact, detail = [], []
    for i in range(nc):
        if cls.open[i] or opening[i]:
            contact.append("separated")
            detail.append(())
        else:
            contact.append("sliding" if sliding[i] else "sticking")
            detail.append(tuple(sliding[i]))
    actuator = []
    flows_a = zeta[nzero + len(faces) :]
    moving = np.zeros(qm.na, bool)
    moving[acts] = flows_a > ftol
    for a in range(qm.na):
        if qm.bd[a]:
            actuator.append("backdrivable")
        elif qm.locked[a]:
            actuator.append("locked")
        else:
            actuator.append("moving" if moving[a] else "holding")
    dc = dc.copy()
    for i in np.flatnonzero(cls.open | opening):
        dc[i * d : (i + 1) * d] = 0.0
    return Segment(
        status="ok",
        dvs=u[:nv].copy(),
        dc=dc,
        df=df,
        dlam_c=dlam,
        dhold=dhold,
        dslip=dslip,
        contact=tuple(contact),
        detail=tuple(detail),
        actuator=tuple(actuator),
        lcp_size=nz,
        pivots=res.pivots if res is not None else 0,
        control=control,
        lam_rate=lam_rate,
    )


def rescaled(seg: Segment, factor: float) -> Segment:
    """``seg`` with every rate multiplied by ``factor`` (displacement → load control)."""
    out = Segment(**{**seg.__dict__})
    for name in ("dvs", "dc", "df", "dlam_c", "dhold", "dslip"):
        setattr(out, name, getattr(seg, name) * factor)
    out.lam_rate = seg.lam_rate * factor
    return out


__all__ = ["Classes", "Segment", "StageSpec", "State", "classify", "rates", "rescaled", "LCPStatus"]
