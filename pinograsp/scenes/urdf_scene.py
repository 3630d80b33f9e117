"""URDF scenes (``hand:`` key): a hand, its configuration and an object -> the grasp's parts.

Contacts come from Coal and Pinocchio (:mod:`pinograsp.robots.grasp`); an optional ``frame``
re-expresses them in *analysis axes* and ``hand.lock`` holds joints rigid (docs/scenes.md).
Hands are cached per process (:func:`clear_cache`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..core.actuation import Actuator, Coupling
from ..core.contact import Contact
from ..errors import PinograspError
from .fields import SceneFile, mtime
from .schema import URDF_KEYS, GraspParts

if TYPE_CHECKING:  # the URDF side is imported when a URDF scene is built
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

_HAND_CACHE: dict[tuple, Hand] = {}
#: Keys of an ``object`` block for each shape (besides ``shape``, ``pose``, ``center_of_mass``, ``name``).
_SHAPE_KEYS = {
    "box": ("size",),
    "cylinder": ("radius", "length"),
    "sphere": ("radius",),
    "mesh": ("file", "scale", "convex"),
}


def clear_cache() -> None:
    """Forget the hands loaded by earlier scenes (e.g. after editing a URDF in place)."""
    _HAND_CACHE.clear()


# ---------------------------------------------------------------------------- the hand
def _urdf_hand(f: SceneFile, s: Mapping) -> Hand:
    """A hand from ``{urdf, description, package_dirs}`` (cached per file version)."""
    from ..robots.hand import Hand

    urdf = f.relpath(s["urdf"], "hand.urdf")
    if not urdf.is_file():
        raise f.error("hand.urdf", f"URDF file not found: {urdf}")
    desc: dict | Path | None = None
    if s.get("description") is not None:
        if isinstance(s["description"], Mapping):
            desc = dict(s["description"])
        else:
            desc = f.relpath(s["description"], "hand.description")
            if not desc.is_file():
                raise f.error("hand.description", f"hand description file not found: {desc}")
    dirs = None
    if s.get("package_dirs") is not None:
        dirs = [str(f.relpath(d, f"hand.package_dirs[{i}]")) for i, d in enumerate(s["package_dirs"])]
    key = (
        "urdf",
        str(urdf.resolve()),
        mtime(urdf),
        repr(desc) if not isinstance(desc, Path) else (str(desc.resolve()), mtime(desc)),
        tuple(dirs or ()),
    )
    if key not in _HAND_CACHE:
        try:
            _HAND_CACHE[key] = Hand.from_urdf(urdf, desc, package_dirs=dirs)
        except PinograspError as exc:
            raise f.error("hand", str(exc)) from exc
    return _HAND_CACHE[key]


def _load_hand(f: SceneFile, spec: object) -> tuple[Hand, list[str]]:
    """The scene's hand (cached per process) and its locked joints."""
    from ..robots.hand import BUILTIN_HANDS, Hand

    if isinstance(spec, str):
        spec = {"builtin": spec}
    s = f.mapping(spec, "hand", "a built-in hand name or a mapping with 'builtin' or 'urdf'")
    f.keys(s, ("builtin", "urdf", "description", "package_dirs", "lock"), "hand")
    lock = f.names(s["lock"], "hand.lock") if s.get("lock") is not None else []
    if ("builtin" in s) == ("urdf" in s):
        raise f.error("hand", "give exactly one of 'builtin' (a shipped hand) or 'urdf' (a file)")
    if "urdf" in s:
        return _urdf_hand(f, s), lock
    name = f.string(s["builtin"], "hand.builtin")
    if "description" in s or "package_dirs" in s:
        raise f.error("hand", "'description' and 'package_dirs' only go with 'urdf'")
    if name not in BUILTIN_HANDS:
        raise f.error("hand.builtin", f"unknown hand {name!r}; built-in hands: {', '.join(BUILTIN_HANDS)}")
    key = ("builtin", name)
    if key not in _HAND_CACHE:
        _HAND_CACHE[key] = Hand.builtin(name)
    return _HAND_CACHE[key], lock


