"""The quasi-static method's answers in the package's common records:
:func:`quasistatic_max_wrench` (:class:`~pinograsp.MaxWrench`: the limit load λ*, no bisection)
and :func:`quasistatic_response` (:class:`~pinograsp.PassiveResponse`: the state reached on
the path at the load, or not resisted)."""

from __future__ import annotations

import time
from dataclasses import dataclass, replace

import numpy as np

from ...core.audit import energy_check, friction_use
from ...core.axes import wrench_direction
from ...core.giveway import GiveWay, giveway_thresholds
from ...core.model import GraspModel
from ...core.results import Audit, MaxWrench, PassiveResponse
from ...core.settings import Settings
from ...core.validate import force, load_within
from ...solvers.threads import single_threaded
from .api import run_path, unit_again
from .giveway import Thresholds, Trace, walk
from .model import QSModel, balance_residuals
from .path import MAX_SEGMENTS
from .prepared import Prepared, checked_settings, path_of_variant, prepare
from .result import LoadingPath

#: Name of the method in the records.
METHOD = "quasistatic"


def _modes(states: tuple[str, ...]) -> tuple[str, ...]:
    return tuple("separated" if s == "separated" else "touching" for s in states)


def _state_audit(
    p: Prepared, lp: LoadingPath, st: dict, w6: np.ndarray, status: str, settings: Settings
) -> tuple[Audit, float, np.ndarray]:
    """The :class:`Audit` of a path state (with its energy check when ``resisted``), its
    tolerance [N] and the net wrench left on the object (nw,)."""
    m = p.model
    c = st["contact_forces"]
    cc = c[:, : m.d].reshape(-1)
    f = st["actuator_forces"]
    q = st["joint_displacements"]
    x6 = st["object_displacements"]
    qm = st.get("geometry") or p.qm  # a state reached with the geometry updated: its invariant
    x = m.reduce_wrench(x6)
    rows = balance_residuals(
        qm, cc[None], (f * p.signs)[None], st["coupling_forces"][None], m.reduce_wrench(w6)[None], x[None]
    )
    net, hand, slack = (r[0] for r in rows)
    tol = settings.tolerance * max(float(np.abs(c).max(initial=0.0)), float(np.abs(w6).max()), 1e-300)
    ell = m.length_scale
    lever = p.qm.lever
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
        equilibrium=float(np.linalg.norm(net * p.qm.weights)),
        hand=float(np.abs(hand).max(initial=0.0)),
        complementarity=_complementarity(p, x, q, c, f, qm),
        friction=float(max(0.0, -slack.min(initial=0.0))),
        tolerance=tol,
        energy=energy,
    )
    return audit, tol, net


def response_at(
    p: Prepared,
    lp: LoadingPath,
    load: float,
    w6: np.ndarray,
    status: str,
    settings: Settings,
    t0: float,
    state: dict | None = None,
) -> PassiveResponse:
    """The :class:`PassiveResponse` of the path's state at ``load`` (on the path), or of
    ``state`` (:meth:`LoadingPath.state_on`, e.g. on the path's continuation) when given."""
    m = p.model
    st = state if state is not None else lp.state_at(min(load, lp.loads[-1]) if lp.ray is None else load)
    assert st is not None
    c = st["contact_forces"]
    cc = c[:, : m.d].reshape(-1)
    f = st["actuator_forces"]
    q = st["joint_displacements"]
    x6 = st["object_displacement"] if "object_displacement" in st else st["object_displacements"]
    audit, tol, net = _state_audit(p, lp, st, w6, status, settings)
    touching = tuple(s != "separated" for s in st["contact_states"])
    return PassiveResponse.of_model(
        m,
        resistible=status == "resisted",
        status=status,
        method=METHOD,
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
        friction_use=friction_use(c, m.mu, touching, tol),
        contact_states=tuple(st["contact_states"]),
        contact_slip=st["contact_slip"],
    )


