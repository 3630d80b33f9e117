"""Seeded random grasps with a known preload equilibrium, for tests and benchmarks.

:func:`random_grasp` builds ``n_pairs`` pairs of opposing fingers around an object centred at
the origin. Each finger presses on a flat face of the object (normal ``n``, in-plane direction
``e``) with one contact (single-link finger) or two (proximal and distal link, the distal joint
coupled to the proximal one at ``ratio``, Barrett-like). The two fingers of a pair are point
mirror images of each other, so under equal commands their normal forces are collinear and
opposite: **the preload alone is always in equilibrium**, whatever the random draw. Lengths in
[m], commands in [N·m].
"""

from __future__ import annotations

import numpy as np

from .actuation import Actuator, Coupling
from .contact import Contact
from .errors import InvalidInputError
from .model import GraspModel

EZ = np.array([0.0, 0.0, 1.0])


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
        if planar:
            a = rng.uniform(0, 2 * np.pi)
            n = np.array([np.cos(a), np.sin(a), 0.0])
            e = np.cross(EZ, n)
        else:
            n = _unit(rng.normal(size=3))
            e = _unit(np.cross(n, _unit(rng.normal(size=3))))
        r = radius * rng.uniform(0.7, 1.3)
        s = radius * rng.uniform(0.2, 0.5)  # half distance between proximal and distal contact
        off = radius * rng.uniform(-0.3, 0.3)  # offset of the finger along e
        depth, length = radius * rng.uniform(0.5, 1.0), radius * rng.uniform(1.5, 2.5)
        hinge = _unit(np.cross(e, n))
        for side, sign in enumerate((1.0, -1.0)):  # the second finger is the point mirror
            nn = sign * n
            ee = sign * e
            face = -r * nn + off * ee
            name = f"f{2 * k + side}"
            j1 = joint
            if contacts_per_finger == 1:
                p = face
                pivot = p - depth * nn - length * ee
                ax = _closing_axis(hinge, p, pivot, nn)
                contacts.append(Contact.revolute(p, nn, {j1: (pivot, ax)}, nq=nq, mu=mu, name=name))
                actuators.append(Actuator({j1: 1.0}, kind=kind, name=name))
                joint += 1
            else:
                j2 = joint + 1
                p1, p2 = face - s * ee, face + s * ee
                o1 = face - depth * nn - (s + length) * ee
                o2 = face - depth * nn
                a1 = _closing_axis(hinge, p1, o1, nn)
                a2 = _closing_axis(hinge, p2, o2, nn)
                contacts.append(
                    Contact.revolute(p1, nn, {j1: (o1, a1)}, nq=nq, mu=mu, name=f"{name}_proximal")
                )
                contacts.append(
                    Contact.revolute(
                        p2, nn, {j1: (o1, a1), j2: (o2, a2)}, nq=nq, mu=mu, name=f"{name}_distal"
                    )
                )
                actuators.append(Actuator({j1: 1.0}, kind=kind, name=name))
                couplings.append(Coupling.follow(j2, j1, ratio))
                joint += 2
    return GraspModel.from_contacts(
        contacts,
        actuators=actuators,
        couplings=couplings,
        planar=planar,
        edges=edges,
        joint_names=tuple(f"j{i}" for i in range(nq)),
    )
