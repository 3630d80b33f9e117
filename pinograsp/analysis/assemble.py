"""From solved stages to a :class:`~pinograsp.core.results.PassiveResponse`: physical units,
the preload stage added on, modes and the post-solve audit (docs/accuracy.md)."""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.audit import EnergyCheck, audit_message, energy_check, friction_use
from ..core.results import Audit, ContactState, PassiveResponse, ResponseStatus
from ..core.settings import Variant
from ..errors import AuditWarning
from ..solvers.base import RawSolution
from ..solvers.formulation import Layout
from .context import SolveContext
from .stages import Stage

if TYPE_CHECKING:
    from .protocols import MethodRules


@dataclass(frozen=True, eq=False)
class _Physical:
    """A stage's solution in physical units (shapes as :class:`PassiveResponse`)."""

    beta: np.ndarray  # friction-cone edge weights [N]
    c: np.ndarray  # contact forces, contact frames, (nc*d,)
    cf: np.ndarray  # (nc, 3)
    fa: np.ndarray  # actuator forces (na,)
    lam: np.ndarray  # coupling reactions (ncp,)
    q: np.ndarray  # joint displacements from the touching configuration (nq,)
    x_load: np.ndarray  # object displacement of this stage alone (6,)
    x: np.ndarray  # object displacement including the preload stage (reduced)
    u: np.ndarray  # actuator displacements (na,)
    net: np.ndarray  # net wrench on the object (reduced)


def _nan_response(solver: SolveContext, status: ResponseStatus, common: dict[str, Any]) -> PassiveResponse:
    """No solution: every quantity is NaN."""
    m = solver.model
    return PassiveResponse.unsolved(
        m, status, friction_use=np.full(m.nc, np.nan), solver=solver.settings.backend, **common
    )


def _physical(
    solver: SolveContext, lay: Layout, z: np.ndarray, w6: np.ndarray, st: Stage, pre: Stage | None
) -> _Physical:
    """Unscale the stage's solution ``z`` and add the preload stage's displacements (when
    solved)."""
    m, f = solver.model, solver.form
    F = st.data.F
    beta = z[lay.beta] * F
    c = m.D @ beta  # (nc*d,)
    cf = np.zeros((m.nc, 3))
    cf[:, : m.d] = c.reshape(m.nc, m.d)
    fa = z[lay.fh] * F / f.rho if m.na else np.zeros(0)
    lam = z[lay.lam] * F / f.cl_norm if m.ncp else np.zeros(0)
    q = z[lay.qh] * F / f.qscale if m.nq else np.zeros(0)
    x = f.unscale_x(st.xh, F)
    x_load = m.expand_twist(x)
    pre_raw = pre.raw if pre is not None else None
    if pre is not None and pre_raw is not None and pre_raw.z is not None and pre_raw.layout is not None:
        q = q + pre_raw.z[pre_raw.layout.qh] * pre.data.F / f.qscale
        x = x + f.unscale_x(pre.xh, pre.data.F)
    u = m.R.T @ q
    net = m.G @ c + m.reduce_wrench(w6)
    return _Physical(beta, c, cf, fa, lam, q, x_load, x, u, net)


def _complementarity(solver: SolveContext, lay: Layout, z: np.ndarray, st: Stage, ph: _Physical) -> float:
    """Largest ``min(a, b)`` of the complementary pairs [N] (contact force / spring gap,
    actuator motion / over-force)."""
    f, F = solver.form, st.data.F
    qh = z[lay.qh]
    slip = z[lay.slip] if lay.slip.stop > lay.slip.start else None
    gap = f.spring_gap(z[lay.beta], st.xh, qh, st.data.p, slip) * F
    cn = f.E @ ph.beta
    comp = np.minimum(np.abs(cn), np.abs(gap)).max(initial=0.0)
    if slip is not None:  # maximum dissipation: edge weight / dissipation row
        diss = f.dissipation(st.xh, qh, slip) * F
        edge = ph.beta[f.fric_edges]
        comp = max(comp, np.minimum(np.abs(edge), np.abs(diss)).max(initial=0.0))
    if solver.model.na:
        uh = f.Ru @ qh * F
        over = (z[lay.fh] - st.data.fc) * F
        nbd = f.nbd
        comp = max(comp, np.minimum(np.abs(uh[nbd]), np.abs(over[nbd])).max(initial=0.0))
    return float(comp)


