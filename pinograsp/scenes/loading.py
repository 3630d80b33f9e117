"""Scene files: a grasp, its preload and its analysis settings in one YAML file.

``load_scene(name_or_path)`` reads a scene (a built-in name such as ``"case1"``, or a path),
validates it and returns a :class:`Scene`: the :class:`~pinograsp.core.model.GraspModel`, the preload
command, the solver :class:`~pinograsp.analysis.response.Settings` and the analysis settings, so that::

    scene = pg.load_scene("case1")
    pg.max_resistible_wrench(scene.model, scene.command, "-fy", settings=scene.settings)

Two kinds of scenes (schema: ``docs/scenes.md``):

* **URDF scenes** (``hand:`` key): a hand (built-in name, or URDF + description), a joint
  configuration (values, or auto-close from an open pose), an object (box, cylinder, sphere or
  mesh) and its pose; contacts come from Coal and Pinocchio (:mod:`pinograsp.robots.grasp`). An optional
  ``frame`` re-expresses everything in *analysis axes* (e.g. the paper's X/Y), ``hand.lock``
  holds joints rigid (removes them from the model), and ``planar`` reduces to the XY plane of the
  analysis frame.
* **Explicit-contact scenes** (``contacts:`` key): contact points, normals and friction with
  revolute pivots or Jacobian rows, plus actuators and couplings; the analytic grasps of
  :mod:`pinograsp.core.examples` are scenes of this kind.

Every error is a :class:`~pinograsp.errors.SceneError` naming the file and the key path
(``case1.yaml: object.pose.xyz: expected 3 numbers, got 2``).

This module is on the URDF side: it never imports a solver (``Settings`` are built lazily).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..core.actuation import ACTUATOR_KINDS, Actuator, Coupling
from ..core.axes import WRENCH_AXES, axis_index
from ..core.contact import Contact
from ..core.model import GraspModel
from ..core.settings import METHODS, Method
from ..errors import PinograspError, SceneError, UnknownNameError

#: Folder of the built-in scenes shipped with pinograsp.
SCENE_DIR = Path(__file__).resolve().parents[1] / "data" / "scenes"

#: ``analysis`` keys that become :class:`pinograsp.analysis.response.Settings` fields.
_SETTINGS_KEYS = (
    "backend",
    "max_nodes",
    "accelerate",
    "solver",
    "time_limit",
    "bigm",
    "bigm_retries",
    "gamma",
    "eps",
    "improvement",
    "max_iterations",
    "variant",
    "tolerance",
    "eps_rel",
    "complementarity",
    "verify_infeasible",
)
_ANALYSIS_KEYS = (
    "method",
    "upper",
    "steps",
    "plane",
    "planes",
    "n",
    "normalize",
    "directions",
    "wrenches",
    "preloads",
) + _SETTINGS_KEYS
_COMMON_KEYS = ("name", "description", "preload", "analysis", "planar", "edges", "circumscribed", "extends")
_URDF_KEYS = _COMMON_KEYS + (
    "hand",
    "configuration",
    "object",
    "frame",
    "friction",
    "stiffness",
    "tolerance",
    "max_penetration",
    "expect_contacts",
)
_EXPLICIT_KEYS = _COMMON_KEYS + (
    "joints",
    "contacts",
    "actuators",
    "couplings",
    "reference_point",
    "friction",
    "stiffness",
)
_DEG = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*deg\s*$")


# ---------------------------------------------------------------------------- the result
@dataclass(frozen=True)
class SceneAnalysis:
    """A scene file's ``analysis`` block, validated (docs/scenes.md).

    Attributes:
        method: Analysis method.
        upper: Upper limit of the max-wrench search [N or N·m].
        steps: Search steps (resolution ``upper / 2**steps``).
        n: Directions of a profile.
        plane: Default profile plane (two axis names or two 6-vectors).
        planes: Named planes, name -> plane.
        normalize: Profile normalisation (``None``, ``True`` or an axis name / vector).
        directions: Named directions, name -> unit 6-vector.
        wrenches: Named wrenches, name -> 6-vector [N, N·m].
        preloads: Named preloads, name -> ``{actuator: command}``.
    """

    method: Method = Method.ITERATIVE
    upper: float = 1e3
    steps: int = 20
    n: int = 72
    plane: tuple = ("fx", "fy")
    planes: dict[str, tuple] = field(default_factory=dict)
    normalize: object = None
    directions: dict[str, np.ndarray] = field(default_factory=dict)
    wrenches: dict[str, np.ndarray] = field(default_factory=dict)
    preloads: dict[str, dict[str, float]] = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class Scene:
    """A loaded scene: the grasp model, its preload and its analysis settings.

    Attributes:
        name: Scene name.
        description: One-line description.
        path: The scene file.
        model: The :class:`~pinograsp.core.model.GraspModel` (in the analysis frame).
        command: The preload ``{actuator: value}`` over every actuator of the model
            (``model.all_actuator_names``) [N·m or N].
        settings: Solver settings (:class:`pinograsp.analysis.response.Settings`) from the ``analysis``
            block.
        analysis: The validated ``analysis`` block (:class:`SceneAnalysis`).
        hand: The :class:`~pinograsp.robots.hand.Hand` (``None`` for explicit-contact scenes).
        q: Hand configuration, URDF coordinates (``None`` for explicit-contact scenes).
        object: The :class:`~pinograsp.robots.objects.RigidObject` (``None`` for explicit scenes).
        frame: Analysis frame in the hand base frame, 4×4 (identity by default; ``None`` for
            explicit scenes). Model points, normals, Jacobians and every wrench of the scene
            are expressed in it.
        contacts: The contacts handed to the model (analysis frame).
        data: The scene file's content as read (after overrides).
    """

    name: str
    description: str
    path: Path
    model: GraspModel
    command: dict[str, float]
    settings: Any
    analysis: SceneAnalysis
    hand: Any = None
    q: np.ndarray | None = None
    object: Any = None
    frame: np.ndarray | None = None
    contacts: tuple[Contact, ...] = ()
    data: dict[str, Any] = field(default_factory=dict, repr=False)

    def preload(self, name: str | None = None) -> dict[str, float]:
        """The scene's preload, or the named preload of ``analysis.preloads``."""
        if name is None:
            return dict(self.command)
        if not isinstance(name, str) or name not in self.analysis.preloads:
            raise UnknownNameError("preload", name, list(self.analysis.preloads))
        return dict(self.analysis.preloads[name])

    def direction(self, name: str) -> np.ndarray:
        """A named direction of ``analysis.directions`` (unit 6-vector)."""
        if not isinstance(name, str) or name not in self.analysis.directions:
            raise UnknownNameError("direction", name, list(self.analysis.directions))
        return np.array(self.analysis.directions[name])

    def _query_args(self, overrides: dict[str, Any]) -> dict[str, Any]:
        """The scene's analysis block (method, upper, steps, settings) with ``overrides``."""
        kw = {k: overrides.pop(k, getattr(self.analysis, k)) for k in ("method", "upper", "steps")}
        kw["settings"] = overrides.pop("settings", self.settings)
        return kw

    def passive_response(self, wrench: object, command: object = None, **overrides: Any) -> Any:
        """:func:`pinograsp.passive_response` with the scene's method and settings
        (``command``: the scene preload by default, or a named preload)."""
        from ..analysis.response import passive_response

        kw = self._query_args(overrides)
        cmd = self.preload(command) if command is None or isinstance(command, str) else command
        return passive_response(self.model, cmd, wrench, kw["method"], settings=kw["settings"], **overrides)

    def max_resistible_wrench(self, direction: object, command: object = None, **overrides: Any) -> Any:
        """:func:`pinograsp.max_resistible_wrench` with the scene's method, ``upper``, ``steps``
        and settings; ``direction`` may name one of ``analysis.directions``."""
        from ..analysis.max_wrench import max_resistible_wrench

        kw = self._query_args(overrides)
        if isinstance(direction, str) and direction in self.analysis.directions:
            direction = self.direction(direction)
        cmd = self.preload(command) if command is None or isinstance(command, str) else command
        return max_resistible_wrench(self.model, cmd, direction, **kw, **overrides)

    def profile(self, plane: object = None, command: object = None, **overrides: Any) -> Any:
        """:func:`pinograsp.resistance_profile` with the scene's method, ``upper``, ``steps``,
        ``n``, ``normalize`` and settings; ``plane`` may name one of ``analysis.planes``."""
        from ..analysis.profile import resistance_profile

        kw = self._query_args(overrides)
        if plane is None:
            plane = self.analysis.plane
        elif isinstance(plane, str):
            if plane not in self.analysis.planes:
                raise UnknownNameError("plane", plane, list(self.analysis.planes))
            plane = self.analysis.planes[plane]
        kw["n"] = overrides.pop("n", self.analysis.n)
        kw["normalize"] = overrides.pop("normalize", self.analysis.normalize)
        cmd = self.preload(command) if command is None or isinstance(command, str) else command
        return resistance_profile(self.model, cmd, plane, **kw, **overrides)

    def summary(self) -> str:
        """A short human-readable description of the scene."""
        lines = [f"scene {self.name!r}: {self.description}", self.model.summary()]
        lines.append("  contacts: " + ", ".join(self.model.contact_names))
        lines.append("  preload: " + ", ".join(f"{k}={v:g}" for k, v in self.command.items()))
        return "\n".join(lines)


