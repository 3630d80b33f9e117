"""The preload as a path (docs/quasistatic.md, "The preload is a path too").

* ``"held"`` (default, the simulation's ``preload="held"``): from the touching configuration
  the commands ramp ``f = s f_c``, ``s: 0 -> 1``, with the object held still and friction off
  (the model's friction is free inside the cone, not wound up by the closing); then friction
  is switched on with every anchor at the contact's current position (no tangential force
  stored) and the object is released: the holder's wrench is removed gradually, one more
  stage of the path, which must reach its end (else the preload is not an equilibrium).
  A finger that has no frictionless equilibrium under the commands (e.g. a ratchet at zero
  command lets a joint close while its contacts slide along the object: the energy falls
  without bound) closes with friction on from the touch instead — the simulation's closing
  is not frictionless there either: its relaxed contacts keep their tangential damping, the
  finger creeps and friction catches it when the object is released. Fingers (groups of
  joints and contacts that move independently while the object is held,
  :func:`~.model.finger_groups`) that close without friction keep doing so.
* ``"settled"``: the object is free and friction is on while the commands ramp.

Both start from zero force, where the problem is positively homogeneous, so the closing is
usually one segment; the release can have events.
"""

from __future__ import annotations

import numpy as np

from ...core.axes import WRENCH_AXES
from ...core.methods import method_variant
from ...core.settings import Method, Variant
from ...errors import InvalidInputError, PreloadNotInEquilibriumError
from .model import QSModel, balance_residuals, finger_groups, with_friction_on
from .path import StageRun, follow
from .rates import EVENT_RTOL, StageSpec, State, classify, force_scale
from .statuses import RunStatus

#: The preload paths (the names :class:`~.result.LoadingPath` records).
PRELOAD_VARIANTS = ("held", "settled")
#: The preload path each of the method's variants (:class:`~pinograsp.core.settings.Variant`,
#: its row of :mod:`pinograsp.core.methods`) follows.
PRELOAD_PATHS = {Variant.PRELOAD_FIRST: "held", Variant.SETTLED_PRELOAD: "settled"}


def preload_path_of(variant: object, settings_variant: object) -> str:
    """The preload path (``"held"``/``"settled"``) of a ``variant=`` argument under
    ``Settings.variant``: the variant vocabulary of every other entry point
    (``"preload-first"``/``"settled-preload"``; None: the settings', else the method's
    default), or the path's own name (``"held"``/``"settled"``, as :class:`LoadingPath`
    records it).

    Raises:
        InvalidInputError: Any other value; ``"single-step"`` (in ``variant=`` or in the
            settings) is refused as ``max_resistible_wrench(method="quasistatic")`` refuses it
            (:func:`~pinograsp.core.methods.method_variant`).
    """
    if isinstance(variant, str) and variant in PRELOAD_VARIANTS:
        return variant
    if variant is None or (isinstance(variant, str) and variant in Variant._value2member_map_):
        return PRELOAD_PATHS[
            method_variant(Method.QUASISTATIC, settings_variant if variant is None else variant)
        ]
    valid = [v.value for v in PRELOAD_PATHS] + list(PRELOAD_VARIANTS)
    raise InvalidInputError("variant", f"expected one of {valid} or None, got {variant!r}")


def zero_state(qm: QSModel) -> State:
    """The touching configuration without force."""
    return State(
        np.zeros(qm.nv),
        np.zeros(qm.ncd),
        np.zeros(qm.na),
        np.zeros(qm.ncp),
        np.zeros(qm.nx),
        np.zeros(qm.ncd),
    )


def _fail(
    fc: np.ndarray, stage: str, run: StageRun, why: str = "", unbalanced: np.ndarray | None = None
) -> PreloadNotInEquilibriumError:
    """The error of a preload stage that stopped; ``unbalanced``: the contacts' net wrench on the
    held object at the end of the closing (6,) [N, N·m], named in the message and kept as the
    error's ``residual`` (what the object is pushed by when it is let go)."""
    st = run.states[-1]
    detail = (
        f"method 'quasistatic': the {stage} path of the preload stopped at {st.t:.6g} of the way "
        f"({run.status}: "
        + (
            why
            or (
                "the grasp gives way under the preload"
                if run.status == RunStatus.LIMIT
                else "no continuation"
            )
        )
        + ")"
    )
    if unbalanced is not None:
        shown = ", ".join(f"{a}={v:.3g}" for a, v in zip(WRENCH_AXES, unbalanced) if abs(v) > 0)
        detail += f"; net wrench of the contacts on the held object: {shown or '0'} [N, N·m]"
    return PreloadNotInEquilibriumError(fc.tolist(), detail, unbalanced)


