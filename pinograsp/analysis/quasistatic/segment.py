"""The record of one segment of the loading path (:class:`Segment`) and its assembly from a
solved rate problem (:func:`segment_of`): the rates per unit path parameter, and per contact
and actuator its state on the segment (docs/quasistatic.md)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...core.response_result import ContactState
from .model import QSModel
from .state import StageSpec
from .statuses import SegmentStatus
from .system import StageCache

#: Relative tolerance (to the rate scale of the segment) under which a rate is zero.
RATE_RTOL = 1e-10
#: The largest element (``x.max(initial=...)`` without its Python wrapper: the same reduction).
_amax = np.maximum.reduce
#: A contact's state on a segment by whether it separates (unless it slides).
_SEPARATED: tuple[ContactState, ContactState] = ("sticking", "separated")


@dataclass
class Segment:
    """Rates of one segment per unit of the path parameter, and its states.

    Attributes:
        status: :class:`~.statuses.SegmentStatus`: ``OK``, ``LIMIT`` (no continuation with
            growing load: ``dλ <= 0`` under displacement control), ``UNSTABLE``, the retries
            ``GUESS``/``APEX``, or a failure (``SINGULAR``, the LCP's ``RAY_TERMINATION``,
            ``PIVOT_LIMIT``, ``INACCURATE``).
        dvs, dc, df, dlam_c, dhold, dslip: Rates (as :class:`State`).
        contact: Per contact ``"separated"``, ``"sticking"`` or ``"sliding"``.
        detail: Per contact the sliding faces (indices) — one face, or two at a vertex.
        actuator: Per actuator ``"moving"``, ``"holding"``, ``"backdrivable"``, ``"locked"``.
        lcp_size, pivots: Size of the local LCP and Lemke pivots made.
        control: ``"load"`` or ``"displacement"``.
        stiffness_rate: ``dλ`` per unit scaled displacement along the load (displacement
            control only).
    """

    status: SegmentStatus
    dvs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dc: np.ndarray = field(default_factory=lambda: np.zeros(0))
    df: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dlam_c: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dhold: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dslip: np.ndarray = field(default_factory=lambda: np.zeros(0))
    contact: tuple[ContactState, ...] = ()
    detail: tuple[tuple[int, ...], ...] = ()
    actuator: tuple[str, ...] = ()
    lcp_size: int = 0
    pivots: int = 0
    control: str = "load"
    stiffness_rate: float = float("nan")
    lam_rate: float = 1.0
    flip: np.ndarray | None = None
    tie: bool = False
    active: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    add: np.ndarray | None = None
    separated: np.ndarray | None = None  # (nc,) bool: contact == "separated" (speed only)


@dataclass(eq=False)
class Items:
    """The LCP items of a rate problem (index arrays): zero-force contacts with an opening
    pair (``zero``), boundary faces (``faces``, rows of :attr:`QSModel.Phi`), non-backdrivable
    actuators at their command (``acts``)."""

    zero: np.ndarray
    faces: np.ndarray
    acts: np.ndarray

    @property
    def size(self) -> int:
        """Number of items (the LCP's size)."""
        return len(self.zero) + len(self.faces) + len(self.acts)


@dataclass(eq=False)
class Solved:
    """The rates of one solved rate problem per unit path parameter: displacements ``v`` (nv,),
    contact forces ``dc`` (ncd,), constraint multipliers ``rho`` (ncon,), the load rate
    ``lam_rate`` and the flows ``zeta`` (nz,)."""

    v: np.ndarray
    dc: np.ndarray
    rho: np.ndarray
    lam_rate: float
    zeta: np.ndarray


def separated_on(seg: Segment) -> np.ndarray:
    """Contacts separated on ``seg`` (nc,) bool."""
    if seg.separated is not None:
        return seg.separated
    return np.array([c == "separated" for c in seg.contact], bool)


def segment_of(
    qm: QSModel,
    spec: StageSpec,
    sc: StageCache,
    solved: Solved,
    items: Items,
    *,
    lcp_size: int,
    pivots: int,
    control: str,
    sep: np.ndarray,
    open_: np.ndarray,
    has_zero: bool,
) -> Segment:
    """The :class:`Segment` of a solved rate problem; ``sep``, ``open_`` (nc,): the contacts planned
    separated, with a gap; ``has_zero``: any contact at zero force (``solved.dc`` is kept)."""
    zero, faces, acts = items.zero, items.faces, items.acts
    v, dc, rho, lam_rate, zeta = solved.v, solved.dc, solved.rho, solved.lam_rate, solved.zeta
    d, nx, nc, k = qm.d, qm.nx, qm.nc, qm.k_ref
    df = np.zeros(qm.na)
    if qm.na:
        df[qm.bd] = sc.dfc_bd * lam_rate
        df[sc.act_owner] = k * rho[sc.act_cols] / sc.act_rnorm
    dlam = k * rho[sc.coupling_cols] / qm.c_norm if qm.ncp else np.zeros(0)
    dhold = qm.S[:nx] * k * rho[sc.holder_cols] if spec.held else np.zeros(nx)
    nzero, n1 = len(zero), len(zero) + len(faces)
    flows_f = zeta[nzero:n1]
    dslip = flows_f @ qm.slip_rows[faces] if len(faces) else np.zeros(qm.ncd)
    rscale = max(float(_amax(np.abs(dc), initial=0.0)), sc.r0max * abs(lam_rate), 1e-300)
    ftol = RATE_RTOL * rscale
    if nzero:
        opening = sep.copy()
        opening[zero] = (zeta[:nzero] > ftol) | (dc[zero * d] <= ftol)
    else:
        opening = sep
    flowing = faces[flows_f > ftol]
    sep_all = open_ | opening
    sep_l = sep_all.tolist()
    contact: list[ContactState] = list(map(_SEPARATED.__getitem__, sep_l))
    detail: list[tuple[int, ...]] = [()] * nc
    if len(flowing):  # the sliding faces per contact, in face order
        sliding: dict[int, list[int]] = {}
        for r in flowing.tolist():
            i, f = sc.face_owner_index[r]
            if i in sliding:
                sliding[i].append(f)
            else:
                sliding[i] = [f]
        for i, x in sliding.items():
            if not sep_l[i]:
                contact[i] = "sliding"
                detail[i] = tuple(x)
    actuator = list(sc.act_still)
    if len(acts):
        for a, m in zip(acts.tolist(), (zeta[n1:] > ftol).tolist()):
            if m:
                actuator[a] = "moving"
    if True in sep_l:  # separated contacts carry no force rate
        if has_zero:  # the rates' own dc is read again (_check_guesses)
            dc = dc.copy()
        dc.reshape(nc, d)[sep_all] = 0.0
    return Segment(
        status=SegmentStatus.OK,
        dvs=v,
        dc=dc,
        df=df,
        dlam_c=dlam,
        dhold=dhold,
        dslip=dslip,
        contact=tuple(contact),
        detail=tuple(detail),
        actuator=tuple(actuator),
        lcp_size=lcp_size,
        pivots=pivots,
        control=control,
        lam_rate=lam_rate,
        separated=sep_all,
    )


def rescaled(seg: Segment, factor: float) -> Segment:
    """``seg`` with every rate multiplied by ``factor`` (displacement → load control)."""
    out = Segment(**{**seg.__dict__})
    for name in ("dvs", "dc", "df", "dlam_c", "dhold", "dslip"):
        setattr(out, name, getattr(seg, name) * factor)
    out.lam_rate = 1.0  # per unit load by construction
    return out


__all__ = ["RATE_RTOL", "Items", "Segment", "Solved", "rescaled", "segment_of", "separated_on"]