# ---------------------------------------------------------------------------- validation helpers
class _File:
    """Error factory for one scene file."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def error(self, key: str, detail: str) -> SceneError:
        return SceneError(self.path, key, detail)

    def mapping(self, value: object, key: str, what: str = "a mapping") -> Mapping:
        if not isinstance(value, Mapping):
            raise self.error(key, f"expected {what}, got {_show(value)}")
        return value

    def keys(self, value: Mapping, valid: Sequence[str], key: str) -> None:
        for k in value:
            if k not in valid:
                where = f"{key}.{k}" if key else str(k)
                raise self.error(where, f"unknown key; valid keys: {', '.join(valid)}")

    def require(self, value: Mapping, name: str, key: str) -> object:
        if name not in value or value[name] is None:
            raise self.error(f"{key}.{name}" if key else name, "missing required key")
        return value[name]

    def number(
        self, value: object, key: str, *, positive: bool = False, nonneg: bool = False, angle: bool = False
    ) -> float:
        if isinstance(value, bool):
            raise self.error(key, f"expected a number, got {_show(value)}")
        if angle and isinstance(value, str):
            m = _DEG.match(value)
            if m:
                return math.radians(float(m.group(1)))
        try:
            v = float(value)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            hint = " (angles may be written '60 deg')" if angle else ""
            raise self.error(key, f"expected a number, got {_show(value)}{hint}") from None
        if not math.isfinite(v):
            raise self.error(key, f"must be finite, got {value!r}")
        if positive and v <= 0:
            raise self.error(key, f"must be > 0, got {value!r}")
        if nonneg and v < 0:
            raise self.error(key, f"must be >= 0, got {value!r}")
        return v

    def integer(self, value: object, key: str, minimum: int = 1) -> int:
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise self.error(key, f"expected an integer, got {_show(value)}")
        if value < minimum:
            raise self.error(key, f"must be >= {minimum}, got {value}")
        return int(value)

    def boolean(self, value: object, key: str) -> bool:
        if not isinstance(value, bool):
            raise self.error(key, f"expected true or false, got {_show(value)}")
        return value

    def string(self, value: object, key: str) -> str:
        if not isinstance(value, str) or not value:
            raise self.error(key, f"expected a non-empty string, got {_show(value)}")
        return value

    def vector(self, value: object, n: int | Sequence[int], key: str, *, angle: bool = False) -> np.ndarray:
        sizes = (n,) if isinstance(n, int) else tuple(n)
        want = " or ".join(str(s) for s in sizes)
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
            raise self.error(key, f"expected {want} numbers, got {_show(value)}")
        if len(value) not in sizes:
            raise self.error(key, f"expected {want} numbers, got {len(value)}")
        return np.array([self.number(v, f"{key}[{i}]", angle=angle) for i, v in enumerate(value)])

    def names(self, value: object, key: str) -> list[str]:
        if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
            raise self.error(key, f"expected a list of names, got {_show(value)}")
        return [self.string(v, f"{key}[{i}]") for i, v in enumerate(value)]

    def relpath(self, value: object, key: str) -> Path:
        p = Path(self.string(value, key)).expanduser()
        return p if p.is_absolute() else (self.path.parent / p)


def _show(value: object) -> str:
    text = repr(value)
    kind = type(value).__name__
    return f"{kind} {text if len(text) <= 60 else text[:57] + '...'}"


def _rotation_rpy(r: float, p: float, y: float) -> np.ndarray:
    """URDF convention: ``R = Rz(y) Ry(p) Rx(r)`` (fixed-axis roll, pitch, yaw)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def _pose(f: _File, value: object, key: str) -> np.ndarray:
    """``{xyz: [..], rpy: [..]}`` (URDF convention, radians or 'N deg') -> 4×4."""
    T = np.eye(4)
    if value is None:
        return T
    v = f.mapping(value, key, "a mapping with 'xyz' and/or 'rpy'")
    f.keys(v, ("xyz", "rpy"), key)
    if "xyz" in v:
        T[:3, 3] = f.vector(v["xyz"], 3, f"{key}.xyz")
    if "rpy" in v:
        T[:3, :3] = _rotation_rpy(*f.vector(v["rpy"], 3, f"{key}.rpy", angle=True))
    return T


