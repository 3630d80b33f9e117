"""Auto-close: close a hand on an object, like GraspIt!'s auto-grasp (:func:`pinograsp.close_on`,
also :meth:`~pinograsp.Hand.close_on`).

The joints move along the hand's closing direction (:meth:`~pinograsp.Hand.closing_direction`,
URDF coordinates after the closing signs) in steps; a joint stops when a link it carries touches
the object (located by bisection), when it reaches a limit, or when a joint rigidly coupled to it
stops. Distances come from Coal (:func:`pinograsp.robots.collision.geometry_distances`), one
forward-kinematics pass per trial configuration (:class:`~pinograsp.robots.kinematics.HandConfiguration`).
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..core.validate import contact_tolerance, count, finite_number, number_in
from ..errors import InvalidInputError, NoContactError, PenetrationError, PinograspWarning
from .collision import (
    DEFAULT_MAX_PENETRATION,
    DEFAULT_TOLERANCE,
    closest_per_link,
    geometry_distances,
    inside_surfaces,
)
from .hand_protocol import HandLike
from .kinematics import HandConfiguration

if TYPE_CHECKING:  # pragma: no cover
    from .objects import RigidObject


class _Stops:
    """Which joints still close (``active``), and the rules that stop them.

    Joints rigidly coupled together (a connected component of the couplings) stop together. A
    collision geometry moves while any joint supporting it (its joint and those above) is active.
    """

    def __init__(self, hand: HandLike, active: np.ndarray) -> None:
        self.active = active
        # joints moved rigidly together: connected components of the couplings
        group = np.arange(hand.nq)
        for row in hand.coupling_matrix():
            idx = np.flatnonzero(row)
            g = group[idx].min()
            for i in idx:
                group[group == group[i]] = g
        self.group = group
        self.geo_joint = np.array([g.parentJoint for g in hand.geometry.geometryObjects], dtype=int)
        self.support = {
            int(j): [int(s) - 1 for s in hand.model.supports[int(j)] if s > 0]
            for j in set(self.geo_joint.tolist())
        }

    def moving_geometries(self) -> np.ndarray:
        """Whether each collision geometry moves with the active joints, (ngeom,)."""
        return np.array(
            [any(self.active[s] for s in self.support[int(j)]) for j in self.geo_joint], dtype=bool
        )

    def stop_geometry(self, k: int) -> None:
        """Geometry ``k`` touches: stop every joint carrying it, with their coupled groups."""
        for s in self.support[int(self.geo_joint[k])]:
            self.active[self.group == self.group[s]] = False

    def stop_group(self, j: int) -> None:
        """Joint ``j`` reached a limit: stop its coupled group."""
        self.active[self.group == self.group[j]] = False

    def limit_step(self, hand: HandLike, q: np.ndarray, dq: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Shorten each group's step ``dq`` so that no joint passes a limit; the joints that reach one.

        The group keeps its couplings (all its joints shrink by the same factor).
        """
        room = np.where(dq > 0, hand.upper - q, hand.lower - q)  # signed room to the limit
        frac = np.ones(hand.nq)
        moving = dq != 0
        frac[moving] = np.clip(room[moving] / dq[moving], 0.0, 1.0)
        at_limit = np.zeros(hand.nq, bool)
        for g in np.unique(self.group[moving]):
            members = self.group == g
            alpha = frac[members & moving].min()
            dq[members] *= alpha
            if alpha < 1.0:
                at_limit |= members & self.active
        return dq, at_limit


def _touch(
    hand: HandLike,
    obj: RigidObject,
    q: np.ndarray,
    dist: np.ndarray,
    dq: np.ndarray,
    mov: np.ndarray,
    tol: float,
) -> tuple[np.ndarray, np.ndarray, bool]:
    """Step ``q + dq``, or (bisection) the largest fraction of it with no moving link below ``-tol/2``.

    Returns:
        The new configuration, the distances of the moving geometries there (others ``+inf``),
        and whether the step was shortened by a touch.
    """

    def trial(h: float) -> tuple[np.ndarray, np.ndarray]:
        qt = q + h * dq
        return qt, geometry_distances(HandConfiguration.at(hand, qt), obj, mask=mov)

    qt, dt = trial(1.0)
    if not np.any(dt[mov] < -tol / 2):
        return qt, dt, False
    lo, hi = 0.0, 1.0
    q_lo, d_lo = q, dist
    for _bis in range(40):
        mid = 0.5 * (lo + hi)
        qm, dm = trial(mid)
        if np.any(dm[mov] < -tol / 2):
            hi = mid
        else:
            lo, q_lo, d_lo = mid, qm, dm
            if np.any(dm[mov] <= tol / 2):
                break
    return q_lo, d_lo, True


#: What to do when the hand closes fully without touching the object (:class:`NoContactError`).
MISSED_ADVICE = (
    "every joint closed to its limit without touching: place the object between the fingers (its "
    "pose in the hand base frame [m]; pg.save_png(None, hand=hand, obj=obj, path=...) shows both)"
)


