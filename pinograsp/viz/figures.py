"""Figures: the lazy matplotlib and plotly imports, Axes checks and writing figures to files.

matplotlib is imported lazily by :func:`pyplot`. Without a display (headless Linux, no
``MPLBACKEND``, not in Jupyter) the non-interactive ``Agg`` backend is selected before ``pyplot``
is first imported, so the plots work in scripts, CI and notebooks alike. plotly is optional
(``pip install "pinograsp[viz]"``): :func:`plotly_objects` raises
:class:`~pinograsp.MissingDependencyError` naming the extra when it is missing.

Artists that tests (and users) look up carry a ``gid``; :data:`GID_UNBOUNDED` marks directions
resisted without bound in every plot (``docs/plots.md``).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from ..core.validate import writing
from ..errors import InvalidInputError, MissingDependencyError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.projections.polar import PolarAxes

#: ``gid`` of the artists that mark directions resisted without bound.
GID_UNBOUNDED = "pinograsp-unbounded"


def _headless() -> bool:
    """No display to open windows on (and nobody chose a backend)."""
    if os.environ.get("MPLBACKEND") or "ipykernel" in sys.modules:
        return False
    if sys.platform.startswith(("win", "darwin")):
        return False
    return not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def pyplot() -> Any:
    """``matplotlib.pyplot``, selecting the ``Agg`` backend first when there is no display."""
    import matplotlib

    if "matplotlib.pyplot" not in sys.modules and _headless():
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plotly_objects() -> Any:
    """``plotly.graph_objects``.

    Raises:
        MissingDependencyError: plotly is not installed (``pip install "pinograsp[viz]"``).
    """
    try:
        import plotly.graph_objects as go
    except ImportError as exc:
        raise MissingDependencyError("plotly", "the interactive 3D scene view", extra="viz") from exc
    return go


def polar_axes(ax: Axes | None, figsize: tuple[float, float] = (5.5, 5.5)) -> PolarAxes:
    """``ax`` if it is a polar Axes, a new polar Axes if it is ``None``."""
    if ax is None:
        _, ax = pyplot().subplots(subplot_kw={"projection": "polar"}, figsize=figsize)
    elif getattr(ax, "name", None) != "polar":
        raise InvalidInputError(
            "ax", "a polar profile needs a polar Axes (e.g. plt.subplots(subplot_kw={'projection': 'polar'}))"
        )
    return cast("PolarAxes", ax)  # the "polar" projection's class


def cartesian_axes(ax: Axes | None, figsize: tuple[float, float]) -> Axes:
    """``ax`` if it is a rectilinear (x-y) Axes, a new one of size ``figsize`` [in] if it is ``None``."""
    if ax is None:
        _, ax = pyplot().subplots(figsize=figsize)
        return ax
    if getattr(ax, "name", None) != "rectilinear":
        raise InvalidInputError(
            "ax", f"expected a rectilinear (x-y) Axes, got a {getattr(ax, 'name', ax)!r} Axes"
        )
    return ax


def save_figure(
    fig: Figure | Axes, path: str | os.PathLike[str], *, dpi: int = 120, close: bool = False
) -> Path:
    """Save a figure (or the figure of an Axes) and return the written path.

    Parent folders are created. The format follows the suffix (``.png``, ``.pdf``, ``.svg``, ...).

    Args:
        fig: A matplotlib ``Figure`` or ``Axes``.
        path: Output file.
        dpi: Resolution of raster formats.
        close: Close the figure afterwards (frees memory in loops; pyplot figures only).
    """
    figure = getattr(fig, "figure", None) if not hasattr(fig, "savefig") else fig
    if figure is None or not hasattr(figure, "savefig"):
        raise InvalidInputError("fig", f"expected a matplotlib Figure or Axes, got {type(fig).__name__}")
    if isinstance(path, (str, os.PathLike)) and not isinstance(path, bytes) and not Path(path).suffix:
        raise InvalidInputError("path", f"{str(path)!r} has no suffix (e.g. '.png') to pick the format")
    p = writing(path, lambda f: figure.savefig(f, dpi=dpi, bbox_inches="tight"))
    if close:
        pyplot().close(figure)
    return p


__all__ = [
    "GID_UNBOUNDED",
    "cartesian_axes",
    "plotly_objects",
    "polar_axes",
    "pyplot",
    "save_figure",
]