# ---------------------------------------------------------------------------- hands (cached)
_HAND_CACHE: dict[tuple, Any] = {}


def _mtime(p: Path) -> float:
    try:
        return p.stat().st_mtime
    except OSError:
        return -1.0


def _load_hand(f: _File, spec: object) -> tuple[Any, list[str]]:
    """The scene's hand (cached per process) and its locked joints."""
    from ..robots.hand import BUILTIN_HANDS, Hand  # URDF side

    if isinstance(spec, str):
        spec = {"builtin": spec}
    s = f.mapping(spec, "hand", "a built-in hand name or a mapping with 'builtin' or 'urdf'")
    f.keys(s, ("builtin", "urdf", "description", "package_dirs", "lock"), "hand")
    lock = f.names(s["lock"], "hand.lock") if s.get("lock") is not None else []
    if ("builtin" in s) == ("urdf" in s):
        raise f.error("hand", "give exactly one of 'builtin' (a shipped hand) or 'urdf' (a file)")
    if "builtin" in s:
        name = f.string(s["builtin"], "hand.builtin")
        if "description" in s or "package_dirs" in s:
            raise f.error("hand", "'description' and 'package_dirs' only go with 'urdf'")
        if name not in BUILTIN_HANDS:
            raise f.error(
                "hand.builtin", f"unknown hand {name!r}; built-in hands: {', '.join(BUILTIN_HANDS)}"
            )
        key: tuple = ("builtin", name)
        if key not in _HAND_CACHE:
            _HAND_CACHE[key] = Hand.builtin(name)
        return _HAND_CACHE[key], lock
    urdf = f.relpath(s["urdf"], "hand.urdf")
    if not urdf.is_file():
        raise f.error("hand.urdf", f"URDF file not found: {urdf}")
    desc: Any = None
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
        _mtime(urdf),
        repr(desc) if not isinstance(desc, Path) else (str(desc.resolve()), _mtime(desc)),
        tuple(dirs or ()),
    )
    if key not in _HAND_CACHE:
        try:
            _HAND_CACHE[key] = Hand.from_urdf(urdf, desc, package_dirs=dirs)
        except PinograspError as exc:
            raise f.error("hand", str(exc)) from exc
    return _HAND_CACHE[key], lock


