"""The 3D scene view drawn on matplotlib 3D axes (``docs/plots.md``): no browser, no kaleido.

:func:`scene_axes` draws the elements of :func:`~pinograsp.viz.scene_elements.scene_elements`
(the same as the plotly :func:`~pinograsp.viz.viewer.scene_figure`) on a 3D Axes;
:func:`~pinograsp.viz.viewer.save_png` writes it to a PNG. The view is **upright** by default
(:func:`pinograsp.viz.view3d.upright_view`): the hand's approach axis (hand base towards the
object) points up on the page and the camera looks from above the palm, from the side where the
fewest hand points hide the object.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InvalidInputError
from .figures import pyplot
from .scene_elements import COLORS, SLIP_NAME, STATE_STYLES, Mesh, SceneElements, scene_elements
from .scene_inputs import SceneStyle, distance_count, make_style
from .view3d import draw_closing_mpl, draw_distances_mpl

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject

#: Meshes drawn on top of the surfaces (arrow heads), not depth-sorted with them.
_ARROW_HEADS = ("contact forces", "external force", SLIP_NAME)

#: ``gid`` prefix of the contact points of one state (``prefix + state``).
GID_CONTACTS = "pinograsp-contacts:"


def _decimate(v: np.ndarray, f: np.ndarray, max_faces: int) -> tuple[np.ndarray, np.ndarray]:
    """At most ``max_faces`` faces of the mesh ``(v, f)``, by vertex clustering: vertices are
    merged per cell of a grid over the mesh's box (each cell's mean), collapsed faces dropped,
    the grid coarsened until the mesh fits. A coarse but closed surface (keeping every k-th face
    instead draws a big mesh, e.g. the G1 hand's, as scattered slivers); deterministic."""
    if len(f) <= max_faces:
        return v, f
    lo, hi = v.min(axis=0), v.max(axis=0)
    extent = float(np.max(hi - lo)) or 1.0
    cells = max(int(np.sqrt(max_faces / 2.0)), 2)
    while True:
        size = extent / cells
        keys = np.floor((v - lo) / size).astype(np.int64)
        _, cluster, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
        cluster = cluster.reshape(-1)
        merged = np.zeros((len(counts), 3))
        np.add.at(merged, cluster, v)
        merged /= counts[:, None]
        g = cluster[f]
        keep = (g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 0] != g[:, 2])
        g = np.unique(np.sort(g[keep], axis=1), axis=0) if keep.any() else g[:0]
        if len(g) <= max_faces or cells <= 2:
            return merged, g[:max_faces]
        cells = max(int(cells * 0.7), 2)


def _axes3d(ax: Any) -> Any:
    """``ax`` if it is a 3D Axes, a new pyplot figure's 3D Axes if it is ``None``."""
    if ax is None:
        fig = pyplot().figure(figsize=(6.5, 6.0))
        return fig.add_subplot(projection="3d")
    if getattr(ax, "name", None) != "3d":
        raise InvalidInputError("ax", "expected a 3D Axes (fig.add_subplot(projection='3d'))")
    return ax


def _add_handle(handles: list[Any], name: str, artist: Any) -> None:
    """Add a legend entry ``name`` unless there is one."""
    if name not in [h.get_label() for h in handles]:
        artist.set_label(name)
        handles.append(artist)


def _draw_surfaces(ax: Any, meshes: list[Mesh], max_faces: int, handles: list[Any]) -> None:
    """All meshes in one ``Poly3DCollection`` (``gid`` ``"pinograsp-surfaces"``), so that mplot3d
    depth-sorts their faces together (separate collections are sorted as wholes)."""
    from matplotlib.colors import to_rgba
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    surf_polys, surf_face, surf_edge = [], [], []
    for m in meshes:
        verts, faces = _decimate(m.vertices, m.faces, int(max_faces))
        surf_polys.append(verts[faces])
        surf_face += [to_rgba(m.color, m.opacity)] * len(faces)
        surf_edge += [to_rgba("0.2", 0.4) if m.name == "hand" else (0.0, 0.0, 0.0, 0.0)] * len(faces)
        _add_handle(handles, m.name, Line2D([], [], color=m.color, lw=6, alpha=max(m.opacity, 0.4)))
    if surf_polys:
        coll = Poly3DCollection(
            np.concatenate(surf_polys), facecolors=surf_face, edgecolors=surf_edge, linewidths=0.3
        )
        coll.set_gid("pinograsp-surfaces")
        coll.set_zorder(1)
        ax.add_collection3d(coll)


def _draw_contacts(ax: Any, el: SceneElements, handles: list[Any]) -> None:
    """Contact points: one colour without states; with states one scatter per state present
    (``gid`` :data:`GID_CONTACTS` + state, legend ``contacts: <state>``, :data:`STATE_STYLES`)."""
    from matplotlib.lines import Line2D

    if not len(el.points):
        return
    if not el.contact_states:
        ax.scatter(*el.points.T, color=COLORS["contacts"], s=25, depthshade=False, zorder=4)
        _add_handle(handles, "contacts", Line2D([], [], color=COLORS["contacts"], marker="o", ls="none"))
        return
    for state, idx in el.state_groups():
        color, marker, filled, _ = STATE_STYLES[state]
        face = color if filled else "none"
        sc = ax.scatter(
            *el.points[idx].T,
            marker=marker,
            facecolors=face,
            edgecolors=color,
            s=36,
            depthshade=False,
            zorder=4,
        )
        sc.set_gid(GID_CONTACTS + state)
        mfc = color if filled else "none"
        _add_handle(
            handles, f"contacts: {state}", Line2D([], [], color=color, marker=marker, mfc=mfc, ls="none")
        )


