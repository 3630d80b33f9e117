"""One description of a passive-response problem that every backend reads.

A problem is a *linear-complementarity-constrained least-squares program* over the scaled
variables of :mod:`pinograsp.solvers.formulation` (``z = [beta, obj, qh, fh, lam]``)::

    minimise    |L z + l|^2
    subject to  A z = b
                lo <= C z <= up
                (C[i] z - lo[i]) * (C[j] z - lo[j]) = 0     for every pair (i, j)

The complementarity pairs are the contact pairs (normal force ``c_n`` / spring gap) and the
non-backdrivable actuator pairs (actuator displacement ``u`` / over-force ``f - f_c``). Fixing a
pair's *side* (which of its two rows sits at its lower bound) gives a convex QP; a
:class:`~pinograsp.solvers.base.Mode` fixes every pair.

The problem is built from the numbers of one solve (:class:`~.formulation.ScaledData`), so a
backend never writes constraint rows of its own: the branch-and-bound reads the rows directly,
the cvxpy reference backend turns the pairs into big-M or indicator constraints, and the result
audit reads the same rows. Every row is in scaled force units.

This module never imports a solver library.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

import numpy as np

from .base import Mode
from .formulation import Formulation, Layout, ScaledData

#: Stand-in for an infinite bound (every backend reads it as "no bound").
INF = 1e30
#: An equality row without any variable whose right-hand side exceeds this (scaled force units)
#: makes the problem infeasible (e.g. a wrench component that no contact force can produce).
EMPTY_ROW_TOL = 1e-9


class ProblemKind(str, Enum):
    """Which algorithm's optimisation problem."""

    #: Seed Alg. 1: minimise the spring energy ``|c_n|^2`` subject to equilibrium.
    PRP = "prp"
    #: Seed Alg. 2: the object moves along the previous net wrench by ``s in [0, gamma]``;
    #: minimise the net wrench ``|w + G c|^2``.
    MOVE = "move"
    #: Alg. 1's largest load factor along a direction ``d``: the PRP's constraints with the load
    #: ``t d`` and ``0 <= t <= t_max``; minimise ``(t_max - t)^2`` (i.e. maximise ``t``). The
    #: load factor ``t`` is the last variable.
    LOAD = "load"
    #: The energetic problem (docs/methods.md): the PRP's constraints plus one slip magnitude
    #: per friction contact and the maximum-dissipation pairs (an edge carries force only if
    #: it points most against the contact's slip); minimise the spring energy.
    ENERGETIC = "energetic"
    #: The energetic problem's largest load factor along a direction (as ``LOAD``).
    ENERGETIC_LOAD = "energetic-load"

    @property
    def energetic(self) -> bool:
        """Whether the problem has slip variables and maximum-dissipation pairs."""
        return self in (ProblemKind.ENERGETIC, ProblemKind.ENERGETIC_LOAD)

    @property
    def load(self) -> bool:
        """Whether the problem maximises a load factor (its last variable)."""
        return self in (ProblemKind.LOAD, ProblemKind.ENERGETIC_LOAD)


class PairKind(str, Enum):
    """What a complementarity pair models."""

    CONTACT = "contact"
    ACTUATOR = "actuator"
    #: A friction edge's weight / its dissipation row (energetic problems only).
    FRICTION = "friction"


@dataclass(frozen=True, eq=False)
class Rows:
    """Row offsets of the inequality block ``C`` (the same for every solve of a kind)."""

    beta: slice
    cn: slice
    gap: slice
    u: slice
    f: slice
    step: slice
    diss: slice


def layout_rows(form: Formulation, kind: ProblemKind, n_steps: int = 1) -> Rows:
    """Row slices of the inequality block of ``kind`` (``n_steps`` step rows for ``MOVE``)."""
    o = 0
    sl = []
    nstep = n_steps if kind is ProblemKind.MOVE else (1 if kind.load else 0)
    ndiss = len(form.fric_edges) if kind.energetic else 0
    for size in (form.nb, form.nc, form.nc, form.na, form.na, nstep, ndiss):
        sl.append(slice(o, o + size))
        o += size
    return Rows(*sl)