def clear_cache() -> None:
    """Forget the hands loaded by earlier scenes (e.g. after editing a URDF in place)."""
    _HAND_CACHE.clear()


# ---------------------------------------------------------------------------- objects
def _load_object(f: _File, spec: object) -> Any:
    from dataclasses import replace

    from ..robots.objects import RigidObject  # URDF side (Coal)

    s = f.mapping(spec, "object")
    shape = f.string(f.require(s, "shape", "object"), "object.shape")
    common = ("shape", "pose", "center_of_mass", "name")
    extra = {
        "box": ("size",),
        "cylinder": ("radius", "length"),
        "sphere": ("radius",),
        "mesh": ("file", "scale", "convex"),
    }
    if shape not in extra:
        raise f.error("object.shape", f"unknown shape {shape!r}; valid shapes: {', '.join(extra)}")
    f.keys(s, common + extra[shape], "object")
    pose = _pose(f, s.get("pose"), "object.pose")
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


# ---------------------------------------------------------------------------- configurations
def _joint_values(f: _File, hand: Any, value: object, key: str) -> dict[str, float]:
    v = f.mapping(value, key, "a mapping joint -> value [rad or m]")
    out = {}
    for j, x in v.items():
        if j not in hand.joint_names:
            raise f.error(f"{key}.{j}", f"unknown joint; hand joints: {', '.join(hand.joint_names)}")
        out[str(j)] = f.number(x, f"{key}.{j}", angle=True)
    # URDF mimics: a follower that is not given follows its leader
    for m in hand.mimics:
        if m.leader in out and m.follower not in out:
            out[m.follower] = m.multiplier * out[m.leader] + m.offset
    return out


def _configuration(f: _File, hand: Any, obj: Any, value: object, tol: float) -> np.ndarray:
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
        return hand.close_on(obj, q_open, tolerance=tol, step=step)
    except PinograspError as exc:
        raise f.error("configuration.auto_close", str(exc)) from exc


def _per_name(f: _File, value: object, key: str, names: Sequence[str], default: float, **kw: bool) -> Any:
    """Scalar, or ``{default: x, <name>: y}`` -> scalar or {name: value}."""
    if value is None:
        return default
    if not isinstance(value, Mapping):
        return f.number(value, key, **kw)
    out = {}
    dflt = default
    for k, x in value.items():
        if k == "default":
            dflt = f.number(x, f"{key}.default", **kw)
        elif k not in names:
            raise f.error(f"{key}.{k}", f"unknown name; valid: default, {', '.join(names)}")
        else:
            out[str(k)] = f.number(x, f"{key}.{k}", **kw)
    return {n: out.get(n, dflt) for n in names}


