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

Only distances are used (no Jacobian, no grasp model), so the check works before the hand
touches the object, at any configuration, and for one-joint grippers.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.validate import finite_number, positive_number
from ..errors import InvalidInputError, UnknownNameError
from .collision import PairDistance, closest_per_link, geometry_distances, pair_distances_at
from .hand_protocol import HandLike
from .kinematics import HandConfiguration

if TYPE_CHECKING:  # pragma: no cover
    from .hand import Hand
    from .objects import RigidObject

#: Verdicts of :class:`JointClosing`.
VERDICTS = ("closes", "opens", "no effect")


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
        verdict: ``"closes"`` (distance decreases: sign right), ``"opens"`` (increases: sign
            likely wrong) or ``"no effect"`` (the joint moves no link towards the object).
        link: The link (among those the joint moves) closest to the object before the step, or
            ``None`` if the joint moves no collision geometry.
        distance_before: Closest signed distance [m] of the joint's links to the object at ``q``.
        distance_after: The same after the step [m].
        step: The closing step taken [rad or m] (in closing coordinates: ``+step`` means the
            declared closing sense; negative when the joint was at its closing limit and the
            step was taken the other way, the change being scaled accordingly).
        change: Rate of change of the distance per closing step, ``(after - before)`` [m]
            normalised to a step in the closing sense.
        displacement: How far the closest hand point moved [m] during the step.
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

    @property
    def sign_ok(self) -> bool | None:
        """``True`` (closes), ``False`` (opens: flip the sign) or ``None`` (no effect)."""
        return {"closes": True, "opens": False}.get(self.verdict)

    @property
    def suggested_sign(self) -> int:
        """The closing sign to put in the description (``-sign`` when the joint opens)."""
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
        }

    def line(self) -> str:
        """One readable line: joint, sign, distances [mm] and verdict."""
        head = f"{self.joint} (closing {self.sign:+d})"
        if self.link is None:
            return f"{head}: moves no collision geometry -> no effect"
        what = (
            f"{self.link} {1e3 * self.distance_before:.2f} mm -> {1e3 * self.distance_after:.2f} mm"
            f" ({1e3 * self.change:+.3f} mm per closing step)"
        )
        if self.verdict == "closes":
            tail = "closes: sign ok"
        elif self.verdict == "opens":
            tail = f"OPENS: sign likely wrong, use closing: {{{self.joint}: {self.suggested_sign}}}"
        else:
            tail = "no effect: the joint moves no link towards the object"
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


def _joint_step(hand: HandLike, q0: np.ndarray, j: int, step: float) -> tuple[float, float]:
    """Sense (``+1`` closing, ``-1`` opening) and length [rad or m] of joint ``j``'s check step.

    A joint at its closing limit is stepped the other way; the length is clipped to the limits.
    """
    sign = hand.closing_signs[j]
    h = step / 10.0 if hand.prismatic[j] else step
    room_close = (hand.upper[j] - q0[j]) if sign > 0 else (q0[j] - hand.lower[j])
    room_open = (q0[j] - hand.lower[j]) if sign > 0 else (hand.upper[j] - q0[j])
    if room_close < 0.5 * h and room_open > room_close:
        return -1.0, min(h, max(room_open, 0.0))
    return 1.0, min(h, max(room_close, 0.0))


def _check_joint(
    config: HandConfiguration,
    obj: RigidObject,
    pairs: tuple[PairDistance, ...],
    j: int,
    geoms: list[int],
    step: float,
    threshold: float,
) -> JointClosing:
    """:class:`JointClosing` of hand joint ``j`` (moving the geometries ``geoms``) at ``config``."""
    hand, q0 = config.hand, config.q
    name, sign = hand.joint_names[j], int(hand.closing_signs[j])
    if not geoms:
        return JointClosing(name, sign, "no effect", None, np.inf, np.inf, 0.0, 0.0, 0.0)
    direction, h = _joint_step(hand, q0, j, step)
    k0 = min(geoms, key=lambda k: pairs[k].distance)
    before = float(pairs[k0].distance)
    if h <= 0.0:  # the joint cannot move at all (lower == upper)
        return JointClosing(name, sign, "no effect", pairs[k0].link, before, before, 0.0, 0.0, 0.0)
    q1 = q0.copy()
    q1[j] += direction * sign * h
    mask = np.zeros(len(pairs), bool)
    mask[geoms] = True
    moved = HandConfiguration.at(hand, q1)
    after = float(geometry_distances(moved, obj, mask=mask)[geoms].min())
    # displacement of the closest hand point, carried rigidly with its link
    local = config.geometry_data.oMg[k0].actInv(pairs[k0].point_hand)
    moved_point = moved.geometry_data.oMg[k0].act(local)
    displacement = float(np.linalg.norm(moved_point - pairs[k0].point_hand))
    change = direction * (after - before)
    if displacement <= 1e-12 or abs(change) <= threshold * displacement:
        verdict = "no effect"
    else:
        verdict = "closes" if change < 0 else "opens"
    return JointClosing(
        name, sign, verdict, pairs[k0].link, before, after, direction * h, change, displacement
    )


def check_closing(
    hand: Hand,
    obj: RigidObject,
    q: object = None,
    *,
    step: float = 0.02,
    threshold: float = 0.1,
) -> ClosingCheck:
    """Move each hand joint a small step in its declared closing sense; does it approach the object?

    For joint ``j`` alone (the others held, couplings ignored), the configuration changes by
    ``s_j × step`` in URDF coordinates (``step`` [rad] for revolute joints, ``step / 10`` [m] for
    prismatic ones, as in :meth:`~pinograsp.Hand.close_on`), clipped to the joint limits; a joint
    at its closing limit is stepped the other way and the change negated. The distance watched is
    the closest signed distance (Coal) of the collision geometries the joint moves (its link and
    every link below it) to the object.

    Args:
        hand: The hand (its description's closing signs are checked).
        obj: The object, placed in the hand base frame where the hand should close on it
            (e.g. between the fingers).
        q: Configuration to check at, URDF coordinates (default: the open configuration).
        step: Joint step [rad] (prismatic joints: ``step / 10`` [m]).
        threshold: A change smaller than ``threshold`` × the closest point's displacement counts
            as ``"no effect"`` (the point moves mostly sideways to the object), dimensionless.

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
    results = tuple(_check_joint(config, obj, pairs, j, moved[j], step, threshold) for j in range(hand.nq))
    q0 = tuple(float(v) for v in config.q)
    return ClosingCheck(
        str(hand.name),
        str(getattr(obj, "name", "object")),
        q0,
        results,
        closest_per_link((p.link for p in pairs), (p.distance for p in pairs)),
    )


__all__ = ["VERDICTS", "ClosingCheck", "JointClosing", "check_closing", "moved_geometries"]
