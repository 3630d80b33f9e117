"""What the loading path says about each snap it follows (docs/giveway.md, question 1).

:func:`path_of` runs the same path as the default answer (``max_wrench_prepared``: the same
thresholds, geometry updates and continuation); :func:`snap_metrics` measures each snap of
its continuation in physical units (contact stiffness ``K``, displacement ``x_model * max(k)/K``):

- the jump from the limit state to the landing state: object translation, rotation, the
  displacement along the load ``u = d . x`` and the largest contact displacement ``|G^T x - J q|``;
- ``energy``: the energy the snap sets free under the constant limit load, the area between the
  limit load and the displacement-controlled branch, ``E = int (lam* - lam) du`` [J] (the load's
  work at ``lam*`` less the work the equilibrium branch takes: stored, motors' and friction's);
- ``capacity(lam)``: the area the branch after the landing can absorb, ``int (lam - lam*) du``
  up to the load ``lam`` (the kinetic energy of the jump is taken up there if nothing dissipates);
- the contacts whose state (sticking / sliding / separated) differs between limit and landing.

Read-only use of package internals; nothing here changes the package.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pinograsp.analysis.quasistatic.answers import _thresholds, answer_path, locate_giveway
from pinograsp.analysis.quasistatic.prepared import checked_settings, path_of_variant, prepare
from pinograsp.core.axes import wrench_direction


@dataclass
class Snap:
    """One snap of a continuation, in physical units (see the module docstring)."""

    limit: float  # [N]
    landing: float  # [N]
    du: float  # jump along the load [m]
    dtrans: float  # object translation jump [m]
    drot: float  # object rotation jump [rad]
    dcontact: float  # largest contact displacement jump [m]
    energy: float  # [J]
    drop: float  # lowest load on the descent / limit load
    changed: list[str]  # contacts whose state changes: "name: a -> b"
    trans_at_landing: float  # object translation from the preload at the landing [m]
    rot_at_landing: float  # [rad]
    capacity_next: float  # branch area from the landing to the next peak (limit or end) [J]
    next_peak: float  # the load of that peak [N]
    u_lim: float = 0.0  # displacement along the load at the limit [m]
    extra: dict = field(default_factory=dict)


def path_of(model, command, direction, upper: float, settings=None):
    """``(prepared, path, located, thresholds, d6)`` as the default answer computes them."""
    s = checked_settings(settings)
    p = prepare(model, command, s, path_of_variant(None, s))
    d6 = wrench_direction(model, direction)
    th = _thresholds(p, d6, s, upper)
    lp = answer_path(p, d6, s, upper, th)
    loc = locate_giveway(p, lp, d6, s, upper, th)
    return p, lp, loc, th, d6


def _contact_disp(model, x6: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Contact displacements (nc, d) in the contact frames (model geometry) [model units]."""
    x = model.reduce_wrench(x6)
    g = np.asarray(model.G).T @ x - (np.asarray(model.J) @ q if model.nq else 0.0)
    return g.reshape(model.nc, model.d)


def _area(loads: np.ndarray, u: np.ndarray, ref: float) -> float:
    """``int (ref - lam) du`` over the piecewise-linear record (trapezoids: exact)."""
    return float(np.sum(0.5 * ((ref - loads[1:]) + (ref - loads[:-1])) * np.diff(u)))


def snap_metrics(p, lp, th, d6) -> list[Snap]:
    """Every snap of ``lp``'s continuation (landed ones), physical units."""
    cont = lp.continuation
    if cont is None or not cont.snaps:
        return []
    m = p.model
    sc = th.scale
    x0 = lp.object_displacements[0]
    X = (cont.object_displacements - x0) * sc
    u = X @ d6
    names = m.contact_names
    out = []
    for n, (a, b) in enumerate(cont.snaps):
        lam = float(cont.loads[a])
        dx = X[b] - X[a]
        g = (_contact_disp(m, cont.object_displacements[b], cont.joint_displacements[b])
             - _contact_disp(m, cont.object_displacements[a], cont.joint_displacements[a])) * sc  # fmt: skip
        sa, sb = cont.contact_states[a], cont.contact_states[b]
        changed = sorted({f"{names[i]}: {x} -> {y}" for i, (x, y) in enumerate(zip(sa, sb)) if x != y})
        # states along the descent
        for j in range(a, b):
            for i, (x, y) in enumerate(zip(cont.contact_states[j], cont.contact_states[j + 1])):
                if x != y:
                    changed.append(f"(on the way) {names[i]}: {x} -> {y} at {cont.loads[j + 1]:.4g} N")
        seg_l, seg_u = cont.loads[a : b + 1], u[a : b + 1]
        end = cont.snaps[n + 1][0] if n + 1 < len(cont.snaps) else len(cont.loads) - 1
        after_l, after_u = cont.loads[b : end + 1], u[b : end + 1]
        peak = b + int(np.argmax(after_l))
        cap = -_area(cont.loads[b : peak + 1], u[b : peak + 1], lam)
        out.append(
            Snap(
                limit=lam,
                landing=float(cont.loads[b]),
                du=float(u[b] - u[a]),
                dtrans=float(np.linalg.norm(dx[:3])),
                drot=float(np.linalg.norm(dx[3:])),
                dcontact=float(np.linalg.norm(g, axis=1).max()),
                energy=_area(seg_l, seg_u, lam),
                drop=float(seg_l.min() / lam) if lam > 0 else math.nan,
                changed=changed,
                trans_at_landing=float(np.linalg.norm(X[b, :3])),
                rot_at_landing=float(np.linalg.norm(X[b, 3:])),
                capacity_next=cap,
                next_peak=float(cont.loads[peak]),
                u_lim=float(u[a]),
                extra={
                    "after_loads": after_l,
                    "after_u": after_u,
                    "descent_loads": seg_l,
                    "descent_u": seg_u,
                },
            )
        )
    return out


def stop_load(snap: Snap, efficiency: float = 1.0) -> tuple[float, float]:
    """Where the branch after the landing has absorbed ``efficiency * energy`` (the jump's
    kinetic energy if nothing else dissipates): ``(load, u)``; ``(inf, nan)`` past its peak."""
    e = efficiency * snap.energy
    ll, uu = snap.extra["after_loads"], snap.extra["after_u"]
    acc = 0.0
    for j in range(len(ll) - 1):
        da = 0.5 * ((ll[j] - snap.limit) + (ll[j + 1] - snap.limit)) * (uu[j + 1] - uu[j])
        if acc + da >= e and da > 0:
            s = (e - acc) / da  # linear in area: fine for a report
            return float(ll[j] + s * (ll[j + 1] - ll[j])), float(uu[j] + s * (uu[j + 1] - uu[j]))
        acc += da
    return math.inf, math.nan


__all__ = ["Snap", "path_of", "snap_metrics", "stop_load"]
