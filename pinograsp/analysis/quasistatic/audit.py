"""The audit of a loading path: equilibrium, joint balance and friction residuals at every
breakpoint (and the energy balance per segment); a path that fails it is never a verdict."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...core.model import GraspModel
from .model import balance_residuals, invariant_rows, invariant_terms
from .prepared import Prepared
from .state import State


def stacks(states: list[State]) -> dict[str, np.ndarray]:
    """The states' fields stacked, one row per state (read by the path record and :func:`path_audit`)."""
    return {
        "vs": np.array([s.vs for s in states]),
        "c": np.array([s.c for s in states]),
        "f": np.array([s.f for s in states]),
        "lam": np.array([s.lam_c for s in states]),
        "slip": np.array([s.slip for s in states]),
        "t": np.array([s.t for s in states]),
    }


def _residuals(qm, states, C, Fa, Lc, W, VS):
    """:func:`~.model.balance_residuals` of the states, each against the geometry of the
    segment that reached it (``State.geo``: a model re-linearised at the turned object)."""
    obj, joints, slack = balance_residuals(qm, C, Fa, Lc, W)
    groups: dict[int, list[int]] = {}  # the states of each geometry, in one pass
    for j, s in enumerate(states):
        if s.geo is not None:
            groups.setdefault(id(s.geo), []).append(j)
    if not groups:
        return obj, joints, slack
    X = VS[:, : qm.nx] / qm.S[: qm.nx]
    stacked: dict[int, list[list[int]]] = {}  # the updated geometries by their number of states
    for rows in groups.values():
        g = states[rows[0]].geo
        assert g is not None
        if g.KGp is not None and g.vs_ref is not None and g.e_ref is not None:  # an update's invariant
            stacked.setdefault(len(rows), []).append(rows)
        else:
            obj[rows] = balance_residuals(g, C[rows], Fa[rows], Lc[rows], W[rows], X[rows])[0]
    # one stacked product per number of states: numpy's matmul runs, per geometry, the same
    # BLAS product as on its own (same shapes and strides), so the same bits as one at a time
    for same in stacked.values():
        idx = np.array(same)  # (geometries, states)
        terms = [invariant_terms(states[rows[0]].geo) for rows in same]
        stack = tuple(np.array(part) for part in zip(*terms))
        obj[idx] = invariant_rows(C[idx], X[idx], W[idx], stack, qm.S[: qm.nx])
    return obj, joints, slack


def _geometric_work(qm, states, VS, dx):
    """Per segment, the work of the terms a geometry update adds to the object's balance (its
    invariant ``e_ref`` and geometric stiffness: ``geometry.moved``), so that the energy
    balance of a segment on a re-linearised model closes as on the model's own; 0 elsewhere."""
    out = np.zeros(len(dx))
    for k in range(len(dx)):
        g = states[k + 1].geo
        if g is None or g.KGp is None or g.vs_ref is None or g.e_ref is None:
            continue
        x_mid = 0.5 * (VS[k, : qm.nx] + VS[k + 1, : qm.nx]) / qm.S[: qm.nx]
        x_ref = g.vs_ref[: qm.nx] / qm.S[: qm.nx]
        out[k] = float((g.e_ref - g.KGp @ (x_mid - x_ref)) @ dx[k])
    return out


