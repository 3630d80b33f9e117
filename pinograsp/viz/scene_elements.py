"""What a 3D scene view draws: meshes, line segments and points, in metres (``docs/plots.md``).

:func:`scene_elements` turns a grasp (model, and optionally hand, configuration and object)
into :class:`SceneElements`, which :mod:`pinograsp.viz.viewer` draws with plotly or matplotlib.

Drawing conventions (in the **model's frame**: the hand base frame, unless ``frame`` — a
scene's analysis axes — says otherwise; hand and object are then re-expressed in it):

* Hand links are the hand's **collision** geometries (the ones contacts are computed with),
  placed at ``q`` with Pinocchio; primitives are meshed with trimesh.
* Friction cones and force arrows are drawn on the **hand side** of each contact: a cone has its
  apex at the contact point, axis ``-n`` (away from the object, ``n`` points from the hand into
  the object) and half-angle ``atan(mu)``; the force the hand applies to the object is an arrow
  that *ends* at the contact point (the finger pushes). An arrow inside its cone is a force
  inside the friction cone.
* The external force (the force part of ``response.wrench``) is an arrow starting at the
  object's reference point, never shorter than :data:`EXTERNAL_MIN_FRACTION` × the scene size;
  torques are not drawn.
* With a response that reports contact states (``PassiveResponse.contact_states``), each
  contact point is drawn in the colour and marker of its state (:data:`STATE_STYLES`: sticking,
  sliding, separated), and each sliding contact gets a slip arrow starting at the contact along
  the unit slip ``contact_slip / |contact_slip|`` (the object's motion over the hand there). Its
  length is fixed, :data:`SLIP_FRACTION` × the scene size: the displacements of the model are
  virtual (scaled by the stiffness), so only the slip's direction is drawn. Responses without
  states draw their contacts in one colour, as before.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.model import GraspModel
from ..errors import PinograspWarning
from .meshes import cone, geometry_mesh, merge, transform
from .scene_inputs import (
    CONTACT_STATES,
    SceneStyle,
    positive_or_none,
    resolve_scene,
    response_forces,
    response_states,
)
from .view3d import (
    ClosingArrow,
    View,
    closest_points,
    closing_arrows,
    distance_title,
    hand_up,
    upright_view,
)

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

#: Opacities (mplot3d sorts faces by centre only: a see-through hand keeps the object visible)
#: and the shortest external-force arrow / scene size (the contact forces' scale when longer).
HAND_OPACITY, OBJECT_OPACITY, EXTERNAL_MIN_FRACTION = 0.55, 0.6, 0.2

#: Default colours (hand, object, contacts, cones, contact forces, external force, normals,
#: the contact states and the slip arrows).
COLORS = {
    "hand": "#8c9bb5",
    "object": "#f4a261",
    "contacts": "#1d3557",
    "cones": "#2a9d8f",
    "forces": "#d62828",
    "external": "#7b2cbf",
    "normals": "#555555",
    "sticking": "#2b9348",
    "sliding": "#f72585",
    "separated": "#6c757d",
    "slip": "#f72585",
}

#: Marker of each contact state: (colour, matplotlib marker, filled, plotly symbol).
STATE_STYLES = {
    "sticking": (COLORS["sticking"], "o", True, "circle"),
    "sliding": (COLORS["sliding"], "D", True, "diamond"),
    "separated": (COLORS["separated"], "o", False, "circle-open"),
}

#: Length of a slip arrow as a fraction of the scene size (slip has no physical scale).
SLIP_FRACTION = 0.2

#: Name (legend, ``gid``) of the slip arrows.
SLIP_NAME = "slip directions"


@dataclass
class Mesh:
    """A triangle mesh in the world frame: vertices (n, 3) [m], faces (m, 3), one label per vertex."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    color: str
    opacity: float = 1.0
    labels: list[str] = field(default_factory=list)


@dataclass
class Segments:
    """Line segments (k, 2, 3) [m]."""

    name: str
    segments: np.ndarray
    color: str
    width: float = 4.0
    dash: bool = False


