"""The records of a scene file: its keys, the loaded :class:`Scene` and its parts (docs/scenes.md).

This module imports no solver: :class:`Scene`'s analysis shortcuts import
:mod:`pinograsp.analysis` when they are called, so ``load_scene`` loads neither the solvers nor
cvxpy.
"""

from __future__ import annotations

import builtins
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from ..core.actuation import Actuator, Coupling
from ..core.axes import AXIS_HINT, WRENCH_AXES, wrench_direction
from ..core.contact import Contact
from ..core.model import GraspModel
from ..core.query import Query
from ..core.settings import DEFAULT_METHOD, Method, Settings
from ..errors import UnknownNameError

if TYPE_CHECKING:  # the URDF side and the results only pass through
    from ..core.results import MaxWrench, PassiveResponse, ResistanceProfile
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

#: ``analysis`` keys that become :class:`~pinograsp.core.settings.Settings` fields.
SETTINGS_KEYS = (
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
    "tangential_ratio",
    "contact_stiffness",
    "giveway_slip",
    "giveway_rotation",
    "giveway_joint",
    "limit",
)
#: ``analysis`` keys written in [deg] -> the :class:`~pinograsp.core.settings.Settings` field
#: they set in [rad] (``cone_tolerance_deg: null``: the model's pyramids).
ANGLE_SETTINGS_KEYS = {
    "normal_uncertainty_deg": "normal_uncertainty",
    "cone_tolerance_deg": "cone_tolerance",
    "giveway_rotation_deg": "giveway_rotation",
    "giveway_joint_deg": "giveway_joint",
}
#: Keys of the ``analysis`` block.
ANALYSIS_KEYS = (
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
    *SETTINGS_KEYS,
    *ANGLE_SETTINGS_KEYS,
)
#: Top-level keys of every scene.
COMMON_KEYS = ("name", "description", "preload", "analysis", "planar", "edges", "circumscribed", "extends")
#: Top-level keys of a URDF scene (``hand:``).
URDF_KEYS = COMMON_KEYS + (
    "hand",
    "configuration",
    "object",
    "frame",
    "friction",
    "stiffness",
    "tolerance",
    "max_penetration",
    "expect_contacts",
    "patches",
    "patch_points",
)
#: Top-level keys of an explicit-contact scene (``contacts:``).
EXPLICIT_KEYS = COMMON_KEYS + (
    "joints",
    "contacts",
    "actuators",
    "couplings",
    "reference_point",
    "friction",
    "stiffness",
)

#: A plane of wrench space as written in a scene: two axis names or unit 6-vectors.
Plane = tuple[Any, Any]


@dataclass(frozen=True)
class GraspParts:
    """What a scene builder reads from a file: the pieces of the grasp model.

    Attributes:
        contacts: The contacts, analysis frame.
        actuators: The actuators (``None``: one direct-drive actuator per joint).
        couplings: Joint couplings.
        joint_names: Joint names, one per Jacobian column.
        reference_point: Torque reference point [m], (3,), or ``None`` (the origin).
        default_command: Preload used when the file has no ``preload`` (``None``: required).
        hand: The hand (URDF scenes only).
        q: Hand configuration, URDF coordinates (URDF scenes only).
        object: The grasped object (URDF scenes only).
        frame: Analysis frame in the hand base frame, 4×4 (URDF scenes only).
    """

    contacts: tuple[Contact, ...]
    actuators: tuple[Actuator, ...] | None
    couplings: tuple[Coupling, ...]
    joint_names: tuple[str, ...]
    reference_point: np.ndarray | None = None
    default_command: dict[str, float] | None = None
    hand: Hand | None = None
    q: np.ndarray | None = None
    object: RigidObject | None = None
    frame: np.ndarray | None = None


