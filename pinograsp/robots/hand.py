"""Robot hands from URDF: kinematic model (Pinocchio), collision geometry (Coal) and description.

A :class:`Hand` is a Pinocchio model reduced to the hand's own joints, its collision geometry,
and a :class:`~pinograsp.robots.description.HandDescription` that says how the hand is driven
(closing signs, actuators, couplings; ``docs/hands.md``). A hand holds no kinematic state: the
kinematics at a configuration is a :class:`~pinograsp.robots.kinematics.HandConfiguration`.

Where the rest lives: the description and the built-in hands in
:mod:`~pinograsp.robots.description`, URDF loading in :mod:`~pinograsp.robots.urdf`, auto-close
in :mod:`~pinograsp.robots.autoclose`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..core.actuation import Actuator, Coupling
from ..core.validate import coordinates, finite_number
from ..errors import InvalidInputError, ModelError, UnknownNameError, UrdfError
from . import autoclose
from .description import BUILTIN_HANDS, DATA_DIR, HandDescription, example_robot_data_dir
from .urdf import Mimic, load_urdf_hand

if TYPE_CHECKING:
    from .objects import RigidObject


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
        link_names: Every link of the URDF, in file order.
        prismatic: Whether each joint is prismatic (else revolute), (nq,).
        closing_signs: ``s_j = ±1`` per joint, (nq,).
        lower, upper: Joint limits, URDF coordinates, (nq,) [rad or m].
        actuators: Actuators (closing coordinates, joints by name).
        couplings: Couplings (mimics first, then the description's), joints by name.
        mimics: The URDF mimic tags between hand joints.
        commands: Default commands per actuator name.
        q_open: The open configuration, URDF coordinates, (nq,) [rad or m].
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
        self.geometry = geometry
        self.description = description
        self.urdf_path = Path(urdf_path)
        self.name = description.name or self.urdf_path.stem
        self.joint_names: tuple[str, ...] = _hand_joints(model, self.urdf_path)
        self.prismatic = np.array(
            [
                model.joints[j].shortname().replace("JointModel", "").startswith("P")
                for j in range(1, model.njoints)
            ]
        )
        self.link_names: tuple[str, ...] = tuple(link_names)
        signs = np.ones(self.nq)
        for j, s in description.closing.items():
            signs[self._index_of(j)] = s
        self.closing_signs = signs
        self.closing_signs.setflags(write=False)
        self.lower = np.array(model.lowerPositionLimit, dtype=float)
        self.upper = np.array(model.upperPositionLimit, dtype=float)
        self.mimics = tuple(mimics)
        self.couplings: tuple[Coupling, ...] = self._couplings()
        self.actuators: tuple[Actuator, ...] = self._actuators()
        names = list(self.actuator_names)
        for a in description.commands:
            if a not in names:
                raise UnknownNameError("actuator", a, names)
        self.commands: dict[str, float] = {n: float(description.commands.get(n, 0.0)) for n in names}
        q_open = np.clip(np.zeros(self.nq), self.lower, self.upper)
        for j, v in description.open_configuration.items():
            q_open[self._index_of(j)] = v
        self.q_open = self._mimics_follow(q_open, set(description.open_configuration))
        self.q_open.setflags(write=False)

    def _mimics_follow(self, q: np.ndarray, given: set) -> np.ndarray:
        """``q`` with every URDF mimic follower not in ``given`` placed by its leader
        (``multiplier * q_leader + offset``, clipped to its limits; chains in order): an open
        pose given for a leader opens its followers too."""
        moved = set(given)
        for _ in self.mimics:  # a chain of n mimics settles in n passes
            for m in self.mimics:
                if m.follower in given or m.leader not in moved or m.leader not in self.joint_names:
                    continue
                f, lead = self.joint_names.index(m.follower), self.joint_names.index(m.leader)
                q[f] = np.clip(m.multiplier * q[lead] + m.offset, self.lower[f], self.upper[f])
                moved.add(m.follower)
        return q

    def _index_of(self, name: object) -> int:
        """Index of joint ``name`` named by the description (unknown: :class:`UnknownNameError`)."""
        if name not in self.joint_names:
            raise UnknownNameError("joint", name, self.joint_names)
        return self.joint_names.index(name)

    def _couplings(self) -> tuple[Coupling, ...]:
        """The mimic couplings (closing coordinates), then the description's."""
        couplings: list[Coupling] = []
        for m in self.mimics:
            s_f = self.closing_signs[self.joint_names.index(m.follower)]
            s_l = self.closing_signs[self.joint_names.index(m.leader)]
            couplings.append(
                Coupling.follow(m.follower, m.leader, s_f * m.multiplier * s_l, name=f"mimic:{m.follower}")
            )
        for c in self.description.couplings:
            for key in c.weights:
                if not isinstance(key, str):
                    raise InvalidInputError(f"coupling {c.name!r}", "description couplings must name joints")
                self._index_of(key)
            couplings.append(c)
        return tuple(couplings)

    def _actuators(self) -> tuple[Actuator, ...]:
        """The description's actuators, or one direct drive per joint that mimics no other."""
        if self.description.actuators is None:
            followers = {m.follower for m in self.mimics}
            acts = tuple(Actuator({j: 1.0}, name=j) for j in self.joint_names if j not in followers)
        else:
            acts = self.description.actuators
            for a in acts:
                for key in a.transmission:
                    if not isinstance(key, str):
                        raise InvalidInputError(
                            f"actuator {a.name!r}", "description actuators must name joints"
                        )
                    self._index_of(key)
        names = [a.name for a in acts]
        if len(set(names)) != len(names):
            raise ModelError(f"duplicate actuator names in hand {self.name!r}: {names}")
        return tuple(acts)

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
        desc = _description(path, description)
        urdf = load_urdf_hand(path, desc, package_dirs)
        if desc.name is None:
            desc = replace(desc, name=urdf.xml.robot_name)
        return cls(
            urdf.model, urdf.geometry, desc, urdf_path=path, mimics=urdf.mimics, link_names=urdf.xml.links
        )

    @classmethod
    def builtin(cls, name: str) -> Hand:
        """A hand shipped with pinograsp (or described by it), by name.

        Names: ``barrett_bh8_282``, ``underactuated_2f``, ``parallel_jaw`` (URDFs in
        ``pinograsp/data/urdf``),
        ``allegro_right``, ``panda_hand`` and ``so101`` (URDFs from example-robot-data, descriptions in
        ``pinograsp/data/hands``), and the real hands ``allegro_left``, ``ezgripper``, ``hey5``,
        ``ability``, ``dex3`` and ``talos_gripper`` (each with a built-in scene of the same name;
        docs/hands.md, "Shipped and supported hands").

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
        text = (DATA_DIR / urdf).read_text()
        dirs = [example_robot_data_dir()] if "package://example-robot-data/" in text else None
        return cls.from_urdf(DATA_DIR / urdf, DATA_DIR / desc, package_dirs=dirs)

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
        return np.array(coordinates(name, arr), dtype=float)  # domain: docs/errors.md

    def link_of_geometry(self, index: int) -> str:
        """Name of the link carrying collision geometry ``index``."""
        return self.model.frames[self.geometry.geometryObjects[index].parentFrame].name

    # ------------------------------------------------------------ closing
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
        max_penetration: float | None = None,
    ) -> np.ndarray:
        """Close the hand on an object (like GraspIt!'s auto-grasp) and return the configuration.

        The same as ``pg.close_on(hand, obj, ...)`` (:func:`pinograsp.robots.autoclose.close_on`:
        the algorithm, arguments and errors).

        Returns:
            The closed configuration (URDF coordinates), (nq,) [rad or m].
        """
        return autoclose.close_on(
            self,
            obj,
            q_open,
            tolerance=tolerance,
            step=step,
            max_steps=max_steps,
            max_penetration=max_penetration,
        )

    def __repr__(self) -> str:
        return (
            f"Hand({self.name!r}, joints={list(self.joint_names)}, actuators={list(self.actuator_names)}, "
            f"{len(self.geometry.geometryObjects)} collision geometries)"
        )


def _hand_joints(model: pin.Model, urdf_path: Path) -> tuple[str, ...]:
    """Joint names of a reduced model, refusing joints with more than one coordinate."""
    for j in range(1, model.njoints):
        if model.joints[j].nq != 1 or model.joints[j].nv != 1:
            raise UrdfError(
                urdf_path,
                f"joint {model.names[j]!r} ({model.joints[j].shortname()}) has {model.joints[j].nq} "
                "position coordinates; only 1-DoF revolute/prismatic hand joints are supported "
                "(lock it via the description's 'joints' list, or make it 'revolute' with limits)",
            )
    names = tuple(model.names[j] for j in range(1, model.njoints))
    if model.nq != len(names):
        raise UrdfError(urdf_path, f"model has {model.nq} coordinates for {len(names)} joints")
    return names


def _description(path: Path, description: object) -> HandDescription:
    """The description given to :meth:`Hand.from_urdf`, or the ``<stem>.yaml`` next to the URDF."""
    if description is None:
        side = path.with_suffix(".yaml")
        return HandDescription.from_yaml(side) if side.is_file() else HandDescription()
    if isinstance(description, HandDescription):
        return description
    if isinstance(description, Mapping):
        return HandDescription.from_dict(description)
    if isinstance(description, (str, Path)):
        return HandDescription.from_yaml(description)
    raise InvalidInputError(
        "description",
        f"expected a HandDescription, a mapping or a YAML file path, got {type(description).__name__}",
    )


def _null_space(C: np.ndarray, rtol: float = 1e-10) -> np.ndarray:
    """Orthonormal basis of the null space of ``C``, (n, k)."""
    _, s, vt = np.linalg.svd(C)
    rank = int(np.sum(s > rtol * max(s.max() if s.size else 0.0, 1.0)))
    return vt[rank:].T
