"""Robot hands from URDF: kinematics (Pinocchio), collision geometry (Coal) and a hand description.

A :class:`Hand` is a Pinocchio model reduced to the hand's own joints, its collision geometry,
and a :class:`HandDescription` that says how the hand is driven (docs/design.md):

* **closing signs**: positive motion of every joint, in the grasp model, closes the hand onto the
  object. URDF axes vary, so each joint carries a sign ``s_j = ±1``: closing joint velocity
  ``= s_j × URDF joint velocity``. Configurations ``q`` are always **URDF joint positions**
  ([rad] or [m]); only velocities, Jacobians, transmissions and couplings use closing coordinates.
* **actuators**: name, kind (``non-backdrivable``/``backdrivable``/``locked``) and transmission
  column ``{joint: moment arm}`` in closing coordinates. Default: one non-backdrivable direct-drive
  actuator per hand joint that does not mimic another joint.
* **couplings**: rigid ``C q = 0`` in closing coordinates. URDF ``<mimic>`` tags become couplings
  automatically (``q_f = m q_l + offset`` gives ``qc_f = s_f m s_l qc_l``).
* **hand joints**: the rest (e.g. an arm) are locked at a reference configuration with
  ``pinocchio.buildReducedModel``; the **base link** becomes the world frame of every result.

See ``docs/hands.md`` for the YAML schema.
"""

from __future__ import annotations

import importlib.metadata
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..core.actuation import ACTUATOR_KINDS, Actuator, Coupling
from ..core.validate import finite_number, positive_number, whole_number
from ..errors import InvalidInputError, ModelError, ModelFileError, UnknownNameError, UrdfError

if TYPE_CHECKING:
    from .objects import RigidObject

#: Folder of the URDF files and hand descriptions shipped with pinograsp.
DATA_DIR = Path(__file__).resolve().parents[1] / "data"

#: Hands loadable with :meth:`Hand.builtin`: name -> (URDF, description). A URDF path starting with
#: ``example-robot-data:`` is resolved inside the installed example-robot-data package.
BUILTIN_HANDS: dict[str, tuple[str, str]] = {
    "barrett_bh8_282": ("urdf/barrett_bh8_282.urdf", "urdf/barrett_bh8_282.yaml"),
    "underactuated_2f": ("urdf/underactuated_2f.urdf", "urdf/underactuated_2f.yaml"),
    "parallel_jaw": ("urdf/parallel_jaw.urdf", "urdf/parallel_jaw.yaml"),
    "allegro_right": (
        "example-robot-data:robots/allegro_hand_description/urdf/allegro_right_hand.urdf",
        "hands/allegro_right.yaml",
    ),
    "panda_hand": ("example-robot-data:robots/panda_description/urdf/panda.urdf", "hands/panda_hand.yaml"),
    "so101": ("example-robot-data:robots/so_arm_description/urdf/so101.urdf", "hands/so101.yaml"),
}


def example_robot_data_dir() -> Path:
    """The ``share`` folder of the installed ``example-robot-data`` (use it as ``package_dirs``).

    It contains ``example-robot-data/robots/...``, so that ``package://example-robot-data/...``
    mesh paths resolve.

    Raises:
        ModelFileError: example-robot-data is not installed or ships no robots.
    """
    try:
        files = importlib.metadata.files("example-robot-data") or []
    except importlib.metadata.PackageNotFoundError as exc:
        raise ModelFileError(
            "example-robot-data", "package not installed (pip install example-robot-data)"
        ) from exc
    for f in files:
        parts = Path(str(f)).parts
        if "example-robot-data" in parts and "robots" in parts and parts.index("robots") > 0:
            full = Path(str(f.locate())).resolve()
            # .../share/example-robot-data/robots/... -> .../share
            k = len(parts) - parts.index("example-robot-data")
            return full.parents[k - 1]
    raise ModelFileError("example-robot-data", "installed package contains no robots folder")


# ---------------------------------------------------------------------------- description
_KINDS_HELP = ", ".join(ACTUATOR_KINDS)