@dataclass
class SceneElements:
    """What a scene view draws (world frame, metres); built by :func:`scene_elements`.

    Attributes:
        meshes: Hand (one mesh merging all links), object, friction cones, arrow heads.
        segments: Contact normals, force arrow shafts, external force shaft.
        points: Contact points (nc, 3) [m].
        point_labels: Hover text per contact.
        contact_names: Contact names.
        size: Scene size [m] used for the default scales.
        cone_scale: Cone height [m].
        force_scale: Arrow length per newton [m/N].
        title: Default title.
        closing: Closing-direction arrows, one per hand joint that moves collision geometry
            (drawn without a model, or with ``show_closing=True``).
        closing_length: Drawn length of the closing arrows [m].
        link_distances: Closest signed distance per hand link to the object [m] (as
            :func:`pinograsp.link_distances`; empty without hand or object).
        distance_points: Each link's point closest to the object, (3,) [m].
        view: The upright camera (:func:`pinograsp.viz.view3d.upright_view`) when a hand or an
            object is drawn, else ``None``.
        contact_states: State per contact (nc,), ``"sticking"``, ``"sliding"`` or
            ``"separated"``, when the response reports them; else ``()``.
        slip_directions: Unit slip direction per contact (nc, 3), zero rows where no slip arrow
            is drawn (not sliding, or no slip reported); ``None`` without states.
        slip_length: Drawn length of the slip arrows [m] (0 without states).
    """

    meshes: list[Mesh]
    segments: list[Segments]
    points: np.ndarray
    point_labels: list[str]
    contact_names: tuple[str, ...]
    size: float
    cone_scale: float
    force_scale: float
    title: str
    closing: tuple[ClosingArrow, ...] = ()
    closing_length: float = 0.0
    link_distances: dict[str, float] = field(default_factory=dict)
    distance_points: dict[str, np.ndarray] = field(default_factory=dict)
    view: View | None = None
    contact_states: tuple[str, ...] = ()
    slip_directions: np.ndarray | None = None
    slip_length: float = 0.0

    def state_groups(self) -> list[tuple[str, np.ndarray]]:
        """``(state, contact indices)`` for each state present, in the order of
        :data:`~pinograsp.viz.scene_inputs.CONTACT_STATES` (empty without states)."""
        st = np.array(self.contact_states, dtype=object)
        return [(k, np.flatnonzero(st == k)) for k in CONTACT_STATES if k in self.contact_states]

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounds of everything drawn, (2, 3) [m]."""
        pts = (
            [self.points]
            + [m.vertices for m in self.meshes]
            + [s.segments.reshape(-1, 3) for s in self.segments]
            + [
                np.array([a.point, a.point + self.closing_length * a.velocity / np.linalg.norm(a.velocity)])
                for a in self.closing
            ]
        )
        allp = np.concatenate([p for p in pts if p.size])
        return np.vstack([allp.min(axis=0), allp.max(axis=0)])


@dataclass(frozen=True)
class _Contacts:
    """The contacts drawn (none without a model): points and normals (nc, 3), ``mu`` (nc,), names,
    the model's length scale [m] and the object's reference point (3,) [m]."""

    points: np.ndarray
    normals: np.ndarray
    mu: np.ndarray
    names: tuple[str, ...]
    length_scale: float
    ref_point: np.ndarray


# ----------------------------------------------------------------------------- arrows
def _arrow(
    tail: np.ndarray, tip: np.ndarray, force: np.ndarray, scale: float, size: float, label: str
) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray, str]]:
    """Shaft (2, 3) [m] and head cone of an arrow drawing ``force`` [N] at ``scale`` [m/N]."""
    length = float(np.linalg.norm(scale * force))
    u = force / np.linalg.norm(force)
    hl = min(0.3 * length, 0.08 * size)
    return np.array([tail, tip - hl * u]), cone(tip, -u, hl, 0.4 * hl, 12) + (label,)


# ----------------------------------------------------------------------------- hand and object
def _hand_mesh(hand: Hand, q: object, to_model: np.ndarray, skipped: list[str]) -> Mesh | None:
    """All collision geometries of the hand at ``q`` as one mesh (labels: links)."""
    from ..robots.kinematics import HandConfiguration

    config = HandConfiguration.at(hand, q)
    parts = []
    for k, go in enumerate(hand.geometry.geometryObjects):
        m = geometry_mesh(go.geometry)
        if m is None:
            skipped.append(go.name)
            continue
        T = to_model @ np.asarray(config.geometry_data.oMg[k].homogeneous, dtype=float)
        parts.append(
            (
                transform(np.asarray(m.vertices, float), T),
                np.asarray(m.faces, int),
                hand.link_of_geometry(k),
            )
        )
    v, f, lab = merge(parts)
    return Mesh("hand", v, f, COLORS["hand"], HAND_OPACITY, lab) if len(v) else None


def _object_mesh(obj: RigidObject, to_model: np.ndarray, skipped: list[str]) -> Mesh | None:
    """The object at its pose."""
    m = geometry_mesh(obj.geometry)
    if m is None:
        skipped.append(str(obj.name))
        return None
    v = transform(np.asarray(m.vertices, float), to_model @ np.asarray(obj.pose, float))
    f = np.asarray(m.faces, int)
    return Mesh("object", v, f, COLORS["object"], OBJECT_OPACITY, [str(obj.name)] * len(v))


def _contacts(model: GraspModel | None, obj: RigidObject | None, to_model: np.ndarray) -> _Contacts:
    """The model's contacts; without a model none, the reference point at the object's centre of mass."""
    if model is None:
        ref_point = (
            transform(np.asarray(obj.center_of_mass, float).reshape(1, 3), to_model)[0]
            if obj is not None
            else np.zeros(3)
        )
        return _Contacts(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), (), 0.0, ref_point)
    return _Contacts(
        np.asarray(model.points, dtype=float).reshape(-1, 3),
        np.asarray(model.frames, dtype=float)[:, :, 0],
        np.asarray(model.mu, float),
        tuple(model.contact_names),
        model.length_scale,
        np.asarray(model.reference_point, float),
    )


def _scene_size(c: _Contacts, obj_mesh: Mesh | None, hand_mesh: Mesh | None, with_hand: bool) -> float:
    """Scene size [m]: extent of the contacts, reference point and object (and the hand if
    ``with_hand``), at least twice the model's length scale and 1 mm."""
    ref = np.vstack([c.points, c.ref_point.reshape(1, 3)])
    if obj_mesh is not None:
        ref = np.vstack([ref, obj_mesh.vertices])
    if with_hand and hand_mesh is not None:
        ref = np.vstack([ref, hand_mesh.vertices])
    size = float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0)))
    return max(size, 2.0 * float(c.length_scale), 1e-3)