#: Audit bar of a preload stage's breakpoints, relative to the stage's force scale (a sound
#: path has ~1e-12): object and joint balance, normal forces, polygons and ratchets.
STAGE_AUDIT_RTOL = 1e-6


def stage_sound(qm: QSModel, run: StageRun, spec: StageSpec) -> bool:
    """Whether every breakpoint of a preload stage is an equilibrium of the model: object
    (with the holder's wrench) and joints balanced, normal forces >= 0, friction forces in
    their polygons and ratchets at or above their commands, to :data:`STAGE_AUDIT_RTOL` of the
    force scale [N]. A rate problem accepted on a nearly singular system (a finger that is a
    mechanism) shows here as huge displacements and unbalanced forces: never an "end"."""
    d = qm.d
    for st in run.states:
        if not (np.all(np.isfinite(st.vs)) and np.all(np.isfinite(st.c)) and np.all(np.isfinite(st.f))):
            return False
        tol = STAGE_AUDIT_RTOL * force_scale(qm, st, spec)
        w = spec.w0 + st.t * spec.dw + st.hold
        obj, hand, slack = (
            r[0] for r in balance_residuals(qm, st.c[None], st.f[None], st.lam_c[None], w[None])
        )
        over = (st.f - spec.command(st.t)) * qm.r_norm
        bad = (
            np.abs(obj * qm.weights).max(initial=0.0) > tol
            or np.abs(hand).max(initial=0.0) > tol
            or st.c[::d].min(initial=0.0) < -tol
            or (spec.friction and qm.nf and slack.min() < -tol)
            or over[qm.nbd].min(initial=0.0) < -tol
        )
        if bad:
            return False
    return True


def _ended(qm: QSModel, run: StageRun, spec: StageSpec) -> bool:
    """The stage reached its end through equilibrium states."""
    return run.status == RunStatus.END and stage_sound(qm, run, spec)


def _why(run: StageRun, release: bool = False) -> str:
    """What a preload stage that did not reach its end means."""
    if run.status == RunStatus.END:
        return "its states are not equilibria: the rate problem is nearly singular there"
    if run.status == RunStatus.LIMIT:
        return (
            "the released grasp gives way before the holder's wrench is gone"
            if release
            else "the grasp gives way under the preload"
        )
    if run.status == RunStatus.UNBOUNDED:
        return "the path runs off without bound"
    return "no continuation"


def _held_closing(qm: QSModel, fc: np.ndarray, max_segments: int) -> tuple[StageRun, np.ndarray]:
    """The held closing (object still, commands ramped) and the contacts (nc,) bool that
    close with friction on: none when the frictionless closing reaches its end, else those of
    every finger whose frictionless closing fails while the other fingers have friction (the
    fingers are independent while the object is held, so each is tested once).

    Raises:
        PreloadNotInEquilibriumError: Some finger has no equilibrium even with friction.
    """
    z = np.zeros(qm.nx)
    zero_a = np.zeros(qm.na)
    spec = StageSpec(z, z, zero_a, fc, 1.0, held=True, friction=False)
    run = follow(qm, zero_state(qm), spec, max_segments)
    none = np.zeros(qm.nc, bool)
    if _ended(qm, run, spec):
        return run, none
    with_friction = StageSpec(z, z, zero_a, fc, 1.0, held=True, friction=True)
    on = none.copy()
    for group in finger_groups(qm):
        others = with_friction_on(qm, ~group)
        if not _ended(others, follow(others, zero_state(qm), with_friction, max_segments), with_friction):
            on |= group
    if not on.any():
        raise _fail(fc, "closing (held)", run)
    partial = with_friction_on(qm, on)
    closing = follow(partial, zero_state(qm), with_friction, max_segments)
    if not _ended(partial, closing, with_friction):
        names = ", ".join(qm.model.contact_names[i] for i in np.flatnonzero(on))
        raise _fail(
            fc,
            "closing (held)",
            closing,
            f"the hand has no equilibrium under these commands with the object held, neither "
            f"frictionless nor with friction at {names}",
        )
    return closing, on