# ---------------------------------------------------------------------------- URDF scenes
def _lock_joints(
    f: _File,
    lock: Sequence[str],
    joint_names: Sequence[str],
    contacts: list[Contact],
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


def _build_urdf(f: _File, d: Mapping) -> dict[str, Any]:
    from ..robots.collision import DEFAULT_MAX_PENETRATION, DEFAULT_TOLERANCE
    from ..robots.grasp import scene_contacts

    f.keys(d, _URDF_KEYS, "")
    hand, lock = _load_hand(f, d["hand"])
    tol = f.number(d.get("tolerance", DEFAULT_TOLERANCE), "tolerance", positive=True)
    pen = f.number(d.get("max_penetration", DEFAULT_MAX_PENETRATION), "max_penetration", positive=True)
    obj = _load_object(f, f.require(d, "object", ""))
    q = _configuration(f, hand, obj, d.get("configuration"), tol)
    links = list(hand.contact_link_names)
    mu = _per_name(f, d.get("friction"), "friction", links, 0.5, nonneg=True)
    k = _per_name(f, d.get("stiffness"), "stiffness", links, 1.0, positive=True)
    try:
        contacts, report = scene_contacts(
            hand, q, obj, mu=mu, stiffness=k, tolerance=tol, max_penetration=pen
        )
    except PinograspError as exc:
        raise f.error("configuration", f"{type(exc).__name__}: {exc}") from exc
    if d.get("expect_contacts") is not None:
        want = f.integer(d["expect_contacts"], "expect_contacts")
        if len(contacts) != want:
            got = ", ".join(c.link for c in report.contacts)
            raise f.error("expect_contacts", f"expected {want} contacts, detected {len(contacts)}: {got}")
    T = _pose(f, d.get("frame"), "frame")
    o = T[:3, :3].T @ (obj.center_of_mass - T[:3, 3])
    contacts = [_to_frame(c, T) for c in contacts]
    names, contacts, acts, cps = _lock_joints(
        f, lock, hand.joint_names, contacts, hand.actuators, hand.couplings
    )
    return {
        "hand": hand,
        "q": q,
        "object": obj,
        "frame": T,
        "contacts": contacts,
        "actuators": acts,
        "couplings": cps,
        "joint_names": names,
        "reference_point": o,
        "default_command": dict(hand.commands),
    }


# ---------------------------------------------------------------------------- explicit scenes
def _actuators(f: _File, value: object, key: str) -> list[Actuator]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise f.error(key, f"expected a list of actuators, got {_show(value)}")
    out = []
    for i, a in enumerate(value):
        ka = f"{key}[{i}]"
        a = f.mapping(a, ka)
        f.keys(a, ("name", "kind", "transmission", "bidirectional"), ka)
        tr = f.mapping(f.require(a, "transmission", ka), f"{ka}.transmission", "a mapping joint -> arm")
        trv = {str(j): f.number(v, f"{ka}.transmission.{j}") for j, v in tr.items()}
        kind = str(a.get("kind", "non-backdrivable"))
        if kind not in ACTUATOR_KINDS:
            raise f.error(f"{ka}.kind", f"unknown kind {kind!r}; valid kinds: {', '.join(ACTUATOR_KINDS)}")
        bidir = a.get("bidirectional", False)
        if not isinstance(bidir, bool):
            raise f.error(f"{ka}.bidirectional", f"expected true or false, got {_show(bidir)}")
        out.append(Actuator(trv, kind, str(a.get("name", f"a{i}")), bidirectional=bidir))
    return out


def _couplings(f: _File, value: object, key: str) -> list[Coupling]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Sequence):
        raise f.error(key, f"expected a list of couplings, got {_show(value)}")
    out = []
    for i, c in enumerate(value):
        kc = f"{key}[{i}]"
        c = f.mapping(c, kc)
        f.keys(c, ("name", "weights", "follower", "leader", "ratio"), kc)
        name = str(c.get("name", f"coupling{i}"))
        if "weights" in c:
            w = f.mapping(c["weights"], f"{kc}.weights")
            out.append(Coupling({str(j): f.number(v, f"{kc}.weights.{j}") for j, v in w.items()}, name))
        elif "follower" in c and "leader" in c:
            ratio = f.number(c.get("ratio", 1.0), f"{kc}.ratio")
            fo, le = f.string(c["follower"], f"{kc}.follower"), f.string(c["leader"], f"{kc}.leader")
            if fo == le:
                raise f.error(kc, f"joint {fo!r} cannot follow itself")
            out.append(Coupling.follow(fo, le, ratio, name=name))
        else:
            raise f.error(kc, "give 'weights', or 'follower', 'leader' and 'ratio'")
    return out


