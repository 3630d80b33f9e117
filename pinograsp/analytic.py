"""Analytic planar grasps (docs/design.md) as :class:`GraspModel` factories.

These small models have closed-form answers (derived in ``docs/analytic_cases.md`` and checked
in ``tests/``); they are also the built-in demo scenes. All lengths in [m], torques [N·m].
"""

from __future__ import annotations

import numpy as np

from .actuation import Actuator, Coupling
from .contact import Contact
from .model import GraspModel

EZ = np.array([0.0, 0.0, 1.0])


def _finger_contact(point, normal, pivot_below: float, joint: int, nq: int, closing_axis, **kw) -> Contact:
    p = np.asarray(point, float)
    pivot = p - np.array([0.0, pivot_below, 0.0])
    return Contact.revolute(p, normal, {joint: (pivot, closing_axis)}, nq=nq, **kw)


def pinch(
    a: float = 0.05,
    L: float = 0.1,
    mu: float = 0.5,
    k: float = 1.0,
    h: float = 0.0,
    differential: bool = False,
    planar: bool = True,
    kind: str = "non-backdrivable",
) -> GraspModel:
    """Two single-link fingers pinching an object centred at the origin.

    Contacts at ``(-a, -h)`` and ``(a, h)`` with normals ``(1, 0)`` / ``(-1, 0)``; each finger's
    revolute joint lies ``L`` below its contact, so closing moves the contact along its normal
    with moment arm ``L``. ``h != 0`` offsets the contacts diagonally (the *wedge* case: a
    clockwise object rotation squeezes both contacts). ``differential=True`` drives both
    joints with one actuator through a differential (``R = [1, 1]^T``).
    """
    left = _finger_contact([-a, -h, 0.0], [1.0, 0.0, 0.0], L, 0, 2, -EZ, mu=mu, stiffness=k, name="left")
    right = _finger_contact([a, h, 0.0], [-1.0, 0.0, 0.0], L, 1, 2, EZ, mu=mu, stiffness=k, name="right")
    if differential:
        acts = [Actuator({0: 1.0, 1: 1.0}, kind=kind, name="tendon")]
    else:
        acts = [Actuator({0: 1.0}, kind=kind, name="left"), Actuator({1: 1.0}, kind=kind, name="right")]
    return GraspModel.from_contacts(
        [left, right], actuators=acts, planar=planar, joint_names=("left", "right")
    )


def palm_pinch(
    a: float = 0.05, L: float = 0.1, b: float = 0.04, mu: float = 0.5, mu_palm: float = 0.5
) -> GraspModel:
    """The pinch plus a palm contact at ``(0, -b)`` pushing along ``+y`` (fixed: no joint)."""
    left = _finger_contact([-a, 0.0, 0.0], [1.0, 0.0, 0.0], L, 0, 2, -EZ, mu=mu, name="left")
    right = _finger_contact([a, 0.0, 0.0], [-1.0, 0.0, 0.0], L, 1, 2, EZ, mu=mu, name="right")
    palm = Contact([0.0, -b, 0.0], [0.0, 1.0, 0.0], mu=mu_palm, jacobian=np.zeros((3, 2)), name="palm")
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
    thumb = Contact([-a, 0.0, 0.0], [1.0, 0.0, 0.0], mu=mu, jacobian=np.zeros((3, 2)), name="thumb")
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
