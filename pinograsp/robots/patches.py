"""Contact patches: a face or edge touch as a few contact points (docs/hands.md, "Contact patches").

:mod:`pinograsp.robots.collision` finds, per hand collision geometry, the closest point pair
with the object. When a flat feature of the geometry (a box face or edge, a cylinder cap, a
convex-mesh face) lies on a flat feature of the object, that one point is arbitrary: a pad on a
face would resist neither torsion nor tilt. This module turns such a touch into a **patch**:

1. Coal's contact patch of the pair (``coal.collide`` with a security margin equal to the
   contact tolerance, so contacts at a small positive distance count, then
   ``coal.computeContactPatch`` with the same tolerance as its patch tolerance): the polygon of
   the two shapes' features within tolerance of the contact plane, in that plane (midway between
   the surfaces), with one normal from the hand into the object.
2. Points closer than :data:`MERGE_DISTANCE` are merged. One point left -> a **point** contact;
   all points on one line (within :data:`MERGE_DISTANCE`) -> a **line**, its two end points;
   otherwise a **face**, reduced to at most ``patch_points`` vertices by farthest-point
   selection (start: the vertex farthest from the centroid; each next vertex: the one farthest
   from those chosen).
3. Ties and the order of the points are decided in the **hand geometry's own frame** (points
   rounded to :data:`ORDER_RESOLUTION`, compared lexicographically), so the points and their
   order do not change under a rigid motion of the whole scene nor with the geometries' order.

**Curved** touches stay single points (the closest pair, as with patches off): a sphere or
ellipsoid; a capsule's round end; a cylinder, cone or capsule side whose touch Coal does not
give as a segment along a generator (a sphere on it, a crossing axis, a tilt beyond the
tolerance). A **straight side** (cylinder, cone, capsule: curved across, straight along a
generator) on a surface that is flat along that generator within the tolerance is a **line**:
Coal's patch gives the generator clipped to the other shape's feature, its two end points. Two
straight sides with parallel generators (within the tolerance over their overlap) are a line
too, which Coal gives as one point: :func:`~pinograsp.robots.patch_shapes.parallel_sides`
builds it over the generators' overlap.

**Meshes** (a convex mesh ``Convex``, or a triangle mesh ``BVH`` through its convex hull, built
once per geometry) are flat only where they are: the hull's vertices within the contact
tolerance of the contact plane (on each mesh) must lie within :data:`MESH_FLATNESS` times the
tolerance of one plane (0.1 mm at the default 1 mm). A tessellated curved surface (a rounded
finger, a sphere or torus mesh) fails this and stays one point; a flat mesh face gives Coal's
polygon, as a primitive face does. A mesh patch narrower than the tolerance is a point. A
**tessellated straight side** on a flat face or along a primitive's straight side is a line
(:mod:`~pinograsp.robots.patch_shapes`). A hull patch is kept only where its points lie within
the tolerance of the mesh itself and its normal within :data:`CAP_ANGLE` of the detected one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal, Protocol

import coal
import numpy as np

from ..core.serialize import jsonable
from ..core.validate import count
from .patch_shapes import (
    MESH_FLATNESS,
    MESH_LINE_ASPECT,
    MESH_LINE_LENGTH,
    MeshTouch,
    generator,
    is_mesh,
    mesh_touch,
    midline,
    on_surface,
    parallel_sides,
    samples,
    solid_of,
    top_strip,
)

if TYPE_CHECKING:
    from .kinematics import HandConfiguration
    from .objects import RigidObject

#: Default largest number of points of a face patch (a line always gives 2, a point 1).
DEFAULT_PATCH_POINTS = 4
#: Largest accepted ``patch_points`` (each point is a contact with its own friction cone).
MAX_PATCH_POINTS = 16
#: Patch points closer than this [m] are one point; a patch this thin is a line.
MERGE_DISTANCE = 1e-6
#: Resolution [m] of the coordinates (hand geometry frame) that break ties and order the points.
ORDER_RESOLUTION = 1e-9
#: A cylinder or cone touches with its flat cap when the normal is within this angle [rad] of
#: its axis (cos 0.99, about 8.1 deg); otherwise it touches with its curved side.
CAP_ANGLE = float(np.arccos(0.99))

#: Points Coal samples on a curved edge (a cylinder cap's rim) before the reduction.
CURVED_SAMPLES = 12


class TouchingPair(Protocol):
    """What a patch needs of a detected contact (:class:`~pinograsp.robots.collision.PairDistance`)."""

    @property
    def link(self) -> str: ...
    @property
    def geometry(self) -> str: ...
    @property
    def index(self) -> int: ...
    @property
    def normal(self) -> np.ndarray: ...
    @property
    def point(self) -> np.ndarray: ...


PatchKind = Literal["point", "line", "face"]
_ROUND = ("Sphere", "Ellipsoid")
_AXIAL = ("Cylinder", "Cone", "Capsule")
TouchShape = Literal["curved", "straight", "flat"]


@dataclass(frozen=True)
class ContactPatch:
    """The contact points of one touching hand geometry.

    Attributes:
        link: Hand link carrying the geometry.
        geometry: Name of the collision geometry.
        kind: ``"point"`` (one point), ``"line"`` (two end points) or ``"face"`` (polygon vertices).
        points: Contact points, base frame [m], (k, 3), in canonical order.
        normal: Unit normal from the hand into the object, shared by the points, (3,).
        names: Contact name of each point, (k,): the link name for a single point,
            ``<link>#<i>`` for a patch (``<geometry>#<i>`` when the link has several touching
            geometries).
    """

    link: str
    geometry: str
    kind: PatchKind
    points: np.ndarray
    normal: np.ndarray
    names: tuple[str, ...]

    @property
    def size(self) -> int:
        """Number of contact points of the patch."""
        return len(self.points)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-ready data: names, ``kind``, ``points`` (k × 3 lists) [m], ``normal``."""
        return jsonable(
            {
                "link": self.link,
                "geometry": self.geometry,
                "kind": self.kind,
                "points": self.points,
                "normal": self.normal,
                "names": list(self.names),
            }
        )