def path_audit(
    p: Prepared,
    states: list[State],
    arrays: dict[str, np.ndarray],
    d_red: np.ndarray,
    stacked: dict | None = None,
    energy: bool = True,
) -> dict:
    """Equilibrium, hand and friction residuals per breakpoint; energy balance per segment
    (without ``energy``: an empty array, for a lean record)."""
    qm, m = p.qm, p.model
    st = stacks(states) if stacked is None else stacked
    C = st["c"]  # (k, ncd)
    t = st["t"]
    Fa = st["f"].reshape(len(states), qm.na)
    Lc = st["lam"].reshape(len(states), qm.ncp)
    VS = st["vs"]
    SL = st["slip"]
    obj, joints, slack = _residuals(qm, states, C, Fa, Lc, t[:, None] * d_red, VS)
    eq = np.linalg.norm(obj * qm.weights, axis=1)
    hand = np.abs(joints).max(axis=1) if qm.nq else np.zeros(len(states))
    fr = np.maximum(0.0, -slack.min(axis=1, initial=0.0)) if qm.nf else np.zeros(len(states))
    if not energy:
        return {"equilibrium": eq, "hand": hand, "friction": fr, "energy": np.zeros(0)}
    d = qm.d
    Cc = C.reshape(len(states), qm.nc, d)
    elastic = np.sum(Cc[:, :, 0] ** 2 / (2 * qm.kn), axis=1)
    if d > 1:
        inv_kt = np.where(qm.kt > 0, 1.0 / np.where(qm.kt > 0, qm.kt, 1.0), 0.0)
        elastic = elastic + np.sum(np.sum(Cc[:, :, 1:] ** 2, axis=2) * inv_kt / 2, axis=1)
    dV = np.diff(VS, axis=0)
    dx = dV[:, : qm.nx] / qm.S[: qm.nx]
    w_load = 0.5 * (t[1:] + t[:-1]) * (dx @ d_red)
    if qm.na:
        du = (dV[:, qm.nx :] / qm.S[qm.nx :]) @ np.asarray(m.R)
        w_act = np.sum(0.5 * (Fa[1:] + Fa[:-1]) * du, axis=1)
    else:
        w_act = 0.0
    diss = -np.sum(0.5 * (C[1:] + C[:-1]) * np.diff(SL, axis=0), axis=1)
    energy = w_load + w_act - np.diff(elastic) - diss - _geometric_work(qm, states, VS, dx)
    return {"equilibrium": eq, "hand": hand, "friction": fr, "energy": np.asarray(energy, float)}


#: Audit bar of a reported path: equilibrium, joint balance and polygon residuals at a breakpoint
#: above this fraction of the path's force scale (a sound path has ~1e-12) mean the rate
#: problem's answer was not an equilibrium path (a degenerate LCP accepted): never a verdict.
AUDIT_RTOL = 1e-6


#: A unit load's part that no contact force can balance (:func:`unbalanceable`) up to this size
#: [N per N] is rounding of the contact geometry (the SO-101 ball: 1.3e-6 along the free spin
#: about its contact chord), allowed in the audit's equilibrium residual at each load.
UNBALANCED_RTOL = 1e-5


def unbalanceable(model: GraspModel, d_red: np.ndarray) -> float:
    """The part of the unit load ``d_red`` (nx,) that no contact force can balance, in the
    audit's rows (torques over the length scale) [N per unit load]: 0 when the contacts
    constrain every object motion; where they leave a free motion (two contacts: the spin about
    their chord), the load's rounding-level component along it (auto-closed contact points are
    1e-8 m off a common line), which the rate problem leaves to its least-norm solution when it
    is within its range tolerance (``system.RANGE_RTOL``)."""
    ws = model.wrench_weights
    Gs = np.asarray(model.G, float) * ws[:, None]
    ds = np.asarray(d_red, float) * ws
    c = np.linalg.lstsq(Gs, -ds, rcond=None)[0]
    return float(np.linalg.norm(Gs @ c + ds))


def audit_failure(
    audit: dict, loads: np.ndarray, arrays: dict[str, np.ndarray], rest: float | Callable[[], float] = 0.0
) -> int | None:
    """Index of the first breakpoint whose audit fails (None: all pass); ``rest``: the unit
    load's unbalanceable part (:func:`unbalanceable`), allowed in the equilibrium residual at
    each load when it is rounding (at most :data:`UNBALANCED_RTOL`); a callable is evaluated
    only when the audit fails without that allowance (which only ever loosens the bar)."""
    if callable(rest):
        if audit_failure(audit, loads, arrays, 0.0) is None:
            return None
        rest = rest()
    c = arrays["contact_forces"]
    force = max(float(np.abs(c).max(initial=0.0)), float(np.abs(loads).max(initial=0.0)), 1e-300)
    bad = ~np.isfinite(arrays["object_displacements"]).all(axis=1) | ~np.isfinite(loads)
    allow = np.abs(loads) * rest * 2.0 if rest <= UNBALANCED_RTOL else 0.0
    for key in ("equilibrium", "hand", "friction"):
        r = np.asarray(audit[key], float)
        bad |= ~(r <= AUDIT_RTOL * force + (allow if key == "equilibrium" else 0.0))
    return int(np.argmax(bad)) if bad.any() else None


__all__ = ["AUDIT_RTOL", "UNBALANCED_RTOL", "audit_failure", "path_audit", "stacks", "unbalanceable"]
