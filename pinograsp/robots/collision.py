"""Hand–object contact detection with Coal.

For a hand configuration and an object pose, Coal computes the **signed distance** between
every hand collision geometry and the object (``coal.distance`` with
``enable_signed_distance``). Coal 3 conventions, checked by ``tests/test_collision.py``:

* the returned normal points **from the first object to the second**: with the hand geometry
  first, it points from the hand into the object — the pinograsp contact normal (docs/design.md);
* the distance is **negative when the shapes overlap** (penetration depth = ``-distance``).

A geometry whose signed distance is ``<= tolerance`` gives one contact: the point midway
between the two nearest points, the Coal normal, and the link name. Each collision geometry
gives at most one contact (the closest point pair); where it touches along a face or an edge,
:mod:`pinograsp.robots.patches` turns that contact into a patch of several points
(:attr:`ContactReport.patches`). The default tolerance :data:`DEFAULT_TOLERANCE` is **1 mm**; distances below
``-max_penetration`` (default :data:`DEFAULT_MAX_PENETRATION`, **5 mm**) raise
:class:`~pinograsp.errors.PenetrationError`. All positions are in the hand base frame [m].

Non-convex meshes (object or hand) are Coal BVH *surfaces*: a shape entirely inside one is not
detected. For a mesh-mesh pair Coal gives no normal (and 0 when the surfaces cross): the normal
is the nearest points' direction, found after backing the hand off when crossing
(:func:`_mesh_pair`, docs/hands.md "Mesh objects"). A shape overlapping a surface keeps Coal's
normal only where it lies in the normal cone of the surface feature it touches
(:mod:`pinograsp.robots.mesh_normals`: Coal's one-triangle answer can be tangent to a curved
mesh). A touching pair without a unit normal raises
:class:`~pinograsp.errors.ContactDetectionError`; an overlapping one without a normal is
reported as penetrating.

The public functions take ``(hand, q, obj)``; their ``*_at`` versions take a
:class:`~pinograsp.robots.kinematics.HandConfiguration` whose kinematics is already computed.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

import coal
import numpy as np

from ..core.serialize import jsonable
from ..core.validate import contact_tolerance, finite_number
from ..errors import (
    ContactDetectionError,
    InvalidInputError,
    NoContactError,
    PenetrationError,
    UnknownNameError,
)
from .hand_protocol import HandLike
from .kinematics import HandConfiguration
from .mesh_normals import cone_normal, face_normal, flush_normal
from .patches import DEFAULT_PATCH_POINTS, ContactPatch, contact_patches, patch_points_option, single_points

if TYPE_CHECKING:
    from .objects import RigidObject

#: Default contact tolerance [m]: a geometry within this signed distance of the object touches it.
DEFAULT_TOLERANCE = 1e-3
#: Default deepest accepted penetration [m]; deeper overlaps raise PenetrationError.
DEFAULT_MAX_PENETRATION = 5e-3
#: Mesh-mesh pairs: nearest points closer than this [m] give no reliable direction.
MESH_WITNESS_MIN = 1e-9
#: Mesh-mesh overlap back-off: first shift [m], largest shift [m], bisection steps.
MESH_BACKOFF = (1e-5, 0.05, 6)


@dataclass(frozen=True)
class PairDistance:
    """Signed distance between one hand collision geometry and the object.

    Attributes:
        link: Hand link carrying the geometry.
        geometry: Name of the collision geometry.
        index: Index of the geometry in ``hand.geometry``.
        distance: Signed distance [m], negative when overlapping.
        point_hand: Nearest point on the hand geometry, base frame [m], (3,).
        point_object: Nearest point on the object, base frame [m], (3,).
        normal: Unit normal from the hand into the object, (3,) (zeros if Coal gave none).
    """

    link: str
    geometry: str
    index: int
    distance: float
    point_hand: np.ndarray
    point_object: np.ndarray
    normal: np.ndarray

    @property
    def point(self) -> np.ndarray:
        """Contact point: midway between the nearest points [m], (3,)."""
        return 0.5 * (self.point_hand + self.point_object)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: names, ``distance`` [m], points and normal as lists (3,) [m]."""
        return jsonable(
            {
                "link": self.link,
                "geometry": self.geometry,
                "index": self.index,
                "distance": self.distance,
                "point": self.point,
                "point_hand": self.point_hand,
                "point_object": self.point_object,
                "normal": self.normal,
            }
        )


