"""The quasi-static method's answers in the package's common records:
:func:`quasistatic_max_wrench` (:class:`~pinograsp.MaxWrench`: the limit load λ*, no bisection)
and :func:`quasistatic_response` (:class:`~pinograsp.PassiveResponse`: the state reached on
the path at the load, or not resisted)."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ...core.audit import energy_check, friction_use
from ...core.axes import wrench_direction
from ...core.model import GraspModel
from ...core.results import Audit, MaxWrench, PassiveResponse
from ...core.settings import Settings
from ...solvers.threads import single_threaded
from ..limit_search import free_motion_note
from .api import Prepared, _variant, checked_settings, loading_path, prepare, run_path, unit_again
from .path import MAX_SEGMENTS
from .result import LoadingPath

#: Name of the method in the records.
METHOD = "quasistatic"


def _modes(states: tuple[str, ...]) -> tuple[str, ...]:
    return tuple("separated" if s == "separated" else "touching" for s in states)


def response_at(
    p: Prepared, lp: LoadingPath, load: float, w6: np.ndarray, status: str, settings: Settings, t0: float
) -> PassiveResponse:
    """The :class:`PassiveResponse` of the path's state at ``load`` (on the path)."""
    m = p.model
    st = lp.state_at(min(load, lp.loads[-1]) if lp.ray is None else load)
    assert st is not None
    c = st["contact_forces"]
    cc = c[:, : m.d].reshape(-1)
    f = st["actuator_forces"]
    q = st["joint_displacements"]
    x6 = st["object_displacement"] if "object_displacement" in st else st["object_displacements"]
    net = m.G @ cc + m.reduce_wrench(w6)
    tol = settings.tolerance * max(float(np.abs(c).max(initial=0.0)), float(np.abs(w6).max()), 1e-300)
    touching = tuple(s != "separated" for s in st["contact_states"])
    ell = m.length_scale
    wscale = np.ones(m.nw)
    wscale[(2 if m.planar else 3) :] = 1.0 / ell
    lever = p.qm.lever
    fsg = f * p.signs
    hand = (m.J.T @ cc - m.R @ fsg - m.C.T @ st["coupling_forces"]) / lever if m.nq else np.zeros(0)
    x0 = lp.object_displacements[0]
    energy = None
    if status == "resisted":
        energy = energy_check(
            c[:, 0],
            m.k,
            w6,
            x6 - x0,
            p.fc,
            st["actuator_displacements"] * p.signs,
            x6,
            q,
            ell,
            lever,
            m.contact_names,
            tol,
        )
    audit = Audit(
        equilibrium=float(np.linalg.norm(net * wscale)),
        hand=float(np.abs(hand).max(initial=0.0)),
        complementarity=_complementarity(p, m.reduce_wrench(x6), q, c, f),
        friction=float(max(0.0, -(p.qm.Phi @ cc).min(initial=0.0))),
        tolerance=tol,
        energy=energy,
    )
    return PassiveResponse(
        resistible=status == "resisted",
        status=status,  # type: ignore[arg-type]
        method=METHOD,  # type: ignore[arg-type]
        variant=p.variant,
        wrench=w6,
        command=p.fc * p.signs,
        contact_forces=c,
        contact_forces_world=m.world_forces(cc),
        joint_torques=m.J.T @ cc,
        actuator_forces=f,
        coupling_forces=st["coupling_forces"],
        object_displacement=x6,
        joint_displacements=q,
        actuator_displacements=st["actuator_displacements"],
        contact_modes=_modes(st["contact_states"]),
        actuator_modes=tuple(st["actuator_modes"]),
        net_wrench=m.expand_wrench(net),
        audit=audit,
        iterations=lp.segments,
        converged=status == "resisted",
        solver="lemke",
        solve_time=time.perf_counter() - t0,
        n_solves=lp.lcp_solves,
        contact_names=m.contact_names,
        joint_names=m.joint_names,
        actuator_names=m.actuator_names,
        friction_use=friction_use(c, m.mu, touching, tol),
        contact_mu=np.array(m.mu, dtype=float),
        actuator_kinds=tuple(m.kinds),
        contact_states=tuple(st["contact_states"]),
        contact_slip=st["contact_slip"],
        edge_counts=m.edge_counts,
    )


def _complementarity(p: Prepared, x: np.ndarray, q: np.ndarray, c: np.ndarray, f: np.ndarray) -> float:
    """Largest violation [N] of the normal spring law ``c_n = k max(delta, 0)`` and of the
    ratchets' ``f >= f_c`` (forces as contact forces: torques over their lever)."""
    m, qm = p.model, p.qm
    g = np.asarray(m.G).T @ x - (np.asarray(m.J) @ q if m.nq else 0.0)
    delta = -g[:: m.d]
    law = np.abs(c[:, 0] - m.k * np.maximum(delta, 0.0)).max(initial=0.0)
    over = (np.abs(f) - p.fc) * qm.r_norm
    ratchet = float(np.maximum(-over[qm.nbd], 0.0).max(initial=0.0)) if qm.na else 0.0
    return float(max(law, ratchet))


