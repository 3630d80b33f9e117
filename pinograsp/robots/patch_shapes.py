"""The shapes of a touch: mesh features, straight generators and lines (docs/hands.md, "Contact patches").

:mod:`pinograsp.robots.patches` turns a touch into Coal's contact patch. This module holds the
geometry it reads the touching shapes with: whether a mesh is flat, long or curved near the
contact (:func:`mesh_touch`, on the mesh's convex hull, :func:`solid_of`; :func:`on_surface`
checks points against the mesh itself), and the two line contacts that come out of Coal as a
single point:

1. **Two straight sides with parallel generators** (cylinder, cone or capsule sides: a cylinder
   on a cylinder, a capsule finger along a cylindrical object). The line runs through the closest
   pair's midpoint along the two generators' mean direction (in the contact plane), over the
   overlap of the two generators projected on it. It is a line only while the gap stays within
   the tolerance over that overlap: the generators' angle, and each generator's slope out of the
   contact plane, times the overlap length, at most the tolerance. Crossing sides stay a point.
2. **A tessellated straight side** (a cylinder exported as a mesh) on a flat face: the mesh is
   not flat near the contact (its facets bend away across the generator), yet its top vertices
   lie along a line. :func:`midline` reduces the patch of those top features to its middle line;
   :mod:`~pinograsp.robots.patches` keeps it when the mesh's top vertices span a good part of
   the mesh (:data:`MESH_LINE_FRACTION`), the line is long (:data:`MESH_LINE_LENGTH` times the
   tolerance) and narrow (:data:`MESH_LINE_ASPECT`), and the real mesh lies within the tolerance
   of :data:`LINE_SAMPLES` points along it.
3. **A tessellated straight side on a straight side** (a mesh finger whose side is straight
   along a cylindrical object): the mesh's top strip (:func:`top_strip`) and the primitive's
   generator are two straight sides, joined as in 1 (:func:`parallel_sides`), with the mesh
   checked along the line as in 2.

Base frame unless said; the only Coal calls are the hull's construction and point distances.
"""

from __future__ import annotations

from typing import Literal

import coal
import numpy as np

#: Mesh patches: a mesh's vertices within the contact tolerance of the contact plane are a flat
#: feature when they lie within this fraction of the tolerance of one plane (0.1 mm at 1 mm).
MESH_FLATNESS = 0.1

#: A mesh line is at least this many contact tolerances long (10 mm at the default 1 mm); a
#: shorter one is a facet edge of a tessellated curve (one point).
MESH_LINE_LENGTH = 10.0
#: A mesh's top set (its vertices within the flatness of the contact plane) spans at least this
#: fraction of the mesh's largest extent to be a straight side: a tessellated curve (a torus,
#: a rounded finger) bends away after one facet, a small fraction of its size.
MESH_LINE_FRACTION = 0.25
#: A mesh line is at least this many times longer than it is wide (the width of the features
#: within the flatness of the contact plane, e.g. a cylinder mesh's facet under a flat pad).
MESH_LINE_ASPECT = 4.0
#: Points along a mesh line (its ends included) that must lie within the tolerance of the mesh.
LINE_SAMPLES = 9
#: Straight sides and the radius of the end of their generator nearest the apex, per unit radius
#: (a cone narrows to its apex at +z; a cylinder's and a capsule's straight part do not).
_TOP_RADIUS = {"Cylinder": 1.0, "Capsule": 1.0, "Cone": 0.0}
#: How a mesh touches along a direction: a flat feature, a long top set (maybe a straight side),
#: or a tessellated curve (:func:`mesh_touch`).
MeshTouch = Literal["flat", "long", "curved"]

#: A point on a triangle mesh's surface, for the check that a hull patch lies on the mesh.
_PROBE = coal.Sphere(1e-12)


def is_mesh(geometry: coal.CollisionGeometry) -> bool:
    """Whether a Coal geometry is a mesh: a triangle mesh (BVH) or a convex mesh."""
    name = type(geometry).__name__
    return name.startswith("BVH") or name.startswith("Convex")


def solid_of(geometry: coal.CollisionGeometry) -> coal.CollisionGeometry:
    """The geometry Coal's patch code is given: a triangle mesh's convex hull (built once and
    kept on the mesh), any other geometry itself."""
    if not type(geometry).__name__.startswith("BVH"):
        return geometry
    if geometry.convex is None:
        geometry.buildConvexHull(False, "Qt")
    return geometry.convex