@dataclass(frozen=True)
class ContactReport:
    """Result of :func:`detect_contacts`.

    Attributes:
        contacts: Geometry pairs within tolerance (the contacts), in geometry order.
        pairs: Every hand geometry's distance to the object.
        tolerance: Contact tolerance used [m].
        link_distances: Closest signed distance [m] per link (over ``pairs``).
        patches: The contact points of each contact (same order as ``contacts``,
            :mod:`pinograsp.robots.patches`); empty until patches are computed.
    """

    contacts: tuple[PairDistance, ...]
    pairs: tuple[PairDistance, ...]
    tolerance: float
    link_distances: dict[str, float] = field(default_factory=dict)
    patches: tuple[ContactPatch, ...] = ()

    @property
    def points_per_patch(self) -> tuple[int, ...]:
        """Number of contact points of each contact (1 each until patches are computed)."""
        return tuple(p.size for p in self.patches) if self.patches else (1,) * len(self.contacts)

    @property
    def links(self) -> tuple[str, ...]:
        """Links in contact (one entry per contact)."""
        return tuple(c.link for c in self.contacts)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: ``tolerance`` [m], ``links``, ``contacts`` and ``pairs``
        (:meth:`PairDistance.to_dict`), ``link_distances`` [m]."""
        return jsonable(
            {
                "tolerance": self.tolerance,
                "links": list(self.links),
                "contacts": [c.to_dict() for c in self.contacts],
                "pairs": [c.to_dict() for c in self.pairs],
                "link_distances": dict(self.link_distances),
                "patches": [p.to_dict() for p in self.patches],
            }
        )

    def summary(self) -> str:
        """The contacts (link, signed distance [mm]) and the closest links without contact."""
        lines = [f"{len(self.contacts)} contact(s) within {self.tolerance * 1e3:g} mm:"]
        shapes = [f", {p.size} point(s) ({p.kind})" for p in self.patches] or [""] * len(self.contacts)
        lines += [
            f"  {c.link} ({c.geometry}): {c.distance * 1e3:+.3f} mm{shape}"
            for c, shape in zip(self.contacts, shapes)
        ]
        touching = set(self.links)
        others = sorted((d, k) for k, d in self.link_distances.items() if k not in touching)
        if others:
            closest = ", ".join(f"{k} {d * 1e3:.3g} mm" for d, k in others[:3])
            lines.append("closest other links: " + closest)
        return "\n".join(lines)


def is_surface(geometry: coal.CollisionGeometry) -> bool:
    """Whether a Coal geometry is a BVH mesh (a surface, not a solid)."""
    return type(geometry).__name__.startswith("BVH")


def _coal_distance(
    g1: coal.CollisionGeometry, T1: coal.Transform3s, g2: coal.CollisionGeometry, T2: coal.Transform3s
) -> tuple[float, np.ndarray, np.ndarray, coal.DistanceResult]:
    """Coal's signed distance [m], nearest points (3,) [m] and its raw result."""
    req = coal.DistanceRequest()
    req.enable_signed_distance = True
    res = coal.DistanceResult()
    d = coal.distance(g1, T1, g2, T2, req, res)
    return (
        float(d),
        np.array(res.getNearestPoint1(), dtype=float),
        np.array(res.getNearestPoint2(), dtype=float),
        res,
    )


