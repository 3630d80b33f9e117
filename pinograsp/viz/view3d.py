"""Scene-view additions for hands that do not (yet) touch the object, and the upright 3D view.

Used by :mod:`pinograsp.viz.scene_elements` and the views drawn from it (``scene_figure``,
``save_png``, ``scene_axes``):

* :func:`closing_arrows` — for each hand joint, the velocity of the point of its link closest to
  the object when that joint alone closes at unit rate (``s_j`` × the URDF velocity), from
  Pinocchio's joint Jacobian: which way the declared closing sign moves the finger.
* :func:`closest_points` — each link's closest signed distance to the object (equal to
  :func:`pinograsp.link_distances`) and the point of the link where it is reached.
* :func:`upright_view` — a camera that shows the hand upright: the approach axis (from the hand
  base towards the object) points up on the page, the camera looks from the object's side of
  the palm (so the palm does not hide the object) and from the horizontal direction in which
  the fewest hand points stand in front of the object.

Positions are in the drawing frame (the model's frame, see :mod:`pinograsp.viz.scene_elements`) [m].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin

from .meshes import geometry_mesh

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

#: Colours of the closing arrows, one per joint (cycled).
CLOSING_COLORS = ("#2b9348", "#0077b6", "#e85d04", "#9d4edd", "#c9184a", "#6a994e", "#3a86ff", "#8d6e63")
#: ``gid`` prefix of the matplotlib closing arrows (one artist per joint: ``prefix + joint``).
GID_CLOSING = "pinograsp-closing:"
#: ``gid`` of the matplotlib distance annotations.
GID_DISTANCE = "pinograsp-distance"
#: Plotly legend group of the closing arrows (one trace per joint).
CLOSING_GROUP = "closing directions"


@dataclass(frozen=True)
class ClosingArrow:
    """How one joint moves its link when it closes.

    Attributes:
        joint: Hand joint.
        sign: Declared closing sign ``s_j``.
        link: Link whose point is shown (the joint's own link, or the nearest link it moves).
        point: The point (the link's point closest to the object), drawing frame, (3,) [m].
        velocity: Its velocity per unit closing rate, drawing frame, (3,) [m/rad] (prismatic
            joints: [m/m]).
        approach: Rate of approach to the object, ``velocity · n`` with ``n`` the unit
            direction from the point to the object's closest point [m/rad]; positive: closing
            moves the point towards the object (``nan`` without an object).
    """

    joint: str
    sign: int
    link: str
    point: np.ndarray
    velocity: np.ndarray
    approach: float


def _apply(T: np.ndarray, p: np.ndarray) -> np.ndarray:
    return T[:3, :3] @ p + T[:3, 3]


def closest_points(
    hand: Hand, q: np.ndarray, obj: RigidObject, to_model: np.ndarray
) -> tuple[dict[str, float], dict[str, np.ndarray]]:
    """Closest signed distance per link and where it is reached.

    Returns:
        ``distances`` {link: [m]} (as :func:`pinograsp.link_distances`) and ``hand_points``
        {link: (3,) drawing frame [m]}, the link's point closest to the object.
    """
    from ..robots.collision import pair_distances

    dist: dict[str, float] = {}
    hp: dict[str, np.ndarray] = {}
    for p in pair_distances(hand, q, obj):
        if p.distance < dist.get(p.link, np.inf):
            dist[p.link] = float(p.distance)
            hp[p.link] = _apply(to_model, p.point_hand)
    return dist, hp


def closing_arrows(
    hand: Hand, q: np.ndarray, obj: RigidObject | None, to_model: np.ndarray
) -> tuple[ClosingArrow, ...]:
    """One arrow per hand joint that moves collision geometry (see :class:`ClosingArrow`).

    The point of joint ``j``: among the links attached to ``j`` itself (or, if it carries no
    geometry, every link it moves), the one closest to the object and its closest point; without
    an object, the centre of the joint's first geometry's bounding box. Velocity:
    ``v = s_j (J_v[:, j] + J_w[:, j] × (p - o))`` from the ``LOCAL_WORLD_ALIGNED`` Jacobian of
    the link's joint (origin ``o``).
    """
    from ..robots.closing import moved_geometries
    from ..robots.kinematics import HandConfiguration

    config = HandConfiguration.at(hand, q)
    geoms = hand.geometry.geometryObjects
    if obj is not None:
        from ..robots.collision import pair_distances_at

        pairs = pair_distances_at(config, obj)
    R = to_model[:3, :3]
    out = []
    for j, name in enumerate(hand.joint_names):
        moved = moved_geometries(hand)[j]
        if not moved:
            continue
        own = [k for k in moved if int(geoms[k].parentJoint) == j + 1] or moved
        if obj is not None:
            k = min(own, key=lambda i: pairs[i].distance)
            p, target = pairs[k].point_hand, pairs[k].point_object
        else:
            k = own[0]
            m = geometry_mesh(geoms[k].geometry)
            centre = np.zeros(3) if m is None else 0.5 * (m.bounds[0] + m.bounds[1])
            p, target = config.geometry_data.oMg[k].act(centre), None
        jid = int(geoms[k].parentJoint)
        J = np.asarray(
            pin.getJointJacobian(hand.model, config.data, jid, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED), float
        ).reshape(6, -1)
        o = config.data.oMi[jid].translation
        s = float(hand.closing_signs[j])
        v = s * (J[:3, j] + np.cross(J[3:, j], p - o))
        if np.linalg.norm(v) < 1e-12:
            continue
        approach = np.nan
        if target is not None:
            gap = target - p
            n = np.linalg.norm(gap)
            approach = float(v @ gap / n) if n > 1e-12 else 0.0
        out.append(ClosingArrow(name, int(s), hand.link_of_geometry(k), _apply(to_model, p), R @ v, approach))
    return tuple(out)


@dataclass(frozen=True)
class View:
    """A matplotlib 3D camera (``ax.view_init(elev, azim, roll, vertical_axis=...)``).

    Attributes:
        elev, azim, roll: View angles [deg].
        vertical_axis: ``"x"``, ``"y"`` or ``"z"``: the drawing axis closest to ``up``.
        up: Unit up direction of the hand in the drawing frame, (3,).
        eye: Unit direction from the scene towards the camera, (3,).
    """

    elev: float
    azim: float
    roll: float
    vertical_axis: str
    up: np.ndarray
    eye: np.ndarray

    def kwargs(self) -> dict[str, Any]:
        """Keyword arguments of ``Axes3D.view_init``."""
        return {"elev": self.elev, "azim": self.azim, "roll": self.roll, "vertical_axis": self.vertical_axis}


def upright_view(
    up: np.ndarray,
    hand_points: np.ndarray | None = None,
    target: np.ndarray | None = None,
    radius: float = 0.0,
    *,
    elev: float = 25.0,
    n_azim: int = 72,
) -> View:
    """Camera with ``up`` vertical on the page, looking down at the object from above the palm.

    ``up`` is snapped to the nearest drawing axis (matplotlib turns the axes box about a
    coordinate axis only), with a 180° roll when it points along the negative axis. Among
    ``n_azim`` azimuths, the one is chosen that minimises the share of ``hand_points`` standing
    between the camera and the object (within ``radius`` [m] of the line of sight through
    ``target``), then prefers looking at the hand's widest horizontal spread 30° off square.

    Args:
        up: Up direction (e.g. from the hand base to the object), (3,).
        hand_points: Hand vertices in the drawing frame, (n, 3) [m] (optional).
        target: Object centre, (3,) [m] (optional).
        radius: Object radius [m] for the occlusion test.
        elev: Elevation above the plane normal to ``up`` [deg].
        n_azim: Number of azimuths tried.
    """
    u = np.asarray(up, dtype=float)
    k = int(np.argmax(np.abs(u)))
    sign = 1.0 if u[k] >= 0 else -1.0
    axis_up = np.zeros(3)
    axis_up[k] = sign
    i0, i1 = (k + 1) % 3, (k + 2) % 3
    e_rad = np.radians(elev)
    spread = None
    pts = None if hand_points is None else np.asarray(hand_points, float).reshape(-1, 3)
    if pts is not None and len(pts) >= 3:
        flat = pts - pts.mean(axis=0)
        flat[:, k] = 0.0
        w, vecs = np.linalg.eigh(flat.T @ flat)
        spread = vecs[:, -1] if w[-1] > 1e-12 else None
    best, best_score = None, np.inf
    for a in np.radians(np.arange(n_azim) * 360.0 / n_azim):
        h = np.zeros(3)
        h[i0], h[i1] = np.cos(a), np.sin(a)
        eye = np.cos(e_rad) * h + np.sin(e_rad) * axis_up
        score = 0.0
        if pts is not None and target is not None and radius > 0 and len(pts):
            rel = pts - np.asarray(target, float)
            front = rel @ eye > 0
            lateral = np.linalg.norm(rel - np.outer(rel @ eye, eye), axis=1)
            score += float(np.mean(front & (lateral < radius)))
        if spread is not None:
            score += 0.05 * (abs(h @ spread) - 0.5) ** 2
        if score < best_score - 1e-12:
            best, best_score = (float(np.degrees(a)), eye), score
    azim, eye = best  # type: ignore[misc]
    return View(
        elev=float(sign * elev),
        azim=float(azim),
        roll=0.0 if sign > 0 else 180.0,
        vertical_axis="xyz"[k],
        up=u / max(np.linalg.norm(u), 1e-300),
        eye=eye,
    )


def hand_up(hand_origin: np.ndarray, target: np.ndarray | None, hand_points: np.ndarray | None) -> np.ndarray:
    """The hand's up direction: from its base origin to the object (or to the hand's centroid)."""
    for p in (target, None if hand_points is None or not len(hand_points) else hand_points.mean(axis=0)):
        if p is not None:
            d = np.asarray(p, float) - hand_origin
            if np.linalg.norm(d) > 1e-9:
                return d / np.linalg.norm(d)
    return np.array([0.0, 0.0, 1.0])


def _arrow_lines(p: np.ndarray, v: np.ndarray, length: float) -> np.ndarray:
    """Shaft and two barbs of an arrow from ``p`` along ``v``: segments (3, 2, 3)."""
    u = v / np.linalg.norm(v)
    tip = p + length * u
    helper = np.array([1.0, 0.0, 0.0]) if abs(u[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    side = np.cross(u, helper)
    side /= np.linalg.norm(side)
    b = 0.3 * length
    return np.array([[p, tip], [tip, tip - b * u + 0.5 * b * side], [tip, tip - b * u - 0.5 * b * side]])


def closing_label(a: ClosingArrow) -> str:
    """Legend text of a closing arrow: joint and declared sign."""
    return f"closing {a.joint} ({a.sign:+d})"


def draw_closing_mpl(ax: Any, arrows: tuple[ClosingArrow, ...], length: float) -> list[Any]:
    """Closing arrows on a matplotlib 3D Axes: one ``Line3DCollection`` per joint (``gid``
    :data:`GID_CLOSING` + joint), one colour per joint; returns legend handles."""
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    handles = []
    for i, a in enumerate(arrows):
        color = CLOSING_COLORS[i % len(CLOSING_COLORS)]
        lc = Line3DCollection(_arrow_lines(a.point, a.velocity, length), colors=color, linewidths=2.2)
        lc.set_gid(GID_CLOSING + a.joint)
        lc.set_zorder(5)
        ax.add_collection3d(lc)
        handles.append(Line2D([], [], color=color, lw=2, label=closing_label(a)))
    return handles


def draw_distances_mpl(
    ax: Any, distances: dict[str, float], points: dict[str, np.ndarray], n: int
) -> list[str]:
    """Annotate the ``n`` nearest links with their distance [mm]; returns the annotated links."""
    near = sorted(distances, key=lambda k: distances[k])[:n]
    for ln in near:
        ax.scatter(*points[ln], color="k", s=10, depthshade=False, zorder=6)
        t = ax.text(*points[ln], f" {ln}: {1e3 * distances[ln]:.1f} mm", fontsize=6, color="0.1", zorder=6)
        t.set_gid(GID_DISTANCE)
    return near


def closing_traces(go: Any, arrows: tuple[ClosingArrow, ...], length: float) -> list[Any]:
    """Plotly traces of the closing arrows: one ``Scatter3d`` per joint (legend group
    :data:`CLOSING_GROUP`)."""
    traces = []
    for i, a in enumerate(arrows):
        segs = _arrow_lines(a.point, a.velocity, length)
        xyz = np.full((9, 3), np.nan)
        xyz[0::3], xyz[1::3] = segs[:, 0], segs[:, 1]
        traces.append(
            go.Scatter3d(
                x=xyz[:, 0],
                y=xyz[:, 1],
                z=xyz[:, 2],
                mode="lines",
                line={"color": CLOSING_COLORS[i % len(CLOSING_COLORS)], "width": 6},
                name=closing_label(a),
                legendgroup=CLOSING_GROUP,
                legendgrouptitle={"text": CLOSING_GROUP} if i == 0 else None,
                hovertext=f"{a.joint}: closing sign {a.sign:+d}, link {a.link}, "
                f"approach {1e3 * a.approach:.3g} mm/rad",
                hoverinfo="text",
                connectgaps=False,
            )
        )
    return traces


def distance_trace(go: Any, distances: dict[str, float], points: dict[str, np.ndarray], n: int) -> Any:
    """Plotly markers with text at the ``n`` nearest links' closest points (distance [mm])."""
    near = sorted(distances, key=lambda k: distances[k])[:n]
    p = np.array([points[ln] for ln in near]).reshape(-1, 3)
    return go.Scatter3d(
        x=p[:, 0],
        y=p[:, 1],
        z=p[:, 2],
        mode="markers+text",
        marker={"size": 3, "color": "black"},
        text=[f"{ln}: {1e3 * distances[ln]:.1f} mm" for ln in near],
        textfont={"size": 10},
        name="closest distances",
        hoverinfo="text",
    )


def distance_title(distances: dict[str, float], tolerance: float, n: int = 3) -> str:
    """``"no contact\\nclosest: a 7.0 mm, b 9.1 mm, ..."`` (or ``"touching: ..."``)."""
    if not distances:
        return "hand and object"
    near = sorted(distances, key=lambda k: distances[k])[:n]
    touching = [ln for ln in distances if distances[ln] <= tolerance]
    head = f"touching: {', '.join(touching)}" if touching else "no contact"
    return f"{head}\nclosest: " + ", ".join(f"{ln} {1e3 * distances[ln]:.1f} mm" for ln in near)


__all__ = [
    "CLOSING_COLORS",
    "CLOSING_GROUP",
    "GID_CLOSING",
    "GID_DISTANCE",
    "ClosingArrow",
    "View",
    "closest_points",
    "closing_arrows",
    "closing_label",
    "closing_traces",
    "distance_title",
    "distance_trace",
    "draw_closing_mpl",
    "draw_distances_mpl",
    "hand_up",
    "upright_view",
]