def patch_points_option(value: object) -> int:
    """Validated ``patch_points``: an integer in ``[2, MAX_PATCH_POINTS]``."""
    return count("patch_points", value, MAX_PATCH_POINTS, minimum=2, what="points per face patch")


def _to_matrix(T: coal.Transform3s) -> tuple[np.ndarray, np.ndarray]:
    return np.array(T.getRotation(), dtype=float), np.array(T.getTranslation(), dtype=float)


def touch_shape(geometry: coal.CollisionGeometry, T: coal.Transform3s, normal: np.ndarray) -> TouchShape:
    """How ``geometry`` at pose ``T`` touches along ``normal``: ``"curved"`` (a sphere, an
    ellipsoid, a capsule's round end), ``"straight"`` (the side of a cylinder, cone or capsule:
    straight along a generator, the normal more than :data:`CAP_ANGLE` from the axis) or
    ``"flat"`` (everything else: faces, edges, a cylinder or cone cap, meshes)."""
    kind = type(geometry).__name__
    if kind in _ROUND:
        return "curved"
    if kind in _AXIAL:
        axis = _to_matrix(T)[0][:, 2]
        if abs(float(axis @ normal)) < np.cos(CAP_ANGLE):
            return "straight"
        return "curved" if kind == "Capsule" else "flat"
    return "flat"


def is_curved(geometry: coal.CollisionGeometry, T: coal.Transform3s, normal: np.ndarray) -> bool:
    """Whether ``geometry`` at pose ``T`` touches along ``normal`` with a curved surface, a
    straight side included (:func:`touch_shape` is not ``"flat"``)."""
    return touch_shape(geometry, T, normal) != "flat"


