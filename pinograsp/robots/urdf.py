"""Loading a hand's URDF: Pinocchio model reduced to the hand joints, rebased on the base link.

:func:`load_urdf_hand` does, in order (``docs/hands.md``):

1. read the XML (links, ``<mimic>`` tags, ``<collision>`` counts, robot name);
2. build the Pinocchio model and collision geometry, refusing ``<collision>`` elements
   Pinocchio skipped (e.g. ``<capsule>``);
3. lock the joints that are not hand joints at the description's reference configuration
   (``pinocchio.buildReducedModel``);
4. move the base link to the origin (it becomes the world frame of every result);
5. keep the collision geometry that may touch objects (the description's ``contact_links``, or
   every link at or below the base link).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..core.paths import ALLOWED_PATHS_ENV, allowed_roots, escapes, inside
from ..errors import InvalidInputError, ModelError, ModelFileError, UnknownNameError, UrdfError
from .description import HandDescription, example_robot_data_dir
from .objects import MAX_MESH_TRIANGLES


@dataclass(frozen=True)
class Mimic:
    """A URDF ``<mimic>`` tag: ``q_follower = multiplier * q_leader + offset`` (URDF coordinates)."""

    follower: str
    leader: str
    multiplier: float = 1.0
    offset: float = 0.0


#: Most links of a hand URDF (a whole humanoid has ~100; each link is loaded by Pinocchio).
MAX_LINKS = 2000


@dataclass(frozen=True)
class UrdfXml:
    """What pinograsp reads from the URDF's XML itself.

    Attributes:
        robot_name: The ``<robot name=...>`` attribute (``None`` if absent).
        links: Link names in file order.
        mimics: The ``<mimic>`` tags.
        collisions: Number of ``<collision>`` elements per link.
        parents: Parent link of each child link, over every joint (fixed ones included).
        meshes: The ``filename`` of every collision ``<mesh>``, as written.
    """

    robot_name: str | None
    links: tuple[str, ...]
    mimics: tuple[Mimic, ...]
    collisions: dict[str, int]
    parents: dict[str, str] = field(default_factory=dict)
    meshes: tuple[str, ...] = ()

    def at_or_below(self, base: str) -> set[str]:
        """The link ``base`` and every link below it in the URDF tree, through every joint
        (moving, fixed or locked by the description)."""
        children: dict[str, list[str]] = {}
        for child, parent in self.parents.items():
            children.setdefault(parent, []).append(child)
        out, todo = {base}, [base]
        while todo:
            for c in children.get(todo.pop(), ()):
                if c not in out:
                    out.add(c)
                    todo.append(c)
        return out


@dataclass(frozen=True)
class UrdfHand:
    """A loaded hand URDF, ready for :class:`~pinograsp.robots.hand.Hand`.

    Attributes:
        model: Pinocchio model of the hand joints; its world frame is the base link.
        geometry: Collision geometry that may touch objects.
        mimics: Mimic tags between hand joints.
        xml: What the XML says (link names, robot name).
    """

    model: pin.Model
    geometry: pin.GeometryModel
    mimics: tuple[Mimic, ...]
    xml: UrdfXml


def parse_urdf_xml(path: Path) -> UrdfXml:
    """Read link names, mimic tags, collision counts and the robot name, XML errors per file.

    Raises:
        UrdfError: Malformed XML, a root other than ``<robot>``, an unnamed joint, a bad ``<mimic>``.
    """
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise UrdfError(path, f"malformed XML: {exc}") from exc
    if root.tag != "robot":
        raise UrdfError(path, f"root element is <{root.tag}>, expected <robot>")
    mimics = []
    parents: dict[str, str] = {}
    for jt in root.findall("joint"):
        name = jt.get("name")
        if not name:
            raise UrdfError(path, "a <joint> has no name")
        parent, child = jt.find("parent"), jt.find("child")
        if parent is not None and child is not None and parent.get("link") and child.get("link"):
            parents[str(child.get("link"))] = str(parent.get("link"))
        m = jt.find("mimic")
        if m is None:
            continue
        if not m.get("joint"):
            raise UrdfError(path, f"<mimic> of joint {name!r} has no 'joint' attribute")
        try:
            mimics.append(
                Mimic(name, m.get("joint", ""), float(m.get("multiplier", 1.0)), float(m.get("offset", 0.0)))
            )
        except ValueError as exc:
            raise UrdfError(path, f"<mimic> of joint {name!r}: {exc}") from exc
    links = root.findall("link")
    if len(links) > MAX_LINKS:
        raise UrdfError(path, f"{len(links)} links, more than the {MAX_LINKS} a hand may have (MAX_LINKS)")
    meshes = tuple(str(m.get("filename", "")) for m in root.iterfind("link/collision/geometry/mesh"))
    return UrdfXml(
        root.get("name"),
        tuple(ln.get("name", "") for ln in links),
        tuple(mimics),
        {ln.get("name", ""): len(ln.findall("collision")) for ln in links},
        parents,
        meshes,
    )


def check_mesh_paths(path: Path, xml: UrdfXml, dirs: Sequence[str]) -> None:
    """Every collision mesh stays inside the URDF's folder, its ``package_dirs`` or the allowed
    roots (:mod:`pinograsp.core.paths`): ``package://`` and relative paths without ``..``
    leaving their base, absolute ones inside an allowed root.

    Raises:
        UrdfError: A mesh outside them (the reference is named, nothing is read).
    """
    roots = allowed_roots(path.parent, *dirs)
    for ref in xml.meshes:
        rest = ref[len("package://") :].lstrip("/") if ref.startswith("package://") else None  # package:///x
        if rest is None and ref.startswith("file://"):
            ok = inside(ref[len("file://") :], roots)
        elif rest is None and Path(ref).is_absolute():
            ok = inside(ref, roots)
        else:
            ok = not escapes(rest if rest is not None else ref)
        if not ok:
            raise UrdfError(
                path,
                f"collision mesh {ref[:200]!r} is outside the URDF's folder and its package_dirs "
                f"(docs/scenes.md, 'Paths'; list other folders in {ALLOWED_PATHS_ENV})",
            )


def package_folders(path: Path, package_dirs: Sequence[str | Path] | str | Path | None) -> list[str]:
    """Folders for ``package://`` paths: as given, or the URDF's folder, its parent and example-robot-data."""
    if package_dirs is None:
        dirs = [str(path.parent), str(path.parent.parent)]
        try:
            dirs.append(str(example_robot_data_dir()))
        except ModelFileError:
            pass
        return dirs
    if isinstance(package_dirs, (str, Path)):
        return [str(package_dirs)]
    if isinstance(package_dirs, (Sequence, np.ndarray)) and all(
        isinstance(d, (str, Path)) for d in package_dirs
    ):
        return [str(d) for d in package_dirs]
    raise InvalidInputError("package_dirs", f"expected folder paths, got {package_dirs!r}")


