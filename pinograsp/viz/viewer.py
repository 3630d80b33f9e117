"""3D scene view of a grasp: hand, object, contact points, friction cones and contact-force arrows.

* :func:`scene_figure` builds a plotly ``go.Figure``. It renders in a Jupyter notebook without
  any server (the figure carries its own data; plotly's JavaScript runs in the page) and is
  exported to a standalone HTML file, which works offline, with :func:`save_html`.
* :func:`save_png` (and :func:`scene_axes` for your own figure) draws the same elements with
  matplotlib's 3D axes, so a PNG needs neither kaleido nor a browser.

Both accept a :class:`~pinograsp.GraspModel` alone (explicit-contact scenes: contact points,
normals, friction cones and force arrows) or together with the hand, its configuration and the
object (``hand=``, ``q=``, ``obj=``), or any *scene* object with a ``.model`` attribute (and
optionally ``.hand``, ``.q``, ``.object``, ``.frame``), such as the result of
``pinograsp.load_scene``. What is drawn, and how, is :mod:`pinograsp.viz.scene_elements`.

``model=None`` with ``hand=`` (and ``q=``, default the open configuration) and ``obj=`` draws the
scene **before contact** (or at any configuration, touching or not): each hand joint's closing
direction (the velocity of its link's point closest to the object when the joint alone closes,
from the Jacobian; one arrow per joint) and each link's closest distance to the object (the
nearest three annotated, listed in the title). Nothing is raised when nothing touches.

PNG views are drawn **upright** (:func:`pinograsp.viz.view3d.upright_view`): the hand's approach
axis (hand base towards the object) points up on the page and the camera looks from above the
palm, from the side where the fewest hand points hide the object.

plotly is an optional dependency (``pip install "pinograsp[viz]"``); matplotlib and trimesh
are required dependencies.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.validate import whole_number, writing
from ..errors import InvalidInputError
from .figures import plotly_objects, pyplot
from .scene_elements import COLORS, Mesh, SceneElements, Segments, scene_elements
from .view3d import View, closing_traces, distance_trace, draw_closing_mpl, draw_distances_mpl

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject


def _count(name: str, value: object, el: SceneElements) -> int:
    """How many nearest links to annotate: ``value``, by default 3 without contacts, 0 with."""
    if value is None:  # the nearest three links before contact; none when contacts are drawn
        return 0 if len(el.points) else 3
    return whole_number(name, value, minimum=0)


# ----------------------------------------------------------------------------- plotly
def _mesh_trace(go: Any, m: Mesh, first: bool) -> Any:
    """A ``Mesh3d`` of a mesh (hover: its labels); ``first`` shows it in the legend."""
    return go.Mesh3d(
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


def _segments_trace(go: Any, sg: Segments, first: bool) -> Any:
    """A ``Scatter3d`` of line segments (broken by NaN rows); ``first`` shows it in the legend."""
    xyz = np.full((len(sg.segments) * 3, 3), np.nan)
    xyz[0::3] = sg.segments[:, 0]
    xyz[1::3] = sg.segments[:, 1]
    return go.Scatter3d(
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


def _camera(view: View | None) -> dict[str, Any]:
    """plotly camera of the upright view (``up`` and ``eye``); empty without one."""
    if view is None:
        return {}
    up = np.zeros(3)
    up["xyz".index(view.vertical_axis)] = 1.0 if view.roll == 0 else -1.0
    eye = 1.9 * view.eye
    return {"up": dict(zip("xyz", up.tolist())), "eye": dict(zip("xyz", eye.tolist()))}


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
    go = plotly_objects()
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
        fig.add_trace(_mesh_trace(go, m, not any(t.name == m.name for t in fig.data)))
    for sg in el.segments:
        fig.add_trace(_segments_trace(go, sg, not any(t.name == sg.name for t in fig.data)))
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
    camera = _camera(el.view)
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
#: Meshes drawn on top of the surfaces (arrow heads), not depth-sorted with them.
_ARROW_HEADS = ("contact forces", "external force")


def _decimate(f: np.ndarray, max_faces: int) -> np.ndarray:
    """At most ``max_faces`` faces (every k-th face: a coarse preview of big meshes)."""
    if len(f) <= max_faces:
        return f
    return f[:: int(np.ceil(len(f) / max_faces))]


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
        faces = _decimate(m.faces, int(max_faces))
        surf_polys.append(m.vertices[faces])
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
    if len(el.points):
        ax.scatter(*el.points.T, color=COLORS["contacts"], s=25, depthshade=False, zorder=4)
        _add_handle(handles, "contacts", Line2D([], [], color=COLORS["contacts"], marker="o", ls="none"))
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


__all__ = ["save_html", "save_png", "scene_axes", "scene_figure"]
