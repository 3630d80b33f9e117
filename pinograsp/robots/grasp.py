"""URDF scene → :class:`~pinograsp.core.model.GraspModel` (docs/design.md).

``grasp_model_from_scene(hand, q, obj)`` detects the contacts with Coal
(:mod:`pinograsp.robots.collision`), builds one :class:`~pinograsp.core.contact.Contact` per point of
each touching geometry's patch (:mod:`pinograsp.robots.patches`: one point for a curved touch, the
two ends of a line, up to ``patch_points`` vertices of a face; the geometry's stiffness split
evenly among them) with the hand Jacobian from Pinocchio, and hands them with the description's
actuators and couplings to :meth:`GraspModel.from_contacts`, which prunes what the grasp does
not need (joints beyond the last contact of their chain, actuators reaching no contact).

Jacobian: for a contact at ``p`` on a link carried by joint ``i``, the frame at ``p`` on that
joint's body; the linear part of its ``LOCAL_WORLD_ALIGNED`` frame Jacobian is the world
velocity of the hand point at ``p`` per URDF joint velocity; multiplying column ``j`` by the
closing sign ``s_j`` gives it per **closing** joint velocity (the model's ``q``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..core.actuation import Actuator, Coupling
from ..core.contact import Contact
from ..core.model import GraspModel
from ..errors import InvalidInputError, UnknownNameError
from .collision import (
    DEFAULT_MAX_PENETRATION,
    DEFAULT_TOLERANCE,
    ContactReport,
    contact_options,
    detect_contacts_at,
    with_patches,
)
from .kinematics import HandConfiguration
from .patches import DEFAULT_PATCH_POINTS, patch_points_option

if TYPE_CHECKING:
    from .hand import Hand
    from .objects import RigidObject


def closing_jacobian(config: HandConfiguration, joint_id: int, point: np.ndarray) -> np.ndarray:
    """World linear velocity of the hand point at ``point`` per closing joint velocity, (3, nq) [m/rad].

    Args:
        config: The hand at its configuration (kinematics computed once).
        joint_id: Pinocchio joint carrying the link (0 = base: a zero Jacobian).
        point: The point, base frame [m], (3,).
    """
    hand = config.hand
    if joint_id == 0:
        return np.zeros((3, hand.nq))
    oMi = config.data.oMi[joint_id]
    placement = oMi.inverse() * pin.SE3(
        np.eye(3), np.asarray(point, dtype=float)
    )  # point frame in joint frame
    J6 = pin.getFrameJacobian(hand.model, config.data, joint_id, placement, pin.LOCAL_WORLD_ALIGNED)
    J6 = np.asarray(J6, dtype=float).reshape(6, hand.model.nv)  # a 1-DoF model gives shape (6,)
    return J6[:3] * hand.closing_signs[None, :]


def contact_jacobian(hand: Hand, q: object, joint_id: int, point: np.ndarray) -> np.ndarray:
    """World linear velocity of the hand point at ``point`` per closing joint velocity, (3, nq) [m/rad].

    Args:
        hand: The hand.
        q: Hand configuration (URDF coordinates).
        joint_id: Pinocchio joint carrying the link (0 = base: a zero Jacobian).
        point: The point, base frame [m], (3,).
    """
    return closing_jacobian(HandConfiguration.at(hand, q), joint_id, point)


def _per_contact(hand: Hand, report: ContactReport, name: str, value: object, default: float) -> list[float]:
    """``mu`` or ``stiffness`` per detected contact: a scalar, one value per contact, or ``{link: value}``."""
    nc = len(report.contacts)

    def number(key: str, v: object) -> float:
        try:
            return float(v)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            raise InvalidInputError(
                key, f"must be a number [or a {{link: number}} mapping], got {v!r}"
            ) from None

    if isinstance(value, dict):
        for key in value:
            if key not in hand.link_names:
                raise UnknownNameError(f"{name} link", key, list(hand.link_names))
        return [number(f"{name}[{c.link!r}]", value.get(c.link, default)) for c in report.contacts]
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidInputError(
            name, f"expected a number, a {{link: number}} mapping or {nc} numbers, got {value!r}"
        ) from None
    if arr.size == 1:
        return [float(arr[0])] * nc
    if arr.size != nc:
        raise InvalidInputError(
            name, f"expected a scalar, a {{link: value}} mapping or {nc} values, got {arr.size}"
        )
    return [float(v) for v in arr]


def scene_contacts(
    hand: Hand,
    q: object,
    obj: RigidObject,
    *,
    mu: float | Sequence[float] | dict[str, float] = 0.5,
    stiffness: float | Sequence[float] | dict[str, float] = 1.0,
    tolerance: float = DEFAULT_TOLERANCE,
    max_penetration: float = DEFAULT_MAX_PENETRATION,
    links: Sequence[str] | None = None,
    patches: bool = True,
    patch_points: int = DEFAULT_PATCH_POINTS,
) -> tuple[list[Contact], ContactReport]:
    """The :class:`Contact` objects of a scene (with Jacobians) and the detection report.

    The hand's kinematics at ``q`` is computed once (:class:`HandConfiguration`) and serves both
    the contact detection and the Jacobians. ``mu`` and ``stiffness`` are a scalar, one value per
    detected contact (touching geometry), or a mapping ``{link: value}`` (links not named get the
    defaults 0.5 and 1). With ``patches`` a touching geometry gives one contact per point of its
    patch (``report.patches``), each with the geometry's ``mu`` and ``stiffness / points``: a
    patch has the same total normal stiffness as a single point.
    """
    config = HandConfiguration.at(hand, q)
    options = contact_options(hand, tolerance, max_penetration, links)
    patch_points = patch_points_option(patch_points)
    report = with_patches(detect_contacts_at(config, obj, *options), config, obj, patches, patch_points)
    mus = _per_contact(hand, report, "mu", mu, 0.5)
    ks = _per_contact(hand, report, "stiffness", stiffness, 1.0)
    contacts = []
    for i, (pc, patch) in enumerate(zip(report.contacts, report.patches)):
        joint_id = hand.geometry.geometryObjects[pc.index].parentJoint
        for p, name in zip(patch.points, patch.names):
            jac = closing_jacobian(config, joint_id, p)
            k = ks[i] / patch.size
            contacts.append(
                Contact(point=p, normal=patch.normal, mu=mus[i], jacobian=jac, stiffness=k, name=name)
            )
    return contacts, report


def grasp_model_from_scene(
    hand: Hand,
    q: object,
    obj: RigidObject,
    *,
    mu: float | Sequence[float] | dict[str, float] = 0.5,
    stiffness: float | Sequence[float] | dict[str, float] = 1.0,
    tolerance: float = DEFAULT_TOLERANCE,
    max_penetration: float = DEFAULT_MAX_PENETRATION,
    links: Sequence[str] | None = None,
    patches: bool = True,
    patch_points: int = DEFAULT_PATCH_POINTS,
    actuators: Sequence[Actuator] | None = None,
    couplings: Sequence[Coupling] | None = None,
    reference_point: object = None,
    planar: bool = False,
    edges: int | None = None,
    circumscribed: bool = False,
    prune: bool = True,
) -> GraspModel:
    """Build a :class:`GraspModel` from a hand at configuration ``q`` touching ``obj``.

    Args:
        hand: The hand (:class:`pinograsp.Hand`).
        q: Hand configuration, URDF coordinates [rad or m] (sequence in ``hand.joint_names``
            order, or ``{joint: value}``).
        obj: The object, pose in the hand base frame.
        mu: Friction coefficient(s): scalar, per contact, or ``{link: mu}``.
        stiffness: Contact stiffness(es) [N/m], same forms as ``mu``.
        tolerance: Contact tolerance on the signed distance [m] (default 1 mm).
        max_penetration: Deepest accepted overlap [m] (default 5 mm).
        links: Only these links may touch (default: all contact links).
        patches: A geometry touching along a face or an edge gives several contact points
            (docs/hands.md, "Contact patches"); ``False``: one point per touching geometry.
        patch_points: Largest number of points of a face patch (2 to 16, default 4; a line
            gives 2, a curved touch 1). The geometry's stiffness is split evenly among them.
        actuators: Override the description's actuators (closing coordinates, joints by name).
        couplings: Override the hand's couplings (mimics and description couplings).
        reference_point: Wrench reference point [m] (default: the object's centre of mass).
        planar: Reduce to the XY plane (the scene must be planar).
        edges, circumscribed, prune: As in :meth:`GraspModel.from_contacts`.

    Raises:
        NoContactError: Nothing touches (the message lists the closest distance per link).
        PenetrationError: Deep penetration.
        InvalidInputError: Wrong configuration length, NaN, ...
    """
    contacts, _ = scene_contacts(
        hand,
        q,
        obj,
        mu=mu,
        stiffness=stiffness,
        tolerance=tolerance,
        max_penetration=max_penetration,
        links=links,
        patches=patches,
        patch_points=patch_points,
    )
    o = obj.center_of_mass if reference_point is None else reference_point
    return GraspModel.from_contacts(
        contacts,
        actuators=list(hand.actuators if actuators is None else actuators),
        couplings=list(hand.couplings if couplings is None else couplings),
        planar=planar,
        reference_point=o,
        joint_names=hand.joint_names,
        edges=edges,
        circumscribed=circumscribed,
        prune=prune,
    )