def _complementarity(
    p: Prepared, x: np.ndarray, q: np.ndarray, c: np.ndarray, f: np.ndarray, geo: QSModel | None = None
) -> float:
    """Largest violation [N] of the normal spring law ``c_n = k max(delta, 0)`` and of the
    ratchets' ``f >= f_c`` (forces as contact forces: torques over their lever); ``geo``: the
    re-linearised model that reached the state (its gaps, ``QSModel.gaps``)."""
    m, qm = p.model, p.qm
    if geo is not None and geo.vs_ref is not None:
        delta = -geo.gaps(np.concatenate([x * qm.S[: qm.nx], q * qm.S[qm.nx :]]))
    else:
        g = np.asarray(m.G).T @ x - (np.asarray(m.J) @ q if m.nq else 0.0)
        delta = -g[:: m.d]
    law = np.abs(c[:, 0] - m.k * np.maximum(delta, 0.0)).max(initial=0.0)
    over = (np.abs(f) - p.fc) * qm.r_norm
    ratchet = float(np.maximum(-over[qm.nbd], 0.0).max(initial=0.0)) if qm.na else 0.0
    return float(max(law, ratchet))


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
    p = prepare(model, command, s, path_of_variant(variant, s))
    w6 = model.wrench_vector(wrench)
    # a load: the domains of every load (docs/errors.md, "Input domains")
    load_within(model, model.command_vector(command), "wrench", w6)
    return response_prepared(p, w6, s, t0)


def response_prepared(p: Prepared, w6: np.ndarray, s: Settings, t0: float) -> PassiveResponse:
    """:func:`quasistatic_response` of a prepared grasp, a validated wrench ``w6`` (6,)
    [N, N·m] and validated settings (what a session's method runs)."""
    size = float(np.linalg.norm(w6))
    if size == 0.0:  # the preloaded state
        lp = run_path(p, wrench_direction(p.model, "fx"), MAX_SEGMENTS, 0.0, True, t0)
        return response_at(p, lp, 0.0, w6, "resisted", s, t0)
    lp = run_path(
        p, wrench_direction(p.model, w6 / size), MAX_SEGMENTS, size, True, t0, stiffness=s.contact_stiffness
    )
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
    upper: float = 1e3,
) -> MaxWrench:
    """The load at which the grasp gives way along ``direction`` (docs/giveway.md) as a
    :class:`MaxWrench`: ``"finite"`` (magnitude: the give-way load), ``"unbounded"`` (held
    within the thresholds to any load: the path ends in a ray that does not reach them below
    ``upper``; ``magnitude = inf``), ``"below_resolution"`` (0), ``"above_limit"`` (the path
    stopped without a verdict at or above ``upper``; magnitude ``upper``) or — stopped below
    it — ``"no_solution"`` / ``"segment_limit"`` with the load reached as magnitude (a lower
    bound). ``giveway`` records why, the path's first limit λ*, the snaps survived, the
    stiffness and thresholds; with ``Settings(limit="first")`` the magnitude is λ* itself.
    No bisection: ``resolution = 0``; ``upper`` [N or N·m] (default 1e3) scales the default
    thresholds as in ``pg.simulate_max_wrench``.
    """
    t0 = time.perf_counter()
    upper = force("upper", upper, "N or N·m")
    s = checked_settings(settings)
    p = prepare(model, command, s, path_of_variant(variant, s))
    return max_wrench_prepared(p, wrench_direction(model, direction), s, t0, path, upper=upper)


@dataclass(frozen=True)
class Located:
    """The give-way of a path: the answer's status and magnitude [N or N·m], its record, and
    the state the response is built from (:meth:`LoadingPath.state_on`)."""

    status: str
    magnitude: float
    giveway: GiveWay
    state: dict


def _thresholds(p: Prepared, d6: np.ndarray, s: Settings, upper: float) -> Thresholds:
    """The settings' give-way thresholds along ``d6`` under the largest load ``upper``."""
    m = p.model
    ell = float(m.length_scale)
    K = float(s.contact_stiffness)
    slip, rot = giveway_thresholds(ell, d6, upper, K, s.giveway_slip, s.giveway_rotation)
    return Thresholds(slip, rot, s.giveway_joint, float(np.max(m.k)) / K, ell)


