"""Check a hand description against the geometry: does each joint close towards the object?

Closing signs (``closing: {joint: ±1}`` in the description, ``docs/hands.md``) are the one part
of a hand description that the URDF cannot tell: a URDF axis may point either way. A wrong sign
makes :meth:`~pinograsp.Hand.close_on` open the hand and every analysis drive the finger away
from the object. :func:`check_closing` moves each hand joint alone by a small step in its
declared closing sense and watches the signed distance (Coal) from the links that joint moves
to the object:

* it **decreases**: the sign is right (verdict ``"closes"``);
* it **increases**: the sign is likely wrong (verdict ``"opens"``; the report suggests
  ``closing: {joint: -sign}``);
* it does **not change**: the joint moves no link towards or away from the object (verdict
  ``"no effect"``, e.g. a spread joint, or a finger whose closest point slides along the object).

The joint is judged with what it carries: the joints below it close with it in their declared
senses (as :meth:`~pinograsp.Hand.close_on` moves them), over ``steps`` samples of ``step`` in
each sense, clipped to the limits, and the closest distance reached in the declared sense is
compared with the other sense's. A sense a limit blocks is never suggested. Joints held only by
locked actuators are ``"locked"`` and URDF mimic followers ``"follows"`` (checked with their
leader, whose step moves them by the mimic ratio): neither decides how the hand closes.

Only distances are used (no Jacobian, no grasp model), so the check works before the hand
touches the object, at any configuration, and for one-joint grippers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.validate import finite_number, positive_number, whole_number
from ..errors import InvalidInputError, UnknownNameError
from .collision import PairDistance, closest_per_link, geometry_distances, pair_distances_at
from .hand_protocol import HandLike
from .kinematics import HandConfiguration

if TYPE_CHECKING:  # pragma: no cover
    from .hand import Hand
    from .objects import RigidObject

#: Verdicts of :class:`JointClosing`.
VERDICTS = ("closes", "opens", "no effect", "locked", "follows")


def moved_geometries(hand: Hand) -> list[list[int]]:
    """Indices of the collision geometries each hand joint moves (its own link and those below).

    Returns:
        One list per hand joint (``hand.joint_names`` order) of geometry indices into
        ``hand.geometry.geometryObjects``.
    """
    out: list[list[int]] = [[] for _ in range(hand.nq)]
    for k, go in enumerate(hand.geometry.geometryObjects):
        for jid in hand.model.supports[int(go.parentJoint)]:
            if int(jid) > 0:
                out[int(jid) - 1].append(k)
    return out


@dataclass(frozen=True)
class JointClosing:
    """What a small closing step of one joint does to its distance from the object.

    Attributes:
        joint: Hand joint name.
        sign: Declared closing sign ``s_j`` (``+1`` or ``-1``).
        verdict: ``"closes"`` (the declared sense gets closer: sign right), ``"opens"`` (the
            other sense does: sign likely wrong), ``"no effect"`` (neither approaches),
            ``"locked"`` (held only by locked actuators) or ``"follows"`` (a URDF mimic follower).
        link: The link (among those the joint moves) closest to the object before the step, or
            ``None`` if the joint moves no collision geometry.
        distance_before: Closest signed distance [m] of the joint's links to the object at ``q``.
        distance_after: The closest distance [m] reached sweeping the declared closing sense
            (with the joints it carries); ``distance_before`` when a limit blocks that sense.
        step: How far the joint was swept in its closing sense [rad or m] (0: blocked by a limit).
        change: ``distance_after - distance_before`` [m] (negative: the closing sense approaches).
        displacement: How far the closest hand point moved [m] during the sweep.
        distance_other: Closest distance [m] reached sweeping the other way (``inf``: no room).
        note: Why the verdict is what it is when that is not obvious (locked, mimic follower,
            blocked by a limit), else ``""``.
    """

    joint: str
    sign: int
    verdict: str
    link: str | None
    distance_before: float
    distance_after: float
    step: float
    change: float
    displacement: float
    distance_other: float = float("inf")
    note: str = ""

    @property
    def sign_ok(self) -> bool | None:
        """``True`` (closes), ``False`` (opens: flip the sign) or ``None`` (no effect)."""
        return {"closes": True, "opens": False}.get(self.verdict)

    @property
    def suggested_sign(self) -> int:
        """The closing sign to put in the description (``-sign`` when the joint opens; a locked
        joint or a mimic follower keeps its sign: it does not decide how the hand closes)."""
        return -self.sign if self.verdict == "opens" else self.sign

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "joint": self.joint,
            "sign": self.sign,
            "verdict": self.verdict,
            "sign_ok": self.sign_ok,
            "suggested_sign": self.suggested_sign,
            "link": self.link,
            "distance_before": self.distance_before,
            "distance_after": self.distance_after,
            "step": self.step,
            "change": self.change,
            "displacement": self.displacement,
            "distance_other": self.distance_other,
            "note": self.note,
        }

    def line(self) -> str:
        """One readable line: joint, sign, distances [mm] and verdict."""
        head = f"{self.joint} (closing {self.sign:+d})"
        if self.verdict in ("locked", "follows"):
            return f"{head}: {self.verdict}: {self.note}"
        if self.link is None:
            return f"{head}: moves no collision geometry -> no effect"

        def mm(d: float) -> str:
            return "blocked by a joint limit" if not np.isfinite(d) else f"{1e3 * d:.2f} mm"

        closing = mm(self.distance_after) if self.step != 0.0 else "blocked by a joint limit"
        what = f"{self.link} {1e3 * self.distance_before:.2f} mm; closing sense {closing}, other sense "
        what += mm(self.distance_other)
        if self.verdict == "closes":
            tail = "closes: sign ok"
        elif self.verdict == "opens":
            tail = f"OPENS: sign likely wrong, use closing: {{{self.joint}: {self.suggested_sign}}}"
        else:
            tail = f"no effect: {self.note or 'the joint moves no link towards the object'}"
        return f"{head}: {what} -> {tail}"


@dataclass(frozen=True)
class ClosingCheck:
    """Result of :func:`check_closing`: one :class:`JointClosing` per hand joint.

    Attributes:
        hand: Hand name.
        object: Object name.
        q: The configuration checked, URDF coordinates, (nq,) [rad or m].
        joints: Per-joint results in ``hand.joint_names`` order.
        link_distances: Closest signed distance [m] per link at ``q``.
    """

    hand: str
    object: str
    q: tuple[float, ...]
    joints: tuple[JointClosing, ...]
    link_distances: dict[str, float]

    @property
    def ok(self) -> bool:
        """No joint opens (every sign is right or has no effect)."""
        return all(j.verdict != "opens" for j in self.joints)

    @property
    def wrong(self) -> tuple[str, ...]:
        """Joints whose declared sign opens the hand."""
        return tuple(j.joint for j in self.joints if j.verdict == "opens")

    @property
    def suggested_closing(self) -> dict[str, int]:
        """``closing`` block for the description YAML: every joint with its suggested sign."""
        return {j.joint: j.suggested_sign for j in self.joints}

    def __getitem__(self, joint: str) -> JointClosing:
        for j in self.joints:
            if j.joint == joint:
                return j
        raise UnknownNameError("joint", joint, [j.joint for j in self.joints])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "hand": self.hand,
            "object": self.object,
            "q": list(self.q),
            "ok": self.ok,
            "wrong": list(self.wrong),
            "suggested_closing": self.suggested_closing,
            "joints": [j.to_dict() for j in self.joints],
            "link_distances": dict(self.link_distances),
        }

    def summary(self) -> str:
        """Readable multi-line report (what :func:`print` shows)."""
        lines = [f"closing check of {self.hand!r} on {self.object!r}:"]
        lines += [f"  {j.line()}" for j in self.joints]
        if self.ok:
            lines.append("all declared closing signs move the hand towards the object (or do not matter)")
        else:
            fix = ", ".join(f"{j}: {self[j].suggested_sign}" for j in self.wrong)
            lines.append(f"fix the description: closing: {{{fix}}}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def _group_step(hand: Hand, j: int) -> np.ndarray:
    """URDF-coordinate motion of a unit closing step of joint ``j`` with its URDF mimic
    followers (recursively: ``dq_f = multiplier dq_l``), (nq,)."""
    dq = np.zeros(hand.nq)
    dq[j] = hand.closing_signs[j]
    todo = [j]
    while todo:
        lead = hand.joint_names[todo.pop()]
        for m in hand.mimics:
            if m.leader == lead:
                f = hand.joint_names.index(m.follower)
                if dq[f] == 0.0:
                    dq[f] = m.multiplier * dq[hand.joint_names.index(lead)]
                    todo.append(f)
    return dq


def _carried_closing(hand: Hand, locked: set[int]) -> list[np.ndarray]:
    """Per hand joint, the URDF-coordinate closing motion of the joints it carries (below it in
    the chain, declared senses, mimics followed, locked ones still), (nq,) each."""
    followers = {m.follower for m in hand.mimics}
    out = []
    for j in range(hand.nq):
        dq = np.zeros(hand.nq)
        for i in range(hand.nq):
            if i == j or i in locked or hand.joint_names[i] in followers:
                continue
            if (j + 1) in [int(s) for s in hand.model.supports[i + 1]]:
                step = _group_step(hand, i)
                dq = np.where(dq == 0.0, step, dq)
        dq[j] = 0.0
        out.append(dq)
    return out


def _room(hand: HandLike, q0: np.ndarray, dq: np.ndarray, sense: float) -> float:
    """Largest ``t >= 0`` with ``q0 + sense t dq`` within the joint limits."""
    t = np.inf
    for i in np.flatnonzero(dq):
        v = sense * dq[i]
        t = min(t, (hand.upper[i] - q0[i]) / v if v > 0 else (hand.lower[i] - q0[i]) / v)
    return max(float(t), 0.0)


def _locked_joints(hand: Hand) -> set[int]:
    """Joints moved only by locked actuators (their closing sign does not matter)."""
    driven: set[int] = set()
    locked: set[int] = set()
    for a in hand.actuators:
        for key in a.transmission:
            (locked if a.kind == "locked" else driven).add(hand.joint_index(str(key)))
    return locked - driven


def _sweep(
    config: HandConfiguration, obj: RigidObject, dq: np.ndarray, geoms: list[int], t_max: float, n: int
) -> tuple[float, float]:
    """Closest distance [m] of ``geoms`` over ``n`` samples of ``q0 + t dq``, ``0 < t <= t_max``,
    and the path length [m] the geometries' closest point sweeps (``inf, 0`` without room)."""
    hand, q0 = config.hand, config.q
    if t_max <= 0.0:
        return float("inf"), 0.0
    mask = np.zeros(len(hand.geometry.geometryObjects), bool)
    mask[geoms] = True
    best = float("inf")
    for k in range(1, n + 1):
        moved = HandConfiguration.at(hand, np.clip(q0 + (k / n) * t_max * dq, hand.lower, hand.upper))
        best = min(best, float(geometry_distances(moved, obj, mask=mask)[geoms].min()))
    return best, 0.0