@dataclass(frozen=True, eq=False)
class Problem:
    """Numbers of one complementarity-constrained least-squares problem (see module docstring).

    Attributes:
        kind: :class:`ProblemKind`.
        L: Objective matrix, (m, n).
        l: Objective offset, (m,).
        A: Equality rows, (me, n).
        b: Equality right-hand side, (me,).
        C: Inequality rows, (mi, n).
        lo: Lower bounds of ``C z``, (mi,) (``-INF``: none).
        up: Upper bounds of ``C z``, (mi,) (``INF``: none).
        pairs: Complementarity pairs as inequality-row indices, (npair, 2): side 0 is the
            contact force / actuator displacement / friction edge weight, side 1 the spring
            gap / over-force / dissipation row.
        pair_kind: :class:`PairKind` of each pair.
        pair_owner: Index of the contact, actuator or friction edge (``beta`` column) each
            pair belongs to, (npair,).
        bigm_factor: Scale of each pair side relative to the force scale, (npair, 2), for
            big-M backends (a separated contact's gap grows with the stiffness ratio).
        rows: Row offsets of the inequality block.
        nc, na: Contacts and actuators of the model (for :class:`Mode` conversion).
        eq_names: Name of each equality row (wrench axis, ``hand[j]``, ``coupling[r]``).
        groups: Energetic problems: the friction pairs of each contact with friction, in the
            angular order of their edges (adjacent entries are adjacent edges, cyclically).
        group_owner: The contact of each group.
        layout: Where each block of variables sits (:class:`~.formulation.Layout`); None for
            programs that are not a passive-response problem (e.g. the preload program).
    """

    kind: ProblemKind
    L: np.ndarray
    l: np.ndarray
    A: np.ndarray
    b: np.ndarray
    C: np.ndarray
    lo: np.ndarray
    up: np.ndarray
    pairs: np.ndarray
    pair_kind: tuple[PairKind, ...]
    pair_owner: np.ndarray
    bigm_factor: np.ndarray
    rows: Rows
    nc: int
    na: int
    eq_names: tuple[str, ...] = ()
    groups: tuple[tuple[int, ...], ...] = ()
    group_owner: tuple[int, ...] = ()
    layout: Layout | None = None

    def empty_rows(self) -> list[str]:
        """Names of equality rows ``0 = b`` with ``b != 0``: nothing can satisfy them."""
        empty = ~np.any(self.A != 0, axis=1) & (np.abs(self.b) > EMPTY_ROW_TOL)
        return [self.eq_names[i] if i < len(self.eq_names) else f"row {i}" for i in np.flatnonzero(empty)]

    @property
    def step_index(self) -> int:
        """Index of the (first) step length ``s`` (``MOVE``) among the variables."""
        return self.rows.beta.stop

    def step_lengths(self, z: np.ndarray) -> np.ndarray:
        """Every step variable of a ``MOVE`` point (the coefficients of the directions), (m,)."""
        return self.C[self.rows.step] @ z

    @property
    def n(self) -> int:
        """Number of variables."""
        return self.C.shape[1]

    def objective(self, z: np.ndarray) -> float:
        """``|L z + l|^2`` (scaled)."""
        r = self.L @ z + self.l
        return float(r @ r)

    # ------------------------------------------------------------------ modes
    def sides_of(self, mode: Mode) -> np.ndarray:
        """Pair sides fixed by ``mode``, (npair,) of 0/1: the side held at its lower bound.

        A touching contact holds its gap (side 1) at zero, a separated one its force (side 0);
        a moving actuator holds its over-force (side 1), a holding one its displacement (side 0);
        a friction edge that may carry force holds its dissipation row (side 1), another its
        weight (side 0).
        """
        out = np.zeros(len(self.pairs), np.int8)
        f = 0
        for k, (pk, i) in enumerate(zip(self.pair_kind, self.pair_owner)):
            if pk is PairKind.FRICTION:
                on = mode.edges[f] if f < len(mode.edges) else True
                f += 1
            else:
                on = mode.touching[i] if pk is PairKind.CONTACT else mode.moving[i]
            out[k] = 1 if on else 0
        return out

    def mode_of(self, sides: np.ndarray) -> Mode:
        """The :class:`Mode` whose pairs are fixed at ``sides`` (inverse of :meth:`sides_of`)."""
        touching = [False] * self.nc
        moving = [False] * self.na
        edges = []
        for k, (pk, i) in enumerate(zip(self.pair_kind, self.pair_owner)):
            if pk is PairKind.CONTACT:
                touching[i] = bool(sides[k])
            elif pk is PairKind.ACTUATOR:
                moving[i] = bool(sides[k])
            else:
                edges.append(bool(sides[k]))
        return Mode(tuple(touching), tuple(moving), tuple(edges))

    def natural_sides(self, z: np.ndarray) -> np.ndarray:
        """For each pair, the side closer to its bound at ``z`` (ties: side 1), (npair,)."""
        v = self.C @ z - self.lo
        a, b = v[self.pairs[:, 0]], v[self.pairs[:, 1]]
        return (b <= a).astype(np.int8)

    def bounds(self, fixed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bounds with pairs fixed: ``fixed`` (npair,) holds -1 (free), 0 or 1 (side held)."""
        up = self.up.copy()
        for k in np.flatnonzero(fixed >= 0):
            row = self.pairs[k, fixed[k]]
            up[row] = self.lo[row]
        return self.lo, up

    def complementarity(self, z: np.ndarray) -> np.ndarray:
        """``min(a, b)`` of every pair at ``z`` (scaled force units), (npair,)."""
        v = self.C @ z - self.lo
        return np.minimum(np.abs(v[self.pairs[:, 0]]), np.abs(v[self.pairs[:, 1]]))


def build_problem(
    form: Formulation,
    kind: ProblemKind | str,
    data: ScaledData,
    gamma: float = 1.0,
    t_max: float = 1.0,
) -> Problem:
    """The :class:`Problem` of one solve.

    Args:
        form: Scaled formulation of the model.
        kind: :class:`ProblemKind` (or its value).
        data: Scaled data of the solve (for ``LOAD``, ``data.direction`` is the scaled unit load
            direction and ``data.w`` a constant load added to ``t d``, usually zero). For
            ``MOVE``, ``data.direction`` (nx,) is the movement direction; an (nx, m) matrix
            lets the object move by any combination ``D a`` with ``0 <= a <= gamma`` (the
            extra step variables ``a[1:]`` are appended after every other variable).
        gamma: Step bound of Alg. 2 (scaled; ``MOVE`` only; ``INF`` for no bound).
        t_max: Search limit of the load factor (scaled; ``LOAD`` only).
    """
    kind = ProblemKind(kind)
    move = kind is ProblemKind.MOVE
    lay = form.layout(kind)
    directions = np.asarray(data.direction, float)
    directions = directions.reshape(len(directions), -1) if move else directions
    extra = directions.shape[1] - 1 if move else (1 if kind.load else 0)
    n = lay.n.stop + extra
    L, l_vec = _objective(form, kind, data, lay, n, t_max)
    A, b, eq_names = _equalities(form, kind, data, lay, n)
    rows = layout_rows(form, kind, directions.shape[1] if move else 1)
    C, lo, up = _inequalities(form, kind, data, lay, n, rows, directions, gamma, t_max)
    pairs, pair_kind, owner, factor = _pairs(form, rows, kind.energetic)
    groups = _groups(form, pair_kind, owner)
    return Problem(
        kind=kind,
        L=L,
        l=l_vec,
        A=A,
        b=b,
        C=C,
        lo=lo,
        up=up,
        pairs=pairs,
        pair_kind=pair_kind,
        pair_owner=owner,
        bigm_factor=factor,
        rows=rows,
        nc=form.nc,
        na=form.na,
        eq_names=eq_names,
        groups=tuple(g for _, g in groups),
        group_owner=tuple(i for i, _ in groups),
        layout=lay,
    )


def _objective(
    f: Formulation, kind: ProblemKind, data: ScaledData, lay: Layout, n: int, t_max: float
) -> tuple[np.ndarray, np.ndarray]:
    """``L``, ``l`` of ``|L z + l|^2``: the net wrench (``MOVE``), ``t_max - t`` (``LOAD``) or
    the normal forces (``PRP``)."""
    if kind is ProblemKind.MOVE:
        L = np.zeros((f.nw, n))
        L[:, lay.beta] = f.Gb
        return L, np.asarray(data.w, float).copy()
    if kind.load:
        L = np.zeros((1, n))
        L[0, -1] = 1.0
        return L, np.array([-float(t_max)])
    L = np.zeros((f.nc, n))
    L[:, lay.beta] = f.E
    return L, np.zeros(f.nc)


def _equalities(
    f: Formulation, kind: ProblemKind, data: ScaledData, lay: Layout, n: int
) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """``A``, ``b`` and the row names of the equalities: equilibrium (not for ``MOVE``), hand,
    couplings."""
    sb = lay.beta
    eq, rhs = [], []
    names = []
    if kind is not ProblemKind.MOVE:
        names += ["fx", "fy", "mz"] if f.model.planar else ["fx", "fy", "fz", "mx", "my", "mz"]
        Aeq = np.zeros((f.nw, n))
        Aeq[:, sb] = f.Gb
        if kind.load:
            Aeq[:, -1] = np.asarray(data.direction, float)
        eq.append(Aeq)
        rhs.append(-np.asarray(data.w, float))  # load kinds: a constant part of the load
    names += [f"hand[{j}]" for j in range(f.nq)] + [f"coupling[{r}]" for r in range(f.ncp)]
    Ah = np.zeros((f.nq, n))
    Ah[:, sb] = f.T
    Ah[:, lay.fh] = -f.Rf
    Ah[:, lay.lam] = -f.Cl
    Ac = np.zeros((f.ncp, n))
    Ac[:, lay.qh] = f.Cq
    eq += [Ah, Ac]
    rhs += [np.zeros(f.nq), np.zeros(f.ncp)]
    return np.vstack(eq), np.concatenate(rhs), tuple(names)


def _inequalities(
    f: Formulation,
    kind: ProblemKind,
    data: ScaledData,
    lay: Layout,
    n: int,
    rows: Rows,
    directions: np.ndarray,
    gamma: float,
    t_max: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``C``, ``lo``, ``up`` of the rows beta | c_n | gap | u | f | step (``MOVE``: steps in
    ``[0, gamma]``; ``LOAD``: ``t`` in ``[0, t_max]``)."""
    sb, so, sq = lay.beta, lay.obj, lay.qh
    mi = rows.diss.stop
    C = np.zeros((mi, n))
    lo = np.full(mi, -INF)
    up = np.full(mi, INF)
    C[rows.beta, sb] = np.eye(f.nb)
    lo[rows.beta] = 0.0
    C[rows.cn, sb] = f.E
    lo[rows.cn] = 0.0
    C[rows.gap, sb] = f.E
    C[rows.gap, sq] = -f.Kq
    p = np.asarray(data.p, float)
    if kind is ProblemKind.MOVE:
        cols = [so.start] + list(range(lay.n.stop, n))
        KD = f.Kx @ directions
        lo[rows.gap] = p - f.Kx @ data.x0
        for k, c in enumerate(cols):
            C[rows.gap, c] = KD[:, k]
            C[rows.step.start + k, c] = 1.0
        lo[rows.step], up[rows.step] = 0.0, float(gamma)
    else:
        C[rows.gap, so] = f.Kx
        lo[rows.gap] = p
    if kind.load:
        C[rows.step, -1] = 1.0
        lo[rows.step], up[rows.step] = 0.0, float(t_max)
    if kind.energetic:
        sl = lay.slip
        C[rows.diss, so] = f.Sx
        C[rows.diss, sq] = f.Sq
        C[rows.diss, sl] = f.Sl
        lo[rows.diss] = 0.0
        # worst-case tilted normal: slip loses tan(u) of compression (cones.py)
        C[rows.gap.start + f.slip_contacts, sl.start + np.arange(f.nsl)] = f.tilt
    C[rows.u, sq] = f.Ru
    C[rows.f, lay.fh] = np.eye(f.na)
    fc = np.asarray(data.fc, float)
    # actuator kinds: backdrivable f = f_c, u free; locked u = 0, f free; non-backdrivable
    # u >= 0, f >= f_c, complementary
    lo[rows.u] = np.where(f.bdr, -INF, 0.0)
    up[rows.u] = np.where(f.lck, 0.0, INF)
    lo[rows.f] = np.where(f.lck, -INF, fc)
    up[rows.f] = np.where(f.bdr, fc, INF)
    return C, lo, up


def _pairs(
    f: Formulation, rows: Rows, energetic: bool = False
) -> tuple[np.ndarray, tuple[PairKind, ...], np.ndarray, np.ndarray]:
    """The complementarity pairs (contacts, non-backdrivable actuators, then for energetic
    problems the friction edges): their rows (npair, 2), kinds, owners (npair,) and big-M
    factors (npair, 2)."""
    gap_m, u_m = _bigm_factors(f)
    nc = f.nc
    nbd = np.flatnonzero(f.nbd)
    edges = f.fric_edges if energetic else np.zeros(0, int)
    pairs = [(rows.cn.start + i, rows.gap.start + i) for i in range(nc)]
    pairs += [(rows.u.start + a, rows.f.start + a) for a in nbd]
    pairs += [(rows.beta.start + b, rows.diss.start + r) for r, b in enumerate(edges)]
    kinds = (PairKind.CONTACT,) * nc + (PairKind.ACTUATOR,) * len(nbd) + (PairKind.FRICTION,) * len(edges)
    owner = np.concatenate([np.arange(nc), nbd, edges]).astype(int)
    slip_m = gap_m[f.model.beta_contact[edges]] if len(edges) else np.zeros(0)
    factor = np.vstack(
        [
            np.column_stack([np.ones(nc), gap_m]),
            np.column_stack([u_m[nbd], np.ones(len(nbd))]),
            np.column_stack([np.ones(len(edges)), slip_m]),
        ]
    )
    return np.array(pairs, int).reshape(-1, 2), kinds, owner, factor.reshape(-1, 2)


def _groups(
    form: Formulation, kinds: tuple[PairKind, ...], owner: np.ndarray
) -> list[tuple[int, tuple[int, ...]]]:
    """Friction pairs per contact, in the angular order of their edges, with the contact (see
    :class:`Problem`)."""
    m = form.model
    d = m.d
    by_contact: dict[int, list[tuple[float, int]]] = {}
    for k, (pk, b) in enumerate(zip(kinds, owner)):
        if pk is PairKind.FRICTION:
            i = int(m.beta_contact[b])
            t = m.D[i * d + 1 : (i + 1) * d, b]
            angle = (
                float(np.mod(np.arctan2(t[1], t[0]), 2 * np.pi)) if d == 3 else (0.0 if t[0] > 0 else np.pi)
            )
            by_contact.setdefault(i, []).append((angle, k))
    return [(i, tuple(k for _, k in sorted(v))) for i, v in sorted(by_contact.items())]


def _bigm_factors(form: Formulation) -> tuple[np.ndarray, np.ndarray]:
    """Per-row big-M factors (>= 1) of the spring gaps (nc,) and actuator displacements (na,).

    Every bounded quantity is in scaled force units, but a separated contact of stiffness
    ``k_i`` has a gap of order ``(k_i / k_min) F`` and an actuator's displacement is measured in
    the stiffness of its stiffest joint (docs/stability.md).
    """
    m = form.model
    kmin = float(m.k.min())
    gap = np.maximum(m.k / kmin, 1.0)
    if form.na:
        reach = np.abs(m.R) > 0  # (nq, na)
        u = np.array([max(float(form.kq[reach[:, a]].max(initial=kmin)) / kmin, 1.0) for a in range(form.na)])
    else:
        u = np.zeros(0)
    return gap, u