def close_on(
    hand: HandLike,
    obj: RigidObject,
    q_open: object = None,
    *,
    tolerance: float | None = None,
    step: float = 0.03,
    max_steps: int = 2000,
    max_penetration: float | None = None,
) -> np.ndarray:
    """Close the hand on an object (like GraspIt!'s auto-grasp) and return the configuration.

    Joints move along :meth:`~pinograsp.Hand.closing_direction` from ``q_open`` in steps of at
    most ``step`` [rad] (``step / 10`` [m] for prismatic joints). When a link comes within the
    contact tolerance of the object, the joints that carry it stop, with every joint rigidly
    coupled to them; joints further out keep closing. A joint stops at its limit (and its coupled
    joints with it). Each touch is located by bisection so that the touching link's signed
    distance ends in ``[-tolerance/2, tolerance/2]``.

    Args:
        hand: The hand.
        obj: The object (pose in the hand base frame).
        q_open: Start configuration (default: the description's open configuration).
        tolerance: Contact tolerance [m] (default :data:`pinograsp.robots.collision.DEFAULT_TOLERANCE`).
        step: Largest joint step per iteration [rad]; thin objects need a smaller one.
        max_steps: Safety limit on the number of steps.
        max_penetration: Deepest overlap [m] accepted at ``q_open`` (default
            :data:`pinograsp.robots.collision.DEFAULT_MAX_PENETRATION`, 5 mm, as in
            :func:`~pinograsp.grasp_model_from_scene`): a link that already overlaps the object
            by at most this much touches it (its joints do not move); deeper raises.

    Returns:
        The closed configuration (URDF coordinates), (nq,) [rad or m].

    Raises:
        PenetrationError: ``q_open`` already penetrates the object by more than ``max_penetration``.
        NoContactError: every joint reached its limit and no link touches the object (the
            error lists each link's closest distance [m]).
    """
    tol = DEFAULT_TOLERANCE if tolerance is None else contact_tolerance("tolerance", tolerance, positive=True)
    pen = (
        DEFAULT_MAX_PENETRATION
        if max_penetration is None
        else finite_number("max_penetration", max_penetration)
    )
    if pen < 0:
        raise InvalidInputError("max_penetration", f"must be finite and >= 0 [m], got {pen}")
    pen = max(pen, tol)
    step = number_in("step", step, 1e-6, 1.0, "rad (prismatic: x 0.1 m)")  # domains: docs/errors.md
    max_steps = count("max_steps", max_steps, 10**6, what="closing steps")
    q = np.clip(hand.configuration(q_open, "q_open"), hand.lower, hand.upper)
    d = hand.closing_direction() * hand.closing_signs  # URDF-coordinate rates
    rate = d * np.where(hand.prismatic, step / 10.0, step)
    stops = _Stops(hand, d != 0)
    dist = geometry_distances(HandConfiguration.at(hand, q), obj)
    deep = {hand.link_of_geometry(k): v for k, v in enumerate(dist) if v < -pen}
    if deep:
        raise PenetrationError(deep, pen, {hand.link_of_geometry(k): v for k, v in enumerate(dist)})
    for k in np.flatnonzero(dist <= tol / 2):
        stops.stop_geometry(int(k))
    for _ in range(max_steps):
        if not stops.active.any():
            break
        mov = stops.moving_geometries()
        dq, at_limit = stops.limit_step(hand, q, np.where(stops.active, rate, 0.0))
        q, dt, touched = _touch(hand, obj, q, dist, dq, mov, tol)
        dist = np.where(mov, dt, dist)
        for k in np.flatnonzero(mov & (dist <= tol / 2)):
            stops.stop_geometry(int(k))
        if not touched:  # a touch shortened the step: no joint reached its limit
            for j in np.flatnonzero(at_limit):
                stops.stop_group(int(j))
    if not np.any(dist <= tol):  # every joint stopped at a limit without touching: say where the object is
        links = (hand.link_of_geometry(k) for k in range(len(dist)))
        inside = inside_surfaces(HandConfiguration.at(hand, q), obj)
        raise NoContactError(closest_per_link(links, dist), tol, inside, MISSED_ADVICE)
    _warn_rigid_group(hand, stops, dist, tol)
    return q


#: A rigidly coupled group of at least this many joints stopped by one touch is worth a warning
#: (a whole hand or finger on one motor through URDF mimics).
RIGID_GROUP = 3


def _warn_rigid_group(hand: HandLike, stops: _Stops, dist: np.ndarray, tol: float) -> None:
    """Warn (:class:`PinograspWarning`) when the grasp has a single touching link and it
    belongs to a rigidly coupled group of joints (URDF mimics or the description's couplings on
    one motor) that stopped as a whole at that first touch, its other links off the object: a
    real underactuated hand keeps closing its other phalanges, the rigid model cannot."""
    if len({hand.link_of_geometry(int(k)) for k in np.flatnonzero(dist <= tol)}) != 1:
        return  # several links touch: other fingers oppose the one that stopped
    for g in np.unique(stops.group):
        members = np.flatnonzero(stops.group == g)
        if len(members) < RIGID_GROUP:
            continue
        carried = [k for k in range(len(dist)) if int(stops.geo_joint[k]) - 1 in members]
        links = {hand.link_of_geometry(k) for k in carried}
        touching = {hand.link_of_geometry(k) for k in carried if dist[k] <= tol}
        if len(touching) == 1 and len(links) > 1:
            names = ", ".join(hand.joint_names[j] for j in members)
            warnings.warn(
                f"auto-close: joints {names} are coupled rigidly (URDF mimics or couplings of one "
                f"motor) and stopped together when {next(iter(touching))} touched: 1 of their "
                f"{len(links)} links touches, so the grasp has one contact there and no preload can "
                "squeeze the object. A real underactuated hand keeps closing its other phalanges: "
                "describe the coupling as a tendon or differential (docs/hands.md, 'Tendon and "
                "underactuated fingers'), or give each finger its own motor",
                PinograspWarning,
                stacklevel=3,
            )