def _energy(
    solver: SolveContext, w6: np.ndarray, fc: np.ndarray, st: Stage, pre: Stage | None, ph: _Physical
) -> EnergyCheck:
    """Energy balance of an equilibrium, rounding relative to the larger of this stage's and
    the preload stage's scale."""
    m = solver.model
    return energy_check(
        ph.cf[:, 0],
        m.k,
        w6,
        ph.x_load,
        fc,
        ph.u,
        m.expand_twist(ph.x),
        ph.q,
        m.length_scale,
        solver.form.lever,
        m.contact_names,
        solver.settings.tolerance * max(st.data.F, pre.data.F if pre is not None else 0.0),
    )


#: Net wrench an exact method's equilibrium may leave, relative to the force scale.
EXACT_EQUILIBRIUM = 1e-6


def carries_residual(method: MethodRules, pre_method: MethodRules | None) -> bool:
    """Whether ``method``'s load stage balances the net wrench its preload stage (solved by
    ``pre_method``; None: no preload stage) left: :attr:`MethodRules.carries_residual` on an
    inexact preload (the energetic method on the held-still, iterative preload)."""
    return pre_method is not None and method.carries_residual and not pre_method.exact


def equilibrium_tolerance(
    solver: SolveContext, method: MethodRules, st: Stage, pre: Stage | None, carried: bool
) -> float | None:
    """What the object's net wrench [N] may be at ``method``'s equilibrium (None: an inexact
    method, judged by its own tolerance ``eps``): an exact method :data:`EXACT_EQUILIBRIUM` of the
    force scale; a load stage that carried its preload stage's residual (``carried``,
    :func:`carries_residual`) also that residual, at most the preload's tolerance
    ``eps + eps_rel F`` (docs/methods.md)."""
    if not method.exact:
        return None
    tol = EXACT_EQUILIBRIUM * max(st.data.F, 1e-300)
    if carried and pre is not None:
        s = solver.settings
        tol += s.eps + s.eps_rel * pre.data.F
    return tol


def _balanced(status: ResponseStatus, audit: Audit) -> ResponseStatus:
    """``"failed"`` for a resisted answer that does not balance the object within the method's
    ``equilibrium_tolerance`` (no verdict; its audit fails too), else ``status``."""
    return "failed" if status == "resisted" and not audit.balanced else status


def _audit(
    solver: SolveContext,
    raw: RawSolution,
    lay: Layout,
    z: np.ndarray,
    st: Stage,
    ph: _Physical,
    energy: EnergyCheck | None,
    eq_tol: float | None,
) -> Audit:
    """Residual checks of the solution ``raw`` (variables ``z``) in force units [N]; ``eq_tol``:
    the net wrench [N] the method's equilibrium may leave (None: judged by ``eps``)."""
    m, f = solver.model, solver.form
    hand = (
        (m.J.T @ ph.c - m.R @ ph.fa - m.C.T @ ph.lam) / np.where(f.lever > 0, f.lever, 1.0)
        if m.nq
        else np.zeros(0)
    )
    return Audit(
        equilibrium=float(np.linalg.norm(ph.net * f.wscale)),
        hand=float(np.abs(hand).max(initial=0.0)),
        complementarity=_complementarity(solver, lay, z, st, ph),
        friction=float(max(0.0, -ph.beta.min(initial=0.0))),
        bigm_ratio=raw.bigm_ratio,
        bigm_retries=raw.bigm_retries,
        polished=raw.polished,
        tolerance=solver.settings.tolerance * max(st.data.F, 1e-300),
        energy=energy,
        equilibrium_tolerance=eq_tol,
        pull=float(max(0.0, -ph.cf[:, 0].min(initial=0.0))),
        finite=bool(all(np.all(np.isfinite(a)) for a in (ph.c, ph.fa, ph.lam, ph.q, ph.x, ph.net))),
    )