# ----------------------------------------------------------------------------- contacts and forces
def _contact_labels(
    c: _Contacts, forces: np.ndarray | None, states: tuple[str, ...], slip_dirs: np.ndarray | None
) -> list[str]:
    """Hover text per contact: name, ``mu``, normal, the force [N] and ``c_n`` if finite, and the
    state (with the unit slip direction of a sliding contact) if reported."""
    labels = []
    for i, name in enumerate(c.names):
        text = f"{name}<br>mu = {c.mu[i]:g}<br>n = {np.round(c.normals[i], 3).tolist()}"
        if forces is not None and np.all(np.isfinite(forces[i])):
            c_n = float(forces[i] @ c.normals[i])
            text += f"<br>force [N] = {np.round(forces[i], 3).tolist()}<br>c_n = {c_n:.4g} N"
        if states:
            text += f"<br>state: {states[i]}"
            if slip_dirs is not None and np.any(slip_dirs[i]):
                text += f"<br>slip direction = {np.round(slip_dirs[i], 3).tolist()}"
        labels.append(text)
    return labels


def _slip_directions(states: tuple[str, ...], slip: np.ndarray | None, nc: int) -> np.ndarray | None:
    """Unit slip (nc, 3) of the sliding contacts with a non-zero slip, zero rows elsewhere;
    ``None`` without states."""
    if not states:
        return None
    out = np.zeros((nc, 3))
    if slip is None:
        return out
    for i, state in enumerate(states):
        norm = float(np.linalg.norm(slip[i]))
        if state == "sliding" and norm > 0.0:
            out[i] = slip[i] / norm
    return out