def _build_models(path: Path, dirs: list[str], xml: UrdfXml) -> tuple[pin.Model, pin.GeometryModel]:
    """Pinocchio model and collision geometry of the whole URDF, every ``<collision>`` loaded."""
    try:
        model, geom = pin.buildModelsFromUrdf(
            str(path), package_dirs=dirs, geometry_types=pin.GeometryType.COLLISION
        )
    except (ValueError, RuntimeError) as exc:
        msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise UrdfError(path, f"Pinocchio cannot load it: {msg} (package_dirs: {dirs})") from exc
    # Pinocchio silently skips collision elements it cannot parse (e.g. <capsule>): refuse that
    loaded: dict[str, int] = {}
    for g in geom.geometryObjects:
        loaded[model.frames[g.parentFrame].name] = loaded.get(model.frames[g.parentFrame].name, 0) + 1
    for ln, n in xml.collisions.items():
        if loaded.get(ln, 0) < n:
            raise UrdfError(
                path,
                f"link {ln!r}: {n - loaded.get(ln, 0)} of {n} <collision> elements were not loaded "
                "(unsupported geometry such as <capsule>? use box, cylinder, sphere or mesh)",
            )
    return model, geom


def _rename_shadowing_joint_frames(model: pin.Model) -> None:
    """Rename, in place, a joint frame that has the name of a link (``<name>_joint``).

    URDFs may name a fixed joint like its child link (z1.urdf: ``gripperStator``); Pinocchio's
    ``buildReducedModel`` then cannot tell the two frames apart and raises ``ValueError``.
    """
    bodies = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    for i in range(len(model.frames)):
        fr = model.frames[i]
        if fr.type != pin.FrameType.BODY and fr.name in bodies:
            fr.name = f"{fr.name}_joint"
            model.frames[i] = fr