def on_surface(
    geometry: coal.CollisionGeometry, T: coal.Transform3s, points: np.ndarray, tolerance: float
) -> bool:
    """Whether every point (k, 3) [m] lies within ``tolerance`` [m] of a triangle mesh's surface."""
    req, R = coal.DistanceRequest(), np.eye(3)
    for p in points:
        res = coal.DistanceResult()
        if coal.distance(_PROBE, coal.Transform3s(R, p), geometry, T, req, res) > tolerance:
            return False
    return True


def _hull_vertices(geometry: coal.CollisionGeometry) -> np.ndarray:
    """The vertices (m, 3) [m] of a mesh's hull (:func:`solid_of`) in its own frame."""
    return np.asarray(solid_of(geometry).points(), dtype=float).reshape(-1, 3)


def mesh_touch(
    geometry: coal.CollisionGeometry, T: coal.Transform3s, direction: np.ndarray, tolerance: float
) -> MeshTouch:
    """How a mesh touches along ``direction`` (3,) (out of it, towards the other shape).

    ``"flat"``: its hull vertices within ``tolerance`` [m] of its support plane lie within
    ``MESH_FLATNESS * tolerance`` of one plane (three or fewer always do). Otherwise ``"long"``
    when its top vertices (within ``MESH_FLATNESS * tolerance`` of the support plane) lie along
    a strip at least ``MESH_LINE_LENGTH * tolerance`` and ``MESH_LINE_FRACTION`` of the hull's
    largest extent long and ``MESH_LINE_ASPECT`` times longer than wide (a tessellated straight
    side), else ``"curved"`` (a vertex or facet of a tessellated curve, a flat ring of vertices
    such as a torus's top, a wide face whose neighbours bend within the tolerance).
    """
    vertices = _hull_vertices(geometry)
    depth = vertices @ (np.array(T.getRotation(), dtype=float).T @ direction)
    band = vertices[depth >= depth.max() - tolerance]
    if len(band) <= 3:
        return "flat"
    centred = band - band.mean(axis=0)
    normal = np.linalg.svd(centred, full_matrices=False)[2][2]
    if float(np.max(np.abs(centred @ normal))) <= MESH_FLATNESS * tolerance:
        return "flat"
    span, width = principal_extents(vertices[depth >= depth.max() - MESH_FLATNESS * tolerance])
    if span < MESH_LINE_LENGTH * tolerance or MESH_LINE_ASPECT * width > span:
        return "curved"  # one facet of a curve, or not along a line (a flat ring, a wide face)
    size = float(np.max(vertices.max(axis=0) - vertices.min(axis=0)))
    return "long" if span >= MESH_LINE_FRACTION * size else "curved"


def top_strip(
    geometry: coal.CollisionGeometry, T: coal.Transform3s, direction: np.ndarray, tolerance: float
) -> np.ndarray:
    """The ends (2, 3) [m] of a mesh's top strip along ``direction`` (3,) (out of it): its hull
    vertices within ``MESH_FLATNESS * tolerance`` of the support plane, spanned along their
    first principal direction (a straight side's tessellated generator; base frame)."""
    R, t = np.array(T.getRotation(), dtype=float), np.array(T.getTranslation(), dtype=float)
    vertices = _hull_vertices(geometry) @ R.T + t
    depth = vertices @ direction
    top = vertices[depth >= depth.max() - MESH_FLATNESS * tolerance]
    centre = top.mean(axis=0)
    if len(top) < 2:
        return np.array([centre, centre])
    axis = np.linalg.svd(top - centre, full_matrices=False)[2][0]
    s = (top - centre) @ axis
    return np.array([centre + s.min() * axis, centre + s.max() * axis])