def _slip_arrows(
    c: _Contacts, dirs: np.ndarray, length: float, size: float
) -> tuple[list[Segments], list[Mesh]]:
    """Arrows of length ``length`` [m] from the sliding contacts along their unit slip ``dirs``."""
    shafts, heads = [], []
    for p, u, name in zip(c.points, dirs, c.names):
        if np.any(u):
            shaft, head = _arrow(p, p + length * u, u, length, size, name)
            shafts.append(shaft)
            heads.append(head)
    if not shafts:
        return [], []
    v, f, lab = merge(heads)
    return (
        [Segments(SLIP_NAME, np.array(shafts), COLORS["slip"], 6.0)],
        [Mesh(SLIP_NAME, v, f, COLORS["slip"], 1.0, lab)],
    )


def _title(nc: int, status: str, states: tuple[str, ...]) -> str:
    """``"2 contacts — resisted: 2 sliding"`` (count per state present, if reported)."""
    title = f"{nc} contacts" + (f" — {status}" if status else "")
    counts = [f"{states.count(k)} {k}" for k in CONTACT_STATES if k in states]
    return title + (f": {', '.join(counts)}" if counts else "")


def _largest_force(forces: np.ndarray | None, wrench: np.ndarray | None) -> float:
    """Largest finite contact force or external force [N] (0 without forces)."""
    if forces is None:
        return 0.0
    finite = np.all(np.isfinite(forces), axis=1)
    mags = np.linalg.norm(np.where(finite[:, None], forces, 0.0), axis=1)
    ext = 0.0 if wrench is None or not np.all(np.isfinite(wrench)) else float(np.linalg.norm(wrench[:3]))
    return max(float(mags.max()) if mags.size else 0.0, ext)


def _force_arrows(
    c: _Contacts, forces: np.ndarray, wrench: np.ndarray | None, s: float, size: float
) -> tuple[list[Segments], list[Mesh]]:
    """Arrows of the contact forces (ending at the contacts) and of the external force (from
    the reference point), ``s`` [m/N]; non-finite or negligible ones are left out."""
    segments: list[Segments] = []
    meshes: list[Mesh] = []
    shafts, heads = [], []
    for p, f, name in zip(c.points, forces, c.names):
        if not np.all(np.isfinite(f)) or np.linalg.norm(f) * s < 1e-9 * size:
            continue
        shaft, head = _arrow(p - s * f, p, f, s, size, name)
        shafts.append(shaft)
        heads.append(head)
    if shafts:
        segments.append(Segments("contact forces", np.array(shafts), COLORS["forces"], 6.0))
        v, f_, lab = merge(heads)
        meshes.append(Mesh("contact forces", v, f_, COLORS["forces"], 1.0, lab))
    if wrench is not None and np.all(np.isfinite(wrench)) and np.linalg.norm(wrench[:3]) * s > 1e-9 * size:
        o = c.ref_point
        se = max(s, EXTERNAL_MIN_FRACTION * size / float(np.linalg.norm(wrench[:3])))
        shaft, (v, f_, _) = _arrow(o, o + se * wrench[:3], wrench[:3], se, size, "external force")
        segments.append(Segments("external force", shaft[None], COLORS["external"], 6.0))
        meshes.append(Mesh("external force", v, f_, COLORS["external"], 1.0, ["external force"] * len(v)))
    return segments, meshes