def _reduce(
    path: Path, model: pin.Model, geom: pin.GeometryModel, desc: HandDescription, mimics: Sequence[Mimic]
) -> tuple[pin.Model, pin.GeometryModel, tuple[Mimic, ...]]:
    """Lock the joints that are not hand joints; the mimic tags between hand joints."""
    movable = [model.names[j] for j in range(1, model.njoints)]
    hand_joints = list(movable) if desc.joints is None else list(desc.joints)
    for j in hand_joints:
        if j not in movable:
            raise UnknownNameError("joint", j, movable)
    q_ref = pin.neutral(model)
    for j, v in desc.reference_configuration.items():
        if j not in movable:
            raise UnknownNameError("joint", j, movable)
        jid = model.getJointId(j)
        if model.joints[jid].nq != 1:
            raise InvalidInputError(
                f"reference_configuration[{j!r}]", "only 1-DoF joints can be given a value"
            )
        q_ref[model.joints[jid].idx_q] = v
    lock = [model.getJointId(j) for j in movable if j not in hand_joints]
    if lock:
        _rename_shadowing_joint_frames(model)
        model, geom = pin.buildReducedModel(model, geom, lock, q_ref)
    hand_mimics = []
    for m in mimics if desc.use_mimic else ():
        f_in, l_in = m.follower in hand_joints, m.leader in hand_joints
        if f_in and l_in:
            hand_mimics.append(m)
        elif f_in and m.leader not in movable:
            raise ModelError(
                f"{path}: joint {m.follower!r} mimics {m.leader!r}, which is not a movable joint of "
                f"this URDF (a name the file gets wrong?). Set 'use_mimic: false' in the description "
                "(URDF mimics ignored: each joint moves on its own) and, to keep the linkage, add the "
                f"coupling yourself: couplings: [{{follower: {m.follower}, leader: <the real joint>, "
                f"ratio: {m.multiplier:g}}}] (closing coordinates; docs/hands.md)"
            )
        elif f_in != l_in:
            raise ModelError(
                f"{path}: joint {m.follower!r} mimics {m.leader!r} but only one of them is a hand joint; "
                "keep both in (or both out of) the description's 'joints', or set 'use_mimic: false' "
                "(URDF mimics ignored) and give the couplings you want under 'couplings'"
            )
    return model, geom, tuple(hand_mimics)


def _rebase(model: pin.Model, geom: pin.GeometryModel, bMo: pin.SE3) -> None:
    """Re-express everything attached to the universe in the base frame (in place)."""
    for j in range(1, model.njoints):
        if model.parents[j] == 0:
            model.jointPlacements[j] = bMo * model.jointPlacements[j]
    for i in range(len(model.frames)):
        fr = model.frames[i]
        if fr.parentJoint == 0:
            fr.placement = bMo * fr.placement
            model.frames[i] = fr
    for g in geom.geometryObjects:
        if g.parentJoint == 0:
            g.placement = bMo * g.placement  # geometry objects are held by reference