@dataclass(frozen=True)
class SceneAnalysis:
    """A scene file's ``analysis`` block, validated (docs/scenes.md).

    Attributes:
        method: Analysis method (``"quasistatic"``, the default when the file names none,
            ``"iterative"``, ``"prp"`` or ``"energetic"``).
        upper: Upper limit of the max-wrench search [N or N·m].
        steps: Search steps (resolution ``upper / 2**steps``).
        n: Directions of a profile.
        plane: Default profile plane (two axis names or two unit 6-vectors).
        planes: Named planes, name -> plane.
        normalize: Profile normalisation (``None``, ``True`` or an axis name / vector).
        directions: Named directions, name -> unit 6-vector.
        wrenches: Named wrenches, name -> 6-vector [N, N·m].
        preloads: Named preloads, name -> ``{actuator: command}`` [N·m or N].
    """

    method: str = Method(DEFAULT_METHOD)
    upper: float = 1e3
    steps: int = 20
    n: int = 72
    plane: Plane = ("fx", "fy")
    planes: dict[str, Plane] = field(default_factory=dict)
    normalize: object = None
    directions: dict[str, np.ndarray] = field(default_factory=dict)
    wrenches: dict[str, np.ndarray] = field(default_factory=dict)
    preloads: dict[str, dict[str, float]] = field(default_factory=dict)

    @property
    def query(self) -> Query:
        """The block's search as one record: method, ``upper``, ``steps`` (search ``"auto"``)."""
        return Query(self.method, self.upper, self.steps)


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
        settings: Solver settings from the ``analysis`` block.
        analysis: The validated ``analysis`` block.
        hand: The hand (``None`` for explicit-contact scenes).
        q: Hand configuration, URDF coordinates (``None`` for explicit-contact scenes).
        object: The grasped object (``None`` for explicit-contact scenes).
        frame: Analysis frame in the hand base frame, 4×4 (identity by default; ``None`` for
            explicit scenes). Model points, normals, Jacobians and every wrench of the scene
            are expressed in it.
        contacts: The contacts handed to the model (analysis frame).
        data: The scene file's content as read (after ``extends`` and overrides).
    """

    name: str
    description: str
    path: Path
    model: GraspModel
    command: dict[str, float]
    settings: Settings
    analysis: SceneAnalysis
    hand: Hand | None = None
    q: np.ndarray | None = None
    object: RigidObject | None = None
    frame: np.ndarray | None = None
    contacts: tuple[Contact, ...] = ()
    data: dict[str, Any] = field(default_factory=dict, repr=False)

    def preload(self, name: str | None = None) -> dict[str, float]:
        """The scene's preload, or the named preload of ``analysis.preloads`` [N·m or N]."""
        if name is None:
            return dict(self.command)
        if not isinstance(name, str) or name not in self.analysis.preloads:
            raise UnknownNameError(
                "preload",
                name,
                list(self.analysis.preloads),
                f"pass None for the scene's own preload {self.command}, or a command (a number, "
                "one value per actuator, or {actuator: value}) [N·m or N]",
            )
        return dict(self.analysis.preloads[name])

    def direction(self, name: str) -> np.ndarray:
        """A named direction of ``analysis.directions`` (unit 6-vector)."""
        if not isinstance(name, str) or name not in self.analysis.directions:
            raise UnknownNameError("direction", name, list(self.analysis.directions))
        return np.array(self.analysis.directions[name])

    def _command(self, command: builtins.object) -> builtins.object:
        """The scene preload (``None``), a named preload (a string) or ``command`` as given."""
        return self.preload(command) if command is None or isinstance(command, str) else command

    def _query_args(self, overrides: dict[str, Any]) -> dict[str, Any]:
        """The scene's query (:attr:`SceneAnalysis.query` with ``method``, ``upper``, ``steps``,
        ``search`` from ``overrides``) and settings."""
        change = {k: overrides.pop(k) for k in ("method", "upper", "steps", "search") if k in overrides}
        query = replace(self.analysis.query, **change)
        return {"query": query, "settings": overrides.pop("settings", self.settings)}

    def passive_response(
        self, wrench: builtins.object, command: builtins.object = None, **overrides: Any
    ) -> PassiveResponse:
        """:func:`pinograsp.passive_response` with the scene's method and settings
        (``command``: the scene preload by default, or a named preload)."""
        from ..analysis.response import passive_response

        kw = self._query_args(overrides)
        cmd = self._command(command)
        method = str(kw["query"].method)
        return passive_response(self.model, cmd, wrench, method, settings=kw["settings"], **overrides)

    def max_resistible_wrench(
        self, direction: builtins.object, command: builtins.object = None, **overrides: Any
    ) -> MaxWrench:
        """:func:`pinograsp.max_resistible_wrench` with the scene's method, ``upper``, ``steps``
        and settings; ``direction`` may name one of ``analysis.directions``."""
        from ..analysis.max_wrench import max_resistible_wrench

        kw = self._query_args(overrides)
        if isinstance(direction, str) and direction in self.analysis.directions:
            direction = self.direction(direction)
        elif isinstance(direction, str):
            try:
                wrench_direction(self.model, direction)
            except UnknownNameError:
                named = list(self.analysis.directions)
                hint = f"{AXIS_HINT}, or one of the scene's named directions" if named else AXIS_HINT
                raise UnknownNameError("direction", direction, [*WRENCH_AXES, *named], hint) from None
        return max_resistible_wrench(self.model, self._command(command), direction, **kw, **overrides)

    def profile(
        self, plane: builtins.object = None, command: builtins.object = None, **overrides: Any
    ) -> ResistanceProfile:
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
        axes = cast("Sequence[builtins.object]", plane)  # validated by resistance_profile
        return resistance_profile(self.model, self._command(command), axes, **kw, **overrides)

    def summary(self) -> str:
        """A short human-readable description of the scene."""
        lines = [f"scene {self.name!r}: {self.description}", self.model.summary()]
        lines.append("  contacts: " + ", ".join(self.model.contact_names))
        lines.append("  preload: " + ", ".join(f"{k}={v:g}" for k, v in self.command.items()))
        return "\n".join(lines)