# ---------------------------------------------------------------------------- the object
def _load_object(f: SceneFile, spec: object) -> RigidObject:
    """The ``object`` block: a box, cylinder, sphere or mesh [m] at its pose."""
    from ..robots.objects import RigidObject

    s = f.mapping(spec, "object")
    shape = f.string(f.require(s, "shape", "object"), "object.shape")
    if shape not in _SHAPE_KEYS:
        raise f.error("object.shape", f"unknown shape {shape!r}; valid shapes: {', '.join(_SHAPE_KEYS)}")
    f.keys(s, ("shape", "pose", "center_of_mass", "name") + _SHAPE_KEYS[shape], "object")
    pose = f.pose(s.get("pose"), "object.pose")
    name = f.string(s["name"], "object.name") if "name" in s else shape
    if shape == "box":
        size = f.vector(f.require(s, "size", "object"), 3, "object.size")
        for i, v in enumerate(size):
            if v <= 0:
                raise f.error(f"object.size[{i}]", f"must be > 0, got {v}")
        obj = RigidObject.box(size, pose, name=name)
    elif shape == "cylinder":
        r = f.number(f.require(s, "radius", "object"), "object.radius", positive=True)
        h = f.number(f.require(s, "length", "object"), "object.length", positive=True)
        obj = RigidObject.cylinder(r, h, pose, name=name)
    elif shape == "sphere":
        r = f.number(f.require(s, "radius", "object"), "object.radius", positive=True)
        obj = RigidObject.sphere(r, pose, name=name)
    else:
        path = f.relpath(f.require(s, "file", "object"), "object.file")
        if not path.is_file():
            raise f.error("object.file", f"mesh file not found: {path}")
        scale = f.number(s.get("scale", 1.0), "object.scale", positive=True)
        convex = None if s.get("convex") is None else f.boolean(s["convex"], "object.convex")
        try:
            obj = RigidObject.from_mesh(path, pose, scale=scale, convex=convex, name=name)
        except PinograspError as exc:
            raise f.error("object.file", str(exc)) from exc
    if s.get("center_of_mass") is not None:
        com = f.vector(s["center_of_mass"], 3, "object.center_of_mass")
        obj = replace(obj, com_local=com)
    return obj


# ---------------------------------------------------------------------------- the configuration
def _joint_values(f: SceneFile, hand: Hand, value: object, key: str) -> dict[str, float]:
    """``{joint: value [rad or m]}``; a URDF mimic follower not given follows its leader."""
    v = f.mapping(value, key, "a mapping joint -> value [rad or m]")
    out = {}
    for j, x in v.items():
        if j not in hand.joint_names:
            raise f.error(f"{key}.{j}", f"unknown joint; hand joints: {', '.join(hand.joint_names)}")
        out[str(j)] = f.number(x, f"{key}.{j}", angle=True)
    for m in hand.mimics:
        if m.leader in out and m.follower not in out:
            out[m.follower] = m.multiplier * out[m.leader] + m.offset
    return out


def _configuration(
    f: SceneFile, hand: Hand, obj: RigidObject, value: object, tol: float, pen: float | None = None
) -> np.ndarray:
    """The hand configuration: joint values, or ``auto_close`` on the object (tolerance and
    deepest accepted overlap [m])."""
    if value is None:
        raise f.error("configuration", "missing required key (joint values, or auto_close)")
    v = f.mapping(value, "configuration", "a mapping joint -> value, or {auto_close: {...}}")
    if "auto_close" not in v:
        q = _joint_values(f, hand, v, "configuration")
        return hand.configuration(q)
    f.keys(v, ("auto_close",), "configuration")
    ac = v["auto_close"] if v["auto_close"] is not None else {}
    ac = f.mapping(ac, "configuration.auto_close")
    f.keys(ac, ("from", "step"), "configuration.auto_close")
    q_open = None
    if ac.get("from") is not None:
        q_open = _joint_values(f, hand, ac["from"], "configuration.auto_close.from")
    step = f.number(ac.get("step", 0.03), "configuration.auto_close.step", positive=True)
    try:
        return hand.close_on(obj, q_open, tolerance=tol, step=step, max_penetration=pen)
    except PinograspError as exc:
        raise f.error("configuration.auto_close", str(exc)) from exc