def build_response(
    solver: SolveContext,
    method: MethodRules,
    variant: Variant,
    w6: np.ndarray,
    fc: np.ndarray,
    st: Stage,
    pre: Stage | None,
    *,
    pre_fresh: bool = True,
    pre_method: MethodRules | None = None,
) -> PassiveResponse:
    """The :class:`PassiveResponse` of the load stage ``st`` on top of the preload stage ``pre``
    (each solution read with its own layout, ``raw.layout``).

    Args:
        solver: The session that solved the stages.
        method: The method of the load stage; variant: the ``Variant`` used.
        w6: Applied wrench (6,) [N, N·m]; fc: commands (na,) [N·m or N].
        pre_fresh: The preload stage was solved by this query (it counts in time and solves).
        pre_method: The method that solved ``pre`` (its residual carried? :func:`carries_residual`).
    """
    m = solver.model
    status = st.status
    counted = pre if (pre is not None and pre_fresh) else None  # a cached preload costs nothing
    name = method.name
    common: dict[str, Any] = dict(
        method=name,
        variant=variant,
        wrench=w6,
        command=fc,
        iterations=st.iterations,
        residual_history=st.history,
        solve_time=st.solve_time + (counted.solve_time if counted is not None else 0.0),
        n_solves=st.n_solves + (counted.n_solves if counted is not None else 0),
    )
    raw = st.raw
    if raw is None or raw.z is None or raw.layout is None or raw.mode is None:
        return _nan_response(solver, status, common)
    z, lay, mode = raw.z, raw.layout, raw.mode
    ph = _physical(solver, lay, z, w6, st, pre)
    energy = _energy(solver, w6, fc, st, pre, ph) if status == "resisted" else None  # an equilibrium
    eq_tol = equilibrium_tolerance(solver, method, st, pre, carries_residual(method, pre_method))
    audit = _audit(solver, raw, lay, z, st, ph, energy, eq_tol)
    slip = _slip(solver, lay, z, st, ph)
    if energy is not None and not (energy.energy_ok and energy.displacement_ok):
        warnings.warn(audit_message(name, energy), AuditWarning, stacklevel=6)
    status = _balanced(status, audit)
    return PassiveResponse.of_model(
        m,
        resistible=status == "resisted",
        status=status,
        contact_forces=ph.cf,
        contact_forces_world=m.world_forces(ph.c),
        joint_torques=m.J.T @ ph.c,
        actuator_forces=ph.fa,
        coupling_forces=ph.lam,
        object_displacement=m.expand_twist(ph.x),
        joint_displacements=ph.q,
        actuator_displacements=ph.u,
        contact_modes=tuple("touching" if t else "separated" for t in mode.touching),
        actuator_modes=tuple(
            ("moving" if mv else "holding") if k == "non-backdrivable" else k
            for k, mv in zip(m.kinds, mode.moving)
        ),
        net_wrench=m.expand_wrench(ph.net),
        audit=audit,
        friction_use=friction_use(ph.cf, m.mu, mode.touching, audit.tolerance),
        converged=st.converged,
        solver=raw.backend,
        contact_states=contact_states(ph.cf[:, 0], slip, m.k, mode.touching, audit.tolerance),
        contact_slip=slip,
        **common,
    )


def _slip(solver: SolveContext, lay: Layout, z: np.ndarray, st: Stage, ph: _Physical) -> np.ndarray:
    """Slip of the object over the hand at each contact during the load stage, world frame
    (nc, 3) [m]: the tangential part of ``G^T x - J q``."""
    m = solver.model
    q_stage = z[lay.qh] * st.data.F / solver.form.qscale if m.nq else np.zeros(0)
    v = m.G.T @ m.reduce_wrench(ph.x_load)
    if m.nq:
        v = v - m.J @ q_stage
    v = v.reshape(m.nc, m.d).copy()
    v[:, 0] = 0.0
    return np.einsum("ijk,ik->ij", m.frames[:, :, : m.d], v)


def contact_states(
    cn: np.ndarray, slip: np.ndarray, k: np.ndarray, touching: tuple[bool, ...], tol: float
) -> tuple[ContactState, ...]:
    """``"separated"`` (not touching or no normal force), ``"sliding"`` (slip above ``tol`` in
    spring-force units ``k |s|``) or ``"sticking"`` per contact."""
    out: list[ContactState] = []
    for i, on in enumerate(touching):
        if not on or cn[i] <= tol:
            out.append("separated")
        else:
            out.append("sliding" if k[i] * np.linalg.norm(slip[i]) > tol else "sticking")
    return tuple(out)