def _build_explicit(f: _File, d: Mapping) -> dict[str, Any]:
    f.keys(d, _EXPLICIT_KEYS, "")
    joints = f.names(d["joints"], "joints") if d.get("joints") is not None else []
    if len(set(joints)) != len(joints):
        raise f.error("joints", f"duplicate joint names in {joints}")
    nq = len(joints)
    raw = d["contacts"]
    if isinstance(raw, (str, bytes)) or not isinstance(raw, Sequence) or not raw:
        raise f.error("contacts", f"expected a non-empty list of contacts, got {_show(raw)}")
    cnames = []
    for i, c in enumerate(raw):
        c = f.mapping(c, f"contacts[{i}]")
        cnames.append(str(c.get("name", f"c{i}")))
    mu = _per_name(f, d.get("friction"), "friction", cnames, 0.5, nonneg=True)
    kk = _per_name(f, d.get("stiffness"), "stiffness", cnames, 1.0, positive=True)
    contacts = []
    for i, c in enumerate(raw):
        kc = f"contacts[{i}]"
        f.keys(c, ("name", "point", "normal", "mu", "stiffness", "tangent", "revolute", "jacobian"), kc)
        p = f.vector(f.require(c, "point", kc), 3, f"{kc}.point")
        n = f.vector(f.require(c, "normal", kc), 3, f"{kc}.normal")
        nn = float(np.linalg.norm(n))
        if not nn > 0:
            raise f.error(f"{kc}.normal", "zero-length normal")
        n = n / nn
        mu_i = f.number(c["mu"], f"{kc}.mu", nonneg=True) if "mu" in c else _pick(mu, cnames[i])
        k_i = (
            f.number(c["stiffness"], f"{kc}.stiffness", positive=True)
            if "stiffness" in c
            else _pick(kk, cnames[i])
        )
        t = f.vector(c["tangent"], 3, f"{kc}.tangent") if c.get("tangent") is not None else None
        if "revolute" in c and "jacobian" in c:
            raise f.error(kc, "give 'revolute' or 'jacobian', not both")
        jac = np.zeros((3, nq))
        if c.get("revolute") is not None:
            rv = f.mapping(c["revolute"], f"{kc}.revolute", "a mapping joint -> {pivot, axis}")
            for j, spec in rv.items():
                kj = f"{kc}.revolute.{j}"
                if j not in joints:
                    raise f.error(kj, f"unknown joint; joints: {', '.join(joints) or '(none declared)'}")
                spec = f.mapping(spec, kj, "a mapping with 'pivot' and 'axis'")
                f.keys(spec, ("pivot", "axis"), kj)
                pivot = f.vector(f.require(spec, "pivot", kj), 3, f"{kj}.pivot")
                axis = f.vector(f.require(spec, "axis", kj), 3, f"{kj}.axis")
                if not np.linalg.norm(axis) > 0:
                    raise f.error(f"{kj}.axis", "zero-length axis")
                jac[:, joints.index(str(j))] = np.cross(axis / np.linalg.norm(axis), p - pivot)
        elif c.get("jacobian") is not None:
            rows = c["jacobian"]
            if isinstance(rows, (str, bytes)) or not isinstance(rows, Sequence) or len(rows) != 3:
                raise f.error(f"{kc}.jacobian", f"expected 3 rows of {nq} numbers, got {_show(rows)}")
            jac = np.array([f.vector(r, nq, f"{kc}.jacobian[{ri}]") for ri, r in enumerate(rows)])
        try:
            contacts.append(Contact(p, n, mu_i, jac, t, k_i, cnames[i]))
        except PinograspError as exc:
            raise f.error(kc, str(exc)) from exc
    acts = _actuators(f, d["actuators"], "actuators") if d.get("actuators") is not None else None
    cps = _couplings(f, d["couplings"], "couplings") if d.get("couplings") is not None else []
    for key, items, attr in (("actuators", acts or [], "transmission"), ("couplings", cps, "weights")):
        for i, it in enumerate(items):
            for j in getattr(it, attr):
                if j not in joints:
                    raise f.error(
                        f"{key}[{i}].{attr}.{j}", f"unknown joint; joints: {', '.join(joints) or '(none)'}"
                    )
    o = f.vector(d["reference_point"], 3, "reference_point") if d.get("reference_point") is not None else None
    return {
        "contacts": contacts,
        "actuators": acts,
        "couplings": cps,
        "joint_names": joints,
        "reference_point": o,
        "default_command": None,
    }


def _pick(value: Any, name: str) -> float:
    return float(value[name]) if isinstance(value, dict) else float(value)


# ---------------------------------------------------------------------------- preload and analysis
def _command(f: _File, model: GraspModel, value: object, key: str) -> dict[str, float]:
    """Validate a command (scalar, list over actuators, or {actuator: value}) -> full dict."""
    names = model.all_actuator_names
    if isinstance(value, Mapping):
        for a in value:
            if a not in names:
                raise f.error(f"{key}.{a}", f"unknown actuator; actuators: {', '.join(names)}")
        vals = {a: f.number(value.get(a, 0.0), f"{key}.{a}") for a in names}
    elif isinstance(value, Sequence) and not isinstance(value, (str, bytes)):
        if len(value) != len(names):
            raise f.error(
                key, f"expected {len(names)} values (actuators {', '.join(names)}), got {len(value)}"
            )
        vals = {a: f.number(v, f"{key}[{i}]") for i, (a, v) in enumerate(zip(names, value))}
    else:
        x = f.number(value, key)
        vals = dict.fromkeys(names, x)
    try:
        model.command_vector(vals)
    except PinograspError as exc:  # pragma: no cover - validated above
        raise f.error(key, str(exc)) from exc
    return vals


def _wrench(f: _File, model: GraspModel, value: object, key: str, unit: bool) -> np.ndarray:
    if isinstance(value, str):
        name = value.strip()
        sign = -1.0 if name.startswith("-") else 1.0
        try:
            idx = axis_index(name.lstrip("+-"))
        except UnknownNameError:
            raise f.error(key, f"unknown wrench axis {value!r}; axes: {', '.join(WRENCH_AXES)}") from None
        w = np.zeros(6)
        w[idx] = sign
    else:
        w = f.vector(value, (3, 6) if model.planar else 6, key)
    try:
        w = model.wrench_vector(w, key)
    except PinograspError as exc:
        raise f.error(key, str(exc).split(": ", 1)[-1]) from exc
    if unit:
        n = float(np.linalg.norm(w))
        if not n > 0:
            raise f.error(key, "zero-length direction")
        w = w / n
    return w


