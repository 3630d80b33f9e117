"""What a 3D scene view is given, checked: the grasp model (or a scene), hand, configuration,
object and frame, and the contact forces, states and slip of a response (``docs/plots.md``).

A *scene* is any object with a ``.model`` :class:`~pinograsp.GraspModel` (and optionally
``.hand``, ``.q``, ``.object``, ``.frame``), such as the result of ``pinograsp.load_scene``;
arguments given explicitly win over its attributes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..core.model import GraspModel
from ..core.validate import positive_number, whole_number
from ..errors import InvalidInputError

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject


def positive_or_none(name: str, value: object) -> float | None:
    """``None``, or a finite number ``> 0`` (:func:`~pinograsp.core.validate.positive_number`)."""
    return None if value is None else positive_number(name, value)


@dataclass(frozen=True)
class SceneStyle:
    """How a 3D scene view draws (one value for :func:`~pinograsp.viz.viewer.scene_figure`,
    :func:`~pinograsp.viz.scene_mpl.scene_axes` and :func:`~pinograsp.view`), validated once.

    Attributes:
        cone_scale: Friction-cone height [m] (None: 0.3 x the scene size).
        force_scale: Arrow length per newton [m/N] (None: the largest force as long as a cone).
        show_cones, show_forces: Draw friction cones / force arrows.
        show_closing: Draw each joint's closing direction (None: only without a model).
        show_distances: Nearest links annotated with their distance (None: 3 before contact,
            0 with contacts).
        tolerance: Contact tolerance [m] of the title's "touching" (None: 1 mm).
        title: Figure title (None: contact count and response status).
    """

    cone_scale: float | None = None
    force_scale: float | None = None
    show_cones: bool = True
    show_forces: bool = True
    show_closing: bool | None = None
    show_distances: int | None = None
    tolerance: float | None = None
    title: str | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "cone_scale", positive_or_none("cone_scale", self.cone_scale))
        set_(self, "force_scale", positive_or_none("force_scale", self.force_scale))
        set_(self, "tolerance", positive_or_none("tolerance", self.tolerance))
        if self.show_distances is not None:
            set_(self, "show_distances", whole_number("show_distances", self.show_distances, minimum=0))
        for name in ("show_cones", "show_forces"):
            set_(self, name, bool(getattr(self, name)))
        if self.show_closing is not None:
            set_(self, "show_closing", bool(self.show_closing))
        if self.title is not None and not isinstance(self.title, str):
            raise InvalidInputError("title", f"must be a string or None, got {type(self.title).__name__}")


def make_style(style: SceneStyle | None, **loose: object) -> SceneStyle:
    """``style``, or one built from the loose keywords (those not None); both is an error."""
    given = {k: v for k, v in loose.items() if v is not None}
    if style is None:
        return SceneStyle(**given)  # type: ignore[arg-type]  # validated by SceneStyle
    if not isinstance(style, SceneStyle):
        raise InvalidInputError("style", f"must be a pinograsp.viz.SceneStyle, got {type(style).__name__}")
    if given:
        raise InvalidInputError("style", f"give either style= or the keywords {sorted(given)}, not both")
    return style


def distance_count(value: object, has_contacts: bool) -> int:
    """How many nearest links to annotate with their distance: ``value`` (an integer >= 0), by
    default 3 before contact and none when contacts are drawn."""
    if value is None:
        return 0 if has_contacts else 3
    return whole_number("show_distances", value, minimum=0)


def resolve_scene(
    model: object, hand: Hand | None, q: object, obj: RigidObject | None, frame: object
) -> tuple[GraspModel | None, Hand | None, object, RigidObject | None, np.ndarray]:
    """The model, hand, configuration, object and the 4×4 transform from the hand base frame to
    the model's frame (the inverse of ``frame``), checked.

    ``model=None`` needs a hand or an object; the hand's configuration then defaults to its open
    one (before any contact).
    """
    if model is None:
        if hand is None and obj is None:
            raise InvalidInputError("model", "model=None needs a hand= and/or an obj= to draw")
        if hand is not None and q is None and hasattr(hand, "q_open"):
            q = np.array(hand.q_open)  # before any contact: the open configuration
    elif not isinstance(model, GraspModel):
        inner = getattr(model, "model", None)
        if not isinstance(inner, GraspModel):
            raise InvalidInputError(
                "model",
                f"expected a GraspModel or a scene with a .model GraspModel, got {type(model).__name__}",
            )
        hand = hand if hand is not None else getattr(model, "hand", None)
        q = q if q is not None else getattr(model, "q", None)
        if obj is None:
            obj = getattr(model, "object", None)
            obj = obj if obj is not None else getattr(model, "obj", None)
        frame = frame if frame is not None else getattr(model, "frame", None)
        model = inner
    if hand is not None:
        if not (hasattr(hand, "geometry") and hasattr(hand, "model") and hasattr(hand, "configuration")):
            raise InvalidInputError("hand", f"expected a pinograsp Hand, got {type(hand).__name__}")
        if q is None:
            raise InvalidInputError("q", "drawing a hand needs its configuration q (URDF joint values)")
    if obj is not None and not (hasattr(obj, "geometry") and hasattr(obj, "pose")):
        raise InvalidInputError("obj", f"expected a pinograsp RigidObject, got {type(obj).__name__}")
    from ..robots.objects import pose_matrix

    T = pose_matrix(frame, "frame")
    # hand-base coordinates -> the model's (analysis) frame: p_a = R^T (p - t)
    to_model = np.eye(4)
    to_model[:3, :3] = T[:3, :3].T
    to_model[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return model, hand, q, obj, to_model


def response_forces(
    model: GraspModel | None, response: object
) -> tuple[np.ndarray | None, np.ndarray | None, str]:
    """World contact forces (nc, 3) [N], the applied wrench (6,) or ``None``, and a status label.

    ``response``: a :class:`~pinograsp.PassiveResponse`, a
    :class:`~pinograsp.LinearComplianceResult`, a :class:`~pinograsp.MaxWrench` (its response),
    world forces (nc, 3) [N], or ``None`` (no forces).
    """
    if response is None:
        return None, None, ""
    if model is None:
        raise InvalidInputError(
            "response", "forces need contacts: pass the grasp model (model=None draws none)"
        )
    if hasattr(response, "response") and hasattr(response, "unbounded"):  # MaxWrench
        response = response.response
        if response is None:
            raise InvalidInputError("response", "the MaxWrench carries no passive response")
    if hasattr(response, "contact_forces_world"):
        f = np.asarray(response.contact_forces_world, dtype=float)
        w = getattr(response, "wrench", None)
        w = None if w is None else np.asarray(w, dtype=float).reshape(-1)
        status = str(getattr(response, "status", "linear compliance"))
    else:
        try:
            f = np.asarray(response, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(
                "response",
                f"expected a PassiveResponse, a LinearComplianceResult or an (nc, 3) array, got {response!r}",
            ) from exc
        w, status = None, ""
    if f.shape != (model.nc, 3):
        raise InvalidInputError(
            "response", f"expected world contact forces of shape ({model.nc}, 3), got {f.shape}"
        )
    if w is not None and w.shape != (6,):
        w = None
    return f, w, status


#: Contact states a response reports (``PassiveResponse.contact_states``), in drawing order.
CONTACT_STATES = ("sticking", "sliding", "separated")


def response_states(model: GraspModel | None, response: object) -> tuple[tuple[str, ...], np.ndarray | None]:
    """Contact states (nc,) and slip (nc, 3) [m] of a response, or ``((), None)``.

    Only a :class:`~pinograsp.PassiveResponse` (directly or as a ``MaxWrench``'s response) with
    one known state per contact carries them; responses without states (older ones, other result
    types, forces) give ``()``. The slip is ``None`` unless it is finite and of shape (nc, 3).
    """
    if model is None or response is None:
        return (), None
    if hasattr(response, "response") and hasattr(response, "unbounded"):  # MaxWrench
        response = response.response
    states = getattr(response, "contact_states", None)
    if not isinstance(states, (tuple, list)) or len(states) != model.nc:
        return (), None
    if not all(isinstance(s, str) and s in CONTACT_STATES for s in states):
        return (), None
    slip = getattr(response, "contact_slip", None)
    try:
        slip = None if slip is None else np.asarray(slip, dtype=float)
    except (TypeError, ValueError):
        slip = None
    if slip is not None and (slip.shape != (model.nc, 3) or not np.all(np.isfinite(slip))):
        slip = None
    return tuple(states), slip


__all__ = [
    "CONTACT_STATES",
    "distance_count",
    "positive_or_none",
    "resolve_scene",
    "response_forces",
    "response_states",
]