def _frame_axes(ax: Any, bounds: np.ndarray) -> None:
    """A cube around ``bounds`` (2, 3) [m] with equal axes, labelled in metres."""
    lo, hi = bounds
    c, r = 0.5 * (lo + hi), 0.5 * float((hi - lo).max()) * 1.05 + 1e-9
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]", fontsize=8)
    ax.set_ylabel("y [m]", fontsize=8)
    ax.set_zlabel("z [m]", fontsize=8)
    ax.tick_params(labelsize=6)


def scene_axes(
    model: object,
    response: object = None,
    *,
    ax: Any = None,
    hand: Hand | None = None,
    q: object = None,
    obj: RigidObject | None = None,
    frame: object = None,
    style: SceneStyle | None = None,
    cone_scale: float | None = None,
    force_scale: float | None = None,
    show_cones: bool | None = None,
    show_forces: bool | None = None,
    show_closing: bool | None = None,
    show_distances: int | None = None,
    tolerance: float | None = None,
    title: str | None = None,
    elev: float | None = None,
    azim: float | None = None,
    upright: bool = True,
    max_faces: int = 4000,
) -> Any:
    """Draw the scene of :func:`~pinograsp.viz.viewer.scene_figure` on a matplotlib 3D Axes and return it.

    Meshes are ``Poly3DCollection`` (each limited to ``max_faces`` faces by vertex clustering),
    segments lines, contacts points. ``ax``: a 3D Axes (default: a new pyplot figure). Other
    arguments as :func:`~pinograsp.viz.viewer.scene_figure`. ``elev``/``azim``: view angles
    [deg] (z vertical); by default (both ``None`` and ``upright=True``) the view of
    :func:`pinograsp.viz.view3d.upright_view`: the hand's approach axis up on the page, the
    camera on the object's side of the palm. Closing arrows are ``Line3DCollection`` artists with ``gid``
    ``"pinograsp-closing:<joint>"``, distance labels texts with ``gid`` ``"pinograsp-distance"``.
    With contact states, the contacts of each state are one scatter with ``gid``
    ``"pinograsp-contacts:<state>"``; slip arrows are the ``Line3DCollection``
    ``"pinograsp-slip-directions"`` with heads ``"pinograsp-slip-directions-heads"``.
    """
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    style = make_style(
        style,
        cone_scale=cone_scale,
        force_scale=force_scale,
        show_cones=show_cones,
        show_forces=show_forces,
        show_closing=show_closing,
        show_distances=show_distances,
        tolerance=tolerance,
        title=title,
    )
    el = scene_elements(
        model,
        response,
        hand=hand,
        q=q,
        obj=obj,
        frame=frame,
        style=style,
    )
    n_dist = distance_count(style.show_distances, len(el.points) > 0)
    ax = _axes3d(ax)
    from matplotlib.lines import Line2D

    # Surfaces first; force arrows, normals and contact points are drawn on top of them in this
    # order, so that they are never hidden by the hand.
    ax.computed_zorder = False
    handles: list[Any] = []
    top = [m for m in el.meshes if m.name in _ARROW_HEADS]
    _draw_surfaces(ax, [m for m in el.meshes if m.name not in _ARROW_HEADS], max_faces, handles)
    for sg in el.segments:
        lc = Line3DCollection(
            sg.segments, colors=sg.color, linewidths=sg.width / 2.5, linestyles="--" if sg.dash else "-"
        )
        lc.set_gid(f"pinograsp-{sg.name.replace(' ', '-')}")
        lc.set_zorder(2)
        ax.add_collection3d(lc)
        _add_handle(handles, sg.name, Line2D([], [], color=sg.color, lw=2, ls="--" if sg.dash else "-"))
    for m in top:
        heads = Poly3DCollection(m.vertices[m.faces], facecolors=m.color, edgecolors=m.color, linewidths=0.3)
        heads.set_gid(f"pinograsp-{m.name.replace(' ', '-')}-heads")
        heads.set_zorder(3)
        ax.add_collection3d(heads)
    _draw_contacts(ax, el, handles)
    if el.closing:
        handles += draw_closing_mpl(ax, el.closing, el.closing_length)
    if el.link_distances and n_dist:
        draw_distances_mpl(ax, el.link_distances, el.distance_points, n_dist)
        _add_handle(handles, "closest distances", Line2D([], [], color="k", marker="o", ms=3, ls="none"))
    _frame_axes(ax, el.bounds)
    if elev is None and azim is None and upright and el.view is not None:
        ax.view_init(**el.view.kwargs())
    else:
        ax.view_init(elev=30.0 if elev is None else elev, azim=-60.0 if azim is None else azim)
    shown = el.title if style.title is None else style.title
    ax.set_title(shown, fontsize=9 if len(shown) > 60 else 10, wrap=True)
    ax.legend(handles=handles, loc="upper left", fontsize=7, framealpha=0.85)
    return ax


__all__ = ["GID_CONTACTS", "scene_axes"]
