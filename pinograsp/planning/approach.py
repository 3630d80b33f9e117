"""Approach poses: where a hand grasps an object, as the object's pose in the hand base frame.

A hand is reduced to its **approach frame** (:class:`ApproachFrame`): the grasp centre ``c``
(the centre of the box bounding the moving contact geometries' centres over the hand's free
closing sweep, from the open configuration to the joint limits, hand base frame [m]), the
approach axis ``a`` (unit, from the palm — the mean of the fixed contact geometries' centres,
or the base origin — to ``c``) and a reference axis ``b`` perpendicular to it (the closing
direction at roll 0), and the reach ``r = |c - palm|`` [m]. A sampled approach
(:func:`surface_samples`) is a point ``p`` on the object's surface with its outward normal ``n``
(object frame), a roll and a standoff ``s`` in ``[0, 1]``: the hand is placed so that ``a``
points along ``-n``, ``b`` is turned by the roll about ``n``, and the palm point sits at
``p + s r n`` (``s = 0``: the palm on the surface; ``s = 1``: the grasp centre on it), i.e. ``c``
at the depth ``(1 - s) r`` below ``p``. The open hand then **comes in** along ``-n`` from where
its bounding sphere clears the object's and stops at that depth or at its first touch
(:func:`first_touch`, Coal distances of the open-pose collision geometry), whichever comes
first, so that no sampled approach starts with the open fingers inside the object. The pose
returned is the object's in the hand base frame (what :class:`~pinograsp.batch.grasps.ObjectSpec`
holds). Everything is a pure function of its inputs and of a ``numpy`` PCG64 stream: the same
seed gives the same poses on every machine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from ..batch.grasps import ObjectSpec
from ..errors import InvalidInputError


@dataclass(frozen=True)
class ApproachFrame:
    """How a hand approaches: grasp centre ``centre`` [m] (3,), unit approach axis ``axis`` (3,),
    unit reference axis ``reference`` (3,) perpendicular to it, all in the hand base frame, and
    the reach ``reach`` [m] from the palm point to the grasp centre."""

    centre: np.ndarray
    axis: np.ndarray
    reference: np.ndarray
    reach: float

    @classmethod
    def of_hand(cls, hand: Any, q_open: object = None) -> ApproachFrame:
        """The approach frame of a :class:`~pinograsp.robots.hand.Hand` (``q_open``: the open
        configuration ``{joint: value}``, or ``None`` for the description's).

        The grasp centre is the centre of the box bounding the moving geometries' centres at five
        configurations of the free closing sweep (each closing joint from ``q_open`` to its limit
        in the closing direction): a thumb opposing two fingers does not pull it to the fingers'
        side. The approach axis is the mean direction in which the moving geometries set off
        when the hand starts closing (2 % of the sweep) — the palm normal of a hand whose fingers
        curl (Barrett, Ability, Allegro) — unless those motions mostly cancel (a gripper's
        opposed jaws: less than 0.3 of their mean length), then from the palm to the centre."""
        is_moving = np.array([g.parentJoint > 0 for g in hand.geometry.geometryObjects])
        if not is_moving.any():
            raise InvalidInputError("hand", f"{hand.name}: no moving contact geometry to grasp with")
        sweep = [_centres(c) for c in _closing_sweep(hand, q_open, (0.0, 0.02, 0.25, 0.5, 0.75, 1.0))]
        pts = np.concatenate([c[is_moving] for c in sweep[:1] + sweep[2:]])
        centre = (pts.min(axis=0) + pts.max(axis=0)) / 2
        palm = np.mean(sweep[0][~is_moving], axis=0) if (~is_moving).any() else np.zeros(3)
        axis = centre - palm
        reach = float(np.linalg.norm(axis))
        if not reach > 1e-9:
            raise InvalidInputError("hand", f"{hand.name}: grasp centre at the palm; no approach axis")
        start = (sweep[1] - sweep[0])[is_moving]  # how the moving geometries set off when closing
        mean = start.mean(axis=0)
        if np.linalg.norm(mean) > 0.3 * float(np.linalg.norm(start, axis=1).mean()):
            axis = mean  # the fingers curl that way (a palm normal), not opposed as a gripper's jaws
        axis = axis / np.linalg.norm(axis)
        return cls(centre, axis, _perpendicular(axis), reach)


def _centres(config: Any) -> np.ndarray:
    """The collision geometries' centres at a computed configuration, hand base frame [m], (ngeom, 3)."""
    return np.array([np.array(m.translation) for m in config.geometry_data.oMg])


def _closing_sweep(hand: Any, q_open: object, fractions: tuple[float, ...]) -> list[Any]:
    """Forward kinematics at ``fractions`` of the way from ``q_open`` to the joint limits along
    the closing direction (each closing joint interpolated to its limit; the others at ``q_open``)."""
    from ..robots.kinematics import HandConfiguration

    q0 = np.clip(
        hand.configuration(None if q_open is None else dict(cast(Any, q_open))), hand.lower, hand.upper
    )
    d = hand.closing_direction() * hand.closing_signs
    end = np.where(d > 0, hand.upper, np.where(d < 0, hand.lower, q0))
    end = np.where(np.isfinite(end), end, q0 + np.sign(d) * math.pi)  # a continuous joint: half a turn
    return [HandConfiguration.at(hand, q0 + t * (end - q0)) for t in fractions]


class OpenHand:
    """The open hand and the object (in its own frame) for :meth:`first_touch`.

    Args:
        hand: The :class:`~pinograsp.robots.hand.Hand`.
        q_open: Its open configuration (``{joint: value}`` or ``None``: the description's).
        obj: The object's :class:`ObjectSpec` (its pose is ignored).
        frame: The hand's approach frame.
        tolerance: The contact tolerance [m]: the approach stops with the nearest geometry
            between 1.6 and 1.8 of it from the object, just outside the contact detection (a
            palm that no finger can press against is not a contact: no preload could load it),
            or, touching, between 0.6 and 0.8 of it (a contact that the auto-close does not
            stop, which stops below half of it).
    """

    def __init__(self, hand: Any, q_open: object, obj: ObjectSpec, frame: ApproachFrame, tolerance: float):
        from ..robots.kinematics import HandConfiguration

        self.config = HandConfiguration.at(hand, None if q_open is None else dict(cast(Any, q_open)))
        self.object = obj.with_pose((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)).to_object()
        self.frame, self.tolerance = frame, tolerance
        g = self.object.geometry
        g.computeLocalAABB()
        self.object_centre, self.object_radius = np.array(g.aabb_center), float(g.aabb_radius)
        radius = 0.0
        for k, go in enumerate(hand.geometry.geometryObjects):
            go.geometry.computeLocalAABB()
            oMg = self.config.geometry_data.oMg[k]
            at = oMg.rotation @ np.array(go.geometry.aabb_center) + oMg.translation
            radius = max(radius, float(np.linalg.norm(at - frame.centre)) + float(go.geometry.aabb_radius))
        self.hand_radius = radius

    def centred(self, point: np.ndarray, normal: np.ndarray, pull: float) -> np.ndarray:
        """``point`` (object frame [m], (3,)) moved across ``normal`` toward the line through the
        object's bounding-box centre along it by the fraction ``pull`` in ``[0, 1]`` (on a box face
        it stays on the face, nearer its middle; a sphere's points do not move)."""
        n = normal / np.linalg.norm(normal)
        off = point - self.object_centre
        return point - pull * (off - float(off @ n) * n)

    def clearance(self, T: np.ndarray) -> float:
        """The smallest signed distance [m] of the open hand's geometries to the object at the
        object pose ``T`` (hand base frame, 4×4); ``-inf`` for a deep overlap of meshes."""
        from ..robots.collision import geometry_distances

        return float(geometry_distances(self.config, self.object.with_pose(T)).min())

    def first_touch(
        self, point: np.ndarray, normal: np.ndarray, roll: float, depth: float, touch: bool = False
    ) -> float:
        """The depth [m] at which the open hand, coming in along ``-normal`` from where the
        bounding spheres are apart, first comes within ``1.8 * tolerance`` of the object (with
        ``touch``: ``0.8 * tolerance``, so that what touches first — a palm the fingers press
        the object against — is a contact), or ``depth`` if it gets there first (conservative
        advancement: each step is the current clearance less ``1.6`` (``0.6``) ``* tolerance``,
        so the hand never enters the object; at most 64 steps, then the last clear depth)."""
        frame, tol = self.frame, self.tolerance
        depth_now = -(
            float(np.linalg.norm(point - self.object_centre)) + self.object_radius + self.hand_radius
        )
        for _ in range(64):
            gap = 0.6 * tol if touch else 1.6 * tol
            advance = self.clearance(approach_pose(frame, point, normal, roll, depth_now)) - gap
            if advance <= 0.2 * tol:
                return depth_now
            if depth_now + advance >= depth:
                return depth
            depth_now += advance
        return depth_now


def _perpendicular(v: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to the unit ``v``: the base axis least aligned with it, made
    perpendicular (x first on ties)."""
    e = np.eye(3)[int(np.argmin(np.abs(v)))]
    u = e - float(e @ v) * v
    return u / np.linalg.norm(u)


def _box_points(size: np.ndarray, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    areas = np.repeat([size[1] * size[2], size[0] * size[2], size[0] * size[1]], 2)
    face = rng.choice(6, size=n, p=areas / areas.sum())
    uv = rng.uniform(-0.5, 0.5, size=(n, 3)) * size
    points, normals = uv.copy(), np.zeros((n, 3))
    for k in range(n):
        axis, sign = divmod(int(face[k]), 2)
        points[k, axis] = (0.5 if sign == 0 else -0.5) * size[axis]
        normals[k, axis] = 1.0 if sign == 0 else -1.0
    return points, normals


def _cylinder_points(r: float, h: float, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    side, cap = 2 * math.pi * r * h, math.pi * r * r
    on_side = rng.uniform(0.0, side + 2 * cap, n) < side
    angle = rng.uniform(0.0, 2 * math.pi, n)
    z = rng.uniform(-0.5, 0.5, n) * h
    rho = r * np.sqrt(rng.uniform(0.0, 1.0, n))
    top = rng.uniform(0.0, 1.0, n) < 0.5
    c, s = np.cos(angle), np.sin(angle)
    points = np.where(
        on_side[:, None], np.c_[r * c, r * s, z], np.c_[rho * c, rho * s, np.where(top, h, -h) / 2]
    )
    normals = np.where(on_side[:, None], np.c_[c, s, 0 * z], np.c_[0 * z, 0 * z, np.where(top, 1.0, -1.0)])
    return np.asarray(points, dtype=float), np.asarray(normals, dtype=float)


def _mesh_points(obj: ObjectSpec, rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    mesh: Any = trimesh.load(str(obj.file), force="mesh")
    v = np.array(mesh.vertices, dtype=np.float64) * obj.scale
    f = np.asarray(mesh.faces)
    tri = v[f]  # (nf, 3, 3)
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(cross, axis=1)
    keep = area > 0
    face = rng.choice(np.flatnonzero(keep), size=n, p=area[keep] / area[keep].sum())
    u, w = rng.uniform(0.0, 1.0, n), rng.uniform(0.0, 1.0, n)
    flip = u + w > 1.0
    u, w = np.where(flip, 1.0 - u, u), np.where(flip, 1.0 - w, w)
    t = tri[face]
    points = t[:, 0] + u[:, None] * (t[:, 1] - t[:, 0]) + w[:, None] * (t[:, 2] - t[:, 0])
    normals = cross[face] / area[face][:, None]
    return points, normals


def surface_samples(obj: ObjectSpec, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``n`` points spread uniformly by area on the object's surface and their outward unit
    normals, object frame, (n, 3) [m] and (n, 3): exact for boxes, spheres and cylinders (axis
    along z, centred), face normals for meshes (outward for a consistently wound mesh)."""
    if obj.shape == "box":
        return _box_points(np.asarray(obj.size, dtype=float), rng, n)
    if obj.shape == "sphere":
        d = rng.normal(size=(n, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        return float(cast(float, obj.radius)) * d, d
    if obj.shape == "cylinder":
        return _cylinder_points(float(cast(float, obj.radius)), float(cast(float, obj.length)), rng, n)
    return _mesh_points(obj, rng, n)


def aligned_roll(normal: np.ndarray, pick: int) -> float:
    """The roll [rad] about ``normal`` (object frame, unit, (3,)) that turns the hand's reference
    axis onto one of the object frame's axes seen across the normal: the axes not within 60° of
    the normal, each with both signs, in order x, y, z; ``pick`` chooses among them (modulo their
    number). A box face's edges, a cylinder's axis or its circumference."""
    n = normal / np.linalg.norm(normal)
    u = _perpendicular(n)
    v = np.cross(n, u)
    options = []
    for e in np.eye(3):
        d = e - float(e @ n) * n
        if np.linalg.norm(d) > 0.5:
            options += [d, -d]
    if not options:  # unreachable: two of three orthogonal axes are always > 60° from a unit normal
        return 0.0
    d = options[pick % len(options)]
    return math.atan2(float(d @ v), float(d @ u))


def approach_pose(
    frame: ApproachFrame, point: np.ndarray, normal: np.ndarray, roll: float, depth: float
) -> np.ndarray:
    """The object's pose in the hand base frame, 4×4, for an approach at ``point`` (object frame
    [m], (3,)) along ``-normal`` (unit, (3,)), turned by ``roll`` [rad] about the normal, the grasp
    centre at ``point - depth * normal`` (``depth`` [m])."""
    n = normal / np.linalg.norm(normal)
    u = _perpendicular(n)
    v = np.cross(n, u)
    t = math.cos(roll) * u + math.sin(roll) * v
    hand_axes = np.column_stack([frame.axis, frame.reference, np.cross(frame.axis, frame.reference)])
    object_axes = np.column_stack([-n, t, np.cross(-n, t)])
    R_oh = object_axes @ hand_axes.T  # hand base frame in the object frame
    t_oh = point - depth * n - R_oh @ frame.centre
    T = np.eye(4)
    T[:3, :3] = R_oh.T
    T[:3, 3] = -R_oh.T @ t_oh
    return T


def moved(T: np.ndarray, centre: np.ndarray, translation: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """The object pose ``T`` (hand base frame, 4×4) moved by a small hand motion: turned by the
    rotation vector ``rotation`` [rad] (3,) about the grasp ``centre`` [m], then shifted by
    ``translation`` [m] (3,), both in the hand base frame."""
    angle = float(np.linalg.norm(rotation))
    R = np.eye(3)
    if angle > 0:
        k = rotation / angle
        K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        R = np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)
    out = np.eye(4)
    out[:3, :3] = R @ T[:3, :3]
    out[:3, 3] = R @ (T[:3, 3] - centre) + centre + translation
    return out


def pose_distance(A: np.ndarray, B: np.ndarray, centre: np.ndarray) -> tuple[float, float]:
    """How far apart two object poses (hand base frame, 4×4) put the hand on the object: the
    distance [m] between the grasp centre's positions in the object frame, and the angle [rad]
    between the hand's orientations."""
    ca = A[:3, :3].T @ (centre - A[:3, 3])
    cb = B[:3, :3].T @ (centre - B[:3, 3])
    cos = (float(np.trace(A[:3, :3].T @ B[:3, :3])) - 1.0) / 2.0
    return float(np.linalg.norm(ca - cb)), math.acos(max(-1.0, min(1.0, cos)))