def generator(
    geometry: coal.CollisionGeometry, R: np.ndarray, t: np.ndarray, point: np.ndarray
) -> np.ndarray:
    """The straight generator of a cylinder, cone or capsule side under ``point`` (3,) [m]: its
    two ends (2, 3) [m], bottom (local z = -half length) then top, at the azimuth of ``point``
    about the axis (a capsule: its straight part, between the round ends).

    Args:
        geometry: A ``coal.Cylinder``, ``coal.Cone`` or ``coal.Capsule``.
        R: Its rotation (3, 3); ``t``: its position (3,) [m] (base frame).
        point: A point near its side [m] (base frame), e.g. the contact point.
    """
    local = R.T @ (np.asarray(point, dtype=float) - t)
    radial = np.array([local[0], local[1], 0.0])
    norm = float(np.linalg.norm(radial))
    e = radial / norm if norm > 0.0 else np.array([1.0, 0.0, 0.0])
    r, h = float(geometry.radius), float(geometry.halfLength)
    top = _TOP_RADIUS[type(geometry).__name__]
    ends = np.array([r * e - [0.0, 0.0, h], top * r * e + [0.0, 0.0, h]])
    return ends @ R.T + t


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def parallel_sides(
    sides: tuple[np.ndarray, np.ndarray], point: np.ndarray, normal: np.ndarray, tolerance: float
) -> np.ndarray | None:
    """The line contact of two straight sides, or ``None`` when they touch at a point.

    Args:
        sides: The two generators under the contact, each (2, 3) [m] (:func:`generator`).
        point: The closest pair's midpoint (3,) [m], in the contact plane.
        normal: The contact normal (3,), unit.
        tolerance: Contact tolerance [m]: the largest gap along the line.

    Returns:
        The line's two end points (2, 3) [m] in the contact plane (unordered), or ``None`` when
        the generators cross or leave the contact plane by more than ``tolerance`` over their
        overlap, when the overlap is a point, or when ``point`` is off the overlap (a rim).
    """
    d1, d2 = (_unit(s[1] - s[0]) for s in sides)
    mean = d1 + (1.0 if float(d1 @ d2) >= 0.0 else -1.0) * d2
    axis = mean - (mean @ normal) * normal
    if not np.linalg.norm(axis) > 0.0:
        return None
    axis = _unit(axis)
    spans = [np.sort((s - point) @ axis) for s in sides]
    lo, hi = max(s[0] for s in spans), min(s[1] for s in spans)
    length = hi - lo
    if not length > 0.0 or lo > tolerance or hi < -tolerance:
        return None
    slope = max(float(np.linalg.norm(np.cross(d1, d2))), abs(float(d1 @ normal)), abs(float(d2 @ normal)))
    if slope * length > tolerance:
        return None
    return np.array([point + lo * axis, point + hi * axis])


def midline(points: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, float, float]:
    """The middle line of a patch polygon along its longest principal direction.

    Args:
        points: Patch vertices (k, 3) [m], in the contact plane.
        normal: The contact normal (3,), unit.

    Returns:
        ``(ends (2, 3) [m], length [m], width [m])``: the ends of the bounding rectangle's middle
        line along the principal direction (in the contact plane), its length and the rectangle's
        width across it (0 for a line, both 0 for one point).
    """
    centre = points.mean(axis=0)
    flat = (points - centre) - np.outer((points - centre) @ normal, normal)
    if len(points) < 2 or not np.max(np.linalg.norm(flat, axis=1)) > 0.0:
        return np.array([centre, centre]), 0.0, 0.0
    axis = np.linalg.svd(flat, full_matrices=False)[2][0]
    axis = _unit(axis - (axis @ normal) * normal)
    across = np.cross(normal, axis)
    s, w = flat @ axis, flat @ across
    mid = centre + 0.5 * (w.max() + w.min()) * across
    ends = np.array([mid + s.min() * axis, mid + s.max() * axis])
    return ends, float(s.max() - s.min()), float(w.max() - w.min())


def samples(ends: np.ndarray, n: int = LINE_SAMPLES) -> np.ndarray:
    """``n`` evenly spaced points (n, 3) [m] from ``ends[0]`` to ``ends[1]``, both included."""
    return ends[0] + np.linspace(0.0, 1.0, n)[:, None] * (ends[1] - ends[0])


def principal_extents(points: np.ndarray) -> tuple[float, float]:
    """Extents [m] of points (k, 3) along their first and second principal directions (the
    length and the width of a strip; 0 for fewer points than directions)."""
    if len(points) < 2:
        return 0.0, 0.0
    centred = points - points.mean(axis=0)
    axes = np.linalg.svd(centred, full_matrices=False)[2]
    s = centred @ axes[:2].T
    width = float(np.ptp(s[:, 1])) if len(axes) > 1 else 0.0
    return float(np.ptp(s[:, 0])), width