def _move_base(path: Path, model: pin.Model, geom: pin.GeometryModel, base_link: str | None) -> int:
    """Make the base link (default: the first body) the world frame, in place; its frame id."""
    body_frames = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    base = base_link or next((f.name for f in model.frames if f.type == pin.FrameType.BODY), None)
    if base is None or base not in body_frames:
        raise UnknownNameError("link", base, body_frames)
    # by type: a fixed joint may share the link's name (z1.urdf: joint and link "gripperStator")
    base_id = model.getFrameId(base, pin.FrameType.BODY)
    if model.frames[base_id].parentJoint != 0:
        mover = model.names[model.frames[base_id].parentJoint]
        raise ModelError(
            f"{path}: base link {base!r} moves with joint {mover!r}; "
            "the base link must be fixed (lock the joints above it)"
        )
    _rebase(model, geom, model.frames[base_id].placement.inverse())
    return base_id


def _contact_geometry(
    model: pin.Model,
    geom: pin.GeometryModel,
    contact_links: tuple[str, ...] | None,
    base_id: int,
    xml: UrdfXml,
) -> pin.GeometryModel:
    """The geometry of ``contact_links``, or of every link at or below the base link in the
    URDF tree (through locked joints too: a finger whose joints the description locks still
    touches; Pinocchio's reduced model does not link a locked joint's frame to its parent, so
    the tree comes from the XML)."""
    if contact_links is not None:
        body_frames = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        for ln in contact_links:
            if ln not in body_frames:
                raise UnknownNameError("link", ln, body_frames)
        keep = [g for g in geom.geometryObjects if model.frames[g.parentFrame].name in contact_links]
    else:
        below = xml.at_or_below(model.frames[base_id].name)
        keep = [g for g in geom.geometryObjects if model.frames[g.parentFrame].name in below]
    contact_geom = pin.GeometryModel()
    for g in keep:
        contact_geom.addGeometryObject(g)
    return contact_geom


def _check_triangles(path: Path, geom: pin.GeometryModel) -> None:
    """Refuse a collision mesh of more triangles than an object mesh may have
    (:data:`~pinograsp.robots.objects.MAX_MESH_TRIANGLES`): every contact query walks it.

    Raises:
        UrdfError: The mesh, its link and its triangle count, and what to do.
    """
    for g in geom.geometryObjects:
        n = int(getattr(g.geometry, "num_tris", 0))  # a BVH mesh's triangles; primitives have none
        if n > MAX_MESH_TRIANGLES:
            raise UrdfError(
                path,
                f"collision mesh {g.meshPath or g.name!r} of {g.name!r} has {n} triangles, more than "
                f"{MAX_MESH_TRIANGLES} (MAX_MESH_TRIANGLES): decimate it or use a convex hull",
            )


def load_urdf_hand(
    path: Path, desc: HandDescription, package_dirs: Sequence[str | Path] | str | Path | None = None
) -> UrdfHand:
    """Load the URDF at ``path`` as the hand ``desc`` describes (steps in the module docstring).

    Raises:
        UrdfError: Malformed URDF, missing mesh, a ``<collision>`` Pinocchio cannot load.
        UnknownNameError: The description names a joint or link that does not exist.
        ModelError: A moving base link, a mimic between a hand joint and a locked one.
    """
    xml = parse_urdf_xml(path)
    dirs = package_folders(path, package_dirs)
    check_mesh_paths(path, xml, dirs)
    model, geom = _build_models(path, dirs, xml)
    _check_triangles(path, geom)
    model, geom, mimics = _reduce(path, model, geom, desc, xml.mimics)
    base_id = _move_base(path, model, geom, desc.base_link)
    return UrdfHand(model, _contact_geometry(model, geom, desc.contact_links, base_id, xml), mimics, xml)