# ----------------------------------------------------------------------------- assembly
def scene_elements(
    model: object,
    response: object = None,
    *,
    hand: Hand | None = None,
    q: object = None,
    obj: RigidObject | None = None,
    frame: object = None,
    style: SceneStyle | None = None,
) -> SceneElements:
    """The meshes, segments and points a scene view draws (see
    :func:`~pinograsp.viz.viewer.scene_figure` for the arguments; ``style``: how, default
    :class:`~pinograsp.viz.scene_inputs.SceneStyle`)."""
    style = SceneStyle() if style is None else style
    model, hand, q, obj, to_model = resolve_scene(model, hand, q, obj, frame)
    show_closing = model is None if style.show_closing is None else style.show_closing
    forces, wrench, status = response_forces(model, response)
    states, slip = response_states(model, response)
    skipped: list[str] = []
    hand_mesh = None if hand is None else _hand_mesh(hand, q, to_model, skipped)
    obj_mesh = None if obj is None else _object_mesh(obj, to_model, skipped)
    meshes = [m for m in (hand_mesh, obj_mesh) if m is not None]
    if skipped:
        warnings.warn(
            f"not drawn (unbounded or unsupported geometry): {', '.join(skipped)}",
            PinograspWarning,
            stacklevel=3,
        )
    c = _contacts(model, obj, to_model)
    nc = len(c.points)
    size = _scene_size(c, obj_mesh, hand_mesh, model is None)
    h = style.cone_scale if style.cone_scale is not None else 0.3 * size
    segments: list[Segments] = []
    if nc:
        segments.append(
            Segments(
                "contact normals",
                np.stack([c.points, c.points - h * c.normals], axis=1),
                COLORS["normals"],
                2.0,
                True,
            )
        )
    if style.show_cones and nc:
        parts = [
            cone(p, -n, h, h * float(m)) + (name,)
            for p, n, m, name in zip(c.points, c.normals, c.mu, c.names)
            if m > 0
        ]
        v, f, lab = merge(parts)
        if len(v):
            meshes.append(Mesh("friction cones", v, f, COLORS["cones"], 0.3, lab))
    fmax = _largest_force(forces, wrench)
    s = style.force_scale if style.force_scale is not None else (0.3 * size / fmax if fmax > 0 else 0.0)
    if style.show_forces and forces is not None and fmax > 0:
        arrow_segments, arrow_meshes = _force_arrows(c, forces, wrench, s, size)
        segments += arrow_segments
        meshes += arrow_meshes
    slip_dirs = _slip_directions(states, slip, nc)
    slip_length = SLIP_FRACTION * size if states else 0.0
    if slip_dirs is not None:
        slip_segments, slip_meshes = _slip_arrows(c, slip_dirs, slip_length, size)
        segments += slip_segments
        meshes += slip_meshes
    title = _title(nc, status, states)
    extra = _hand_extras(
        hand, q, obj, to_model, hand_mesh, obj_mesh, c.ref_point, size, show_closing, style.tolerance
    )
    if model is None:
        title = extra.pop("title")
    else:
        extra.pop("title")
    labels = _contact_labels(c, forces, states, slip_dirs)
    extra.update(contact_states=states, slip_directions=slip_dirs, slip_length=slip_length)
    return SceneElements(meshes, segments, c.points, labels, c.names, size, h, s, title, **extra)


def _hand_extras(
    hand: Hand | None,
    q: object,
    obj: RigidObject | None,
    to_model: np.ndarray,
    hand_mesh: Mesh | None,
    obj_mesh: Mesh | None,
    ref_point: np.ndarray,
    size: float,
    show_closing: bool,
    tolerance: float | None,
) -> dict[str, Any]:
    """Closing arrows, per-link distances, the upright camera and the contact-free title."""
    from ..robots.collision import DEFAULT_TOLERANCE

    tol = DEFAULT_TOLERANCE if tolerance is None else float(positive_or_none("tolerance", tolerance) or 0.0)
    out: dict[str, Any] = {"title": "hand and object" if hand is not None and obj is not None else "scene"}
    qv = None if hand is None else hand.configuration(q)
    if hand is not None and qv is not None and obj is not None:
        dist, points = closest_points(hand, qv, obj, to_model)
        out.update(link_distances=dist, distance_points=points, title=distance_title(dist, tol))
    if hand is not None and qv is not None and show_closing:
        out["closing"] = closing_arrows(hand, qv, obj, to_model)
        out["closing_length"] = 0.18 * size
    if hand_mesh is None and obj_mesh is None:
        return out
    target = None if obj_mesh is None else ref_point
    radius = 0.0
    if obj_mesh is not None:
        radius = 0.5 * float(np.linalg.norm(obj_mesh.vertices.max(axis=0) - obj_mesh.vertices.min(axis=0)))
    verts = None if hand_mesh is None else hand_mesh.vertices
    origin = to_model[:3, 3] if hand is not None else np.zeros(3)
    up = hand_up(origin, target, verts)
    out["view"] = upright_view(up, verts, target, radius)
    return out


__all__ = [
    "COLORS",
    "SLIP_FRACTION",
    "SLIP_NAME",
    "STATE_STYLES",
    "Mesh",
    "SceneElements",
    "Segments",
    "scene_elements",
]
