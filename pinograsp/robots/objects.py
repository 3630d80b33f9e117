"""Rigid objects to grasp: Coal collision geometry, pose in the hand base frame, centre of mass.

Poses are given in the **hand base frame** (the world frame of docs/design.md) as a 4×4 homogeneous
matrix or a ``pinocchio.SE3``. Lengths in metres. The object's centre of mass is the default
wrench reference point ``o`` of a grasp built from a scene.

Geometry kinds:

* primitives (:meth:`RigidObject.box`, :meth:`RigidObject.cylinder`, :meth:`RigidObject.sphere`):
  exact solids; signed distances (penetration depths) are exact.
* convex meshes (:meth:`RigidObject.from_mesh` on a convex file, or ``convex=True``): a Coal
  ``Convex`` hull, a solid with signed distances.
* non-convex meshes: a Coal ``BVHModelOBBRSS`` — a **surface, not a solid**. Coal measures the
  distance to the nearest triangle, so a hand link that lies entirely inside the mesh is *not*
  seen as penetrating, and penetration depths are only meaningful while they are shallower than
  the local wall thickness. Keep hands outside such objects (auto-close does), or pass
  ``convex=True`` to use the hull.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import coal
import numpy as np

from ..core.validate import coordinates, positive_number
from ..core.validate import size as check_size
from ..errors import InvalidInputError, ModelFileError

#: Tolerance on the orthonormality of a pose's rotation block.
ROTATION_TOL = 1e-6


def pose_matrix(pose: object, name: str = "pose") -> np.ndarray:
    """Validate a pose and return it as a 4×4 homogeneous matrix.

    Args:
        pose: ``None`` (identity), a 4×4 array, a 3-vector (pure translation [m]) or a
            ``pinocchio.SE3``.
        name: Argument name used in error messages.

    Raises:
        InvalidInputError: Wrong shape, non-finite entries or a non-rotation block.
    """
    if pose is None:
        return np.eye(4)
    if hasattr(pose, "homogeneous"):  # pinocchio.SE3
        return np.array(pose.homogeneous, dtype=float)
    if isinstance(pose, (str, bytes)):
        raise InvalidInputError(name, f"expected a 4x4 matrix or a pinocchio.SE3, got {pose!r}")
    try:
        arr = np.asarray(pose, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected a 4x4 matrix or a pinocchio.SE3, got {pose!r}") from exc
    if arr.shape == (3,):
        out = np.eye(4)
        out[:3, 3] = arr
        arr = out
    if arr.shape != (4, 4):
        raise InvalidInputError(name, f"expected a 4x4 homogeneous matrix, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InvalidInputError(name, "contains NaN or inf")
    rot = arr[:3, :3]
    if np.abs(rot.T @ rot - np.eye(3)).max() > ROTATION_TOL or np.linalg.det(rot) < 0:
        raise InvalidInputError(name, "the upper-left 3x3 block is not a rotation matrix")
    if np.abs(arr[3] - [0.0, 0.0, 0.0, 1.0]).max() > 0:
        raise InvalidInputError(name, "the last row must be (0, 0, 0, 1)")
    coordinates(f"{name} translation", arr[:3, 3], "m")  # domain: docs/errors.md
    return arr.copy()


def coal_transform(T: np.ndarray) -> coal.Transform3s:
    """Coal transform of a 4×4 homogeneous matrix."""
    out = coal.Transform3s()
    out.setRotation(np.ascontiguousarray(T[:3, :3]))
    out.setTranslation(np.ascontiguousarray(T[:3, 3]))
    return out


def _vector3(name: str, value: object) -> np.ndarray:
    """Three numbers (not necessarily finite) or :class:`InvalidInputError`."""
    if isinstance(value, (str, bytes)):
        raise InvalidInputError(name, f"expected 3 numbers, got {value!r}")
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(name, f"expected 3 numbers, got {value!r}") from exc
    if arr.shape != (3,):
        raise InvalidInputError(name, f"expected 3 numbers, got {value!r}")
    return arr


def _vertices(points: np.ndarray) -> coal.StdVec_Vec3s:
    out = coal.StdVec_Vec3s()
    out.extend([np.array(p, dtype=float) for p in points])
    return out


#: Largest object mesh file [bytes] and its most triangles (a BVH of 1e6 triangles builds in
#: seconds; each distance query walks it).
MAX_MESH_BYTES = 256 * 2**20
MAX_MESH_TRIANGLES = 1_000_000
#: What a mesh file must be (the end of :class:`ModelFileError` messages of :meth:`RigidObject.from_mesh`).
MESH_FORMATS_HINT = (
    "give a triangle mesh file trimesh reads (STL, OBJ, PLY, OFF or GLB), in metres or with scale="
)


@dataclass(frozen=True, eq=False)
class RigidObject:
    """A rigid object placed in the hand base frame.

    Attributes:
        geometry: Coal collision geometry, expressed in the object frame.
        pose: Object frame in the hand base frame, 4×4 homogeneous matrix [m].
        com_local: Centre of mass in the object frame [m], (3,).
        kind: ``"box"``, ``"cylinder"``, ``"sphere"``, ``"convex"`` or ``"mesh"`` (BVH surface).
        name: Label used in messages.
        dimensions: The primitive's parameters [m] (``size``, ``radius``, ``length``), or the
            mesh's file and bounding-box extents.
    """

    geometry: coal.CollisionGeometry
    pose: np.ndarray = field(default_factory=lambda: np.eye(4))
    com_local: np.ndarray = field(default_factory=lambda: np.zeros(3))
    kind: str = "convex"
    name: str = "object"
    dimensions: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        T = pose_matrix(self.pose)
        T.setflags(write=False)
        object.__setattr__(self, "pose", T)
        com = _vector3("com_local", self.com_local)
        if not np.all(np.isfinite(com)):
            raise InvalidInputError("com_local", f"expected 3 finite numbers, got {self.com_local!r}")
        com.setflags(write=False)
        object.__setattr__(self, "com_local", com)

    # ------------------------------------------------------------ constructors
    @classmethod
    def box(cls, size: object, pose: object = None, name: str = "box") -> RigidObject:
        """A solid box centred on its frame.

        Args:
            size: Full edge lengths ``(sx, sy, sz)`` [m] (a scalar gives a cube).
            pose: Box frame in the hand base frame (4×4 or ``pinocchio.SE3``).
            name: Label.
        """
        if isinstance(size, (str, bytes)):
            raise InvalidInputError("size", f"expected 3 edge lengths, got {size!r}")
        try:
            s = np.asarray(size, dtype=float)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError("size", f"expected 3 edge lengths, got {size!r}") from exc
        if s.ndim == 0:
            s = np.full(3, float(s))
        if s.shape != (3,):
            raise InvalidInputError("size", f"expected 3 edge lengths, got {size!r}")
        sx, sy, sz = (check_size(f"size[{i}]", v) for i, v in enumerate(s))
        return cls(coal.Box(sx, sy, sz), pose_matrix(pose), np.zeros(3), "box", name, {"size": (sx, sy, sz)})

    @classmethod
    def cylinder(
        cls, radius: float, length: float, pose: object = None, name: str = "cylinder"
    ) -> RigidObject:
        """A solid cylinder centred on its frame, axis along the frame's z.

        Args:
            radius: Radius [m].
            length: Length along the axis [m].
            pose: Cylinder frame in the hand base frame.
            name: Label.
        """
        r, h = check_size("radius", radius), check_size("length", length)
        return cls(
            coal.Cylinder(r, h), pose_matrix(pose), np.zeros(3), "cylinder", name, {"radius": r, "length": h}
        )

    @classmethod
    def sphere(cls, radius: float, pose: object = None, name: str = "sphere") -> RigidObject:
        """A solid sphere centred on its frame (``pose`` may be a 3-vector: the centre [m])."""
        r = check_size("radius", radius)
        return cls(coal.Sphere(r), pose_matrix(pose), np.zeros(3), "sphere", name, {"radius": r})

    @classmethod
    def from_mesh(
        cls,
        path: str | Path,
        pose: object = None,
        *,
        scale: float = 1.0,
        convex: bool | None = None,
        name: str | None = None,
    ) -> RigidObject:
        """An object from a mesh file (STL, OBJ, PLY, ... through trimesh).

        Args:
            path: Mesh file. Coordinates are in the object frame, in metres after ``scale``.
            pose: Object frame in the hand base frame.
            scale: Factor applied to the vertices (e.g. 1e-3 for a file in millimetres).
            convex: ``True``: use the convex hull (a solid). ``False``: a BVH surface.
                ``None`` (default): the hull if the mesh is convex, otherwise the BVH.
            name: Label (default: the file stem).

        The centre of mass is trimesh's volume centroid for a watertight mesh, otherwise the
        area-weighted surface centroid.

        Raises:
            ModelFileError: The file is missing, unreadable or has no triangles.
        """
        import trimesh  # local: only needed for meshes

        if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
            raise InvalidInputError("path", f"expected a mesh file path (str or os.PathLike), got {path!r}")
        p = Path(path)
        if not p.is_file():
            where = "is a directory" if p.is_dir() else "not found"
            looked = (
                ""
                if p.is_absolute()
                else (f" (looked for {p.resolve()}; a relative path is taken from the working directory)")
            )  # an absolute path was resolved by the caller (a scene or GRASPS file: its folder)
            raise ModelFileError(
                p, f"mesh file {where}{looked}: give the path of an existing STL, OBJ, PLY, OFF or GLB file"
            )
        if p.stat().st_size > MAX_MESH_BYTES:
            raise ModelFileError(p, f"{p.stat().st_size} bytes, more than a mesh may have (MAX_MESH_BYTES)")
        try:
            mesh = trimesh.load(str(p), force="mesh")
        except Exception as exc:  # trimesh raises many exception types for bad files (not quoted)
            raise ModelFileError(
                p, f"cannot read mesh ({type(exc).__name__}: {exc}); {MESH_FORMATS_HINT}"
            ) from exc
        if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
            raise ModelFileError(p, f"the file contains no triangle mesh; {MESH_FORMATS_HINT}")
        if len(mesh.faces) > MAX_MESH_TRIANGLES:
            raise ModelFileError(
                p,
                f"{len(mesh.faces)} triangles, more than {MAX_MESH_TRIANGLES}: decimate it",
            )
        s = positive_number("scale", scale)
        if s != 1.0:
            mesh.apply_scale(s)
        use_hull = bool(mesh.is_convex) if convex is None else bool(convex)
        if use_hull:
            hull = mesh if mesh.is_convex else mesh.convex_hull
            geom = coal.Convex.convexHull(_vertices(hull.vertices), False, None)
            com = hull.center_mass
            kind = "convex"
        else:
            geom = coal.BVHModelOBBRSS()
            geom.beginModel(len(mesh.faces), len(mesh.vertices))
            tris = coal.StdVec_Triangle()
            tris.extend([coal.Triangle(int(a), int(b), int(c)) for a, b, c in mesh.faces])
            geom.addSubModel(_vertices(mesh.vertices), tris)
            geom.endModel()
            com = (
                mesh.center_mass
                if mesh.is_watertight
                else mesh.triangles_center.T @ mesh.area_faces / mesh.area
            )
            kind = "mesh"
        dims = {"file": str(p), "extents": tuple(float(e) for e in mesh.extents)}
        return cls(geom, pose_matrix(pose), np.asarray(com, dtype=float), kind, name or p.stem, dims)

    # ------------------------------------------------------------ derived
    @property
    def is_solid(self) -> bool:
        """Whether signed distances inside the object are exact (False for a BVH surface)."""
        return self.kind != "mesh"

    @property
    def center_of_mass(self) -> np.ndarray:
        """Centre of mass in the hand base frame [m], (3,)."""
        return self.pose[:3, :3] @ self.com_local + self.pose[:3, 3]

    @property
    def transform(self) -> coal.Transform3s:
        """The pose as a Coal transform."""
        return coal_transform(self.pose)

    def with_pose(self, pose: object) -> RigidObject:
        """The same object at another pose."""
        return RigidObject(
            self.geometry, pose_matrix(pose), self.com_local, self.kind, self.name, dict(self.dimensions)
        )

    def moved(self, translation: object = (0.0, 0.0, 0.0), rotation: object = None) -> RigidObject:
        """The object displaced by a rigid motion in the hand base frame.

        Args:
            translation: Translation [m], (3,).
            rotation: 3×3 rotation applied about the base origin before translating (default none).
        """
        T = np.eye(4)
        if rotation is not None:
            try:
                R = np.asarray(rotation, dtype=float)
            except (TypeError, ValueError, OverflowError) as exc:
                raise InvalidInputError(
                    "rotation", f"expected a 3x3 rotation matrix, got {rotation!r}"
                ) from exc
            if R.shape != (3, 3):
                raise InvalidInputError("rotation", f"expected a 3x3 rotation matrix, got shape {R.shape}")
            T[:3, :3] = R
        T[:3, 3] = _vector3("translation", translation)
        return self.with_pose(pose_matrix(T, "rotation") @ self.pose)

    def __repr__(self) -> str:
        pos = np.round(self.pose[:3, 3], 6).tolist()
        return f"RigidObject({self.name!r}, kind={self.kind!r}, position={pos})"