def _check_joint(
    config: HandConfiguration,
    obj: RigidObject,
    pairs: tuple[PairDistance, ...],
    j: int,
    geoms: list[int],
    step: float,
    threshold: float,
    context: dict[str, Any],
) -> JointClosing:
    """:class:`JointClosing` of hand joint ``j`` (moving the geometries ``geoms``) at ``config``."""
    hand, q0 = config.hand, config.q
    name, sign = hand.joint_names[j], int(hand.closing_signs[j])
    inf = float("inf")
    if j in context["locked"]:
        note = "held by a locked actuator; its sign does not matter for closing"
        return JointClosing(name, sign, "locked", None, inf, inf, 0.0, 0.0, 0.0, inf, note)
    if name in context["leader_of"]:
        note = f"URDF mimic of {context['leader_of'][name]!r}, checked with it (its sign is a convention)"
        return JointClosing(name, sign, "follows", None, inf, inf, 0.0, 0.0, 0.0, inf, note)
    dq = context["group"][j]
    geoms = sorted({k for i in np.flatnonzero(dq) for k in context["moved"][i]})
    # the joints below it close with it, in their declared senses (as close_on moves them): a
    # joint is judged by the finger it carries, not alone (the Allegro thumb's joint_13.0 alone
    # turns link_14.0 away, while with the thumb closing it brings the tip onto the object)
    below = context["below"][j]
    if not geoms:
        return JointClosing(name, sign, "no effect", None, inf, inf, 0.0, 0.0, 0.0)
    h = step / 10.0 if hand.prismatic[j] else step
    span = context["steps"] * h
    k0 = min(geoms, key=lambda k: pairs[k].distance)
    before = float(pairs[k0].distance)
    t_close = min(span, _room(hand, q0, dq, 1.0))
    t_open = min(span, _room(hand, q0, dq, -1.0))
    n = context["steps"]
    d_close, _ = _sweep(config, obj, dq + below, geoms, t_close, n)
    d_open, _ = _sweep(config, obj, -dq + below, geoms, t_open, n)
    # how far the closest hand point travels over the longer sweep, carried with its link
    t_far, sense = (t_close, 1.0) if t_close >= t_open else (t_open, -1.0)
    moved = HandConfiguration.at(hand, np.clip(q0 + sense * t_far * (dq + below), hand.lower, hand.upper))
    local = config.geometry_data.oMg[k0].actInv(pairs[k0].point_hand)
    displacement = float(np.linalg.norm(moved.geometry_data.oMg[k0].act(local) - pairs[k0].point_hand))
    a_close = before - d_close if np.isfinite(d_close) else 0.0
    a_open = before - d_open if np.isfinite(d_open) else 0.0
    note = ""
    if displacement <= 1e-12 or max(a_close, a_open) <= threshold * displacement:
        verdict = "no effect"
        if a_close < 0.0 and not np.isfinite(d_open):
            note = (
                "it moves away in its closing sense and a joint limit blocks the other sense: "
                "the object is not where this joint closes (move it, or the open configuration)"
            )
    else:
        verdict = "closes" if a_close >= a_open else "opens"
    after = d_close if np.isfinite(d_close) else before
    return JointClosing(
        name,
        sign,
        verdict,
        pairs[k0].link,
        before,
        after,
        t_close,
        after - before,
        displacement,
        d_open,
        note,
    )


