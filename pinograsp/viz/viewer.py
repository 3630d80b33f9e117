"""3D scene view: hand, object, contact points, friction cones and contact-force arrows.

* :func:`scene_figure` builds a plotly ``go.Figure``. It renders in a Jupyter notebook without
  any server (the figure carries its own data; plotly's JavaScript runs in the page) and is
  exported to a standalone HTML file, which works offline, with :func:`save_html`.
* :func:`save_png` (and :func:`scene_axes` for your own figure) draws the same elements with
  matplotlib's 3D axes, so a PNG needs neither kaleido nor a browser.

Both accept a :class:`~pinograsp.GraspModel` alone (explicit-contact scenes: contact points,
normals, friction cones and force arrows) or together with the hand, its configuration and the
object (``hand=``, ``q=``, ``obj=``), or any *scene* object with a ``.model`` attribute (and
optionally ``.hand``, ``.q``, ``.object``, ``.frame``), such as the result of
``pinograsp.load_scene``.

``model=None`` with ``hand=`` (and ``q=``, default the open configuration) and ``obj=`` draws the
scene **before contact** (or at any configuration, touching or not): each hand joint's closing
direction (the velocity of its link's point closest to the object when the joint alone closes,
from the Jacobian; one arrow per joint) and each link's closest distance to the object (the
nearest three annotated, listed in the title). Nothing is raised when nothing touches.

PNG views are drawn **upright** (:func:`pinograsp.viz.view3d.upright_view`): the hand's approach
axis (hand base towards the object) points up on the page and the camera looks from above the
palm, from the side where the fewest hand points hide the object.

Drawing conventions (metres, in the **model's frame**: the hand base frame, unless ``frame`` —
a scene's analysis axes — says otherwise; hand and object are then re-expressed in it):

* Hand links are the hand's **collision** geometries (the ones contacts are computed with),
  placed at ``q`` with Pinocchio; primitives are meshed with trimesh.
* Friction cones and force arrows are drawn on the **hand side** of each contact: a cone has its
  apex at the contact point, axis ``-n`` (away from the object, ``n`` points from the hand into
  the object) and half-angle ``atan(mu)``; the force the hand applies to the object is an arrow
  that *ends* at the contact point (the finger pushes). An arrow inside its cone is a force
  inside the friction cone.
* The external force (the force part of ``response.wrench``) is an arrow starting at the
  object's reference point. Torques are not drawn.

plotly is an optional dependency (``pip install "pinograsp[viz]"``); matplotlib and trimesh
are required dependencies.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.model import GraspModel
from ..core.validate import writing
from ..errors import InvalidInputError, MissingDependencyError, PinograspWarning
from .view3d import (
    ClosingArrow,
    View,
    closest_points,
    closing_arrows,
    closing_traces,
    distance_title,
    distance_trace,
    draw_closing_mpl,
    draw_distances_mpl,
    geometry_mesh,
    hand_up,
    upright_view,
)

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

#: Default colours (hand, object, contacts, cones, contact forces, external force, normals).
COLORS = {
    "hand": "#8c9bb5",
    "object": "#f4a261",
    "contacts": "#1d3557",
    "cones": "#2a9d8f",
    "forces": "#d62828",
    "external": "#7b2cbf",
    "normals": "#555555",
}


# ----------------------------------------------------------------------------- elements
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


def _transform(vertices: np.ndarray, T: np.ndarray) -> np.ndarray:
    return vertices @ T[:3, :3].T + T[:3, 3]


def _cone(apex: np.ndarray, axis: np.ndarray, height: float, radius: float, sections: int = 24):
    """Open cone surface: apex, unit axis; returns vertices (sections + 1, 3), faces (sections, 3)."""
    a = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(a, helper)
    u /= np.linalg.norm(u)
    v = np.cross(a, u)
    t = 2.0 * np.pi * np.arange(sections) / sections
    ring = apex + height * a + radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)
    verts = np.vstack([apex, ring])
    k = np.arange(sections)
    faces = np.column_stack([np.zeros(sections, int), 1 + k, 1 + (k + 1) % sections])
    return verts, faces


def _merge(parts: Sequence[tuple[np.ndarray, np.ndarray, str]]) -> tuple[np.ndarray, np.ndarray, list[str]]:
    verts, faces, labels, off = [], [], [], 0
    for v, f, lab in parts:
        verts.append(v)
        faces.append(f + off)
        labels += [lab] * len(v)
        off += len(v)
    if not verts:
        return np.zeros((0, 3)), np.zeros((0, 3), int), []
    return np.vstack(verts), np.vstack(faces), labels


def _resolve(
    model: object, hand: Hand | None, q: object, obj: RigidObject | None, frame: object
) -> tuple[GraspModel | None, Hand | None, object, RigidObject | None, np.ndarray]:
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


def _forces(model: GraspModel | None, response: object) -> tuple[np.ndarray | None, np.ndarray | None, str]:
    """World contact forces (nc, 3), applied wrench (6,) or None, and a status label."""
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


def _count(name: str, value: object, el: SceneElements) -> int:
    if value is None:  # the nearest three links before contact; none when contacts are drawn
        return 0 if len(el.points) else 3
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise InvalidInputError(name, f"expected a count >= 0, got {value!r}")
    return int(value)


def _positive_or_none(name: str, value: object) -> float | None:
    if value is None:
        return None
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(name, f"expected a positive number, got {value!r}") from exc
    if not np.isfinite(v) or v <= 0:
        raise InvalidInputError(name, f"must be finite and > 0, got {value!r}")
    return v


def scene_elements(
    model: object,
    response: object = None,
    *,
    hand: Hand | None = None,
    q: object = None,
    obj: RigidObject | None = None,
    frame: object = None,
    cone_scale: float | None = None,
    force_scale: float | None = None,
    show_cones: bool = True,
    show_forces: bool = True,
    show_closing: bool | None = None,
    tolerance: float | None = None,
) -> SceneElements:
    """The meshes, segments and points a scene view draws (see :func:`scene_figure` for the arguments)."""
    model, hand, q, obj, to_model = _resolve(model, hand, q, obj, frame)
    show_closing = model is None if show_closing is None else bool(show_closing)
    cone_scale = _positive_or_none("cone_scale", cone_scale)
    force_scale = _positive_or_none("force_scale", force_scale)
    forces, wrench, status = _forces(model, response)
    meshes: list[Mesh] = []
    skipped: list[str] = []
    if hand is not None:
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
                    _transform(np.asarray(m.vertices, float), T),
                    np.asarray(m.faces, int),
                    hand.link_of_geometry(k),
                )
            )
        v, f, lab = _merge(parts)
        if len(v):
            meshes.append(Mesh("hand", v, f, COLORS["hand"], 1.0, lab))
    if obj is not None:
        m = geometry_mesh(obj.geometry)
        if m is None:
            skipped.append(str(obj.name))
        else:
            v = _transform(np.asarray(m.vertices, float), to_model @ np.asarray(obj.pose, float))
            meshes.append(
                Mesh("object", v, np.asarray(m.faces, int), COLORS["object"], 0.45, [str(obj.name)] * len(v))
            )
    if skipped:
        warnings.warn(
            f"not drawn (unbounded or unsupported geometry): {', '.join(skipped)}",
            PinograspWarning,
            stacklevel=3,
        )

    obj_mesh = next((m for m in meshes if m.name == "object"), None)
    hand_mesh = next((m for m in meshes if m.name == "hand"), None)
    if model is None:
        pts, normals = np.zeros((0, 3)), np.zeros((0, 3))
        mu, names, length_scale = np.zeros(0), (), 0.0
        ref_point = (
            _transform(np.asarray(obj.center_of_mass, float).reshape(1, 3), to_model)[0]
            if obj is not None
            else np.zeros(3)
        )
    else:
        pts = np.asarray(model.points, dtype=float).reshape(-1, 3)
        normals = np.asarray(model.frames, dtype=float)[:, :, 0]
        mu, names, length_scale = np.asarray(model.mu, float), tuple(model.contact_names), model.length_scale
        ref_point = np.asarray(model.reference_point, float)
    nc = len(pts)
    # scene size: object and contacts (not the whole hand; the whole scene without contacts)
    ref = np.vstack([pts, ref_point.reshape(1, 3)])
    if obj_mesh is not None:
        ref = np.vstack([ref, obj_mesh.vertices])
    if model is None and hand_mesh is not None:
        ref = np.vstack([ref, hand_mesh.vertices])
    size = float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0)))
    size = max(size, 2.0 * float(length_scale), 1e-3)
    h = cone_scale if cone_scale is not None else 0.3 * size
    segments: list[Segments] = []
    if nc:
        segments.append(
            Segments(
                "contact normals", np.stack([pts, pts - h * normals], axis=1), COLORS["normals"], 2.0, True
            )
        )
    if show_cones and nc:
        parts = [
            _cone(p, -n, h, h * float(m)) + (name,) for p, n, m, name in zip(pts, normals, mu, names) if m > 0
        ]
        v, f, lab = _merge(parts)
        if len(v):
            meshes.append(Mesh("friction cones", v, f, COLORS["cones"], 0.3, lab))

    labels = []
    for i, name in enumerate(names):
        text = f"{name}<br>mu = {mu[i]:g}<br>n = {np.round(normals[i], 3).tolist()}"
        if forces is not None and np.all(np.isfinite(forces[i])):
            c_n = float(forces[i] @ normals[i])
            text += f"<br>force [N] = {np.round(forces[i], 3).tolist()}<br>c_n = {c_n:.4g} N"
        labels.append(text)

    fmax = 0.0
    if forces is not None:
        finite = np.all(np.isfinite(forces), axis=1)
        mags = np.linalg.norm(np.where(finite[:, None], forces, 0.0), axis=1)
        ext = 0.0 if wrench is None or not np.all(np.isfinite(wrench)) else float(np.linalg.norm(wrench[:3]))
        fmax = max(float(mags.max()) if mags.size else 0.0, ext)
    s = force_scale if force_scale is not None else (0.3 * size / fmax if fmax > 0 else 0.0)
    if show_forces and forces is not None and fmax > 0:
        shafts, heads = [], []
        for p, f, name in zip(pts, forces, names):
            if not np.all(np.isfinite(f)) or np.linalg.norm(f) * s < 1e-9 * size:
                continue
            tail = p - s * f
            length = float(np.linalg.norm(s * f))
            u = f / np.linalg.norm(f)
            hl = min(0.3 * length, 0.08 * size)
            shafts.append([tail, p - hl * u])
            heads.append(_cone(p, -u, hl, 0.4 * hl, 12) + (name,))
        if shafts:
            segments.append(Segments("contact forces", np.array(shafts), COLORS["forces"], 6.0))
            v, f_, lab = _merge(heads)
            meshes.append(Mesh("contact forces", v, f_, COLORS["forces"], 1.0, lab))
        if (
            wrench is not None
            and np.all(np.isfinite(wrench))
            and np.linalg.norm(wrench[:3]) * s > 1e-9 * size
        ):
            o = ref_point
            tip = o + s * wrench[:3]
            length = float(np.linalg.norm(s * wrench[:3]))
            u = wrench[:3] / np.linalg.norm(wrench[:3])
            hl = min(0.3 * length, 0.08 * size)
            segments.append(
                Segments("external force", np.array([[o, tip - hl * u]]), COLORS["external"], 6.0)
            )
            v, f_ = _cone(tip, -u, hl, 0.4 * hl, 12)
            meshes.append(Mesh("external force", v, f_, COLORS["external"], 1.0, ["external force"] * len(v)))
    title = f"{nc} contacts" + (f" — {status}" if status else "")
    extra = _hand_extras(
        hand, q, obj, to_model, hand_mesh, obj_mesh, ref_point, size, show_closing, tolerance
    )
    if model is None:
        title = extra.pop("title")
    else:
        extra.pop("title")
    return SceneElements(meshes, segments, pts, labels, names, size, h, s, title, **extra)


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

    tol = DEFAULT_TOLERANCE if tolerance is None else float(_positive_or_none("tolerance", tolerance) or 0.0)
    out: dict[str, Any] = {"title": "hand and object" if hand is not None and obj is not None else "scene"}
    qv = None if hand is None else hand.configuration(q)
    if hand is not None and obj is not None:
        dist, points, _, _ = closest_points(hand, qv, obj, to_model)
        out.update(link_distances=dist, distance_points=points, title=distance_title(dist, tol))
    if hand is not None and show_closing:
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


# ----------------------------------------------------------------------------- plotly
def _plotly() -> Any:
    try:
        import plotly.graph_objects as go
    except ImportError as exc:
        raise MissingDependencyError("plotly", "the interactive 3D scene view", extra="viz") from exc
    return go


def scene_figure(
    model: object,
    response: object = None,
    *,
    hand: Hand | None = None,
    q: object = None,
    obj: RigidObject | None = None,
    frame: object = None,
    cone_scale: float | None = None,
    force_scale: float | None = None,
    show_cones: bool = True,
    show_forces: bool = True,
    show_closing: bool | None = None,
    show_distances: int | None = None,
    tolerance: float | None = None,
    title: str | None = None,
    height: int = 600,
) -> Any:
    """Interactive 3D view of a grasp as a plotly ``go.Figure``.

    Traces (legend names): ``hand`` (all collision geometries merged; hover shows the link),
    ``object``, ``contacts``, ``contact normals``, ``friction cones``, ``contact forces``,
    ``external force`` — only those that apply.

    Without a model (``model=None``), the traces are ``hand``, ``object``, one ``closing
    <joint> (<sign>)`` trace per hand joint that moves collision geometry (legend group
    ``closing directions``) and ``closest distances``. The camera looks at the hand upright.

    Args:
        model: A :class:`~pinograsp.GraspModel`, or a scene with ``.model`` (and optionally
            ``.hand``, ``.q``, ``.object``, used unless given explicitly), or ``None``: hand and
            object only, before (or without) contact.
        response: Contact forces to draw: a :class:`~pinograsp.PassiveResponse`, a
            :class:`~pinograsp.LinearComplianceResult`, a :class:`~pinograsp.MaxWrench` (its
            response), or world forces (nc, 3) [N]. Non-finite rows are not drawn.
        hand: Hand whose collision geometry is drawn at ``q`` (required with ``hand``).
        q: Hand configuration (URDF joint values, see :meth:`~pinograsp.Hand.configuration`).
        obj: Object to draw at its pose.
        frame: The model's frame in the hand base frame, 4×4 (a scene's ``.frame``, e.g. the
            paper's analysis axes; default identity). Contacts, forces and wrenches are in the
            model's frame; hand and object are re-expressed in it, so the view is drawn in the
            axes the analysis uses.
        cone_scale: Friction-cone height [m] (default 0.3 × the scene size: the extent of the
            object and the contacts).
        force_scale: Arrow length per newton [m/N] (default: the largest force, contact or
            external, is as long as the cones' default height).
        show_cones, show_forces: Draw friction cones / force arrows.
        show_closing: Draw each joint's closing direction (default: only without a model).
        show_distances: Number of nearest links annotated with their distance to the object
            (default: 3 without contacts, 0 with).
        tolerance: Contact tolerance [m] of the title's "touching" (default 1 mm).
        title: Figure title (default: contact count and the response status; without a model,
            contact state and the nearest links' distances [mm]).
        height: Figure height in pixels.

    Raises:
        MissingDependencyError: plotly is not installed (``pip install "pinograsp[viz]"``).
        InvalidInputError: A model/scene, response, hand, ``q`` or scale that does not fit.
    """
    go = _plotly()
    el = scene_elements(
        model,
        response,
        hand=hand,
        q=q,
        obj=obj,
        frame=frame,
        cone_scale=cone_scale,
        force_scale=force_scale,
        show_cones=show_cones,
        show_forces=show_forces,
        show_closing=show_closing,
        tolerance=tolerance,
    )
    n_dist = _count("show_distances", show_distances, el)
    fig = go.Figure()
    for m in el.meshes:
        first = not any(t.name == m.name for t in fig.data)
        fig.add_trace(
            go.Mesh3d(
                x=m.vertices[:, 0],
                y=m.vertices[:, 1],
                z=m.vertices[:, 2],
                i=m.faces[:, 0],
                j=m.faces[:, 1],
                k=m.faces[:, 2],
                color=m.color,
                opacity=m.opacity,
                name=m.name,
                legendgroup=m.name,
                showlegend=first,
                hovertext=m.labels or None,
                hoverinfo="text" if m.labels else "name",
                flatshading=True,
                lighting={"ambient": 0.55, "diffuse": 0.7, "specular": 0.1},
            )
        )
    for sg in el.segments:
        xyz = np.full((len(sg.segments) * 3, 3), np.nan)
        xyz[0::3] = sg.segments[:, 0]
        xyz[1::3] = sg.segments[:, 1]
        first = not any(t.name == sg.name for t in fig.data)
        fig.add_trace(
            go.Scatter3d(
                x=xyz[:, 0],
                y=xyz[:, 1],
                z=xyz[:, 2],
                mode="lines",
                line={"color": sg.color, "width": sg.width, "dash": "dash" if sg.dash else "solid"},
                name=sg.name,
                legendgroup=sg.name,
                showlegend=first,
                hoverinfo="name",
                connectgaps=False,
            )
        )
    if len(el.points):
        fig.add_trace(
            go.Scatter3d(
                x=el.points[:, 0],
                y=el.points[:, 1],
                z=el.points[:, 2],
                mode="markers",
                marker={"size": 5, "color": COLORS["contacts"]},
                name="contacts",
                hovertext=el.point_labels,
                hoverinfo="text",
            )
        )
    for tr in closing_traces(go, el.closing, el.closing_length):
        fig.add_trace(tr)
    if el.link_distances and n_dist:
        fig.add_trace(distance_trace(go, el.link_distances, el.distance_points, n_dist))
    camera = {}
    if el.view is not None:
        up = np.zeros(3)
        up["xyz".index(el.view.vertical_axis)] = 1.0 if el.view.roll == 0 else -1.0
        eye = 1.9 * el.view.eye
        camera = {"up": dict(zip("xyz", up.tolist())), "eye": dict(zip("xyz", eye.tolist()))}
    fig.update_layout(
        title={"text": el.title if title is None else title},
        height=height,
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"itemsizing": "constant"},
        scene={
            "aspectmode": "data",
            "xaxis_title": "x [m]",
            "yaxis_title": "y [m]",
            "zaxis_title": "z [m]",
            **({"camera": camera} if camera else {}),
        },
    )
    return fig


def save_html(fig: Any, path: str | os.PathLike[str]) -> Path:
    """Write a plotly figure to a standalone HTML file (plotly.js embedded: works offline).

    Parent folders are created; returns the written path.
    """
    if not hasattr(fig, "write_html"):
        raise InvalidInputError(
            "fig", f"expected a plotly Figure (from scene_figure), got {type(fig).__name__}"
        )
    return writing(path, lambda f: fig.write_html(str(f), include_plotlyjs=True, full_html=True))


# ----------------------------------------------------------------------------- matplotlib
def _decimate(v: np.ndarray, f: np.ndarray, max_faces: int) -> np.ndarray:
    """At most ``max_faces`` faces (every k-th face: a coarse preview of big meshes)."""
    if len(f) <= max_faces:
        return f
    return f[:: int(np.ceil(len(f) / max_faces))]


def scene_axes(
    model: object,
    response: object = None,
    *,
    ax: Any = None,
    hand: Hand | None = None,
    q: object = None,
    obj: RigidObject | None = None,
    frame: object = None,
    cone_scale: float | None = None,
    force_scale: float | None = None,
    show_cones: bool = True,
    show_forces: bool = True,
    show_closing: bool | None = None,
    show_distances: int | None = None,
    tolerance: float | None = None,
    title: str | None = None,
    elev: float | None = None,
    azim: float | None = None,
    upright: bool = True,
    max_faces: int = 4000,
) -> Any:
    """Draw the scene of :func:`scene_figure` on a matplotlib 3D Axes and return it.

    Meshes are ``Poly3DCollection`` (each limited to ``max_faces`` faces, every k-th face kept),
    segments lines, contacts points. ``ax``: a 3D Axes (default: a new pyplot figure).
    Other arguments as :func:`scene_figure`. ``elev``/``azim``: view angles [deg] (z vertical);
    by default (both ``None`` and ``upright=True``) the view of
    :func:`pinograsp.viz.view3d.upright_view`: the hand's approach axis up on the page, the camera on
    the object's side of the palm. Closing arrows are ``Line3DCollection`` artists with ``gid``
    ``"pinograsp-closing:<joint>"``, distance labels texts with ``gid`` ``"pinograsp-distance"``.
    """
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    el = scene_elements(
        model,
        response,
        hand=hand,
        q=q,
        obj=obj,
        frame=frame,
        cone_scale=cone_scale,
        force_scale=force_scale,
        show_cones=show_cones,
        show_forces=show_forces,
        show_closing=show_closing,
        tolerance=tolerance,
    )
    n_dist = _count("show_distances", show_distances, el)
    if ax is None:
        from .plots import pyplot

        fig = pyplot().figure(figsize=(6.5, 6.0))
        ax = fig.add_subplot(projection="3d")
    elif getattr(ax, "name", None) != "3d":
        raise InvalidInputError("ax", "expected a 3D Axes (fig.add_subplot(projection='3d'))")
    from matplotlib.colors import to_rgba
    from matplotlib.lines import Line2D

    # Surfaces go into one Poly3DCollection so that mplot3d depth-sorts their faces together
    # (separate collections are sorted as wholes); force arrows, normals and contact points are
    # drawn on top of them in this order, so that they are never hidden by the hand.
    ax.computed_zorder = False
    handles: list[Any] = []

    def legend(name: str, artist: Any) -> None:
        if name not in [h.get_label() for h in handles]:
            artist.set_label(name)
            handles.append(artist)

    surf_polys, surf_face, surf_edge = [], [], []
    top = [m for m in el.meshes if m.name in ("contact forces", "external force")]
    for m in el.meshes:
        if m in top:
            continue
        faces = _decimate(m.vertices, m.faces, int(max_faces))
        surf_polys.append(m.vertices[faces])
        surf_face += [to_rgba(m.color, m.opacity)] * len(faces)
        surf_edge += [to_rgba("0.2", 0.4) if m.name == "hand" else (0.0, 0.0, 0.0, 0.0)] * len(faces)
        legend(m.name, Line2D([], [], color=m.color, lw=6, alpha=max(m.opacity, 0.4)))
    if surf_polys:
        coll = Poly3DCollection(
            np.concatenate(surf_polys), facecolors=surf_face, edgecolors=surf_edge, linewidths=0.3
        )
        coll.set_gid("pinograsp-surfaces")
        coll.set_zorder(1)
        ax.add_collection3d(coll)
    for sg in el.segments:
        lc = Line3DCollection(
            sg.segments, colors=sg.color, linewidths=sg.width / 2.5, linestyles="--" if sg.dash else "-"
        )
        lc.set_gid(f"pinograsp-{sg.name.replace(' ', '-')}")
        lc.set_zorder(2)
        ax.add_collection3d(lc)
        legend(sg.name, Line2D([], [], color=sg.color, lw=2, ls="--" if sg.dash else "-"))
    for m in top:
        heads = Poly3DCollection(m.vertices[m.faces], facecolors=m.color, edgecolors=m.color, linewidths=0.3)
        heads.set_gid(f"pinograsp-{m.name.replace(' ', '-')}-heads")
        heads.set_zorder(3)
        ax.add_collection3d(heads)
    if len(el.points):
        ax.scatter(*el.points.T, color=COLORS["contacts"], s=25, depthshade=False, zorder=4)
        legend("contacts", Line2D([], [], color=COLORS["contacts"], marker="o", ls="none"))
    if el.closing:
        handles += draw_closing_mpl(ax, el.closing, el.closing_length)
    if el.link_distances and n_dist:
        draw_distances_mpl(ax, el.link_distances, el.distance_points, n_dist)
        legend("closest distances", Line2D([], [], color="k", marker="o", ms=3, ls="none"))
    lo, hi = el.bounds
    c, r = 0.5 * (lo + hi), 0.5 * float((hi - lo).max()) * 1.05 + 1e-9
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]", fontsize=8)
    ax.set_ylabel("y [m]", fontsize=8)
    ax.set_zlabel("z [m]", fontsize=8)
    ax.tick_params(labelsize=6)
    if elev is None and azim is None and upright and el.view is not None:
        ax.view_init(**el.view.kwargs())
    else:
        ax.view_init(elev=30.0 if elev is None else elev, azim=-60.0 if azim is None else azim)
    ax.set_title(el.title if title is None else title, fontsize=9 if len(el.title) > 60 else 10, wrap=True)
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
    return ax


def save_png(
    model: object,
    response: object = None,
    *,
    path: str | os.PathLike[str],
    dpi: int = 120,
    figsize: tuple[float, float] = (6.5, 6.0),
    **kwargs: Any,
) -> Path:
    """Render the scene with matplotlib 3D (no browser, no kaleido) and write a PNG.

    Args:
        model, response: As :func:`scene_figure`.
        path: Output file (parent folders are created).
        dpi, figsize: Figure resolution and size [in].
        **kwargs: Passed to :func:`scene_axes` (``hand``, ``q``, ``obj``, scales, ``title``,
            ``elev``, ``azim``, ``upright``, ``show_closing``, ``show_distances``,
            ``max_faces``, ...). ``model=None`` with ``hand``/``q``/``obj`` draws the scene
            before contact.

    Returns:
        The written path.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    writing(path, lambda f: None)  # the path is checked before the drawing
    fig = Figure(figsize=figsize)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    scene_axes(model, response, ax=ax, **kwargs)
    return writing(path, lambda f: fig.savefig(f, dpi=dpi, format="png"))


__all__ = [
    "COLORS",
    "SceneElements",
    "geometry_mesh",
    "save_html",
    "save_png",
    "scene_axes",
    "scene_elements",
    "scene_figure",
]