def _mesh_pair(
    g1: coal.CollisionGeometry,
    T1: coal.Transform3s,
    g2: coal.CollisionGeometry,
    T2: coal.Transform3s,
    d: float,
    p1: np.ndarray,
    p2: np.ndarray,
    face: int,
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Signed distance, nearest points and normal of two BVH meshes, for which Coal gives no
    normal and a distance of 0 whenever the surfaces cross (docs/hands.md, "Mesh objects").

    Apart: the normal is the direction from the nearest point on ``g1`` to the nearest point on
    ``g2``. Crossing: ``g1`` is moved back along the normal of the ``g2`` triangle ``face`` that
    Coal found (doubling shifts, then bisection, then the opposite sense in case the triangle is
    wound inwards) until the two are apart; the normal is the direction of the nearest points
    there, the distance ``d_apart - shift * (normal . n_face)`` (negative) and the nearest point
    on ``g1`` is moved back with it. No separation within the largest shift: distance
    ``-shift``, zero normal (reported as a deep penetration).
    """
    gap = p2 - p1
    size = float(np.linalg.norm(gap))
    if d > 0 and size > MESH_WITNESS_MIN:
        return d, p1, p2, gap / size
    first, cap, steps = MESH_BACKOFF
    n_face = -face_normal(g2, T2, face)  # into g2
    R, t = np.asarray(T1.getRotation()), np.asarray(T1.getTranslation())

    def apart(shift: float, u: np.ndarray) -> tuple[float, np.ndarray, np.ndarray] | None:
        ds, q1, q2, _ = _coal_distance(g1, coal.Transform3s(R, t - shift * u), g2, T2)
        return (ds, q1, q2) if ds > 0 and np.linalg.norm(q2 - q1) > MESH_WITNESS_MIN else None

    for u in (n_face, -n_face):
        inside, shift = 0.0, first
        while shift <= cap:
            found = apart(shift, u)
            if found is not None:
                for _ in range(steps):  # bisection between the last crossing and the first apart shift
                    mid = 0.5 * (inside + shift)
                    trial = apart(mid, u)
                    inside, shift, found = (inside, mid, trial) if trial is not None else (mid, shift, found)
                ds, q1, q2 = found
                n = (q2 - q1) / np.linalg.norm(q2 - q1)
                return ds - shift * float(n @ u), q1 + shift * u, q2, n
            inside, shift = shift, 2.0 * shift
    return -cap, p1, p2, np.zeros(3)


def _signed_distance(
    g1: coal.CollisionGeometry, T1: coal.Transform3s, g2: coal.CollisionGeometry, T2: coal.Transform3s
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Signed distance [m], nearest points on ``g1`` and ``g2`` (3,) [m], unit normal from ``g1``
    into ``g2`` (3,) (zeros when none could be found)."""
    d, p1, p2, res = _coal_distance(g1, T1, g2, T2)
    if is_surface(g1) and is_surface(g2):  # Coal 3 leaves the normal of a BVH-BVH pair unset
        return _mesh_pair(g1, T1, g2, T2, d, p1, p2, int(res.b2))
    n = np.array(res.normal, dtype=float)
    nn = np.linalg.norm(n)
    n = n / nn if nn > 1e-12 else np.zeros(3)
    return d, p1, p2, n


def pair_distances_at(config: HandConfiguration, obj: RigidObject) -> tuple[PairDistance, ...]:
    """Signed distance of every hand collision geometry to the object, at a computed configuration."""
    hand = config.hand
    T_obj = obj.transform
    out = []
    for k, go in enumerate(hand.geometry.geometryObjects):
        oMg = config.geometry_data.oMg[k]
        d, p1, p2, n = _signed_distance(
            go.geometry, coal.Transform3s(oMg.rotation, oMg.translation), obj.geometry, T_obj
        )
        if d <= 0 and np.any(n) and is_surface(obj.geometry) and not is_surface(go.geometry):
            T_g = coal.Transform3s(oMg.rotation, oMg.translation)
            n = cone_normal(n, obj.geometry, T_obj, p2)  # Coal's one-triangle normal may be tangent
            n = flush_normal(n, go.geometry, T_g, p1, obj.geometry, T_obj, p2)  # flush faces, edges met
        out.append(PairDistance(hand.link_of_geometry(k), go.name, k, d, p1, p2, n))
    return tuple(out)


def pair_distances(hand: HandLike, q: object, obj: RigidObject) -> tuple[PairDistance, ...]:
    """Signed distance of every hand collision geometry to the object.

    Args:
        hand: The hand.
        q: Hand configuration (URDF coordinates, see :meth:`Hand.configuration`).
        obj: The object, pose in the hand base frame.
    """
    return pair_distances_at(HandConfiguration.at(hand, q), obj)


def geometry_distances(
    config: HandConfiguration, obj: RigidObject, mask: np.ndarray | None = None
) -> np.ndarray:
    """Signed distances [m] of the hand collision geometries to the object, (ngeom,).

    Geometries outside ``mask`` get ``+inf`` (not computed). A pair for which Coal gives no
    normal while overlapping (deep overlap with a BVH surface) gets ``-inf``.
    """
    geometries = config.hand.geometry.geometryObjects
    T_obj = obj.transform
    out = np.full(len(geometries), np.inf)
    for k, go in enumerate(geometries):
        if mask is not None and not mask[k]:
            continue
        oMg = config.geometry_data.oMg[k]
        d, _, _, n = _signed_distance(
            go.geometry, coal.Transform3s(oMg.rotation, oMg.translation), obj.geometry, T_obj
        )
        out[k] = -np.inf if (d <= 0 and not np.any(n)) else d
    return out


def closest_per_link(links: Iterable[str], distances: Iterable[float]) -> dict[str, float]:
    """Closest signed distance [m] of each link, from the distances of its geometries."""
    out: dict[str, float] = {}
    for link, d in zip(links, distances):
        out[link] = min(out.get(link, np.inf), float(d))
    return out


def link_distances(hand: HandLike, q: object, obj: RigidObject) -> dict[str, float]:
    """Closest signed distance [m] of each hand link (over its geometries) to the object."""
    pairs = pair_distances(hand, q, obj)
    return closest_per_link((p.link for p in pairs), (p.distance for p in pairs))


def contact_options(
    hand: HandLike, tolerance: object, max_penetration: object, links: object
) -> tuple[float, float, tuple[str, ...] | None]:
    """Validated ``tolerance`` [m], ``max_penetration`` [m] and ``links`` of :func:`detect_contacts`."""
    tolerance = contact_tolerance("tolerance", tolerance)  # domain: docs/errors.md
    max_penetration = finite_number("max_penetration", max_penetration)
    if max_penetration < 0:
        raise InvalidInputError("max_penetration", f"must be finite and >= 0, got {max_penetration}")
    if links is None:
        return tolerance, max_penetration, None
    if isinstance(links, (str, bytes)) or not isinstance(links, (list, tuple)):
        raise InvalidInputError("links", f"expected a list of link names, got {links!r}")
    valid = hand.contact_link_names
    for ln in links:
        if not isinstance(ln, str) or ln not in valid:
            raise UnknownNameError("link", ln, valid)
    return tolerance, max_penetration, tuple(links)


def detect_contacts_at(
    config: HandConfiguration,
    obj: RigidObject,
    tolerance: float,
    max_penetration: float,
    links: tuple[str, ...] | None,
    require: bool = True,
) -> ContactReport:
    """:func:`detect_contacts` at a computed configuration, options validated by :func:`contact_options`."""
    pairs = pair_distances_at(config, obj)
    if links is not None:
        pairs = tuple(p for p in pairs if p.link in links)
    dist = closest_per_link((p.link for p in pairs), (p.distance for p in pairs))
    deep = {
        p.link: p.distance
        for p in pairs
        if p.distance < -max_penetration or (p.distance <= 0 and not np.any(p.normal))
    }
    if deep:
        raise PenetrationError(deep, max_penetration, dist)
    contacts = tuple(p for p in pairs if p.distance <= tolerance)
    for p in contacts:
        _check_contact(config, obj, p)
    if require and not contacts:
        raise NoContactError(dist, tolerance, inside_surfaces(config, obj))
    return ContactReport(contacts, pairs, float(tolerance), dist)


def _check_contact(config: HandConfiguration, obj: RigidObject, p: PairDistance) -> None:
    """Raise :class:`ContactDetectionError` (naming object, link, geometry and pose) unless the
    pair has a finite point and a unit normal."""
    norm = float(np.linalg.norm(p.normal))
    if np.all(np.isfinite(p.point)) and abs(norm - 1.0) <= 1e-9:
        return
    raise ContactDetectionError(
        obj.name,
        p.link,
        p.geometry,
        obj.pose[:3, 3],
        config.q,
        f"no usable contact normal (|n| = {norm:.3g}) at signed distance {p.distance * 1e3:+.3f} mm "
        f"(nearest points {np.round(p.point_hand * 1e3, 3).tolist()} mm on the hand, "
        f"{np.round(p.point_object * 1e3, 3).tolist()} mm on the object)",
    )


def with_patches(
    report: ContactReport,
    config: HandConfiguration,
    obj: RigidObject,
    enabled: bool = True,
    max_points: int = DEFAULT_PATCH_POINTS,
) -> ContactReport:
    """``report`` with its :attr:`~ContactReport.patches` filled: the contact patches
    (:func:`~pinograsp.robots.patches.contact_patches`) when ``enabled``, else one point per contact."""
    if not isinstance(enabled, (bool, np.bool_)):
        raise InvalidInputError("patches", f"expected true or false, got {enabled!r}")
    max_points = patch_points_option(max_points)
    if enabled:
        patches = contact_patches(config, obj, report.contacts, report.tolerance, max_points)
    else:
        patches = single_points(report.contacts)
    return replace(report, patches=patches)


def inside_surfaces(config: HandConfiguration, obj: RigidObject) -> tuple[str, ...]:
    """Links whose mesh is a surface (Coal BVH) with the object's centre inside its local
    bounding box: the object may sit inside the link, where the signed distance (to the wall)
    is positive (a hint for :class:`~pinograsp.errors.NoContactError`)."""
    hand = config.hand
    centre = np.asarray(obj.center_of_mass, float)
    out: list[str] = []
    for k, g in enumerate(hand.geometry.geometryObjects):
        geo = g.geometry
        if not is_surface(geo):
            continue
        geo.computeLocalAABB()
        local = config.geometry_data.oMg[k].actInv(centre)
        box = geo.aabb_local
        if np.all(local >= np.asarray(box.min_)) and np.all(local <= np.asarray(box.max_)):
            name = hand.link_of_geometry(k)
            if name not in out:
                out.append(name)
    return tuple(out)


def detect_contacts(
    hand: HandLike,
    q: object,
    obj: RigidObject,
    *,
    tolerance: float = DEFAULT_TOLERANCE,
    max_penetration: float = DEFAULT_MAX_PENETRATION,
    links: list[str] | tuple[str, ...] | None = None,
    require: bool = True,
    patches: bool = True,
    patch_points: int = DEFAULT_PATCH_POINTS,
) -> ContactReport:
    """Find the hand–object contacts at configuration ``q``.

    Args:
        hand: The hand.
        q: Hand configuration (URDF coordinates [rad or m]; sequence or ``{joint: value}``).
        obj: The object, pose in the hand base frame.
        tolerance: A geometry whose signed distance to the object is ``<= tolerance`` [m]
            touches it (default 1 mm).
        max_penetration: Deepest accepted overlap [m] (default 5 mm).
        links: Only these links may touch (default: every contact link of the hand).
        require: Raise :class:`NoContactError` when nothing touches.
        patches: Represent a face or edge touch by several points (``report.patches``,
            :mod:`pinograsp.robots.patches`); ``False``: one point per contact.
        patch_points: Largest number of points of a face patch (2 to 16, default 4).

    Returns:
        The contacts (normals from the hand into the object), every pair's distance and the
        contact points of each contact.

    Raises:
        NoContactError: No geometry within tolerance (lists the closest distance per link).
        PenetrationError: A geometry overlaps the object by more than ``max_penetration``, or a
            BVH pair overlaps without a usable normal.
        UnknownNameError: ``links`` names a link without contact geometry.
    """
    options = contact_options(hand, tolerance, max_penetration, links)
    config = HandConfiguration.at(hand, q)
    report = detect_contacts_at(config, obj, *options, require=require)
    return with_patches(report, config, obj, patches, patch_points)