def coal_patch(
    g1: coal.CollisionGeometry,
    T1: coal.Transform3s,
    g2: coal.CollisionGeometry,
    T2: coal.Transform3s,
    tolerance: float,
    patch_tolerance: float | None = None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """Coal's contact patch of two shapes within ``tolerance`` [m]: points (k, 3) [m] in the
    contact plane and the normal from ``g1`` into ``g2`` (3,); ``None`` if Coal finds none.
    ``patch_tolerance`` [m] (default ``tolerance``): how far from the contact plane a feature
    still belongs to the patch."""
    tol = max(float(tolerance), MERGE_DISTANCE)
    req = coal.CollisionRequest()
    req.security_margin = tol
    req.num_max_contacts = 1
    res = coal.CollisionResult()
    coal.collide(g1, T1, g2, T2, req, res)
    if res.numContacts() == 0:
        return None
    ptol = tol if patch_tolerance is None else max(float(patch_tolerance), MERGE_DISTANCE)
    preq = coal.ContactPatchRequest(1, CURVED_SAMPLES, ptol)
    pres = coal.ContactPatchResult(preq)
    coal.computeContactPatch(g1, T1, g2, T2, res, preq, pres)
    if pres.numContactPatches() == 0:
        return None
    patch = pres.getContactPatch(0)
    if patch.size() == 0:
        return None
    points = np.array([patch.getPoint(i) for i in range(patch.size())], dtype=float).reshape(-1, 3)
    normal = np.array(patch.getNormal(), dtype=float)
    norm = np.linalg.norm(normal)
    if not np.all(np.isfinite(points)) or not norm > 0.5:
        return None
    return points, normal / norm


def _keys(local: np.ndarray) -> list[tuple[int, ...]]:
    """Rounded local coordinates (hand geometry frame) of each point: the canonical tie-breaks."""
    return [tuple(int(v) for v in np.round(p / ORDER_RESOLUTION)) for p in local]


def select_points(points: np.ndarray, local: np.ndarray, max_points: int) -> tuple[PatchKind, np.ndarray]:
    """Reduce a patch polygon to its representative points.

    Args:
        points: Patch vertices, base frame [m], (m, 3).
        local: The same vertices in the hand geometry's frame [m], (m, 3) (canonical order).
        max_points: Largest number of points of a face (>= 2).

    Returns:
        The kind and the indices of the chosen vertices, in canonical order (sorted by ``local``).
    """
    keys = _keys(local)
    order = sorted(range(len(points)), key=lambda i: keys[i])
    kept: list[int] = []
    for i in order:  # merge duplicates, keeping the canonically first one
        if all(np.linalg.norm(points[i] - points[j]) > MERGE_DISTANCE for j in kept):
            kept.append(i)
    if len(kept) == 1:
        return "point", np.array(kept)
    centroid = points[kept].mean(axis=0)

    def farthest(score: dict[int, float]) -> int:
        best = max(round(s / ORDER_RESOLUTION) for s in score.values())
        return min(
            (i for i, s in score.items() if round(s / ORDER_RESOLUTION) == best), key=lambda i: keys[i]
        )

    first = farthest({i: float(np.linalg.norm(points[i] - centroid)) for i in kept})
    second = farthest({i: float(np.linalg.norm(points[i] - points[first])) for i in kept})
    chosen = [first, second]
    axis = (points[second] - points[first]) / np.linalg.norm(points[second] - points[first])
    off = points[kept] - points[first]
    off_line = off - np.outer(off @ axis, axis)
    if np.max(np.linalg.norm(off_line, axis=1)) <= MERGE_DISTANCE:
        # a line: the vertex farthest from the centroid is an end, the one farthest from it the other
        return "line", np.array(sorted(chosen, key=lambda i: keys[i]))
    while len(chosen) < min(max_points, len(kept)):
        rest = {
            i: min(float(np.linalg.norm(points[i] - points[j])) for j in chosen)
            for i in kept
            if i not in chosen
        }
        chosen.append(farthest(rest))
    return "face", np.array(sorted(chosen, key=lambda i: keys[i]))


def pair_patch(
    g1: coal.CollisionGeometry,
    T1: coal.Transform3s,
    g2: coal.CollisionGeometry,
    T2: coal.Transform3s,
    tolerance: float,
    max_points: int,
    detected: np.ndarray | None = None,
) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """The patch of hand geometry ``g1`` at ``T1`` on object ``g2`` at ``T2`` (world frame).

    Args:
        detected: The detected contact normal (3,): a patch found on a triangle mesh's hull
            must agree with it within :data:`CAP_ANGLE`.

    Returns:
        ``(kind, points (k, 3) [m], normal (3,))`` with the points in canonical order, or
        ``None`` when the touch is a single point (curved, a corner, a tessellated curve, a
        hull facet off the mesh, or no Coal patch): the caller keeps its closest-point contact.
    """
    pair = _Pair(g1, T1, g2, T2, tolerance, detected)
    meshes = is_mesh(g1) or is_mesh(g2)
    if meshes and detected is not None:
        touch = _mesh_pair(pair, detected)
        if touch != "flat":  # a tessellated curve (no Coal patch needed), or maybe a straight side
            return None if touch == "curved" else _mesh_line(pair)
    found = coal_patch(solid_of(g1), T1, solid_of(g2), T2, tolerance)
    if found is None:
        return None
    points, normal = found
    shapes = (touch_shape(g1, T1, normal), touch_shape(g2, T2, normal))
    if "curved" in shapes:
        return None
    if shapes == ("straight", "straight"):  # Coal gives one point: the line of parallel sides
        return _sides_line(pair, points.mean(axis=0), normal)
    if meshes:
        touch = _mesh_pair(pair, normal)
        if touch != "flat":
            return None if touch == "curved" else _mesh_line(pair)
    R, t = _to_matrix(T1)
    kind, idx = select_points(points, (points - t) @ R, max_points)
    if kind == "point" or ("straight" in shapes and kind != "line"):
        return None  # a straight side touches along a generator or at a point, never a face
    points = points[idx]
    if meshes and float(np.max(np.linalg.norm(points[:, None] - points[None], axis=2))) < tolerance:
        return None  # a mesh patch narrower than the tolerance: a facet of a tessellated curve
    return (kind, points, normal) if pair.on_meshes(points, normal) else None


@dataclass(frozen=True)
class _Pair:
    """A touching pair: hand geometry ``g1`` at ``T1`` on object ``g2`` at ``T2`` (world
    frame), the patch ``tolerance`` [m] and the detected contact normal (3,) or None."""

    g1: coal.CollisionGeometry
    T1: coal.Transform3s
    g2: coal.CollisionGeometry
    T2: coal.Transform3s
    tolerance: float
    detected: np.ndarray | None

    def on_meshes(self, points: np.ndarray, normal: np.ndarray) -> bool:
        """Whether every triangle mesh of the pair has ``points`` (k, 3) [m] on it
        (:func:`_on_mesh`)."""
        return all(
            not type(g).__name__.startswith("BVH")
            or _on_mesh(g, T, points, normal, self.tolerance, self.detected)
            for g, T in ((self.g1, self.T1), (self.g2, self.T2))
        )


def _mesh_pair(pair: _Pair, normal: np.ndarray) -> MeshTouch:
    """How the pair touches along ``normal`` (``g1`` into ``g2``), by :func:`mesh_touch` of its
    meshes: ``"curved"`` if one is; ``"flat"`` if each is flat; ``"long"`` if one is long and
    the other flat (a flat mesh, or a primitive whose :func:`touch_shape` is ``"flat"``: a
    straight side on a flat face) or a primitive's straight side (two straight sides); else
    ``"curved"`` (one point)."""
    ends = ((pair.g1, pair.T1), (pair.g2, pair.T2))
    touches: list[str | None] = []
    for (g, T), d in zip(ends, (normal, -normal)):
        touches.append(mesh_touch(g, T, d, pair.tolerance) if is_mesh(g) else None)
        if touches[-1] == "curved":  # the other mesh need not be measured
            return "curved"
    if "long" not in touches:
        return "flat"
    partner = [t if t is not None else touch_shape(g, T, normal) for t, (g, T) in zip(touches, ends)]
    return "long" if sorted(partner) in (["flat", "long"], ["long", "straight"]) else "curved"


def _line(
    ends: np.ndarray, normal: np.ndarray, T1: coal.Transform3s
) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """A line patch of two end points (2, 3) [m] in canonical order; ``None`` if they coincide."""
    R, t = _to_matrix(T1)
    kind, idx = select_points(ends, (ends - t) @ R, 2)
    return ("line", ends[idx], normal) if kind == "line" else None


def _sides_line(
    pair: _Pair, point: np.ndarray, normal: np.ndarray
) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """The line of two straight sides touching at ``point`` (3,) [m] with parallel generators
    (:func:`~pinograsp.robots.patch_shapes.parallel_sides`), or ``None`` (crossing: a point)."""
    sides = (generator(pair.g1, *_to_matrix(pair.T1), point), generator(pair.g2, *_to_matrix(pair.T2), point))
    ends = parallel_sides(sides, point, normal, pair.tolerance)
    return None if ends is None else _line(ends, normal, pair.T1)


def _mesh_line(pair: _Pair) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """The line of a mesh pair with a long top set (a tessellated straight side): along a
    primitive's straight side :func:`_strip_on_side`; else the middle line of Coal's patch of
    the features within ``MESH_FLATNESS * tolerance`` of the plane, at least
    ``MESH_LINE_LENGTH`` tolerances and ``MESH_LINE_ASPECT`` times its width long, on the mesh
    (:func:`_checked_line`); otherwise ``None`` (one point)."""
    g1, T1, g2, T2, tolerance = pair.g1, pair.T1, pair.g2, pair.T2, pair.tolerance
    found = coal_patch(solid_of(g1), T1, solid_of(g2), T2, tolerance, MESH_FLATNESS * tolerance)
    if found is None:
        return None
    points, normal = found
    shapes = (touch_shape(g1, T1, normal), touch_shape(g2, T2, normal))
    if "curved" in shapes:
        return None
    if "straight" in shapes:  # a mesh's straight side on a primitive's: two straight sides
        return _strip_on_side(pair, points.mean(axis=0), normal)
    if _mesh_pair(pair, normal) == "curved":
        return None
    ends, length, width = midline(points, normal)
    if length < MESH_LINE_LENGTH * tolerance or MESH_LINE_ASPECT * width > length:
        return None
    return _checked_line(pair, ends, normal)


def _checked_line(
    pair: _Pair, ends: np.ndarray, normal: np.ndarray
) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """The line ``ends`` (2, 3) [m] if each triangle mesh is within the tolerance along it."""
    return _line(ends, normal, pair.T1) if pair.on_meshes(samples(ends), normal) else None


def _strip_on_side(
    pair: _Pair, point: np.ndarray, normal: np.ndarray
) -> tuple[PatchKind, np.ndarray, np.ndarray] | None:
    """The line of a mesh's long top strip on a primitive's straight side through ``point``
    (3,) [m] as two parallel sides, at least :data:`MESH_LINE_LENGTH` tolerances long and on the
    mesh (:func:`_checked_line`); otherwise ``None`` (one point)."""
    tolerance = pair.tolerance
    sides = tuple(
        top_strip(g, T, d, tolerance) if is_mesh(g) else generator(g, *_to_matrix(T), point)
        for g, T, d in ((pair.g1, pair.T1, normal), (pair.g2, pair.T2, -normal))
    )
    ends = parallel_sides((sides[0], sides[1]), point, normal, tolerance)
    if ends is None or float(np.linalg.norm(ends[1] - ends[0])) < MESH_LINE_LENGTH * tolerance:
        return None
    return _checked_line(pair, ends, normal)


def _on_mesh(
    g: coal.CollisionGeometry,
    T: coal.Transform3s,
    points: np.ndarray,
    normal: np.ndarray,
    tolerance: float,
    detected: np.ndarray | None,
) -> bool:
    """Whether a patch found on the hull of triangle mesh ``g`` is on the mesh: its normal
    within :data:`CAP_ANGLE` of the detected one and its points within ``tolerance`` of it."""
    if detected is not None and float(normal @ detected) < np.cos(CAP_ANGLE):
        return False
    return on_surface(g, T, points, tolerance)


def contact_patches(
    config: HandConfiguration,
    obj: RigidObject,
    contacts: Sequence[TouchingPair],
    tolerance: float,
    max_points: int = DEFAULT_PATCH_POINTS,
) -> tuple[ContactPatch, ...]:
    """The patch of each detected contact (same order as ``contacts``).

    Args:
        config: The hand at its configuration.
        obj: The object.
        contacts: The touching geometry pairs (:attr:`ContactReport.contacts`).
        tolerance: Contact tolerance [m]: Coal's security margin and patch tolerance.
        max_points: Largest number of points of a face patch.
    """
    geometries = config.hand.geometry.geometryObjects
    per_link: dict[str, int] = {}
    for c in contacts:
        per_link[c.link] = per_link.get(c.link, 0) + 1
    out = []
    for c in contacts:
        oMg = config.geometry_data.oMg[c.index]
        T1 = coal.Transform3s(oMg.rotation, oMg.translation)
        found = pair_patch(
            geometries[c.index].geometry, T1, obj.geometry, obj.transform, tolerance, max_points, c.normal
        )
        if found is None:
            out.append(ContactPatch(c.link, c.geometry, "point", c.point[None, :], c.normal, (c.link,)))
            continue
        kind, points, normal = found
        stem = c.link if per_link[c.link] == 1 else c.geometry
        names = tuple(f"{stem}#{i}" for i in range(len(points)))
        out.append(ContactPatch(c.link, c.geometry, kind, points, normal, names))
    return tuple(out)


def single_points(contacts: Sequence[TouchingPair]) -> tuple[ContactPatch, ...]:
    """One-point patches of the detected contacts (patches off): each closest-point contact."""
    return tuple(
        ContactPatch(c.link, c.geometry, "point", c.point[None, :], c.normal, (c.link,)) for c in contacts
    )