def _items(owner: str, value: object) -> list:
    """The entries of a list-valued description key (a mapping or a scalar is refused)."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (Sequence, np.ndarray)):
        raise InvalidInputError(owner, f"expected a list, got {value!r}")
    return list(value)


def _name_map(owner: str, value: object) -> dict[str, float]:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise InvalidInputError(owner, f"expected a mapping name -> number, got {value!r}")
    out = {}
    for k, v in value.items():
        if isinstance(v, (str, bytes)):
            raise InvalidInputError(owner, f"value of {k!r} is not a number: {v!r}")
        try:
            fv = float(v)
        except (TypeError, ValueError, OverflowError) as exc:
            raise InvalidInputError(owner, f"value of {k!r} is not a number: {v!r}") from exc
        if not np.isfinite(fv):
            raise InvalidInputError(owner, f"value of {k!r} is not finite")
        out[str(k)] = fv
    return out


@dataclass(frozen=True)
class HandDescription:
    """How a URDF hand is driven; every field is optional (see module docstring, ``docs/hands.md``).

    Attributes:
        name: Hand name (default: the URDF robot name).
        joints: Hand joints kept in the model; other movable joints are locked at
            ``reference_configuration``. ``None``: every movable joint.
        base_link: Link whose frame is the world (hand base) frame of all results; it must not
            move with the hand joints. ``None``: the URDF root link.
        reference_configuration: Positions of locked joints, URDF coordinates [rad or m]
            (default 0, Pinocchio's neutral).
        closing: Closing sign ``+1``/``-1`` per hand joint (default ``+1``).
        open_configuration: The open pose used by auto-close, URDF coordinates [rad or m]
            (default 0 clipped into the joint limits).
        actuators: Actuators in closing coordinates. ``None``: one non-backdrivable direct-drive
            actuator per hand joint that does not mimic another.
        couplings: Extra rigid couplings in closing coordinates (URDF mimics are added to them
            when ``use_mimic``).
        commands: Default actuator commands (preload) [N·m for direct drive, N for tendons].
        contact_links: Links whose collision geometry may touch the object. ``None``: every
            link at or below ``base_link``.
        use_mimic: Turn URDF ``<mimic>`` tags into couplings.
        source: File the description was read from, if any.
    """

    name: str | None = None
    joints: tuple[str, ...] | None = None
    base_link: str | None = None
    reference_configuration: Mapping[str, float] = field(default_factory=dict)
    closing: Mapping[str, float] = field(default_factory=dict)
    open_configuration: Mapping[str, float] = field(default_factory=dict)
    actuators: tuple[Actuator, ...] | None = None
    couplings: tuple[Coupling, ...] = ()
    commands: Mapping[str, float] = field(default_factory=dict)
    contact_links: tuple[str, ...] | None = None
    use_mimic: bool = True
    source: str | None = None

    def __post_init__(self) -> None:
        for key in ("name", "base_link", "source"):
            v = getattr(self, key)
            if v is not None and not isinstance(v, str):
                raise InvalidInputError(key, f"expected a string, got {v!r}")
        for key in ("joints", "contact_links"):
            v = getattr(self, key)
            if v is None:
                continue
            if isinstance(v, (str, bytes)) or not isinstance(v, (Sequence, np.ndarray)):
                raise InvalidInputError(key, f"expected a list of names, got {v!r}")
            for n in v:
                if not isinstance(n, str):
                    raise InvalidInputError(key, f"expected names (strings), got {n!r}")
            object.__setattr__(self, key, tuple(str(n) for n in v))
        if not isinstance(self.use_mimic, (bool, np.bool_)):
            raise InvalidInputError("use_mimic", f"expected true or false, got {self.use_mimic!r}")
        for key in ("reference_configuration", "closing", "open_configuration", "commands"):
            object.__setattr__(self, key, _name_map(key, getattr(self, key)))
        for j, s in self.closing.items():
            if s not in (1.0, -1.0):
                raise InvalidInputError(f"closing[{j!r}]", f"closing signs must be +1 or -1, got {s}")
        if self.actuators is not None:
            acts = tuple(self.actuators)
            for a in acts:
                if not isinstance(a, Actuator):
                    raise InvalidInputError(
                        "actuators", f"expected pinograsp.Actuator, got {type(a).__name__}"
                    )
            object.__setattr__(self, "actuators", acts)
        cps = tuple(self.couplings or ())
        for c in cps:
            if not isinstance(c, Coupling):
                raise InvalidInputError("couplings", f"expected pinograsp.Coupling, got {type(c).__name__}")
        object.__setattr__(self, "couplings", cps)

    @classmethod
    def from_dict(cls, data: Mapping[str, object], source: str | None = None) -> HandDescription:
        """Build a description from a mapping with the YAML schema of ``docs/hands.md``.

        Raises:
            UnknownNameError: An unknown key (the valid keys are listed).
            InvalidInputError: A malformed value.
        """
        if data is None:
            data = {}
        if not isinstance(data, Mapping):
            raise InvalidInputError("hand description", f"expected a mapping, got {type(data).__name__}")
        valid = [f.name for f in fields(cls) if f.name != "source"] + ["urdf"]
        for key in data:
            if key not in valid:
                raise UnknownNameError("hand description key", key, valid)
        kw: dict[str, object] = {k: v for k, v in data.items() if k not in ("actuators", "couplings", "urdf")}
        if "actuators" in data and data["actuators"] is not None:
            acts = []
            for i, a in enumerate(_items("actuators", data["actuators"])):
                if not isinstance(a, Mapping) or "transmission" not in a:
                    raise InvalidInputError(
                        f"actuators[{i}]", "expected a mapping with 'transmission' (and 'name', 'kind')"
                    )
                valid = ["name", "kind", "transmission", "bidirectional"]
                extra = set(a) - set(valid)
                if extra:
                    raise UnknownNameError("actuator key", sorted(extra)[0], valid)
                acts.append(
                    Actuator(
                        transmission=a["transmission"],
                        kind=a.get("kind", "non-backdrivable"),
                        name=a.get("name", f"a{i}"),
                        bidirectional=a.get("bidirectional", False),
                    )
                )
            kw["actuators"] = tuple(acts)
        cps = []
        for i, c in enumerate(_items("couplings", data.get("couplings") or ())):
            if not isinstance(c, Mapping):
                raise InvalidInputError(f"couplings[{i}]", f"expected a mapping, got {c!r}")
            name = c.get("name", f"coupling{i}")
            if "weights" in c:
                cps.append(Coupling(c["weights"], name=name))
            elif {"follower", "leader"} <= set(c):
                cps.append(
                    Coupling.follow(
                        str(c["follower"]),
                        str(c["leader"]),
                        finite_number(f"couplings[{i}].ratio", c.get("ratio", 1.0)),
                        name=name,
                    )
                )
            else:
                raise InvalidInputError(
                    f"couplings[{i}]", "give 'weights' or 'follower', 'leader' and 'ratio'"
                )
        kw["couplings"] = tuple(cps)
        for key in ("joints", "contact_links"):
            if kw.get(key) is not None:
                if isinstance(kw[key], (str, bytes)) or not isinstance(kw[key], Sequence):
                    raise InvalidInputError(key, f"expected a list of names, got {kw[key]!r}")
                kw[key] = tuple(kw[key])  # type: ignore[arg-type]
        return cls(**kw, source=source)  # type: ignore[arg-type]

    @classmethod
    def from_yaml(cls, path: str | Path) -> HandDescription:
        """Read a hand description YAML file.

        Raises:
            ModelFileError: Missing or malformed file (the path is in the message).
        """
        import yaml

        p = Path(path)
        if not p.is_file():
            raise ModelFileError(p, "hand description file not found")
        try:
            data = yaml.safe_load(p.read_text())
        except yaml.YAMLError as exc:
            raise ModelFileError(p, f"malformed YAML: {exc}") from exc
        try:
            return cls.from_dict(data or {}, source=str(p))
        except (InvalidInputError, UnknownNameError) as exc:
            raise ModelFileError(p, str(exc)) from exc


# ---------------------------------------------------------------------------- URDF parsing
@dataclass(frozen=True)
class Mimic:
    """A URDF ``<mimic>`` tag: ``q_follower = multiplier * q_leader + offset`` (URDF coordinates)."""

    follower: str
    leader: str
    multiplier: float = 1.0
    offset: float = 0.0


def _parse_urdf_xml(path: Path) -> tuple[list[str], list[str], list[Mimic]]:
    """Joint names, link names and mimic tags of a URDF, with XML errors reported per file."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise UrdfError(path, f"malformed XML: {exc}") from exc
    if root.tag != "robot":
        raise UrdfError(path, f"root element is <{root.tag}>, expected <robot>")
    joints, links, mimics = [], [], []
    for ln in root.findall("link"):
        links.append(ln.get("name", ""))
    for jt in root.findall("joint"):
        name = jt.get("name")
        if not name:
            raise UrdfError(path, "a <joint> has no name")
        joints.append(name)
        m = jt.find("mimic")
        if m is not None:
            if not m.get("joint"):
                raise UrdfError(path, f"<mimic> of joint {name!r} has no 'joint' attribute")
            try:
                mimics.append(
                    Mimic(
                        name, m.get("joint", ""), float(m.get("multiplier", 1.0)), float(m.get("offset", 0.0))
                    )
                )
            except ValueError as exc:
                raise UrdfError(path, f"<mimic> of joint {name!r}: {exc}") from exc
    return joints, links, mimics


# ---------------------------------------------------------------------------- hand
class Hand:
    """A robot hand: reduced Pinocchio model, Coal collision geometry and description.

    Build it with :meth:`from_urdf` or :meth:`builtin`. Attributes (read-only by convention):

    Attributes:
        name: Hand name.
        urdf_path: The URDF file.
        description: The :class:`HandDescription`.
        model: Pinocchio model with only the hand joints; its world frame is the base link.
        geometry: Pinocchio ``GeometryModel`` of the collision geometries that may touch objects.
        joint_names: Hand joints in configuration order, (nq,).
        closing_signs: ``s_j = ±1`` per joint, (nq,).
        lower, upper: Joint limits, URDF coordinates, (nq,) [rad or m].
        actuators: Actuators (closing coordinates, joints by name).
        couplings: Couplings (mimics first, then the description's), joints by name.
        mimics: The URDF mimic tags between hand joints.
        commands: Default commands per actuator name.
    """

    def __init__(
        self,
        model: pin.Model,
        geometry: pin.GeometryModel,
        description: HandDescription,
        *,
        urdf_path: Path,
        mimics: Sequence[Mimic] = (),
        link_names: Sequence[str] = (),
    ) -> None:
        self.model = model
        self.data = model.createData()
        self.geometry = geometry
        self.geometry_data = (
            geometry.createData() if hasattr(geometry, "createData") else pin.GeometryData(geometry)
        )
        self.description = description
        self.urdf_path = Path(urdf_path)
        self.name = description.name or self.urdf_path.stem
        self.joint_names: tuple[str, ...] = tuple(model.names[j] for j in range(1, model.njoints))
        nq = len(self.joint_names)
        for j in range(1, model.njoints):
            if model.joints[j].nq != 1 or model.joints[j].nv != 1:
                raise UrdfError(
                    urdf_path,
                    f"joint {model.names[j]!r} ({model.joints[j].shortname()}) has {model.joints[j].nq} "
                    "position coordinates; only 1-DoF revolute/prismatic hand joints are supported "
                    "(lock it via the description's 'joints' list, or make it 'revolute' with limits)",
                )
        if model.nq != nq:
            raise UrdfError(urdf_path, f"model has {model.nq} coordinates for {nq} joints")
        self._is_prismatic = np.array(
            [
                model.joints[j].shortname().replace("JointModel", "").startswith("P")
                for j in range(1, model.njoints)
            ]
        )
        self.link_names: tuple[str, ...] = tuple(link_names)

        def check_joint(owner: str, name: str) -> str:
            if name not in self.joint_names:
                raise UnknownNameError("joint", name, self.joint_names)
            return name

        signs = np.ones(nq)
        for j, s in description.closing.items():
            signs[self.joint_names.index(check_joint("closing", j))] = s
        self.closing_signs = signs
        self.closing_signs.setflags(write=False)
        self.lower = np.array(model.lowerPositionLimit, dtype=float)
        self.upper = np.array(model.upperPositionLimit, dtype=float)

        self.mimics = tuple(mimics)
        couplings: list[Coupling] = []
        followers = set()
        for m in self.mimics:
            s_f = signs[self.joint_names.index(m.follower)]
            s_l = signs[self.joint_names.index(m.leader)]
            couplings.append(
                Coupling.follow(m.follower, m.leader, s_f * m.multiplier * s_l, name=f"mimic:{m.follower}")
            )
            followers.add(m.follower)
        for c in description.couplings:
            for key in c.weights:
                if not isinstance(key, str):
                    raise InvalidInputError(f"coupling {c.name!r}", "description couplings must name joints")
                check_joint(f"coupling {c.name!r}", key)
            couplings.append(c)
        self.couplings: tuple[Coupling, ...] = tuple(couplings)

        if description.actuators is None:
            acts = tuple(Actuator({j: 1.0}, name=j) for j in self.joint_names if j not in followers)
        else:
            acts = description.actuators
            for a in acts:
                for key in a.transmission:
                    if not isinstance(key, str):
                        raise InvalidInputError(
                            f"actuator {a.name!r}", "description actuators must name joints"
                        )
                    check_joint(f"actuator {a.name!r}", key)
        names = [a.name for a in acts]
        if len(set(names)) != len(names):
            raise ModelError(f"duplicate actuator names in hand {self.name!r}: {names}")
        self.actuators: tuple[Actuator, ...] = tuple(acts)
        for a in description.commands:
            if a not in names:
                raise UnknownNameError("actuator", a, names)
        self.commands: dict[str, float] = {n: float(description.commands.get(n, 0.0)) for n in names}

        q_open = np.clip(np.zeros(nq), self.lower, self.upper)
        for j, v in description.open_configuration.items():
            q_open[self.joint_names.index(check_joint("open_configuration", j))] = v
        self.q_open = q_open
        self.q_open.setflags(write=False)

    # ------------------------------------------------------------ construction
    @classmethod
    def from_urdf(
        cls,
        urdf_path: str | Path,
        description: HandDescription | Mapping[str, object] | str | Path | None = None,
        package_dirs: Sequence[str | Path] | str | Path | None = None,
    ) -> Hand:
        """Load a hand from a URDF file.

        Args:
            urdf_path: The URDF file.
            description: A :class:`HandDescription`, a mapping with the YAML schema, a YAML file,
                or ``None``: the ``<urdf stem>.yaml`` next to the URDF if it exists, otherwise
                the default description (every movable joint a non-backdrivable direct-drive
                actuator closing in its positive sense; mimics as couplings).
            package_dirs: Folders in which ``package://`` mesh paths are resolved. Default: the
                URDF's folder and its parent, plus example-robot-data's ``share`` folder when
                installed.

        Raises:
            UrdfError: Missing or malformed URDF, missing mesh file, unsupported hand joint.
            ModelFileError: Missing or malformed description file.
            UnknownNameError: The description names a joint, link or actuator that does not exist.
        """
        if not isinstance(urdf_path, (str, Path)):
            raise InvalidInputError("urdf_path", f"expected a file path, got {urdf_path!r}")
        path = Path(urdf_path)
        if not path.is_file():
            raise UrdfError(path, "URDF file not found")
        if description is not None and not isinstance(description, (HandDescription, Mapping, str, Path)):
            raise InvalidInputError(
                "description",
                "expected a HandDescription, a mapping or a YAML file path, "
                f"got {type(description).__name__}",
            )
        if description is None:
            side = path.with_suffix(".yaml")
            desc = HandDescription.from_yaml(side) if side.is_file() else HandDescription()
        elif isinstance(description, HandDescription):
            desc = description
        elif isinstance(description, Mapping):
            desc = HandDescription.from_dict(description)
        else:
            desc = HandDescription.from_yaml(description)

        urdf_joints, urdf_links, mimics = _parse_urdf_xml(path)
        if package_dirs is None:
            dirs = [str(path.parent), str(path.parent.parent)]
            try:
                dirs.append(str(example_robot_data_dir()))
            except ModelFileError:
                pass
        elif isinstance(package_dirs, (str, Path)):
            dirs = [str(package_dirs)]
        elif isinstance(package_dirs, (Sequence, np.ndarray)) and all(
            isinstance(d, (str, Path)) for d in package_dirs
        ):
            dirs = [str(d) for d in package_dirs]
        else:
            raise InvalidInputError("package_dirs", f"expected folder paths, got {package_dirs!r}")
        try:
            model, geom = pin.buildModelsFromUrdf(
                str(path), package_dirs=dirs, geometry_types=pin.GeometryType.COLLISION
            )
        except (ValueError, RuntimeError) as exc:
            msg = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise UrdfError(path, f"Pinocchio cannot load it: {msg} (package_dirs: {dirs})") from exc

        # Pinocchio silently skips collision elements it cannot parse (e.g. <capsule>): refuse that
        expected: dict[str, int] = {}
        for ln in ET.parse(path).getroot().findall("link"):
            expected[ln.get("name", "")] = len(ln.findall("collision"))
        loaded: dict[str, int] = {}
        for g in geom.geometryObjects:
            loaded[model.frames[g.parentFrame].name] = loaded.get(model.frames[g.parentFrame].name, 0) + 1
        for ln, n in expected.items():
            if loaded.get(ln, 0) < n:
                raise UrdfError(
                    path,
                    f"link {ln!r}: {n - loaded.get(ln, 0)} of {n} <collision> elements were not loaded "
                    "(unsupported geometry such as <capsule>? use box, cylinder, sphere or mesh)",
                )
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
            model, geom = pin.buildReducedModel(model, geom, lock, q_ref)

        hand_mimics = []
        for m in mimics if desc.use_mimic else ():
            f_in, l_in = m.follower in hand_joints, m.leader in hand_joints
            if f_in and l_in:
                hand_mimics.append(m)
            elif f_in != l_in:
                raise ModelError(
                    f"{path}: joint {m.follower!r} mimics {m.leader!r} but only one of them is a hand joint; "
                    "keep both in (or both out of) the description's 'joints'"
                )

        # base link -> world frame
        body_frames = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        base = desc.base_link or next((f.name for f in model.frames if f.type == pin.FrameType.BODY), None)
        if base is None or not model.existFrame(base):
            raise UnknownNameError("link", base, body_frames)
        base_id = model.getFrameId(base)
        if model.frames[base_id].parentJoint != 0:
            mover = model.names[model.frames[base_id].parentJoint]
            raise ModelError(
                f"{path}: base link {base!r} moves with joint {mover!r}; "
                "the base link must be fixed (lock the joints above it)"
            )
        _rebase(model, geom, model.frames[base_id].placement.inverse())

        # contact geometry: the given links, or every link at or below the base link
        def below_base(fid: int) -> bool:
            while True:
                if fid == base_id:
                    return True
                parent = model.frames[fid].parentFrame
                if parent == fid:
                    return False
                fid = parent

        if desc.contact_links is not None:
            for ln in desc.contact_links:
                if ln not in body_frames:
                    raise UnknownNameError("link", ln, body_frames)
            keep = [g for g in geom.geometryObjects if model.frames[g.parentFrame].name in desc.contact_links]
        else:
            keep = [g for g in geom.geometryObjects if below_base(g.parentFrame)]
        contact_geom = pin.GeometryModel()
        for g in keep:
            contact_geom.addGeometryObject(g)
        if desc.name is None:
            try:
                robot_name = ET.parse(path).getroot().get("name")
            except ET.ParseError:  # pragma: no cover - parsed above
                robot_name = None
            desc = HandDescription(
                **{**{f.name: getattr(desc, f.name) for f in fields(desc)}, "name": robot_name}
            )
        return cls(model, contact_geom, desc, urdf_path=path, mimics=hand_mimics, link_names=urdf_links)

    @classmethod
    def builtin(cls, name: str) -> Hand:
        """A hand shipped with pinograsp (or described by it), by name.

        Names: ``barrett_bh8_282``, ``underactuated_2f``, ``parallel_jaw`` (URDFs in
        ``pinograsp/data/urdf``),
        ``allegro_right``, ``panda_hand`` and ``so101`` (URDFs from example-robot-data, descriptions in
        ``pinograsp/data/hands``).

        Raises:
            UnknownNameError: Unknown hand name (the valid ones are listed).
        """
        if not isinstance(name, str) or name not in BUILTIN_HANDS:
            raise UnknownNameError("hand", name, sorted(BUILTIN_HANDS))
        urdf, desc = BUILTIN_HANDS[name]
        if urdf.startswith("example-robot-data:"):
            share = example_robot_data_dir()
            urdf_path = share / "example-robot-data" / urdf.split(":", 1)[1]
            return cls.from_urdf(urdf_path, DATA_DIR / desc, package_dirs=[share])
        return cls.from_urdf(DATA_DIR / urdf, DATA_DIR / desc)

    # ------------------------------------------------------------ sizes and names
    @property
    def nq(self) -> int:
        """Number of hand joints."""
        return len(self.joint_names)

    @property
    def actuator_names(self) -> tuple[str, ...]:
        """Actuator names."""
        return tuple(str(a.name) for a in self.actuators)

    @property
    def contact_link_names(self) -> tuple[str, ...]:
        """Links that carry contact geometry (in geometry order, without repeats)."""
        out: list[str] = []
        for g in self.geometry.geometryObjects:
            n = self.model.frames[g.parentFrame].name
            if n not in out:
                out.append(n)
        return tuple(out)

    def joint_index(self, name: str) -> int:
        """Index of a hand joint in ``q``."""
        if name not in self.joint_names:
            raise UnknownNameError("joint", name, self.joint_names)
        return self.joint_names.index(name)

    def configuration(self, q: object = None, name: str = "q") -> np.ndarray:
        """Validate a hand configuration (URDF coordinates [rad or m]) and return it, (nq,).

        Args:
            q: ``None`` (the open configuration), a sequence of ``nq`` numbers in
                :attr:`joint_names` order, or a mapping ``{joint: value}`` (other joints at the
                open configuration).
            name: Argument name used in error messages.
        """
        if q is None:
            return np.array(self.q_open)
        if isinstance(q, Mapping):
            out = np.array(self.q_open)
            for k, v in q.items():
                out[self.joint_index(str(k))] = finite_number(f"{name}[{k!r}]", v)
            arr = out
        else:
            if isinstance(q, (str, bytes)):
                raise InvalidInputError(name, f"expected {self.nq} numbers, got {q!r}")
            try:
                arr = np.asarray(q, dtype=float).reshape(-1)
            except (TypeError, ValueError, OverflowError) as exc:
                raise InvalidInputError(name, f"expected {self.nq} numbers, got {q!r}") from exc
            if arr.shape != (self.nq,):
                raise InvalidInputError(
                    name, f"expected {self.nq} joint values (joints {list(self.joint_names)}), got {arr.size}"
                )
        if not np.all(np.isfinite(arr)):
            raise InvalidInputError(name, "contains NaN or inf", arr)
        return np.array(arr, dtype=float)

    def forward(self, q: np.ndarray) -> None:
        """Forward kinematics, frame and collision-geometry placements at ``q`` (validated)."""
        pin.forwardKinematics(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        pin.updateGeometryPlacements(self.model, self.data, self.geometry, self.geometry_data)

    def link_of_geometry(self, index: int) -> str:
        """Name of the link carrying collision geometry ``index``."""
        return self.model.frames[self.geometry.geometryObjects[index].parentFrame].name

    # ------------------------------------------------------------ auto-close
    def closing_direction(self) -> np.ndarray:
        """Closing rate per joint in closing coordinates, (nq,).

        Every actuator that is not locked pulls with unit effort: joint ``j`` gets the sum of its
        positive moment arms; joints in a locked actuator's transmission do not move; the rates
        are projected onto the couplings' null space (``C d = 0``) and scaled to a largest
        component of 1.
        """
        d = np.zeros(self.nq)
        frozen = np.zeros(self.nq, bool)
        for a in self.actuators:
            for j, arm in a.transmission.items():
                idx = self.joint_index(str(j))
                if a.kind == "locked":
                    frozen[idx] = True
                else:
                    d[idx] += max(arm, 0.0)
        C = self.coupling_matrix()
        d[frozen] = 0.0
        if C.shape[0]:
            # joints that share a coupling with a frozen joint are frozen too
            changed = True
            while changed:
                changed = False
                for row in C:
                    touched = row != 0
                    if np.any(frozen & touched) and not np.all(frozen[touched]):
                        frozen |= touched
                        changed = True
            d[frozen] = 0.0
            N = _null_space(C)  # (nq, k)
            d = N @ (N.T @ d)
            d[np.abs(d) < 1e-12] = 0.0
        m = np.abs(d).max() if d.size else 0.0
        return d / m if m > 0 else d

    def coupling_matrix(self) -> np.ndarray:
        """``C`` of the couplings in closing coordinates, (ncp, nq)."""
        C = np.zeros((len(self.couplings), self.nq))
        for r, c in enumerate(self.couplings):
            for j, w in c.weights.items():
                C[r, self.joint_index(str(j))] += w
        return C

    def close_on(
        self,
        obj: RigidObject,
        q_open: object = None,
        *,
        tolerance: float | None = None,
        step: float = 0.03,
        max_steps: int = 2000,
    ) -> np.ndarray:
        """Close the hand on an object (like GraspIt!'s auto-grasp) and return the configuration.

        Joints move along :meth:`closing_direction` from ``q_open`` in steps of at most ``step``
        [rad] (``step / 10`` [m] for prismatic joints). When a link comes within the contact
        tolerance of the object, the joints that carry it stop, with every joint rigidly
        coupled to them; joints further out keep closing. A joint stops at its limit (and its
        coupled joints with it). Each touch is located by bisection so that the touching
        link's signed distance ends in ``[-tolerance/2, tolerance/2]``.

        Args:
            obj: The object (pose in the hand base frame).
            q_open: Start configuration (default: the description's open configuration).
            tolerance: Contact tolerance [m] (default :data:`pinograsp.robots.collision.DEFAULT_TOLERANCE`).
            step: Largest joint step per iteration [rad]; thin objects need a smaller one.
            max_steps: Safety limit on the number of steps.

        Returns:
            The closed configuration (URDF coordinates), (nq,).

        Raises:
            PenetrationError: ``q_open`` already penetrates the object.
            NoContactError: every joint reached its limit and no link touches the object (the
                error lists each link's closest distance [m]).
        """
        from .collision import DEFAULT_TOLERANCE, geometry_distances

        tol = DEFAULT_TOLERANCE if tolerance is None else positive_number("tolerance", tolerance)
        step = positive_number("step", step)
        max_steps = whole_number("max_steps", max_steps)
        q = self.configuration(q_open, "q_open")
        q = np.clip(q, self.lower, self.upper)
        d = self.closing_direction() * self.closing_signs  # URDF-coordinate rates
        scale = np.where(self._is_prismatic, step / 10.0, step)
        C = self.coupling_matrix()
        # joints moved rigidly together: connected components of the couplings
        group = np.arange(self.nq)
        for row in C:
            idx = np.flatnonzero(row)
            g = group[idx].min()
            for i in idx:
                group[group == group[i]] = g
        geo_joint = np.array([g.parentJoint for g in self.geometry.geometryObjects], dtype=int)
        support = {
            int(j): [int(s) - 1 for s in self.model.supports[int(j)] if s > 0]
            for j in set(geo_joint.tolist())
        }
        # geometry k moves when any joint in its support moves
        active = d != 0

        def moving_geoms() -> np.ndarray:
            return np.array([any(active[s] for s in support[int(j)]) for j in geo_joint], dtype=bool)

        def stop_for(k: int) -> None:
            for s in support[int(geo_joint[k])]:
                active[group == group[s]] = False

        dist = geometry_distances(self, q, obj)
        deep = {self.link_of_geometry(k): v for k, v in enumerate(dist) if v < -tol}
        if deep:
            from ..errors import PenetrationError

            raise PenetrationError(deep, tol, {self.link_of_geometry(k): v for k, v in enumerate(dist)})
        for k in np.flatnonzero(dist <= tol / 2):
            stop_for(int(k))

        for _ in range(max_steps):
            if not active.any():
                break
            mov = moving_geoms()
            dq = np.where(active, d * scale, 0.0)
            # shorten each coupled group's step so that none of its joints passes a limit (the
            # group keeps its couplings); a group that reaches a limit stops
            room = np.where(dq > 0, self.upper - q, self.lower - q)  # signed room to the limit
            frac = np.ones(self.nq)
            moving = dq != 0
            frac[moving] = np.clip(room[moving] / dq[moving], 0.0, 1.0)
            at_limit = np.zeros(self.nq, bool)
            for g in np.unique(group[moving]):
                members = group == g
                alpha = frac[members & moving].min()
                dq[members] *= alpha
                if alpha < 1.0:
                    at_limit |= members & active

            def trial(
                h: float, q0: np.ndarray = q, dq: np.ndarray = dq, mov: np.ndarray = mov
            ) -> tuple[np.ndarray, np.ndarray]:
                qt = q0 + h * dq
                return qt, geometry_distances(self, qt, obj, mask=mov)

            lo, hi = 0.0, 1.0
            qt, dt = trial(1.0)
            if np.any(dt[mov] < -tol / 2):
                # bisection on the step: largest h with no moving link below -tol/2
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
                qt, dt = q_lo, d_lo
                at_limit = np.zeros_like(at_limit)
            q, dist = qt, np.where(mov, dt, dist)
            for k in np.flatnonzero(mov & (dist <= tol / 2)):
                stop_for(int(k))
            for j in np.flatnonzero(at_limit):
                active[group == group[j]] = False
        if not np.any(dist <= tol):
            # every joint stopped at a limit without touching: say where the object is
            from ..errors import NoContactError

            near: dict[str, float] = {}
            for k, v in enumerate(dist):
                link = self.link_of_geometry(k)
                near[link] = min(float(v), near.get(link, np.inf))
            raise NoContactError(near, tol)
        return q

    def __repr__(self) -> str:
        return (
            f"Hand({self.name!r}, joints={list(self.joint_names)}, actuators={list(self.actuator_names)}, "
            f"{len(self.geometry.geometryObjects)} collision geometries)"
        )


def _null_space(C: np.ndarray, rtol: float = 1e-10) -> np.ndarray:
    """Orthonormal basis of the null space of ``C``, (n, k)."""
    _, s, vt = np.linalg.svd(C)
    rank = int(np.sum(s > rtol * max(s.max() if s.size else 0.0, 1.0)))
    return vt[rank:].T


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