def _peak(cont: LoadingPath) -> dict:
    """The state at the largest load after the last landing of ``cont`` (where it gives way)."""
    start = cont.snaps[-1][1] if cont.snaps else 0
    j = start + int(np.argmax(cont.loads[start:]))
    return cont.state_on(j, 0.0)


def locate_giveway(
    p: Prepared, lp: LoadingPath, d6: np.ndarray, s: Settings, upper: float, th: Thresholds | None = None
) -> Located:
    """Where the path ``lp`` (with its continuation) gives way under the settings' thresholds
    (docs/giveway.md): the first threshold crossing, snaps that land within the thresholds
    followed; a crossing above ``upper`` on a path that ends in a ray is ``"unbounded"`` (no
    limit, and held within the thresholds up to ``upper``).
    Status ``"no_solution"``/``"segment_limit"`` when the path stopped first (magnitude: the
    load reached); ``th``: the thresholds when the caller has them."""
    th = _thresholds(p, d6, s, upper) if th is None else th
    stopped = lp.status in ("no_solution", "segment_limit")
    cont = lp.continuation if lp.status in ("finite", "below_resolution") else None
    follow = cont is not None and bool(cont.snaps)
    main = lp.trace()
    if stopped:  # only the breakpoints the audit passed
        keep = int(np.searchsorted(lp.loads, lp.limit, side="right"))
        main = Trace(lp.loads[:keep], lp.object_displacements[:keep], lp.joint_displacements[:keep])
    point, survived = walk(main, cont.trace() if follow and cont else None, cont.snaps if cont else (), th)
    tail = cont if follow and cont is not None else lp
    note = ""
    if point is not None and not (point.load > upper and tail.status == "unbounded"):
        rec = lp if point.trace == 0 else tail
        status, load, reason = "finite", point.load, point.reason
        state = rec.state_on(point.index, point.step, point.on_ray)
    elif tail.status == "unbounded":
        status, load, reason, state = (
            "unbounded",
            float("inf"),
            "held",
            tail.state_on(len(tail.loads) - 1, 0.0),
        )
    elif stopped:
        status, load, reason, state = (
            lp.status,
            float(lp.limit),
            "held",
            lp.state_on(len(main.loads) - 1, 0.0),
        )
    elif tail is cont and cont is not None and cont.status == "finite":
        state = _peak(cont)
        status, load, reason = "finite", float(cont.limit), "limit"
    else:  # the first limit: nothing to land on, or the path past it stopped without a verdict
        status, load, reason = lp.status, float(lp.limit), "limit"
        state = lp.state_on(len(lp.loads) - 1, 0.0)
        if tail is cont and cont is not None:
            note = (
                f"the path past the first limit stopped without a verdict ({cont.status}, "
                f"{cont.stop_reason}): the first limit is reported, a lower bound of the give-way load"
            )
    if status == "finite" and load <= 0.0:
        status = "below_resolution"
    x = (np.asarray(state["object_displacements"]) - lp.object_displacements[0]) * th.scale
    snaps = tuple((float(cont.loads[a]), float(cont.loads[b])) for a, b in survived) if cont else ()
    first = float("inf") if lp.status == "unbounded" else float(lp.limit)
    record = GiveWay(
        load=load if status in ("finite", "below_resolution") else float("inf"),
        reason=reason,  # type: ignore[arg-type]
        first_limit=first,
        first_status=lp.status,
        snaps=snaps,
        stiffness=float(s.contact_stiffness),
        tangential_ratio=p.ratio,
        slip=th.slip,
        rotation=th.rotation,
        joint=th.joint,
        translation=float(np.linalg.norm(x[:3])),
        turned=float(np.linalg.norm(x[3:])),
        note=note,
    )
    return Located(status, load, record, state)