def _plane(f: _File, model: GraspModel, value: object, key: str) -> tuple:
    if isinstance(value, str):
        value = [v.strip() for v in value.split(",")]
    if isinstance(value, (bytes, Mapping)) or not isinstance(value, Sequence) or len(value) != 2:
        raise f.error(key, f"expected two wrench axes (e.g. [fx, fy]) or two vectors, got {_show(value)}")
    b = [_wrench(f, model, v, f"{key}[{i}]", unit=True) for i, v in enumerate(value)]
    if np.linalg.norm(b[1] - (b[1] @ b[0]) * b[0]) < 1e-9:
        raise f.error(key, "the two directions are parallel")
    return tuple(v if isinstance(v, str) else tuple(float(x) for x in b[i]) for i, v in enumerate(value))


def _analysis(f: _File, model: GraspModel, value: object) -> tuple[SceneAnalysis, Any]:
    from ..core.settings import make_settings

    a = f.mapping(value if value is not None else {}, "analysis")
    f.keys(a, _ANALYSIS_KEYS, "analysis")
    out: dict[str, Any] = {}
    method = a.get("method", "iterative")
    if method not in METHODS:
        raise f.error("analysis.method", f"must be one of {', '.join(METHODS)}, got {method!r}")
    out["method"] = Method(method)
    out["upper"] = f.number(a.get("upper", 1e3), "analysis.upper", positive=True)
    out["steps"] = f.integer(a.get("steps", 20), "analysis.steps")
    out["n"] = f.integer(a.get("n", 72), "analysis.n")
    planes: dict[str, tuple] = {}
    if a.get("planes") is not None:
        pm = f.mapping(a["planes"], "analysis.planes", "a mapping name -> [axis, axis]")
        for k, v in pm.items():
            planes[str(k)] = _plane(f, model, v, f"analysis.planes.{k}")
    if a.get("plane") is not None:
        out["plane"] = _plane(f, model, a["plane"], "analysis.plane")
    else:
        out["plane"] = next(iter(planes.values())) if planes else ("fx", "fy")
    out["planes"] = planes or {"default": out["plane"]}
    norm = a.get("normalize", None)
    if norm is not None and not isinstance(norm, bool):
        _wrench(f, model, norm, "analysis.normalize", unit=True)
    out["normalize"] = norm
    dirs = f.mapping(a.get("directions") or {}, "analysis.directions", "a mapping name -> axis or vector")
    out["directions"] = {
        str(k): _wrench(f, model, v, f"analysis.directions.{k}", True) for k, v in dirs.items()
    }
    wr = f.mapping(a.get("wrenches") or {}, "analysis.wrenches", "a mapping name -> wrench vector")
    out["wrenches"] = {str(k): _wrench(f, model, v, f"analysis.wrenches.{k}", False) for k, v in wr.items()}
    pre = f.mapping(a.get("preloads") or {}, "analysis.preloads", "a mapping name -> command")
    out["preloads"] = {str(k): _command(f, model, v, f"analysis.preloads.{k}") for k, v in pre.items()}
    overrides = {k: a[k] for k in _SETTINGS_KEYS if k in a}
    for k, v in overrides.items():
        if k in ("solver", "variant", "backend", "complementarity"):
            if v is not None and not isinstance(v, str):
                raise f.error(f"analysis.{k}", f"expected a string, got {_show(v)}")
        elif k in ("accelerate", "verify_infeasible"):
            f.boolean(v, f"analysis.{k}")
        elif k in ("bigm_retries", "max_iterations", "max_nodes"):
            f.integer(v, f"analysis.{k}", minimum=0)
        else:
            overrides[k] = f.number(v, f"analysis.{k}")
    try:
        settings = make_settings(**overrides)
    except PinograspError as exc:
        bad = getattr(exc, "name", "")
        if bad not in overrides and "solver" in overrides and "solver" in str(exc):
            bad = "solver"
        msg = str(exc).removeprefix(f"{bad}: ") if bad in overrides else str(exc)
        raise f.error(f"analysis.{bad}" if bad in overrides else "analysis", msg) from exc
    return SceneAnalysis(**out), settings


# ---------------------------------------------------------------------------- entry points
def _read(path: Path) -> dict[str, Any]:
    import yaml

    f = _File(path)
    if not path.is_file():
        raise f.error("", "scene file not found")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise f.error("", f"malformed YAML: {' '.join(str(exc).split())}") from exc
    except (OSError, UnicodeDecodeError) as exc:
        raise f.error("", f"cannot read the file: {exc}") from exc
    if not isinstance(data, Mapping):
        raise f.error("", f"expected a mapping of scene keys, got {_show(data)}")
    return dict(data)


