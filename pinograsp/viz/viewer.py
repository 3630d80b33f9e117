"""3D scene view of a grasp: hand, object, contact points, friction cones and contact-force arrows.

* :func:`scene_figure` builds a plotly ``go.Figure``. It renders in a Jupyter notebook without
  any server (the figure carries its own data; plotly's JavaScript runs in the page) and is
  exported to a standalone HTML file, which works offline, with :func:`save_html`.
* :func:`save_png` (and :func:`~pinograsp.viz.scene_mpl.scene_axes` for your own figure) draws
  the same elements with matplotlib's 3D axes, so a PNG needs neither kaleido nor a browser.

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

Both views are drawn **upright** (:func:`pinograsp.viz.view3d.upright_view`): the hand's
approach axis (hand base towards the object) points up on the page.

plotly is an optional dependency (``pip install "pinograsp[viz]"``); matplotlib and trimesh
are required dependencies.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..core.validate import writing
from ..errors import InvalidInputError
from .figures import plotly_objects
from .scene_elements import COLORS, STATE_STYLES, Mesh, SceneElements, Segments, scene_elements
from .scene_inputs import SceneStyle, distance_count, make_style
from .scene_mpl import scene_axes
from .view3d import View, closing_traces, distance_trace

if TYPE_CHECKING:  # pragma: no cover
    from ..robots.hand import Hand
    from ..robots.objects import RigidObject


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


def _points_trace(go: Any, el: SceneElements) -> Any:
    """Markers of the contact points (hover: name, ``mu``, normal, force)."""
    return go.Scatter3d(
        x=el.points[:, 0],
        y=el.points[:, 1],
        z=el.points[:, 2],
        mode="markers",
        marker={"size": 5, "color": COLORS["contacts"]},
        name="contacts",
        hovertext=el.point_labels,
        hoverinfo="text",
    )


def _state_traces(go: Any, el: SceneElements) -> list[Any]:
    """One marker trace per contact state present, ``contacts: <state>`` (hover: name, ``mu``,
    normal, force, state and slip direction)."""
    traces = []
    for state, idx in el.state_groups():
        color, _, _, symbol = STATE_STYLES[state]
        traces.append(
            go.Scatter3d(
                x=el.points[idx, 0],
                y=el.points[idx, 1],
                z=el.points[idx, 2],
                mode="markers",
                marker={"size": 6, "color": color, "symbol": symbol},
                name=f"contacts: {state}",
                hovertext=[el.point_labels[i] for i in idx],
                hoverinfo="text",
            )
        )
    return traces


def _scene_layout(view: View | None) -> dict[str, Any]:
    """The 3D scene of the layout: equal axes in metres, and the camera of the upright view."""
    scene: dict[str, Any] = {
        "aspectmode": "data",
        "xaxis_title": "x [m]",
        "yaxis_title": "y [m]",
        "zaxis_title": "z [m]",
    }
    if view is not None:
        up = np.zeros(3)
        up["xyz".index(view.vertical_axis)] = 1.0 if view.roll == 0 else -1.0
        eye = 1.9 * view.eye
        scene["camera"] = {"up": dict(zip("xyz", up.tolist())), "eye": dict(zip("xyz", eye.tolist()))}
    return scene


def scene_figure(
    model: object,
    response: object = None,
    *,
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
    height: int = 600,
) -> Any:
    """Interactive 3D view of a grasp as a plotly ``go.Figure``.

    Traces (legend names): ``hand`` (all collision geometries merged; hover shows the link),
    ``object``, ``contacts``, ``contact normals``, ``friction cones``, ``contact forces``,
    ``external force`` — only those that apply. A response that reports contact states draws
    ``contacts: sticking`` / ``contacts: sliding`` / ``contacts: separated`` (one trace per state
    present) instead of ``contacts``, and ``slip directions``: an arrow from each sliding contact
    along its unit slip, of fixed length (see :mod:`pinograsp.viz.scene_elements`).

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
        style: How to draw, one :class:`~pinograsp.viz.SceneStyle` (``pg.SceneStyle``); or the
            loose keywords below (not both).
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
    fig = go.Figure()
    for m in el.meshes:
        fig.add_trace(_mesh_trace(go, m, not any(t.name == m.name for t in fig.data)))
    for sg in el.segments:
        fig.add_trace(_segments_trace(go, sg, not any(t.name == sg.name for t in fig.data)))
    if len(el.points):
        for tr in _state_traces(go, el) if el.contact_states else [_points_trace(go, el)]:
            fig.add_trace(tr)
    for tr in closing_traces(go, el.closing, el.closing_length):
        fig.add_trace(tr)
    if el.link_distances and n_dist:
        fig.add_trace(distance_trace(go, el.link_distances, el.distance_points, n_dist))
    fig.update_layout(
        title={"text": el.title if style.title is None else style.title},
        height=height,
        margin={"l": 0, "r": 0, "t": 40, "b": 0},
        legend={"itemsizing": "constant"},
        scene=_scene_layout(el.view),
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
        **kwargs: Passed to :func:`~pinograsp.viz.scene_mpl.scene_axes` (``hand``, ``q``,
            ``obj``, scales, ``title``, ``elev``, ``azim``, ``upright``, ``show_closing``,
            ``show_distances``, ``max_faces``, ...). ``model=None`` with ``hand``/``q``/``obj``
            draws the scene before contact.

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


__all__ = ["save_html", "save_png", "scene_figure"]
