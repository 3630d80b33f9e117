"""Grasp records for batch evaluation: a hand, an object at a pose, a configuration and a preload.

:class:`GraspSpec` and :class:`ObjectSpec` are frozen, plain-data records (strings, floats and
tuples): cheap to pickle to worker processes, Ray or Dask, and rebuilt into a
:class:`~pinograsp.core.model.GraspModel` where they are evaluated (:func:`build_grasp`; hands are
loaded once per process and cached). :func:`sample_grasps` places one object at many poses
around a nominal one, to be auto-closed by the hand.

This module imports neither the solvers nor the URDF side until a grasp is built.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal, cast

import numpy as np

from ..core.build import MAX_EDGES
from ..core.methods import method_name
from ..core.poses import rotation_rpy, rpy_of
from ..core.settings import DEFAULT_METHOD, Method
from ..core.validate import MAX_SAMPLES, choice, count, finite_number, positive_number, whole_number
from ..core.validate import size as check_size
from ..errors import InvalidInputError

#: Object shapes of :class:`ObjectSpec`.
SHAPES = ("box", "sphere", "cylinder", "mesh")
Shape = Literal["box", "sphere", "cylinder", "mesh"]


def _floats(name: str, value: object, n: int | None = None) -> tuple[float, ...]:
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (Sequence, np.ndarray)):
        raise InvalidInputError(name, f"expected {n or 'a list of'} numbers, got {value!r}")
    out = tuple(finite_number(f"{name}[{i}]", v) for i, v in enumerate(value))
    if n is not None and len(out) != n:
        raise InvalidInputError(name, f"expected {n} numbers, got {len(out)}")
    return out


def _pairs(name: str, value: object) -> tuple[tuple[str, float], ...] | tuple[float, ...]:
    """``{name: value}`` -> sorted-as-given ``((name, value), ...)``; a sequence -> floats."""
    if isinstance(value, Mapping):
        return tuple((str(k), finite_number(f"{name}.{k}", v)) for k, v in value.items())
    return _floats(name, value)


@dataclass(frozen=True)
class ObjectSpec:
    """An object and its pose in the hand base frame, as plain data.

    Attributes:
        shape: ``"box"``, ``"sphere"``, ``"cylinder"`` (axis along its z) or ``"mesh"``.
        size: Box edge lengths ``(sx, sy, sz)`` [m] (box only).
        radius: Sphere or cylinder radius [m].
        length: Cylinder length [m].
        file: Mesh file (STL/OBJ/PLY; mesh only).
        scale: Mesh vertex scale (e.g. 1e-3 for millimetres).
        convex: Mesh as its convex hull (``True``), a surface (``False``) or by its shape (``None``).
        xyz: Position of the object frame [m], (3,).
        rpy: Orientation, URDF roll-pitch-yaw [rad], (3,).
        name: Label (default: the shape).
    """

    shape: Shape
    size: tuple[float, float, float] | None = None
    radius: float | None = None
    length: float | None = None
    file: str | None = None
    scale: float = 1.0
    convex: bool | None = None
    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)
    name: str | None = None

    def __post_init__(self) -> None:
        choice("shape", self.shape, SHAPES)
        need = {"box": ("size",), "sphere": ("radius",), "cylinder": ("radius", "length"), "mesh": ("file",)}
        for key in ("size", "radius", "length", "file"):
            given = getattr(self, key) is not None
            if given != (key in need[self.shape]):
                what = "needs" if not given else "takes no"
                raise InvalidInputError(key, f"a {self.shape} {what} '{key}'")
        if self.size is not None:
            sz = _floats("size", self.size, 3)
            for i, v in enumerate(sz):
                check_size(f"size[{i}]", v)
            object.__setattr__(self, "size", sz)
        for key in ("radius", "length"):
            if getattr(self, key) is not None:
                object.__setattr__(self, key, check_size(key, getattr(self, key)))
        if self.file is not None and (not isinstance(self.file, str) or not self.file):
            raise InvalidInputError("file", f"expected a mesh file path, got {self.file!r}")
        object.__setattr__(self, "scale", positive_number("scale", self.scale))
        if self.convex is not None and not isinstance(self.convex, bool):
            raise InvalidInputError("convex", f"expected True, False or None, got {self.convex!r}")
        object.__setattr__(self, "xyz", _floats("xyz", self.xyz, 3))
        object.__setattr__(self, "rpy", _floats("rpy", self.rpy, 3))
        if self.name is not None and not isinstance(self.name, str):
            raise InvalidInputError("name", f"expected a string, got {self.name!r}")

    @property
    def pose(self) -> np.ndarray:
        """The object frame in the hand base frame, 4×4."""
        T = np.eye(4)
        T[:3, :3] = rotation_rpy(self.rpy)
        T[:3, 3] = self.xyz
        return T

    def with_pose(self, xyz: Sequence[float], rpy: Sequence[float]) -> ObjectSpec:
        """The same object at another pose (position [m], roll-pitch-yaw [rad])."""
        xyz3, rpy3 = tuple(float(v) for v in xyz), tuple(float(v) for v in rpy)
        return replace(self, xyz=xyz3, rpy=rpy3)  # type: ignore[arg-type]  # __post_init__ checks (3,)

    @classmethod
    def from_object(cls, obj: Any) -> ObjectSpec:
        """The record of a primitive :class:`~pinograsp.robots.objects.RigidObject` (box, sphere,
        cylinder; meshes need an :class:`ObjectSpec` with their file and scale)."""
        kind = getattr(obj, "kind", None)
        if kind not in ("box", "sphere", "cylinder"):
            raise InvalidInputError(
                "obj", f"expected an ObjectSpec or a box/sphere/cylinder RigidObject, got {obj!r}"
            )
        if np.any(np.asarray(obj.com_local) != 0):
            raise InvalidInputError("obj", "a RigidObject with a shifted centre of mass has no ObjectSpec")
        T = np.asarray(obj.pose)
        dims = dict(obj.dimensions)
        return cls(kind, xyz=tuple(T[:3, 3]), rpy=rpy_of(T[:3, :3]), name=obj.name, **dims)

    def to_object(self) -> Any:
        """The :class:`~pinograsp.robots.objects.RigidObject` (imports Coal)."""
        from ..robots.objects import RigidObject

        if self.shape == "mesh":
            file = cast(str, self.file)  # each shape's own fields are set (__post_init__)
            pose, scale, convex = self.pose, self.scale, self.convex
            return RigidObject.from_mesh(file, pose, scale=scale, convex=convex, name=self.name)
        name = self.name or self.shape
        if self.shape == "box":
            return RigidObject.box(self.size, self.pose, name=name)
        radius = cast(float, self.radius)
        if self.shape == "sphere":
            return RigidObject.sphere(radius, self.pose, name=name)
        return RigidObject.cylinder(radius, cast(float, self.length), self.pose, name=name)


@dataclass(frozen=True)
class GraspSpec:
    """One grasp to evaluate, as plain data.

    Attributes:
        hand: A built-in hand name (``pg.Hand.builtin``) or the path of a URDF file.
        object: The object and its pose (an :class:`ObjectSpec`; a primitive ``RigidObject`` or
            a mapping of its fields is converted).
        description: Hand description YAML for a URDF path (default: next to the URDF).
        package_dirs: Folders for ``package://`` meshes of a URDF path.
        q: Hand configuration, URDF coordinates [rad or m]: ``{joint: value}`` or one value per
            hand joint; ``None``: auto-close (``Hand.close_on``) from ``q_open``.
        q_open: Open configuration of the auto-close ``{joint: value}`` (default: the description's).
        step: Largest joint step of the auto-close [rad].
        tolerance: Contact tolerance [m] of the auto-close and of the contact detection
            (``None``: the default, 1 mm).
        max_penetration: Deepest accepted overlap of a link into the object [m], for the
            auto-close and the contact detection (``None``: the default, 5 mm); deeper is a
            ``PenetrationError`` (a ``no_grasp`` row, reason ``penetration``).
        max_steps: Step limit of the auto-close (a count).
        mu: Friction coefficient of every contact.
        stiffness: Normal stiffness of every contact [N/m].
        patches: Flat and line contacts as patches of corner points (docs/hands.md, "Contact
            patches"); ``False`` (default for a batch record: one point per touching geometry,
            so that existing tables keep their numbers).
        edges: Friction pyramid edges per contact, in [3, 256] (``None``: the model's default, 8;
            docs/planning.md, "Friction pyramid": a planner's candidates use 16).
        command: ``"auto"`` (``pg.equilibrium_preload``: its commands when ``"found"``, and
            also when ``"slides"`` or ``"separates"``, with a :class:`~pinograsp.errors.PinograspWarning`
            in the row's ``warnings``; else a ``no_preload`` row), a number (every actuator) or
            ``{actuator: value}`` [N·m or N].
        max_command: Bound of every command of the ``"auto"`` preload [N·m or N].
        preload_method: Whose preload stage ``"auto"`` verifies (:func:`pinograsp.equilibrium_preload`
            at ``w = 0``): ``"quasistatic"`` (default: its preload path, the object held),
            ``"iterative"``, ``"prp"`` (the object settles) or ``"energetic"``. The energetic method's
            preload stage is the iterative one (the object held still while the hand closes),
            so it verifies the same commands, plus one
            energetic solve at ``w = 0``; it is accepted so that a batch scored with
            ``method="energetic"`` can name the same method throughout.
        id: Label of the grasp's row (default: its position in the batch).
    """

    hand: str
    object: ObjectSpec
    description: str | None = None
    package_dirs: tuple[str, ...] = ()
    q: tuple[tuple[str, float], ...] | tuple[float, ...] | None = None
    q_open: tuple[tuple[str, float], ...] | None = None
    step: float = 0.03
    tolerance: float | None = None
    max_penetration: float | None = None
    max_steps: int = 2000
    mu: float = 0.5
    stiffness: float = 1.0
    patches: bool = False
    edges: int | None = None
    command: Literal["auto"] | float | tuple[tuple[str, float], ...] = "auto"
    max_command: float = 1.0
    preload_method: Method | str = Method(DEFAULT_METHOD)
    id: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.hand, str) or not self.hand:
            raise InvalidInputError(
                "hand", f"expected a built-in hand name or a URDF path, got {self.hand!r}"
            )
        obj = self.object
        if isinstance(obj, Mapping):
            obj = _object_from_mapping(obj)
        elif not isinstance(obj, ObjectSpec):
            obj = ObjectSpec.from_object(obj)
        object.__setattr__(self, "object", obj)
        if self.description is not None and (not isinstance(self.description, str) or not self.description):
            raise InvalidInputError("description", f"expected a file path, got {self.description!r}")
        dirs = self.package_dirs
        if isinstance(dirs, str) or not all(isinstance(d, str) for d in dirs):
            raise InvalidInputError("package_dirs", f"expected a list of folder paths, got {dirs!r}")
        object.__setattr__(self, "package_dirs", tuple(dirs))
        if self.q is not None:  # a mapping, its pairs (dataclasses.replace keeps them) or values
            named = isinstance(self.q, tuple) and bool(self.q) and isinstance(self.q[0], tuple)
            q = dict(cast(tuple[tuple[str, float], ...], self.q)) if named else self.q
            object.__setattr__(self, "q", _pairs("q", q))
        if self.q_open is not None:
            if not isinstance(self.q_open, Mapping) and not all(isinstance(p, tuple) for p in self.q_open):
                raise InvalidInputError("q_open", f"expected a mapping joint -> value, got {self.q_open!r}")
            object.__setattr__(self, "q_open", _pairs("q_open", dict(self.q_open)))
        for key in ("step", "max_command"):
            object.__setattr__(self, key, positive_number(key, getattr(self, key)))
        if self.tolerance is not None:
            object.__setattr__(self, "tolerance", positive_number("tolerance", self.tolerance))
        if self.max_penetration is not None:
            depth = finite_number("max_penetration", self.max_penetration)
            if depth < 0:
                raise InvalidInputError("max_penetration", f"must be >= 0 [m], got {self.max_penetration!r}")
            object.__setattr__(self, "max_penetration", depth)
        object.__setattr__(self, "max_steps", whole_number("max_steps", self.max_steps))
        if not isinstance(self.patches, bool):
            raise InvalidInputError("patches", f"expected True or False, got {self.patches!r}")
        if self.edges is not None:
            object.__setattr__(self, "edges", count("edges", self.edges, MAX_EDGES, 3, "the model's limit"))
        mu = finite_number("mu", self.mu)
        if mu < 0:
            raise InvalidInputError("mu", f"must be >= 0, got {self.mu!r}")
        object.__setattr__(self, "mu", mu)
        object.__setattr__(self, "stiffness", positive_number("stiffness", self.stiffness))
        cmd = self.command
        if isinstance(cmd, str):
            choice("command", cmd, ("auto",))
        elif isinstance(cmd, (Mapping, tuple)):
            object.__setattr__(self, "command", _pairs("command", dict(cmd)))
        else:
            object.__setattr__(self, "command", finite_number("command", cmd))
        object.__setattr__(self, "preload_method", method_name(self.preload_method, "preload_method"))
        if self.id is not None and not isinstance(self.id, str):
            object.__setattr__(self, "id", str(self.id))

    def to_dict(self) -> dict[str, Any]:
        """The record as plain JSON-ready data (mappings for ``q``, ``q_open``, ``command``)."""
        out: dict[str, Any] = {}
        for key in self.__dataclass_fields__:
            v = getattr(self, key)
            if key == "object":
                v = {k: getattr(v, k) for k in v.__dataclass_fields__ if getattr(v, k) is not None}
            elif isinstance(v, tuple) and v and isinstance(v[0], tuple):
                v = dict(v)
            out[key] = list(v) if isinstance(v, tuple) else v
        return out


def _object_from_mapping(data: Mapping) -> ObjectSpec:
    keys = set(ObjectSpec.__dataclass_fields__)
    for k in data:
        if k not in keys:
            raise InvalidInputError(f"object.{k}", f"unknown key; valid keys: {', '.join(sorted(keys))}")
    return ObjectSpec(**dict(data))


def sample_grasps(
    hand: str,
    obj: ObjectSpec | Any,
    n: int,
    seed: int = 0,
    *,
    translation: float | Sequence[float] = 0.005,
    rotation: float = math.radians(10.0),
    include_nominal: bool = True,
    **fields: Any,
) -> list[GraspSpec]:
    """Grasps of one object at ``n`` poses sampled around its nominal pose, auto-closed by ``hand``.

    Each pose is the nominal one displaced by a translation drawn uniformly in the box
    ``±translation`` (per axis, hand base frame) and rotated about the object's origin by an
    angle drawn uniformly in ``[0, rotation]`` about a uniformly random axis. The draws come
    from ``numpy.random.default_rng(seed)``: the same ``seed`` gives the same grasps everywhere.

    Args:
        hand: Built-in hand name or URDF path (as :attr:`GraspSpec.hand`).
        obj: The object at its nominal pose (:class:`ObjectSpec` or a primitive ``RigidObject``).
        n: Number of grasps.
        seed: Seed of the generator.
        translation: Half-width of the position box [m]: a scalar or (3,).
        rotation: Largest rotation angle [rad].
        include_nominal: The first grasp is the nominal pose itself.
        **fields: Other :class:`GraspSpec` fields shared by every grasp (``q_open``, ``mu``,
            ``command``, ...).

    Returns:
        ``n`` grasps with ids ``"s<seed>-<i>"``.
    """
    n = count("n", n, MAX_SAMPLES, what="grasps, checked before sampling")  # docs/errors.md
    seed = whole_number("seed", seed, minimum=0)
    spec = obj if isinstance(obj, ObjectSpec) else ObjectSpec.from_object(obj)
    half = np.asarray(_floats("translation", np.broadcast_to(np.asarray(translation, dtype=float), 3)))
    if np.any(half < 0):
        raise InvalidInputError("translation", f"must be >= 0, got {translation!r}")
    rotation = finite_number("rotation", rotation)
    if rotation < 0:
        raise InvalidInputError("rotation", f"must be >= 0, got {rotation!r}")
    if "id" in fields or "object" in fields:
        raise InvalidInputError("fields", "'id' and 'object' are set by sample_grasps")
    GraspSpec(hand, spec, **fields)  # validate the shared fields once, before sampling
    rng = np.random.default_rng(seed)
    R0, p0 = rotation_rpy(spec.rpy), np.asarray(spec.xyz)
    out = []
    for i in range(n):
        dp = rng.uniform(-1.0, 1.0, 3) * half
        axis = rng.normal(size=3)
        angle = rng.uniform(0.0, rotation)
        if include_nominal and i == 0:
            dp, angle = np.zeros(3), 0.0
        axis = axis / max(float(np.linalg.norm(axis)), 1e-300)
        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        dR = np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)
        placed = spec if angle == 0.0 and not dp.any() else spec.with_pose(p0 + dp, rpy_of(dR @ R0))
        out.append(GraspSpec(hand, placed, id=f"s{seed}-{i}", **fields))
    return out


# ---------------------------------------------------------------------------- building (worker side)
_HANDS: dict[tuple, Any] = {}


def load_hand(spec: GraspSpec) -> Any:
    """The spec's :class:`~pinograsp.robots.hand.Hand`, loaded once per process."""
    from ..robots.hand import BUILTIN_HANDS, Hand

    key = (spec.hand, spec.description, spec.package_dirs)
    if key not in _HANDS:
        if spec.hand in BUILTIN_HANDS and spec.description is None:
            _HANDS[key] = Hand.builtin(spec.hand)
        else:
            dirs = list(spec.package_dirs) or None
            _HANDS[key] = Hand.from_urdf(spec.hand, spec.description, package_dirs=dirs)
    return _HANDS[key]


def _with_mimics(hand: Any, pairs: tuple) -> dict[str, float]:
    """``{joint: value}`` with each URDF mimic follower not given following its leader."""
    q = dict(pairs)
    for m in hand.mimics:
        if m.leader in q and m.follower not in q:
            q[m.follower] = m.multiplier * q[m.leader] + m.offset
    return q


def build_grasp(spec: GraspSpec) -> tuple[Any, dict[str, float], dict[str, float]]:
    """The grasp model and preload command of a spec.

    Returns:
        ``(model, command, times)``: the :class:`~pinograsp.core.model.GraspModel`, the command
        ``{actuator: value}`` [N·m or N] and the wall times [s] ``build`` (hand, auto-close,
        contacts) and ``preload`` (the ``"auto"`` preload design).

    Raises:
        NoContactError: Nothing touches.
        PenetrationError: A link is deeper in the object than ``max_penetration``.
        NoPreloadError: ``command="auto"`` and no preload exists (or none was verified).
        PinograspError: the hand cannot be loaded, ...
    """
    import time

    from ..errors import ModelError, NoPreloadError, PinograspWarning
    from ..robots.grasp import grasp_model_from_scene

    t0 = time.perf_counter()
    hand, obj, q = grasp_configuration(spec)
    contact = _contact_options(spec)
    try:
        model = grasp_model_from_scene(
            hand,
            q,
            obj,
            mu=spec.mu,
            stiffness=spec.stiffness,
            patches=spec.patches,
            edges=spec.edges,
            **contact,
        )
    except ModelError as exc:
        if exc.argument != "contacts":
            raise
        raise NoPreloadError(  # only fixed links (the palm) touch: no actuator can press the object
            f"{exc}; no actuator can press the object, so no preload exists"
        ) from exc
    t1 = time.perf_counter()
    if spec.command == "auto":
        from ..analysis.preload import equilibrium_preload

        if not any(kind != "locked" for kind in model.kinds):
            raise NoPreloadError(
                f"no driving actuator reaches the contacts {list(model.contact_names)} (their links are "
                "carried by locked or undriven joints only)",
                contacts_detected=model.nc,
            )
        pre = equilibrium_preload(model, spec.preload_method, max_command=spec.max_command)
        if not pre.in_equilibrium or pre.command is None:
            raise NoPreloadError(
                pre.reason, pre.status, pre.unloadable_contacts, pre.unbalanced_actuators, model.nc
            )
        if not pre.found:  # it balances, but gives at zero load: analysed as it is, and said
            warnings.warn(f"equilibrium_preload: {pre.status}: {pre.reason}", PinograspWarning, stacklevel=2)
        command = dict(pre.command)
    elif isinstance(spec.command, tuple):
        command = {a: 0.0 for a in model.all_actuator_names} | dict(spec.command)
    else:
        command = dict.fromkeys(model.all_actuator_names, float(spec.command))
    model.command_vector(command)  # validated here: a bad command is this grasp's error
    return model, command, {"build": t1 - t0, "preload": time.perf_counter() - t1}


def _contact_options(spec: GraspSpec) -> dict[str, Any]:
    """The spec's contact detection options (``tolerance``, ``max_penetration``) where given."""
    contact: dict[str, Any] = {} if spec.tolerance is None else {"tolerance": spec.tolerance}
    if spec.max_penetration is not None:
        contact["max_penetration"] = spec.max_penetration
    return contact


def grasp_configuration(spec: GraspSpec) -> tuple[Any, Any, np.ndarray]:
    """The spec's hand (cached per process), object and configuration: ``spec.q``, or the
    auto-close from ``q_open`` (URDF coordinates, (nq,) [rad or m]).

    Raises:
        NoContactError, PenetrationError: From the auto-close.
    """
    hand = load_hand(spec)
    obj = spec.object.to_object()
    if spec.q is None:
        return hand, obj, _close(hand, obj, spec, _contact_options(spec))
    q = hand.configuration(
        _with_mimics(hand, spec.q) if spec.q and isinstance(spec.q[0], tuple) else list(spec.q)
    )
    return hand, obj, q


def _close(hand: Any, obj: Any, spec: GraspSpec, contact: dict[str, Any]) -> Any:
    """``hand.close_on`` with the spec's closing options (``max_penetration`` where the
    auto-close takes it)."""
    import inspect

    from ..robots.autoclose import close_on

    options: dict[str, Any] = {"step": spec.step, "max_steps": spec.max_steps}
    options.update({k: v for k, v in contact.items() if k in inspect.signature(close_on).parameters})
    q_open = None if spec.q_open is None else dict(spec.q_open)
    return close_on(hand, obj, q_open, **options)
