"""One segment of the loading path: the local rate problem at a point of the path.

At a point (the :class:`State`), every contact and actuator is classified by the inequalities
that hold with zero slack (docs/quasistatic.md, "The rate problem is an LCP"):

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

from dataclasses import dataclass

import numpy as np

from ...solvers.lcp import canonical, lemke, principal_pivoting
from ...solvers.lcp_certificates import near_solution
from .model import QSModel
from .segment import RATE_RTOL, Items, Segment, Solved, _amax, rescaled, segment_of, separated_on
from .state import StageSpec, State
from .statuses import SegmentStatus
from .system import StageCache, affine_full, affine_reduced, spring_act, stage_rates

#: Relative tolerance (to the force scale of the state) under which a slack is zero.
EVENT_RTOL = 1e-9
#: Diagonal regularisation of the faces of zero-force contacts in the LCP, relative to ``M``.
APEX_REG = 1e-12


@dataclass(eq=False)
class Classes:
    """Classification of a state (see the module docstring; read-only by convention: a plain
    dataclass, whose ``__init__`` costs a fifth of a frozen one's — speed only)."""

    open: np.ndarray  # (nc,) gap
    zero: np.ndarray  # (nc,) touching, zero force
    pressed: np.ndarray  # (nc,)
    faces: np.ndarray  # indices of boundary faces (of QSModel.Phi rows)
    act_lcp: np.ndarray  # (na,) non-backdrivable at its command
    tol: float  # force tolerance [N]
    fscale: float
    forces: np.ndarray  # the state's contact forces, those at zero force exactly 0 (ncd,) [N]
    # of the state classified (its identity): gaps ``-delta`` (nc,), face slacks (nf,) and
    # actuator over-forces (na,), read again by the event search (speed only)
    src: object = None
    gap: np.ndarray | None = None
    slack: np.ndarray | None = None
    phi: np.ndarray | None = None
    #: whether any contact is at zero force, and the indices of :attr:`act_lcp` (speed only)
    has_zero: bool = True
    acts: np.ndarray | None = None


@dataclass(eq=False)
class LinearPart:
    """The rate problem's linear part, per column (the load, then one per flow): contact force
    rates ``dC`` (ncd, 1+nz), displacement rates ``V`` (nv, 1+nz), load rates ``lam``
    (1+nz,), the complementarity rows ``W`` (nz, 1+nz) and their matrix ``M`` (nz, nz) (the
    LCP is ``w = M zeta + W[:, 0]``), and the constraint multipliers ``Rho`` (ncon, 1+nz)."""

    dC: np.ndarray
    V: np.ndarray
    lam: np.ndarray
    W: np.ndarray
    M: np.ndarray
    Rho: np.ndarray
    keys: np.ndarray  # the items' codes (as :attr:`Segment.active`; speed only)


def force_scale(
    qm: QSModel, st: State, spec: StageSpec, sc: StageCache | None = None, fc: np.ndarray | None = None
) -> float:
    """Force scale of a state [N]: contact forces, load and commands (as forces); ``sc``: the
    stage's cache, whose rates are read instead of computed again, ``fc``: the commands at
    ``st`` (na,) when the caller has them (speed only)."""
    w = spec.w0 + st.t * spec.dw
    fc = spec.command(st.t) if fc is None else fc
    wd, fd = (sc.rates if sc is not None else stage_rates(qm, spec))[:2]
    # one maximum over the three (the same bits as three: a maximum is exact) unless it is NaN
    most = float(_amax(np.abs(np.concatenate((st.c, qm.w_scaled(w), fc * qm.r_norm))), initial=0.0))
    if most == most:
        return max(most, wd, fd, 1e-300)
    parts = [
        float(np.abs(st.c).max(initial=0.0)),
        float(np.abs(qm.w_scaled(w)).max(initial=0.0)),
        wd,
        float(np.abs(fc * qm.r_norm).max(initial=0.0)),
        fd,
    ]
    return max(max(parts), 1e-300)


def classify(qm: QSModel, st: State, spec: StageSpec, sc: StageCache | None = None) -> Classes:
    """Classify contacts, faces and actuators of ``st`` (a pure function: the state is not
    changed); :attr:`Classes.forces` are its contact forces with those of contacts at zero
    force set to exactly 0 (their anchors forgotten), which the segment loop makes the state's
    own; ``sc`` as for :func:`force_scale`."""
    fc = spec.command(st.t)
    fscale = force_scale(qm, st, spec, sc, fc)
    tol = EVENT_RTOL * fscale
    d = qm.d
    cn = st.c[::d]
    gap = qm.gaps(st.vs)
    low = cn <= tol
    full = None  # the face slacks of the state's own forces
    if spec.friction and qm.nf and not low.all():
        # a pressed contact at the apex of its polygon: more faces with zero slack than meet at
        # one vertex (two in 3D, one in a plane) is only possible when ``c_n`` itself is zero
        # within the tolerance — a contact that unloads together with others (a flat pad's
        # corners) lands a rounding above ``tol``, and its faces would all enter the rate
        # problem of a pressed contact, whose LCP is then degenerate. Such a contact is at
        # zero force (its opening pair decides whether it separates).
        full = qm.Phi @ st.c
        low |= np.bincount(qm.face_contact[full <= tol], minlength=qm.nc) > (2 if d == 3 else 1)
    opened = low & (gap * qm.kn > tol)  # (-delta) * kn > tol: the spring would pull
    zero = low & ~opened
    pressed = ~low
    has_zero = bool(zero.any())
    c = st.c
    if low.any():
        c = c.copy()
        c.reshape(qm.nc, d)[low] = 0.0
    if spec.friction and qm.nf:
        slack = full if c is st.c and full is not None else qm.Phi @ c  # (the same product)
        fcon = qm.face_contact
        tight = pressed[fcon] & (slack <= tol)
        faces = (zero[fcon] | tight).nonzero()[0] if has_zero else tight.nonzero()[0]
    else:
        faces, slack = np.zeros(0, int), None
    phi = (st.f - fc) * qm.r_norm
    act_lcp = qm.nbd & (phi <= tol)
    acts = act_lcp.nonzero()[0]
    return Classes(opened, zero, pressed, faces, act_lcp, tol, fscale, c, st, gap, slack, phi, has_zero, acts)


#: Plans for a contact at zero force: both pairs in the LCP, pressed (touching, faces in the
#: LCP, no opening item) or separated (out of the rate problem).
FULL, PRESS, SEPARATE = 0, 1, 2
#: No index (read-only, shared).
_NONE = np.zeros(0, int)
_NONE.setflags(write=False)
#: The load's unit flow (read-only, shared).
_ONE = np.ones(1)
_ONE.setflags(write=False)
#: The load's column among the item columns (the last, zero; read-only, shared).
_LOAD = np.array([-1])
_LOAD.setflags(write=False)


def rates(
    qm: QSModel,
    st: State,
    spec: StageSpec,
    cls: Classes,
    control: str = "load",
    plan: np.ndarray | None = None,
    sc: StageCache | None = None,
    hints: tuple[np.ndarray, ...] = (),
    apex: np.ndarray | None = None,
    near: bool = False,
) -> Segment:
    """The segment's rates at ``st`` under load (``dλ = 1``) or displacement control.

    ``plan`` (nc,) says how each zero-force contact enters (:data:`FULL`, :data:`PRESS`,
    :data:`SEPARATE`; default FULL); a PRESS or SEPARATE guess that its own rates contradict
    comes back in :attr:`Segment.flip` (status ``"guess"``). ``hints``: sets of LCP items
    (sorted codes as :attr:`Segment.active`) guessed to flow, tried first (speed only).
    ``apex`` (nf,) bool: the faces of zero-force contacts taken into the LCP (default all); a
    face left out whose slack rate the rates make negative comes back in :attr:`Segment.add`
    (status ``"apex"``). ``near``: see :func:`_solve_lcp`.
    """
    sc = StageCache.of(qm, spec) if sc is None else sc
    plan = np.zeros(qm.nc, int) if plan is None else plan
    if cls.has_zero:
        sep = cls.zero & (plan == SEPARATE)
        touch = (cls.zero & ~sep) | cls.pressed
    else:  # no zero-force contact: nothing planned (``cls.zero`` is all False)
        sep, touch = cls.zero, cls.pressed
    key = touch.tobytes()
    ks = sc.ks_of.get(key) if sc.ks_of is not None else None
    if ks is None:
        ks = touch[qm.row_contact] * sc.k_rows
        if sc.ks_of is not None:
            sc.ks_of[key] = ks
    items = lcp_items(qm, cls, plan, sep, apex)
    lin = linear_part(qm, sc, spec, ks, items, control)
    if lin is None:
        return Segment(status=SegmentStatus.SINGULAR, lcp_size=items.size, control=control)
    Wrows, Mlcp = lin.W, lin.M
    zero, faces, acts = items.zero, items.faces, items.acts
    nz = Mlcp.shape[0]
    # faces of a contact at zero force: opposite faces' flows cancel (a null direction of M);
    # a relative 1e-12 on their diagonal picks the least flow
    apex_faces = cls.zero[qm.face_contact[faces]] if cls.has_zero else None
    if apex_faces is not None and apex_faces.any():
        at_apex = np.concatenate([np.zeros(len(zero), bool), apex_faces, np.zeros(len(acts), bool)])
        Mlcp[at_apex, at_apex] += APEX_REG * max(float(np.abs(Mlcp).max()), 1.0)
    keys = lin.keys  # item codes: opening of contact i -> i, face f -> nc + f, actuator a -> nc + nf + a
    res = _solve_lcp(Mlcp, Wrows[:, 0], keys, hints, qm.nc + qm.nf + qm.na, near) if nz else None
    if res is not None and not res.solved:
        return Segment(
            status=SegmentStatus(res.status.value), lcp_size=nz, pivots=res.pivots, control=control
        )
    zeta1 = np.concatenate((_ONE, res.z)) if res is not None else _ONE
    v = lin.V @ zeta1
    dc = lin.dC @ zeta1
    solved = Solved(v, dc, lin.Rho @ zeta1, float(lin.lam @ zeta1), zeta1[1:])
    pivots = res.pivots if res is not None else 0
    seg = segment_of(
        qm,
        spec,
        sc,
        solved,
        items,
        lcp_size=nz,
        pivots=pivots,
        control=control,
        sep=sep,
        open_=cls.open,
        has_zero=cls.has_zero,
    )
    if nz:
        assert res is not None  # solved whenever there are items
        ftol = RATE_RTOL * max(float(_amax(np.abs(res.z))), 1e-300)
        seg.active = keys[res.z > ftol]  # sorted: the item codes are increasing
        seg.tie = res.tie
    if not cls.has_zero:  # no zero-force contact: no guess (``sep`` is part of ``cls.zero``)
        return seg
    return _check_guesses(qm, spec, cls, plan, sep, apex, seg, v, dc, sc)


def lcp_items(qm: QSModel, cls: Classes, plan: np.ndarray, sep: np.ndarray, apex: np.ndarray | None) -> Items:
    """The LCP :class:`Items` of a classified state under the zero-force ``plan`` (``sep``: the
    contacts planned separated; ``apex``: the zero-force faces taken, None: all)."""
    acts = cls.acts if cls.acts is not None else cls.act_lcp.nonzero()[0]
    if not cls.has_zero:  # no opening item, no face to leave out
        return Items(_NONE, cls.faces, acts)
    zero = (cls.zero & (plan == FULL)).nonzero()[0]
    faces = cls.faces
    if len(faces) and (sep.any() or (apex is not None and cls.zero.any())):  # else every face stays
        owner_f = qm.face_contact[faces]
        keep = ~sep[owner_f]
        if apex is not None:
            keep &= ~cls.zero[owner_f] | apex[faces]
        faces = faces[keep]
    return Items(zero, faces, acts)


def linear_part(
    qm: QSModel, sc: StageCache, spec: StageSpec, ks: np.ndarray, items: Items, control: str
) -> LinearPart | None:
    """The :class:`LinearPart` of the rate problem with the tangent spring stiffness rows ``ks``
    (ncd,) and the LCP ``items``, under ``"load"`` or ``"displacement"`` control; None when it
    is singular (the load outside the system's range)."""
    zero, faces, acts = items.zero, items.faces, items.acts
    d, k, A = qm.d, qm.k_ref, qm.A
    n0, n1 = len(zero), len(zero) + len(faces)
    nz = n1 + len(acts)
    nc, nf = qm.nc, qm.nf
    # the item codes (as Segment.active) after the load's column (-1: the last, zero)
    if n0:
        keys = np.concatenate((_LOAD, zero, faces + nc, acts + (nc + nf)))
    else:
        keys = np.concatenate((_LOAD, faces + nc, acts + (nc + nf)))
    # contact force rates per unit flow, with the springs' share of the actuator flows'
    # particular motion (Vp: that motion)
    Fm = sc.f_items.take(keys, axis=1)
    Vp = sc.vp_items.take(keys, axis=1)
    cols = _NONE
    if len(acts):
        cols = sc.col_arr[acts]
        Fm[:, 1 + n1 :] -= spring_act(sc, ks, k)[:, cols]
    aff = affine_reduced(qm, sc, ks, Fm, Vp, control)
    if aff is not None:
        V, lam, G = aff
        dC = Fm - ks[:, None] * G
    else:
        if control != "load" and sc.crow is None:
            return None
        F = Fm.copy()
        F[:, 1 + n1 :] = 0.0
        rhs_top = A @ F
        rhs_top[:, 0] = sc.r0
        con_rhs = np.zeros((sc.B.shape[1], 1 + nz))
        if len(acts):
            con_rhs[cols, 1 + n1 + np.arange(len(acts))] = -1.0
        K = (A * ks) @ A.T if qm.KG is None else (A * ks) @ A.T - qm.KG
        full = affine_full(qm, sc, K, rhs_top, con_rhs, control)
        if full is None:
            return None
        V, lam = full
        dC = -ks[:, None] * (A.T @ V) + F
    # multipliers per column: k B rho = K V - r0 lam - A F = -A dC - r0 lam
    Rho = sc.BpA @ dC
    Rho += sc.Bpr0[:, None] * lam  # (the outer product)
    Rho /= -k  # -(x) / k, the same bits
    if qm.KG is not None:  # the geometric stiffness's share of the constraint forces
        Rho -= sc.B_pinv @ (qm.KG @ V) / k
    blocks = []
    if n0:
        blocks.append(dC[zero * d])
    if len(faces):
        blocks.append(qm.Phi[faces] @ dC)
    if len(acts):
        blocks.append(k * Rho[cols] - sc.rdfc[acts][:, None] * lam)
    W = np.concatenate(blocks) if len(blocks) > 1 else blocks[0] if blocks else np.zeros((0, 1 + nz))
    # rounding of a zero load rate (symmetric grasps) is zero
    w0 = np.abs(W[:, 0])
    qscale = max(float(_amax(w0, initial=0.0)), float(_amax(np.abs(dC[:, 0]), initial=0.0)), 1e-300)
    W[w0 <= RATE_RTOL * 1e-3 * qscale, 0] = 0.0
    return LinearPart(dC, V, lam, W, W[:, 1:].copy(), Rho, keys[1:])


def _solve_lcp(
    M: np.ndarray,
    q: np.ndarray,
    keys: np.ndarray,
    hints: tuple[np.ndarray, ...],
    ntot: int,
    near: bool = False,
):
    """Principal pivoting from the first hint (the previous segment's flowing items and the
    inequalities just reached), else Lemke's method; with ``near`` (the path's retry at a stop
    that no certificate decides), where both fail, a solution within rounding
    (:func:`~pinograsp.solvers.lcp_certificates.near_solution`); the canonical (least-norm over
    the tight items) solution."""
    res = None
    for hint in hints[:1]:
        mask = np.zeros(ntot, bool)
        mask[hint] = True
        res = principal_pivoting(M, q, mask[keys])
    if res is None:
        res = lemke(M, q)
    if not res.solved:  # Lemke's method gave no (trustworthy) answer: pivot from both ends
        for start in (np.zeros(q.size, bool), np.ones(q.size, bool)):
            alt = principal_pivoting(M, q, start)
            if alt is not None:
                res = alt
                break
    if near and not res.solved:  # a small, nearly degenerate problem: a solution within rounding
        res = near_solution(M, q) or res
    return canonical(M, q, res)


def _check_guesses(qm, spec, cls, plan, sep, apex, seg, v, dc, sc) -> Segment:
    """Flag a contradicted zero-force guess (status ``"guess"``: a pressed one pulls, a
    separated one closes) or a left-out apex face that the rates cross (``"apex"``)."""
    if not cls.has_zero:  # no zero-force contact: no guess (``sep`` is part of ``cls.zero``)
        return seg
    d = qm.d
    rtol = RATE_RTOL * max(float(np.abs(dc).max(initial=0.0)), sc.r0max, 1e-300)
    bad = cls.zero & (plan == PRESS) & (dc[::d] < -rtol)
    closing = -(qm.A[:, ::d].T @ v) * qm.kn
    bad |= sep & (closing > rtol)
    if bad.any():
        seg.status = SegmentStatus.GUESS
        seg.flip = bad
        return seg
    if apex is not None and spec.friction and qm.nf:
        on = cls.zero & ~sep & ~seg.separated
        rows = (on[qm.face_contact] & ~apex).nonzero()[0]
        if len(rows):
            out = rows[(qm.Phi[rows] @ dc) < -rtol]
            if len(out):
                seg.status = SegmentStatus.APEX
                seg.add = out
    return seg


__all__ = [
    "RATE_RTOL",
    "Classes",
    "Segment",
    "StageCache",
    "StageSpec",
    "State",
    "classify",
    "rates",
    "rescaled",
    "separated_on",
]