def check_closing(
    hand: Hand,
    obj: RigidObject,
    q: object = None,
    *,
    step: float = 0.02,
    threshold: float = 0.1,
    steps: int = 10,
) -> ClosingCheck:
    """Move each hand joint a small step in its declared closing sense; does it approach the object?

    Joint ``j`` is swept in its declared closing sense ``s_j`` and in the other sense, ``steps``
    samples ``step`` apart (``step`` [rad] for revolute joints, ``step / 10`` [m] for prismatic
    ones, as in :meth:`~pinograsp.Hand.close_on`), clipped to the joint limits, with its URDF mimic
    followers and the joints below it closing in their declared senses. The distance watched is
    the closest signed distance (Coal) of the collision geometries it moves to the object; the
    sense that gets closer wins. Locked joints and mimic followers are not judged.

    Args:
        hand: The hand (its description's closing signs are checked).
        obj: The object, placed in the hand base frame where the hand should close on it
            (e.g. between the fingers).
        q: Configuration to check at, URDF coordinates (default: the open configuration).
        step: Joint step [rad] (prismatic joints: ``step / 10`` [m]).
        threshold: An approach smaller than ``threshold`` × the closest point's displacement
            counts as ``"no effect"`` (the point moves mostly sideways to the object), dimensionless.
        steps: Samples of the sweep in each sense, ``step`` apart (the sweep spans
            ``steps × step``, clipped to the joint limits).

    Returns:
        A :class:`ClosingCheck` (``print`` it, or use ``.ok``, ``.wrong``,
        ``.suggested_closing``, ``.to_dict()``).

    Raises:
        InvalidInputError: ``hand``, ``obj``, ``q``, ``step`` or ``threshold`` malformed.
    """
    if not (hasattr(hand, "geometry") and hasattr(hand, "closing_signs") and hasattr(hand, "configuration")):
        raise InvalidInputError("hand", f"expected a pinograsp Hand, got {type(hand).__name__}")
    if not (hasattr(obj, "geometry") and hasattr(obj, "transform")):
        raise InvalidInputError("obj", f"expected a pinograsp RigidObject, got {type(obj).__name__}")
    step = positive_number("step", step)
    threshold = finite_number("threshold", threshold)
    if not 0.0 <= threshold < 1.0:
        raise InvalidInputError("threshold", f"must be in [0, 1), got {threshold}")
    config = HandConfiguration.at(hand, q)
    pairs = pair_distances_at(config, obj)
    moved = moved_geometries(hand)
    context = {
        "locked": _locked_joints(hand),
        "leader_of": {m.follower: m.leader for m in hand.mimics},
        "moved": moved,
        "group": [_group_step(hand, j) for j in range(hand.nq)],
        "steps": whole_number("steps", steps),
        "below": _carried_closing(hand, _locked_joints(hand)),
    }
    results = tuple(
        _check_joint(config, obj, pairs, j, moved[j], step, threshold, context) for j in range(hand.nq)
    )
    q0 = tuple(float(v) for v in config.q)
    return ClosingCheck(
        str(hand.name),
        str(getattr(obj, "name", "object")),
        q0,
        results,
        closest_per_link((p.link for p in pairs), (p.distance for p in pairs)),
    )


__all__ = ["VERDICTS", "ClosingCheck", "JointClosing", "check_closing", "moved_geometries"]