def released_states(
    qm: QSModel, start: State, spec: StageSpec
) -> tuple[tuple[str, ...], tuple[tuple[int, ...], ...], tuple[str, ...]]:
    """The states of the preloaded state ``start`` at zero load, read off its forces (the load
    stage ``spec``'s force tolerance, :data:`~.rates.EVENT_RTOL` of its force scale): per
    contact ``"separated"`` (no normal force: open, or touching without force),
    ``"sliding"`` (pressed, on a face of its friction polygon: it reached its friction limit,
    typically by sliding during the release; a load that pushes it on slides it) or
    ``"sticking"`` (pressed, strictly inside its polygon); the faces it is on (nc,); per
    actuator ``"holding"`` (non-backdrivable) or its kind. The states a path reports at its
    zero-load breakpoint when it has no load segment (``up_to=0``)."""
    cls = classify(qm, start, spec)
    faces: list[list[int]] = [[] for _ in range(qm.nc)]
    for f in cls.faces.tolist():
        i = int(qm.face_contact[f])
        if cls.pressed[i]:
            faces[i].append(int(qm.face_index[f]))
    contact = tuple(
        "separated" if not cls.pressed[i] else ("sliding" if faces[i] else "sticking") for i in range(qm.nc)
    )
    detail = tuple(tuple(f) for f in faces)
    kinds = qm.model.kinds
    actuator = tuple("holding" if qm.nbd[a] else kinds[a] for a in range(qm.na))
    return contact, detail, actuator


def preload_path(
    qm: QSModel, fc: np.ndarray, variant: str, max_segments: int
) -> tuple[State, list[StageRun]]:
    """The preloaded state (``t = 0``, ``slip = 0``) and the stages that led to it (the held
    closing's run carries ``friction_on`` (nc,) bool: the contacts that closed with friction).

    Raises:
        PreloadNotInEquilibriumError: The closing or the release reaches a limit or finds no
            continuation before its end.
    """
    z = np.zeros(qm.nx)
    zero_a = np.zeros(qm.na)
    runs = []
    if variant == "settled":
        spec = StageSpec(z, z, zero_a, fc, 1.0, held=False, friction=True)
        run = follow(qm, zero_state(qm), spec, max_segments)
        runs.append(run)
        if not _ended(qm, run, spec):
            raise _fail(fc, "closing (settled)", run, _why(run))
        st = run.states[-1].copy()
    else:
        run, on = _held_closing(qm, fc, max_segments)
        run.friction_on = on
        runs.append(run)
        st = run.states[-1].copy()
        wh = st.hold.copy()
        st.hold[:] = 0.0
        st.t = 0.0
        tol = EVENT_RTOL * force_scale(qm, st, StageSpec(z, z, fc, zero_a, 0.0, False, True))
        if np.abs(qm.w_scaled(wh)).max(initial=0.0) > tol:
            spec = StageSpec(wh, -wh, fc, zero_a, 1.0, held=False, friction=True)
            run = follow(qm, st, spec, max_segments)
            runs.append(run)
            if not _ended(qm, run, spec):
                unbalanced = qm.model.expand_wrench(-wh) + 0.0  # the holder took -G c
                raise _fail(fc, "release", run, _why(run, release=True), unbalanced)
            st = run.states[-1].copy()
    st.t = 0.0
    st.slip[:] = 0.0
    st.hold[:] = 0.0
    scale, top = float(np.abs(fc * qm.r_norm).max(initial=0.0)), float(np.abs(st.c).max(initial=0.0))
    if scale > 0 and top > PRELOAD_AMPLIFICATION * scale:  # a runaway, not an equilibrium
        raise _runaway(qm, fc, st, top, scale)
    return st, runs


#: Largest contact force of a preload per unit of its commands' largest force (a command's
#: force at the contacts: torque over its lever). A wedge amplifies the command by 1/tan of its
#: half-angle (100 at 0.6°); past 1e6 the "equilibrium" is a runaway of a grasp that has none
#: (a contact normal nearly tangent to the surface it presses: 1e14 N from 1 N·m was seen).
PRELOAD_AMPLIFICATION = 1e6


def _runaway(
    qm: QSModel, fc: np.ndarray, st: State, top: float, scale: float
) -> PreloadNotInEquilibriumError:
    """The error of a preloaded state whose contact forces, up to ``top`` [N], exceed
    :data:`PRELOAD_AMPLIFICATION` times the commands' largest force ``scale`` [N]."""
    worst = int(np.argmax(np.abs(st.c))) // qm.d
    return PreloadNotInEquilibriumError(
        fc.tolist(),
        f"method 'quasistatic': the preloaded state has contact forces up to {top:.3g} N at "
        f"{qm.model.contact_names[worst]!r}, {top / scale:.3g} times the commands' largest "
        f"force ({scale:.3g} N; at most {PRELOAD_AMPLIFICATION:g} is an equilibrium): the "
        "preload has none — check that contact's normal against the surface it presses",
    )
