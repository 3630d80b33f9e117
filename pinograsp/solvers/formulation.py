"""Scaled problem data shared by every passive-response backend.

The solvers work on a **normalised** copy of the model so that one set of big-M constants
and tolerances fits every scene (docs/solvers.md: big-M is a correctness issue):

* torques are divided by the model's ``length_scale`` ``ℓ`` so that every wrench component is
  in force units;
* each solve divides all forces by a data scale ``F`` (largest of the applied wrench, the
  actuator commands and the pre-compression forces, in force units): the model is
  homogeneous of degree one in ``(w, f_c)``, so solutions scale back exactly;
* displacements are multiplied by stiffness (``q̂_j = k_j ℓ_j q_j`` with ``ℓ_j`` the joint's
  lever to its contacts, ``x̂ = k_x (x_lin, ℓ x_rot)``), so every bounded quantity — normal
  force, spring gap, actuator displacement, actuator over-force — is in force units and of
  order one.

Variables of the scaled problem, in this order::

    z = [beta (nb), obj (nx or 1), qh (nq), fh (na), lam (ncp)]

``obj`` is the object displacement ``x̂`` for the PRP (Alg. 1) and the step ``ŝ`` along the
previous net wrench for the movement-constrained PRP (Alg. 2). The energetic problem
(docs/methods.md) appends one slip magnitude ``λ̂_i`` per contact with friction::

    z = [beta, x̂, qh, fh, lam, slip (nsl)]

and one *dissipation row* per friction edge ``b`` of contact ``i`` (unit tangent ``t̂_b``)::

    dissipation  t̂_b · v̂_i + λ̂_i >= 0,  beta_b >= 0,  beta_b · (t̂_b · v̂_i + λ̂_i) = 0

with ``v̂_i = k_i (G_i^T x - J_i q)_t`` the tangential slip of the object over the hand at the
contact, in spring-force units: an edge carries force only if it points most against the slip
(maximum dissipation on the pyramid), and ``λ̂_i = max_b(-t̂_b · v̂_i)`` is the slip's size.

Constraints (every row is in force units)::

    equilibrium  Gb beta + ŵ = 0                           (PRP only)
    hand         T beta - Rf fh - Cl lam = 0               (tau = J^T c = R f + C^T lambda)
    coupling     Cq qh = 0
    spring gap   s = E beta - Kq qh + Kx x̂ - p̂ >= 0,  c_n = E beta >= 0,  c_n · s = 0
    actuator     û = Ru qh,  f̂ - f̂_c  (kind-dependent complementarity, see actuation.py)

This module never imports a solver library.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.actuation import BACKDRIVABLE, LOCKED, NON_BACKDRIVABLE
from ..core.build import coupled_closure
from ..core.model import GraspModel
from ..errors import ModelError

#: Names of the variable layouts: the values of :class:`~pinograsp.solvers.problem.ProblemKind`.
LAYOUT_NAMES = ("prp", "move", "load", "energetic", "energetic-load")


@dataclass(frozen=True)
class Layout:
    """Where each block of variables sits in the scaled vector ``z`` of one problem kind.

    Every :class:`~pinograsp.solvers.problem.Problem` carries its layout and every
    :class:`~pinograsp.solvers.base.RawSolution` keeps it (``raw.layout.beta``), so a solution
    is read by names, not by re-deriving which algorithm produced it.

    Attributes:
        name: The problem kind (a ``ProblemKind`` value).
        beta, obj, qh, fh, lam, slip: Slices of the edge weights (nb), the object displacement
            (nx; one step for ``"move"``), joint displacements (nq), actuator forces (na),
            coupling reactions (ncp) and slip magnitudes (nsl; energetic kinds only).
        n: All of these (``slice(0, n)``); extra step variables of a multi-direction ``"move"``
            problem and the load factor of load kinds follow.
        t: Index of the load factor ``t`` (load kinds), else None.
    """

    name: str
    beta: slice
    obj: slice
    qh: slice
    fh: slice
    lam: slice
    slip: slice
    n: slice
    t: int | None = None

    def __getitem__(self, key: str) -> slice:
        """``layout["beta"]``: the slice by name."""
        value = getattr(self, key)
        if not isinstance(value, slice):
            raise KeyError(key)
        return value


@dataclass(frozen=True, eq=False)
class ScaledData:
    """Normalised right-hand sides of one solve.

    Attributes:
        F: Force scale [N] the data were divided by.
        w: Applied wrench, (nw,), torques / ℓ, divided by ``F``.
        fc: Actuator commands in contact-force units, divided by ``F``, (na,).
        p: Spring pre-compression (preload normal forces of the preload-first variant), (nc,).
        x0: Previous object displacement (scaled), (nx,) — Alg. 2 only.
        direction: Movement direction (scaled previous net wrench), (nx,) — Alg. 2 only.
    """

    F: float
    w: np.ndarray
    fc: np.ndarray
    p: np.ndarray
    x0: np.ndarray
    direction: np.ndarray


class Formulation:
    """Scaled matrices of a :class:`~pinograsp.core.model.GraspModel` (built once per model)."""

    def __init__(self, model: GraspModel) -> None:
        self.model = model
        m = model
        nc, nb, nq, na = m.nc, m.nb, m.nq, m.na
        ell = m.length_scale
        self.nc, self.nb, self.nq, self.na, self.ncp = nc, nb, nq, na, m.ncp
        self.nw = m.nw
        self.nx = m.nw
        # wrench metric: torque rows / ℓ
        self.wscale = m.wrench_weights
        G = m.G * self.wscale[:, None]
        self.Gb = G @ m.D  # (nw, nb)
        self.E = m.E  # (nc, nb)
        nrows = m.normal_rows
        Jn = m.J[nrows]  # (nc, nq)
        absJ = np.abs(m.J)
        # joints that move no contact are only kept when rigidly coupled to one that does (a
        # motor driving its fingers through mimics, core/build.py): they take the length scale
        # and the stiffest contact as their scales (their Jacobian columns are zero)
        self.lever = absJ.max(axis=0) if nq else np.zeros(0)  # (nq,) [m/rad]
        free = self.lever <= 0
        idle = ~coupled_closure(~free, m.C) if nq else free  # coupled to no joint that moves one
        if np.any(idle):
            names = ", ".join(m.joint_names[j] for j in np.flatnonzero(idle))
            raise ModelError(
                f"joint(s) {names} move no contact (a zero Jacobian column) and are coupled to no "
                "joint that does, so no force can hold them; build the model with prune=True (the "
                "default), which removes them",
                "prune",
            )
        self.lever = np.where(free, ell, self.lever)
        # stiffness of each joint's contacts
        reach = np.zeros((nc, nq), bool)
        for i in range(nc):
            reach[i] = np.any(absJ[i * m.d : (i + 1) * m.d] > 0, axis=0)
        reach[:, free] = True
        self.kq = np.array([m.k[reach[:, j]].max() for j in range(nq)]) if nq else np.zeros(0)
        self.kx = float(m.k.max())
        self.qscale = self.kq * self.lever  # qh = qscale * q
        self.Kq = (m.k[:, None] * Jn) / self.qscale[None, :] if nq else np.zeros((nc, 0))
        self.Kx = (m.k / self.kx)[:, None] * G[:, nrows].T  # (nc, nx): object motion along n
        # actuator force scaling: fh = f * rho / F
        if na:
            self.rho = np.abs(m.R / self.lever[:, None]).max(axis=0)
        else:
            self.rho = np.zeros(0)
        T = (m.J.T @ m.D) / self.lever[:, None] if nq else np.zeros((0, nb))
        self.T = T  # (nq, nb)
        self.Rf = m.R / self.lever[:, None] / self.rho[None, :] if na else np.zeros((nq, 0))
        if m.ncp:
            Cl = m.C.T / self.lever[:, None]
            self.cl_norm = np.abs(Cl).max(axis=0)  # lambda = F * lam_hat / cl_norm
            self.Cl = Cl / self.cl_norm[None, :]
            Cq = m.C / self.qscale[None, :]
            self.Cq = Cq / np.abs(Cq).max(axis=1)[:, None]
        else:
            self.Cl = np.zeros((nq, 0))
            self.cl_norm = np.zeros(0)
            self.Cq = np.zeros((0, nq))
        Ru = m.R.T / self.qscale[None, :] if na else np.zeros((0, nq))
        usigma = 1.0 / np.abs(Ru).max(axis=1) if na else np.zeros(0)
        self.Ru = Ru * usigma[:, None]  # (na, nq): û = Ru qh
        self._slip_rows(m, G)
        self.nbd = np.array([k == NON_BACKDRIVABLE for k in m.kinds], bool)
        self.bdr = np.array([k == BACKDRIVABLE for k in m.kinds], bool)
        self.lck = np.array([k == LOCKED for k in m.kinds], bool)

    def _slip_rows(self, m: GraspModel, G: np.ndarray) -> None:
        """Rows of the energetic problem's dissipation block (see the module docstring)."""
        d = m.d
        tang = np.zeros((m.nb, d - 1))
        for b in range(m.nb):
            i = int(m.beta_contact[b])
            tang[b] = m.D[i * d + 1 : (i + 1) * d, b]
        size = np.linalg.norm(tang, axis=1)
        cols = np.flatnonzero(size > 0)
        #: friction edges with a tangential part (the dissipation rows), (nf,)
        self.fric_edges = cols
        contacts = np.unique(m.beta_contact[cols]).astype(int)
        #: contacts with friction, in order: one slip magnitude each, (nsl,)
        self.slip_contacts = contacts
        self.nsl = len(contacts)
        index = {int(c): j for j, c in enumerate(contacts)}
        nf = len(cols)
        self.Sx = np.zeros((nf, self.nx))
        self.Sq = np.zeros((nf, m.nq))
        self.Sl = np.zeros((nf, self.nsl))
        for r, b in enumerate(int(c) for c in cols):
            i = int(m.beta_contact[b])
            unit = tang[b] / size[b]
            trows = np.arange(i * d + 1, (i + 1) * d)
            self.Sx[r] = (m.k[i] / self.kx) * unit @ G[:, trows].T
            if m.nq:
                self.Sq[r] = -(m.k[i] * unit @ m.J[trows]) / self.qscale
            self.Sl[r, index[i]] = 1.0
        #: slip loses compression of the worst-case tilted normal: ``tan(u)`` per unit slip
        self.tilt = float(np.tan(m.normal_uncertainty))

    # ------------------------------------------------------------------ layout
    def layout(self, kind: str) -> Layout:
        """The named variable layout of the problem kind ``kind`` (a
        :class:`~pinograsp.solvers.problem.ProblemKind` value): ``"prp"`` and ``"load"`` (object
        displacement), ``"move"`` (one step) or ``"energetic"`` and ``"energetic-load"`` (object
        displacement and one slip magnitude per friction contact). Load kinds add the load
        factor ``t`` as their last variable."""
        from ..errors import InvalidInputError  # (one import per line: errors above is ModelError)

        name = str(getattr(kind, "value", kind))
        if name not in LAYOUT_NAMES:
            raise InvalidInputError("kind", f"must be one of {list(LAYOUT_NAMES)}, got {kind!r}")
        nobj = 1 if name == "move" else self.nx
        nsl = self.nsl if name.startswith("energetic") else 0
        o = self.nb
        beta, obj = slice(0, o), slice(o, o + nobj)
        o += nobj
        qh = slice(o, o + self.nq)
        o += self.nq
        fh = slice(o, o + self.na)
        o += self.na
        lam = slice(o, o + self.ncp)
        o += self.ncp
        slip = slice(o, o + nsl)
        n = slice(0, o + nsl)
        t = int(n.stop) if name.endswith("load") else None
        return Layout(name, beta, obj, qh, fh, lam, slip, n, t)

    # -------------------------------------------------------------- data scaling
    def scale_data(
        self,
        wrench: np.ndarray,
        command: np.ndarray,
        precompression: np.ndarray | None = None,
        x0: np.ndarray | None = None,
        direction: np.ndarray | None = None,
        F: float | None = None,
    ) -> ScaledData:
        """Normalise one solve's data (physical units in, force-unit scaled out).

        Args:
            wrench: Applied wrench in model coordinates (nw,) [N, N·m].
            command: Actuator commands (na,) [actuator units].
            precompression: Spring pre-compression forces (nc,) [N].
            x0: Previous object displacement in model coordinates (nx,) [m, rad].
            direction: Movement direction, scaled wrench units (nx,) (already normalised).
            F: Force scale to use; default from the data.
        """
        w = np.asarray(wrench, float) * self.wscale
        fc = np.asarray(command, float) * self.rho
        p = np.zeros(self.nc) if precompression is None else np.asarray(precompression, float)
        if F is None:
            F = max(np.abs(w).max(initial=0.0), np.abs(fc).max(initial=0.0), np.abs(p).max(initial=0.0))
            if not F > 0:
                F = 1.0
        xh0 = np.zeros(self.nx) if x0 is None else self.scale_x(np.asarray(x0, float)) / F
        d = np.zeros(self.nx) if direction is None else np.asarray(direction, float)
        return ScaledData(F=float(F), w=w / F, fc=fc / F, p=p / F, x0=xh0, direction=d)

    def scale_x(self, x: np.ndarray) -> np.ndarray:
        """Physical object displacement (translation [m], rotation [rad]) → scaled (force units)."""
        return self.kx * x / self.wscale

    def unscale_x(self, xh: np.ndarray, F: float) -> np.ndarray:
        """Scaled object displacement → physical."""
        return xh * F * self.wscale / self.kx

    def spring_gap(
        self, beta: np.ndarray, xh: np.ndarray, qh: np.ndarray, p: np.ndarray, slip: np.ndarray | None = None
    ) -> np.ndarray:
        """Scaled spring gap ``s = c_n - k delta - p`` (nc,); with the energetic problem's slip
        magnitudes ``slip`` (nsl,), plus the worst-case tilt term ``tan(u) λ̂``."""
        s = self.E @ beta - self.Kq @ qh + self.Kx @ xh - p
        if slip is not None and self.nsl:
            s = s.copy()
            s[self.slip_contacts] += self.tilt * slip
        return s

    def dissipation(self, xh: np.ndarray, qh: np.ndarray, slip: np.ndarray) -> np.ndarray:
        """Scaled dissipation rows ``t̂_b · v̂_i + λ̂_i`` of the friction edges, (nf,)."""
        return self.Sx @ xh + self.Sq @ qh + self.Sl @ slip
