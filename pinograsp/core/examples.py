"""Example grasps: the one home of the analytic and the synthetic grasp models.

* **Analytic planar grasps** (:func:`pinch`, :func:`palm_pinch`, :func:`coupled_finger`,
  :func:`wedge`) have closed-form answers derived in ``docs/analytic_cases.md`` and checked in
  ``tests/``; they are also the built-in demo scenes.
* **Seeded random grasps** (:func:`random_grasp`) build ``n_pairs`` pairs of opposing fingers
  around an object centred at the origin. Each finger presses on a flat face of the object
  (normal ``n``, in-plane direction ``e``) with one contact (single-link finger) or two (proximal
  and distal link, the distal joint coupled to the proximal one at ``ratio``, Barrett-like). The
  two fingers of a pair are point mirror images of each other, so under equal commands their
  normal forces are collinear and opposite: **the preload alone is always in equilibrium**,
  whatever the random draw.

All lengths in [m], torques and commands in [N·m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..errors import InvalidInputError
from .actuation import Actuator, Coupling
from .contact import Contact
from .model import GraspModel

EZ = np.array([0.0, 0.0, 1.0])


def _finger_contact(point, normal, pivot_below: float, joint: int, nq: int, closing_axis, **kw) -> Contact:
    p = np.asarray(point, float)
    pivot = p - np.array([0.0, pivot_below, 0.0])
    return Contact.revolute(p, normal, {joint: (pivot, closing_axis)}, nq=nq, **kw)


def pinch_contacts(
    a: float = 0.05,
    L: float = 0.1,
    mu: float = 0.5,
    k: float = 1.0,
    h: float = 0.0,
    *,
    tilt: float = 0.0,
    right: Sequence[tuple[float, float]] | None = None,
) -> list[Contact]:
    """The contacts of :func:`pinch`: ``left`` at ``(-a, -h)`` on joint 0, ``right`` at ``(a, h)``
    on joint 1, each finger's revolute joint ``L`` below its contact.

    Args:
        a: Half width of the object [m].
        L: Finger length (moment arm of the closing joint) [m].
        mu: Friction coefficient.
        k: Normal stiffness of every contact [N/m].
        h: Diagonal offset of the contacts [m] (the wedge).
        tilt: The left normal rotated by this angle [rad] about z (near-parallel normals).
        right: ``(stiffness [N/m], normal tilt [rad])`` of each of several right contacts at the
            same point of the same finger (coincident contacts ``right0, right1, …``); default
            one contact ``right`` of stiffness ``k``.
    """
    normal = [math.cos(tilt), math.sin(tilt), 0.0] if tilt else [1.0, 0.0, 0.0]
    left = _finger_contact([-a, -h, 0.0], normal, L, 0, 2, -EZ, mu=mu, stiffness=k, name="left")
    rights = [
        _finger_contact(
            [a, h, 0.0],
            [-math.cos(t), math.sin(t), 0.0] if t else [-1.0, 0.0, 0.0],
            L,
            1,
            2,
            EZ,
            mu=mu,
            stiffness=kr,
            name=f"right{i}" if right else "right",
        )
        for i, (kr, t) in enumerate(right or [(k, 0.0)])
    ]
    return [left, *rights]


def pinch(
    a: float = 0.05,
    L: float = 0.1,
    mu: float = 0.5,
    k: float = 1.0,
    h: float = 0.0,
    differential: bool = False,
    planar: bool = True,
    kind: str = "non-backdrivable",
    *,
    tilt: float = 0.0,
    right: Sequence[tuple[float, float]] | None = None,
    edges: int | None = None,
    circumscribed: bool = False,
) -> GraspModel:
    """Two single-link fingers pinching an object centred at the origin.

    Contacts at ``(-a, -h)`` and ``(a, h)`` with normals ``(1, 0)`` / ``(-1, 0)``; each finger's
    revolute joint lies ``L`` below its contact, so closing moves the contact along its normal
    with moment arm ``L``. ``h != 0`` offsets the contacts diagonally (the *wedge* case: a
    clockwise object rotation squeezes both contacts). ``differential=True`` drives both
    joints with one actuator through a differential (``R = [1, 1]^T``). ``tilt`` and ``right``:
    see :func:`pinch_contacts`; ``edges``, ``circumscribed``: the friction pyramids
    (:meth:`GraspModel.from_contacts`).
    """
    contacts = pinch_contacts(a, L, mu, k, h, tilt=tilt, right=right)
    if differential:
        acts = [Actuator({0: 1.0, 1: 1.0}, kind=kind, name="tendon")]
    else:
        acts = [Actuator({0: 1.0}, kind=kind, name="left"), Actuator({1: 1.0}, kind=kind, name="right")]
    return GraspModel.from_contacts(
        contacts,
        actuators=acts,
        planar=planar,
        joint_names=("left", "right"),
        edges=edges,
        circumscribed=circumscribed,
    )


def palm_pinch(
    a: float = 0.05, L: float = 0.1, b: float = 0.04, mu: float = 0.5, mu_palm: float = 0.5
) -> GraspModel:
    """The pinch plus a palm contact at ``(0, -b)`` pushing along ``+y`` (fixed: no joint)."""
    left = _finger_contact([-a, 0.0, 0.0], [1.0, 0.0, 0.0], L, 0, 2, -EZ, mu=mu, name="left")
    right = _finger_contact([a, 0.0, 0.0], [-1.0, 0.0, 0.0], L, 1, 2, EZ, mu=mu, name="right")
    palm = Contact(
        np.array([0.0, -b, 0.0]),
        np.array([0.0, 1.0, 0.0]),
        mu=mu_palm,
        jacobian=np.zeros((3, 2)),
        name="palm",
    )
    acts = [Actuator({0: 1.0}, name="left"), Actuator({1: 1.0}, name="right")]
    return GraspModel.from_contacts(
        [left, right, palm], actuators=acts, planar=True, joint_names=("left", "right")
    )


def coupled_finger(
    a: float = 0.05, L1: float = 0.06, L2: float = 0.04, ratio: float = 1.0 / 3.0, mu: float = 0.5
) -> GraspModel:
    """A fixed thumb at ``(-a, 0)`` and a two-link finger touching at ``(a, 0)`` with its distal link.

    Both finger joints lie on the vertical through the contact (proximal ``L1 + L2`` below,
    distal ``L2`` below), the distal joint is rigidly coupled to the proximal one
    (``q_distal = ratio * q_proximal``, Barrett-like) and one non-backdrivable actuator drives
    the proximal joint. The effective moment arm is ``L1 + L2 + ratio * L2``.
    """
    p = np.array([a, 0.0, 0.0])
    finger = Contact.revolute(
        p,
        [-1.0, 0.0, 0.0],
        {0: (p - [0, L1 + L2, 0], EZ), 1: (p - [0, L2, 0], EZ)},
        nq=2,
        mu=mu,
        name="distal",
    )
    thumb = Contact(
        np.array([-a, 0.0, 0.0]), np.array([1.0, 0.0, 0.0]), mu=mu, jacobian=np.zeros((3, 2)), name="thumb"
    )
    return GraspModel.from_contacts(
        [thumb, finger],
        actuators=[Actuator({"proximal": 1.0}, name="motor")],
        couplings=[Coupling.follow("distal", "proximal", ratio, name="distal_follows")],
        planar=True,
        joint_names=("proximal", "distal"),
    )


def wedge(
    a: float = 0.03, angle: float = np.radians(20.0), L: float = 0.1, mu: float = 0.5, planar: bool = True
) -> GraspModel:
    """Two single-link fingers pressing on a wedge-shaped object from below the sides.

    Contacts at ``(-a, 0)`` and ``(a, 0)`` with normals ``(cos angle, sin angle)`` and
    ``(-cos angle, sin angle)`` (both push inwards and up); each finger's revolute joint sits
    ``L`` from its contact, perpendicular to the normal, so closing moves the contact along its
    normal with moment arm ``L`` [m]. Mirror-symmetric about the y axis.
    """
    cs = []
    for i, (sx, name) in enumerate(((-1.0, "left"), (1.0, "right"))):
        p = np.array([sx * a, 0.0, 0.0])
        n = np.array([-sx * np.cos(angle), np.sin(angle), 0.0])
        t = np.array([n[1], -n[0], 0.0]) * -sx  # in-plane, perpendicular to n, pointing down
        pivot = p + L * t
        axis = EZ if np.cross(EZ, p - pivot) @ n > 0 else -EZ
        cs.append(Contact.revolute(p, n, {i: (pivot, axis)}, nq=2, mu=mu, name=name))
    acts = [Actuator({0: 1.0}, name="left"), Actuator({1: 1.0}, name="right")]
    return GraspModel.from_contacts(cs, actuators=acts, planar=planar, joint_names=("left", "right"))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _closing_axis(axis: np.ndarray, point: np.ndarray, pivot: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """``±axis`` such that positive rotation pushes ``point`` along ``normal``."""
    return axis if np.cross(axis, point - pivot) @ normal > 0 else -axis


def random_grasp(
    seed: int | np.random.Generator = 0,
    n_pairs: int = 2,
    contacts_per_finger: int = 1,
    planar: bool = False,
    mu: float = 0.5,
    edges: int = 8,
    radius: float = 0.04,
    ratio: float = 1.0 / 3.0,
    kind: str = "non-backdrivable",
) -> GraspModel:
    """A random grasp with ``2 * n_pairs * contacts_per_finger`` contacts.

    Args:
        seed: Seed or generator.
        n_pairs: Pairs of opposing fingers (directions drawn at random; in the XY plane if
            ``planar``).
        contacts_per_finger: 1 (single link) or 2 (proximal + distal link, coupled joints).
        planar: Keep everything in the XY plane and reduce the model to (fx, fy, mz).
        mu: Friction coefficient of every contact.
        edges: Friction pyramid edges (3D).
        radius: Distance of the faces from the object centre [m] (varied ±30 % per pair).
        ratio: Distal/proximal joint coupling of two-contact fingers.
        kind: Actuator kind of every finger.

    Returns:
        The :class:`GraspModel`; one actuator per finger named ``f{i}``; command 1 N·m on every
        finger is an equilibrium preload.
    """
    if contacts_per_finger not in (1, 2):
        raise InvalidInputError("contacts_per_finger", f"must be 1 or 2, got {contacts_per_finger!r}")
    if int(n_pairs) < 1:
        raise InvalidInputError("n_pairs", f"must be >= 1, got {n_pairs!r}")
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    contacts: list[Contact] = []
    actuators: list[Actuator] = []
    couplings: list[Coupling] = []
    nq = 2 * n_pairs * contacts_per_finger
    joint = 0
    for k in range(int(n_pairs)):
        n, e, r, off, sizes = _pair_draw(rng, planar, radius)
        hinge = _unit(np.cross(e, n))
        for side, sign in enumerate((1.0, -1.0)):  # the second finger is the point mirror
            nn, ee = sign * n, sign * e
            name = f"f{2 * k + side}"
            face = -r * nn + off * ee
            contacts += _finger(face, nn, ee, hinge, sizes, joint, nq, mu, name, contacts_per_finger)
            actuators.append(Actuator({joint: 1.0}, kind=kind, name=name))
            if contacts_per_finger == 2:
                couplings.append(Coupling.follow(joint + 1, joint, ratio))
            joint += contacts_per_finger
    return GraspModel.from_contacts(
        contacts,
        actuators=actuators,
        couplings=couplings,
        planar=planar,
        edges=edges,
        joint_names=tuple(f"j{i}" for i in range(nq)),
    )


def _pair_draw(
    rng: np.random.Generator, planar: bool, radius: float
) -> tuple[np.ndarray, np.ndarray, float, float, tuple[float, float, float]]:
    """One random pair of fingers: face normal ``n`` and in-plane direction ``e`` (unit, (3,)),
    face distance ``r`` [m], offset ``off`` of the fingers along ``e`` [m] and the finger sizes
    (half distance between proximal and distal contact, depth, length) [m]."""
    if planar:
        a = rng.uniform(0, 2 * np.pi)
        n = np.array([np.cos(a), np.sin(a), 0.0])
        e = np.cross(EZ, n)
    else:
        n = _unit(rng.normal(size=3))
        e = _unit(np.cross(n, _unit(rng.normal(size=3))))
    r = radius * rng.uniform(0.7, 1.3)
    s = radius * rng.uniform(0.2, 0.5)
    off = radius * rng.uniform(-0.3, 0.3)
    depth, length = radius * rng.uniform(0.5, 1.0), radius * rng.uniform(1.5, 2.5)
    return n, e, r, off, (s, depth, length)


def _finger(
    face: np.ndarray,
    nn: np.ndarray,
    ee: np.ndarray,
    hinge: np.ndarray,
    sizes: tuple[float, float, float],
    joint: int,
    nq: int,
    mu: float,
    name: str,
    contacts_per_finger: int,
) -> list[Contact]:
    """The contacts of one finger pressing on the face point ``face`` along ``nn``: one on a
    single link (joint ``joint``), or proximal and distal on two links (joints ``joint`` and
    ``joint + 1``); ``sizes`` = (half contact spacing, depth, length) [m]."""
    s, depth, length = sizes
    if contacts_per_finger == 1:
        pivot = face - depth * nn - length * ee
        ax = _closing_axis(hinge, face, pivot, nn)
        return [Contact.revolute(face, nn, {joint: (pivot, ax)}, nq=nq, mu=mu, name=name)]
    p1, p2 = face - s * ee, face + s * ee
    o1 = face - depth * nn - (s + length) * ee
    o2 = face - depth * nn
    a1 = _closing_axis(hinge, p1, o1, nn)
    a2 = _closing_axis(hinge, p2, o2, nn)
    return [
        Contact.revolute(p1, nn, {joint: (o1, a1)}, nq=nq, mu=mu, name=f"{name}_proximal"),
        Contact.revolute(p2, nn, {joint: (o1, a1), joint + 1: (o2, a2)}, nq=nq, mu=mu, name=f"{name}_distal"),
    ]