# ---------------------------------------------------------------------------- frame and locked joints
def _lock_joints(
    f: SceneFile,
    lock: Sequence[str],
    joint_names: Sequence[str],
    contacts: Sequence[Contact],
    actuators: Sequence[Actuator],
    couplings: Sequence[Coupling],
) -> tuple[list[str], list[Contact], list[Actuator], list[Coupling]]:
    """Remove locked joints: Jacobian columns, transmission entries, couplings among them."""
    for i, j in enumerate(lock):
        if j not in joint_names:
            raise f.error(f"hand.lock[{i}]", f"unknown joint {j!r}; hand joints: {', '.join(joint_names)}")
    keep = [k for k, j in enumerate(joint_names) if j not in lock]
    names = [joint_names[k] for k in keep]
    cs = [
        Contact(
            c.point,
            c.normal,
            c.mu,
            None if c.jacobian is None else c.jacobian[:, keep],
            c.tangent,
            c.stiffness,
            c.name,
        )
        for c in contacts
    ]
    acts = []
    for a in actuators:
        tr = {j: v for j, v in a.transmission.items() if j not in lock}
        if tr:
            acts.append(Actuator(tr, a.kind, a.name, bidirectional=a.bidirectional))
    cps = []
    for c in couplings:
        inside = [j in lock for j in c.weights]
        if all(inside):
            continue
        if any(inside):
            free = [j for j in c.weights if j not in lock]
            raise f.error(
                "hand.lock",
                f"coupling {c.name!r} ties locked and free joints ({', '.join(map(str, free))} free); "
                "lock all of its joints",
            )
        cps.append(c)
    return names, cs, acts, cps


def _to_frame(c: Contact, T: np.ndarray) -> Contact:
    """Re-express a contact in the frame ``T`` (4×4, frame in the hand base frame)."""
    Rt = T[:3, :3].T
    jac = None if c.jacobian is None else Rt @ c.jacobian
    # the default tangent is recomputed in the new frame (planar reductions keep t1 in plane)
    return Contact(Rt @ (c.point - T[:3, 3]), Rt @ c.normal, c.mu, jac, None, c.stiffness, c.name)


# ---------------------------------------------------------------------------- the builder
def build_urdf(f: SceneFile, d: Mapping) -> GraspParts:
    """The parts of a URDF scene's grasp (``d``: the scene's top-level keys)."""
    from ..robots.collision import DEFAULT_MAX_PENETRATION, DEFAULT_TOLERANCE
    from ..robots.grasp import scene_contacts
    from ..robots.patches import DEFAULT_PATCH_POINTS, MAX_PATCH_POINTS

    f.keys(d, URDF_KEYS, "")
    hand, lock = _load_hand(f, d["hand"])
    tol = f.number(d.get("tolerance", DEFAULT_TOLERANCE), "tolerance", positive=True)
    pen = f.number(d.get("max_penetration", DEFAULT_MAX_PENETRATION), "max_penetration", positive=True)
    obj = _load_object(f, f.require(d, "object", ""))
    q = _configuration(f, hand, obj, d.get("configuration"), tol, pen)
    links = list(hand.contact_link_names)
    mu = f.per_name(d.get("friction"), "friction", links, 0.5, nonneg=True)
    k = f.per_name(d.get("stiffness"), "stiffness", links, 1.0, positive=True)
    patches = f.boolean(d.get("patches", True), "patches")
    npts = f.integer(d.get("patch_points", DEFAULT_PATCH_POINTS), "patch_points", minimum=2)
    if npts > MAX_PATCH_POINTS:
        raise f.error("patch_points", f"must be an integer in [2, {MAX_PATCH_POINTS}], got {npts}")
    try:
        contacts, report = scene_contacts(
            hand,
            q,
            obj,
            mu=mu,
            stiffness=k,
            tolerance=tol,
            max_penetration=pen,
            patches=patches,
            patch_points=npts,
        )
    except PinograspError as exc:
        raise f.error("configuration", f"{type(exc).__name__}: {exc}") from exc
    if d.get("expect_contacts") is not None:
        want = f.integer(d["expect_contacts"], "expect_contacts")
        if len(report.contacts) != want:  # touching geometries (a patch counts once)
            got = ", ".join(c.link for c in report.contacts)
            raise f.error(
                "expect_contacts", f"expected {want} contacts, detected {len(report.contacts)}: {got}"
            )
    T = f.pose(d.get("frame"), "frame")
    o = T[:3, :3].T @ (obj.center_of_mass - T[:3, 3])
    names, cs, acts, cps = _lock_joints(
        f, lock, hand.joint_names, [_to_frame(c, T) for c in contacts], hand.actuators, hand.couplings
    )
    return GraspParts(
        contacts=tuple(cs),
        actuators=tuple(acts),
        couplings=tuple(cps),
        joint_names=tuple(names),
        reference_point=o,
        default_command=dict(hand.commands),
        hand=hand,
        q=q,
        object=obj,
        frame=T,
    )