def _extended(f: _File, data: dict[str, Any], seen: list[Path]) -> dict[str, Any]:
    """Apply ``extends: <scene name or file>``: the base's top-level keys, replaced by ours."""
    if data.get("extends") is None:
        data.pop("extends", None)
        return data
    ref = f.string(data.pop("extends"), "extends")
    local = f.relpath(ref, "extends")
    base = local if local.is_file() else SCENE_DIR / f"{ref}.yaml"
    if not base.is_file():
        raise f.error("extends", f"no scene file {local} and no built-in scene {ref!r}")
    if base.resolve() in seen:
        raise f.error("extends", f"circular 'extends' through {base.name}")
    merged = _extended(_File(base), _read(base), [*seen, base.resolve()])
    merged.update(data)
    return merged


def _resolve(name_or_path: str | Path) -> Path:
    if isinstance(name_or_path, Path):
        return name_or_path
    s = str(name_or_path)
    builtin = SCENE_DIR / f"{s}.yaml"
    if "/" not in s and "\\" not in s and not s.endswith((".yaml", ".yml")):
        if builtin.is_file():
            return builtin
        if not Path(s).is_file():
            raise UnknownNameError("scene", s, list(builtin_scenes()))
    return Path(s)


def load_scene(name_or_path: str | Path, **overrides: object) -> Scene:
    """Load a scene: a built-in name (``pg.builtin_scenes()``) or a YAML file.

    Args:
        name_or_path: ``"case1"``, ``"pinch"``, ... or the path of a scene file.
        **overrides: Top-level scene keys replacing the file's (shallow: ``planar=True``,
            ``preload={"f1": 1.0}``, ``analysis={...}`` replaces the whole block).

    Returns:
        The validated :class:`Scene`.

    Raises:
        SceneError: The file is missing or malformed (the message names the file and key).
        UnknownNameError: ``name_or_path`` is neither a built-in scene nor a file.
    """
    path = _resolve(name_or_path)
    f = _File(path)
    data = _extended(f, _read(path), [path.resolve()])
    data.update(overrides)
    if "hand" in data and "contacts" in data:
        raise f.error("", "a scene has either 'hand' (URDF scene) or 'contacts' (explicit scene), not both")
    if "hand" not in data and "contacts" not in data:
        raise f.error(
            "hand", "missing required key ('hand' for a URDF scene, or 'contacts' for explicit contacts)"
        )
    name = f.string(data.get("name", path.stem), "name")
    desc = data.get("description", "")
    if not isinstance(desc, str):
        raise f.error("description", f"expected a string, got {_show(desc)}")
    parts = _build_urdf(f, data) if "hand" in data else _build_explicit(f, data)
    planar = f.boolean(data.get("planar", False), "planar")
    edges = None if data.get("edges") is None else f.integer(data["edges"], "edges", minimum=3)
    circ = f.boolean(data.get("circumscribed", False), "circumscribed")
    try:
        model = GraspModel.from_contacts(
            parts["contacts"],
            actuators=parts["actuators"],
            couplings=parts["couplings"],
            planar=planar,
            reference_point=parts["reference_point"],
            joint_names=parts["joint_names"],
            edges=edges,
            circumscribed=circ,
        )
    except PinograspError as exc:
        key = "planar" if planar and "plane" in str(exc) else ("actuators" if "actuator" in str(exc) else "")
        raise f.error(key, f"cannot build the grasp model: {exc}") from exc
    if data.get("preload") is not None:
        command = _command(f, model, data["preload"], "preload")
    elif parts["default_command"] is not None:
        command = _command(f, model, parts["default_command"], "preload")
    else:
        raise f.error("preload", "missing required key (actuator command [N·m or N])")
    analysis, settings = _analysis(f, model, data.get("analysis"))
    return Scene(
        name=name,
        description=" ".join(desc.split()),
        path=path,
        model=model,
        command=command,
        settings=settings,
        analysis=analysis,
        hand=parts.get("hand"),
        q=parts.get("q"),
        object=parts.get("object"),
        frame=parts.get("frame"),
        contacts=tuple(parts["contacts"]),
        data=data,
    )


_BUILTIN_CACHE: dict[str, tuple[float, str]] = {}


def builtin_scenes() -> dict[str, str]:
    """Built-in scenes: ``{name: description}`` (files in ``pinograsp/data/scenes``)."""
    import yaml

    out = {}
    for p in sorted(SCENE_DIR.glob("*.yaml")):
        mt = _mtime(p)
        hit = _BUILTIN_CACHE.get(str(p))
        if hit is None or hit[0] != mt:
            try:
                data = yaml.safe_load(p.read_text()) or {}
                desc = " ".join(str(data.get("description", "")).split())
            except yaml.YAMLError:  # pragma: no cover - shipped files are tested
                desc = "(malformed scene file)"
            _BUILTIN_CACHE[str(p)] = hit = (mt, desc)
        out[p.stem] = hit[1]
    return out
