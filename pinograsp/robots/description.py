"""Hand descriptions: how a URDF hand is driven, read from YAML (schema in ``docs/hands.md``).

A :class:`HandDescription` says what the URDF cannot (docs/design.md):

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

This module also lists the hands shipped with pinograsp (:data:`BUILTIN_HANDS`) and finds the
installed example-robot-data (:func:`example_robot_data_dir`).
"""

from __future__ import annotations

import importlib.metadata
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ..core.actuation import Actuator, Coupling
from ..core.validate import finite_number
from ..errors import InvalidInputError, ModelFileError, UnknownNameError
from .yamlfile import load_file, yaml_problem

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
    "allegro_left": (
        "example-robot-data:robots/allegro_hand_description/urdf/allegro_left_hand.urdf",
        "hands/allegro_left.yaml",
    ),
    "ezgripper": ("urdf/ezgripper.urdf", "hands/ezgripper.yaml"),
    "hey5": ("example-robot-data:robots/tiago_description/robots/tiago.urdf", "hands/hey5.yaml"),
    "ability": ("urdf/ability.urdf", "hands/ability.yaml"),
    "dex3": ("urdf/dex3.urdf", "hands/dex3.yaml"),
    "talos_gripper": (
        "example-robot-data:robots/talos_data/robots/talos_full_v2.urdf",
        "hands/talos_gripper.yaml",
    ),
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


def _items(owner: str, value: object) -> list:
    """The entries of a list-valued description key (a mapping or a scalar is refused)."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (Sequence, np.ndarray)):
        raise InvalidInputError(owner, f"expected a list, got {value!r}")
    return list(value)


def _name_map(owner: str, value: object) -> dict[str, float]:
    """A ``{name: finite number}`` mapping (``None``: empty)."""
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


def _names(key: str, value: object) -> tuple[str, ...] | None:
    """A list of names as a tuple (``None`` stays ``None``)."""
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not isinstance(value, (Sequence, np.ndarray)):
        raise InvalidInputError(key, f"expected a list of names, got {value!r}")
    for n in value:
        if not isinstance(n, str):
            raise InvalidInputError(key, f"expected names (strings), got {n!r}")
    return tuple(str(n) for n in value)


def _typed(key: str, values: tuple, kind: type) -> tuple:
    """``values``, checking that each is an instance of ``kind``."""
    for v in values:
        if not isinstance(v, kind):
            raise InvalidInputError(key, f"expected pinograsp.{kind.__name__}, got {type(v).__name__}")
    return values


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
            object.__setattr__(self, key, _names(key, getattr(self, key)))
        if not isinstance(self.use_mimic, (bool, np.bool_)):
            raise InvalidInputError("use_mimic", f"expected true or false, got {self.use_mimic!r}")
        for key in ("reference_configuration", "closing", "open_configuration", "commands"):
            object.__setattr__(self, key, _name_map(key, getattr(self, key)))
        for j, s in self.closing.items():
            if s not in (1.0, -1.0):
                raise InvalidInputError(f"closing[{j!r}]", f"closing signs must be +1 or -1, got {s}")
        if self.actuators is not None:
            object.__setattr__(self, "actuators", _typed("actuators", tuple(self.actuators), Actuator))
        object.__setattr__(self, "couplings", _typed("couplings", tuple(self.couplings or ()), Coupling))

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
        if data.get("actuators") is not None:
            kw["actuators"] = _actuators_from(data["actuators"])
        kw["couplings"] = _couplings_from(data.get("couplings"))
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
            data = load_file(p)  # no aliases, bounded size (docs/errors.md)
        except yaml.YAMLError as exc:
            raise ModelFileError(p, yaml_problem(exc)) from exc
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise ModelFileError(p, f"cannot read the file: {exc}") from exc
        try:
            return cls.from_dict(data or {}, source=str(p))
        except (InvalidInputError, UnknownNameError) as exc:
            raise ModelFileError(p, str(exc)) from exc


def _actuators_from(value: object) -> tuple[Actuator, ...]:
    """The ``actuators`` list of a description mapping as :class:`Actuator` objects."""
    acts = []
    for i, a in enumerate(_items("actuators", value)):
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
    return tuple(acts)


def _couplings_from(value: object) -> tuple[Coupling, ...]:
    """The ``couplings`` list of a description mapping (``weights``, or ``follower``/``leader``/``ratio``)."""
    cps = []
    for i, c in enumerate(_items("couplings", value or ())):
        if not isinstance(c, Mapping):
            raise InvalidInputError(f"couplings[{i}]", f"expected a mapping, got {c!r}")
        name = c.get("name", f"coupling{i}")
        if "weights" in c:
            cps.append(Coupling(c["weights"], name=name))
        elif {"follower", "leader"} <= set(c):
            ratio = finite_number(f"couplings[{i}].ratio", c.get("ratio", 1.0))
            cps.append(Coupling.follow(str(c["follower"]), str(c["leader"]), ratio, name=name))
        else:
            raise InvalidInputError(f"couplings[{i}]", "give 'weights' or 'follower', 'leader' and 'ratio'")
    return tuple(cps)
