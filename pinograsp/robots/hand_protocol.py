"""What the kinematics, contact detection and auto-close read from a hand: :class:`HandLike`.

:class:`~pinograsp.robots.hand.Hand` satisfies it structurally (``tests/test_layers.py`` checks
it). The algorithms below the hand (:mod:`~pinograsp.robots.kinematics`,
:mod:`~pinograsp.robots.collision`, :mod:`~pinograsp.robots.autoclose`) are typed with it, so
``hand.py`` may call them (``Hand.close_on``) without an import cycle: the hand sits above the
algorithms that read it.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class HandLike(Protocol):
    """A robot hand as the algorithms read it (see :class:`~pinograsp.robots.hand.Hand` for the
    meaning of each member).

    Attributes:
        model: Pinocchio model of the hand joints only.
        geometry: Pinocchio ``GeometryModel`` of the collision geometries that may touch objects.
        joint_names: Hand joints in configuration order, (nq,).
        prismatic: Whether each joint is prismatic, (nq,) bool.
        closing_signs: ``±1`` per joint, (nq,).
        lower, upper: Joint limits, URDF coordinates, (nq,) [rad or m].
    """

    model: Any
    geometry: Any
    joint_names: tuple[str, ...]
    prismatic: np.ndarray
    closing_signs: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    @property
    def nq(self) -> int:
        """Number of hand joints."""
        ...

    @property
    def contact_link_names(self) -> tuple[str, ...]:
        """Links that carry contact geometry (geometry order, no repeats)."""
        ...

    def configuration(self, q: object = None, name: str = "q") -> np.ndarray:
        """``q`` validated: a configuration (nq,) in URDF coordinates [rad or m]."""
        ...

    def link_of_geometry(self, index: int) -> str:
        """The link carrying collision geometry ``index``."""
        ...

    def closing_direction(self) -> np.ndarray:
        """Closing-coordinate rates of the joints when every actuator closes, (nq,)."""
        ...

    def coupling_matrix(self) -> np.ndarray:
        """The couplings as rows over the joints, (ncp, nq)."""
        ...
