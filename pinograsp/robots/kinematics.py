"""A hand at one configuration: its kinematics, computed once.

:class:`HandConfiguration` holds a hand, a configuration ``q`` (URDF coordinates [rad or m]) and
the result of **one** forward-kinematics pass at ``q``: joint placements, joint Jacobians, frame
placements and collision-geometry placements, all in the hand base frame. Collision
(:mod:`pinograsp.robots.collision`), contact Jacobians (:mod:`pinograsp.robots.grasp`), auto-close
(:mod:`pinograsp.robots.autoclose`) and the closing check (:mod:`pinograsp.robots.closing`) read
it instead of recomputing the kinematics. The Pinocchio ``Data`` lives in the configuration, so a
:class:`~pinograsp.robots.hand.Hand` keeps no kinematic state between calls.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .hand_protocol import HandLike


@dataclass(frozen=True, eq=False)
class HandConfiguration:
    """A hand at configuration ``q`` with its kinematics (build it with :meth:`at`).

    Attributes:
        hand: The hand.
        q: Configuration, URDF coordinates, (nq,) [rad or m] (read-only).
        data: Pinocchio ``Data`` after ``computeJointJacobians`` and ``updateFramePlacements``
            (``data.oMi``, ``data.oMf``, ``data.J``); do not modify it.
        geometry_data: Pinocchio ``GeometryData`` with the collision-geometry placements
            (``geometry_data.oMg``).
    """

    hand: HandLike
    q: np.ndarray
    data: pin.Data
    geometry_data: pin.GeometryData

    @classmethod
    def at(cls, hand: HandLike, q: object = None) -> HandConfiguration:
        """The kinematics of ``hand`` at ``q`` (validated by :meth:`Hand.configuration`).

        Args:
            hand: The hand.
            q: ``None`` (the open configuration), ``nq`` numbers in ``hand.joint_names`` order,
                or ``{joint: value}`` (URDF coordinates [rad or m]).
        """
        qv = hand.configuration(q)
        qv.setflags(write=False)
        model, geometry = hand.model, hand.geometry
        data = model.createData()
        geometry_data = (
            geometry.createData() if hasattr(geometry, "createData") else pin.GeometryData(geometry)
        )
        pin.computeJointJacobians(model, data, qv)  # forward kinematics and joint Jacobians
        pin.updateFramePlacements(model, data)
        pin.updateGeometryPlacements(model, data, geometry, geometry_data)
        return cls(hand, qv, data, geometry_data)