def fresh(resp: PassiveResponse, solve_time: float) -> PassiveResponse:
    """A kept response as a new record: its arrays copied (a caller may write into them), its
    ``solve_time`` [s] this call's."""
    arrays = {k: v.copy() for k, v in vars(resp).items() if isinstance(v, np.ndarray)}
    return replace(resp, solve_time=solve_time, **arrays)


@single_threaded
def quasistatic_response(
    model: GraspModel,
    command: object,
    wrench: object,
    settings: Settings | None = None,
    *,
    variant: str | None = None,
) -> PassiveResponse:
    """Passive response by the quasi-static loading path: the state reached when the load
    grows from 0 to ``wrench`` along its direction (``"resisted"``), or the state at the limit
    load when the path ends before (``"not_resisted"``; ``"failed"`` when it stopped without a
    verdict). Arguments as :func:`pinograsp.passive_response`.
    """
    t0 = time.perf_counter()
    s = checked_settings(settings)
    v = _variant(variant, s)
    p = prepare(model, command, s, v)
    w6 = model.wrench_vector(wrench)
    size = float(np.linalg.norm(w6))
    if size == 0.0:  # the preloaded state: a pure function of the prepared grasp, kept with it
        hit = p.memo.get("zero")
        if hit is None:
            lp = loading_path(model, command, "fx", variant=v, settings=s, up_to=0.0)
            hit = p.memo["zero"] = response_at(p, lp, 0.0, w6, "resisted", s, t0)
        return fresh(hit, time.perf_counter() - t0)
    lp = loading_path(model, command, w6 / size, variant=v, settings=s, up_to=size)
    if lp.status in ("reached", "unbounded"):
        return response_at(p, lp, size, w6, "resisted", s, t0)
    status = "not_resisted" if lp.status in ("finite", "below_resolution") else "failed"
    return response_at(p, lp, float(lp.loads[-1]), w6, status, s, t0)


@single_threaded
def quasistatic_max_wrench(
    model: GraspModel,
    command: object,
    direction: object,
    settings: Settings | None = None,
    *,
    variant: str | None = None,
    path: LoadingPath | None = None,
) -> MaxWrench:
    """The limit load λ* of the loading path along ``direction`` as a :class:`MaxWrench`:
    ``"finite"`` (magnitude λ*), ``"unbounded"`` (decided exactly: the last segment is a ray
    with no event ahead; ``magnitude = inf``), ``"below_resolution"`` (λ* = 0, magnitude 0),
    or — the path stopped without a verdict — ``"no_solution"`` / ``"segment_limit"`` with the
    load reached as magnitude (a lower bound). No bisection: ``steps`` and ``upper`` do not
    apply (``upper = inf``, ``resolution = 0``).
    """
    t0 = time.perf_counter()
    s = checked_settings(settings)
    v = _variant(variant, s)
    p = prepare(model, command, s, v)
    return max_wrench_prepared(p, wrench_direction(model, direction), s, t0, path)


def max_wrench_prepared(
    p: Prepared,
    d6: np.ndarray,
    s: Settings,
    t0: float,
    path: LoadingPath | None = None,
    label: str | None = None,
) -> MaxWrench:
    """:func:`quasistatic_max_wrench` of a prepared grasp along a validated unit direction
    ``d6`` (6,) with validated settings; ``label``: the response's ``variant``."""
    # loading_path's validation done once (the direction normalised again as it would be)
    lp = (
        path
        if path is not None
        else run_path(p, unit_again(d6), MAX_SEGMENTS, None, False, time.perf_counter(), lean=True)
    )
    status = lp.status
    unbounded = status == "unbounded"
    magnitude = float("inf") if unbounded else float(lp.limit)
    at = float(lp.loads[-1])
    resp_status = "resisted" if status in ("finite", "unbounded", "below_resolution") else "failed"
    resp = response_at(p, lp, at, at * d6, resp_status, s, t0)
    note = free_motion_note(p.model, d6) if status == "below_resolution" else ""
    if label is not None:  # the registry's name of the variant
        resp = replace(resp, variant=label)
    return MaxWrench(
        direction=d6,
        magnitude=magnitude,
        unbounded=unbounded,
        status=status,  # type: ignore[arg-type]
        floor=0.0,
        upper=float("inf"),
        resolution=0.0,
        evidence=((at, True),) if status != "unbounded" else ((at, True), (float("inf"), True)),
        method=METHOD,  # type: ignore[arg-type]
        solve_time=lp.wall_time,
        wall_time=time.perf_counter() - t0,
        n_solves=lp.lcp_solves,
        response=resp,
        search="path",
        note=note,
    )


__all__ = ["METHOD", "max_wrench_prepared", "quasistatic_max_wrench", "quasistatic_response", "response_at"]