def _audit_note(lp: LoadingPath, status: str) -> str:
    """Why a path without a verdict stopped where it did, when its audit cut it short."""
    if status not in NO_VERDICT or lp.stop_reason != "audit":
        return ""
    return (
        f"the path went on to {float(lp.loads[-1]):.6g} but its states past {float(lp.limit):.6g} "
        "fail the equilibrium audit (response.audit): the load reached is that of the last state "
        "that passed"
    )


#: Path statuses without a verdict: the path stopped (no or several continuations, or the
#: segment-count limit); the load reached is a lower bound, never reported as the limit.
NO_VERDICT = ("no_solution", "segment_limit")


def answer_path(p: Prepared, d6: np.ndarray, s: Settings, upper: float, th: Thresholds) -> LoadingPath:
    """The lean loading path the default answer reads along ``d6`` (6,): its continuation past
    a limit when the settings ask for the give-way, no geometry update above twice ``upper`` nor
    past the thresholds ``th`` (loading_path's validation done once: the direction normalised
    again as it would be)."""
    return run_path(
        p,
        unit_again(d6),
        MAX_SEGMENTS,
        None,
        s.limit == "giveway",
        time.perf_counter(),
        lean=True,
        until=2.0 * upper,
        stiffness=s.contact_stiffness,
        reach=(th.rotation, th.slip),
    )


def max_wrench_prepared(
    p: Prepared,
    d6: np.ndarray,
    s: Settings,
    t0: float,
    path: LoadingPath | None = None,
    label: str | None = None,
    upper: float = 1e3,
) -> MaxWrench:
    """:func:`quasistatic_max_wrench` of a prepared grasp along a validated unit direction
    ``d6`` (6,) with validated settings; ``label``: the response's ``variant``; ``upper``
    [N or N·m]: the largest load of interest (it scales the default give-way thresholds; a
    path stopped without a verdict at or above it is ``"above_limit"``)."""
    giveway = s.limit == "giveway"
    th = _thresholds(p, d6, s, upper)
    lp = path if path is not None else answer_path(p, d6, s, upper, th)
    record = None
    if giveway:
        loc = locate_giveway(p, lp, d6, s, upper, th)
        status, magnitude, state, record = loc.status, loc.magnitude, loc.state, loc.giveway
        at = float(state["load"])
    else:
        status, state = lp.status, None
        magnitude = float("inf") if status == "unbounded" else float(lp.limit)
        at = float(lp.loads[-1])
    if status in NO_VERDICT and at >= upper:  # held up to upper before the path stopped
        status, magnitude = "above_limit", float(upper)
    elif giveway and status == "finite" and magnitude > upper:  # as the searches and the simulation
        status, magnitude = "above_limit", float(upper)  # (the exact load: giveway.load)
    unbounded = status == "unbounded"
    resp_status = "failed" if status in NO_VERDICT else "resisted"
    resp = response_at(p, lp, at, at * d6, resp_status, s, t0, state)
    note = p.model.free_motion_note(d6) if status == "below_resolution" else ""
    note = note or (record.note if record is not None else "")
    if status in NO_VERDICT and not note:
        note = _audit_note(lp, status)
    if status in ("unbounded", "above_limit") and not note:
        note = p.model.held_free_motion_note()
    if label is not None:  # the registry's name of the variant
        resp = replace(resp, variant=label)
    return MaxWrench(
        direction=d6,
        magnitude=magnitude,
        unbounded=unbounded,
        status=status,  # type: ignore[arg-type]
        floor=0.0,
        upper=float(upper),
        resolution=0.0,
        evidence=((at, True),) if status != "unbounded" else ((at, True), (float("inf"), True)),
        method=METHOD,
        solve_time=lp.wall_time,
        wall_time=time.perf_counter() - t0,
        n_solves=lp.lcp_solves,
        response=resp,
        search="path",
        note=note,
        giveway=record,
    )


__all__ = [
    "METHOD",
    "answer_path",
    "max_wrench_prepared",
    "quasistatic_max_wrench",
    "quasistatic_response",
    "response_at",
    "response_prepared",
]
