"""A grasp ready for loading paths: the analysed model, its :class:`QSModel` and the
preloaded state of a command (docs/quasistatic.md, "The preload")."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...core.model import GraspModel
from ...core.settings import Settings, make_settings
from ...errors import InvalidInputError
from .model import QSModel, build_qs_model
from .path import MAX_SEGMENTS, StageRun
from .preload import preload_path, preload_path_of
from .state import State


@dataclass(frozen=True)
class Prepared:
    """A model ready for paths: the analysed model (normal uncertainty, actuator signs), its
    :class:`QSModel`, the commands (na,) and their signs, the preloaded state."""

    model: GraspModel
    qm: QSModel
    fc: np.ndarray
    signs: np.ndarray
    start: State
    preload_runs: tuple[StageRun, ...]
    variant: str
    ratio: float


def checked_settings(settings: Settings | None) -> Settings:
    """``settings`` validated (:func:`make_settings`): once per public call, at its boundary."""
    return make_settings(settings)


def path_of_variant(variant: object, settings: Settings) -> str:
    return preload_path_of(variant, settings.variant)  # the one variant rule (core.methods)


def prepare(
    model: GraspModel, command: object, settings: Settings, variant: str, max_segments: int = MAX_SEGMENTS
) -> Prepared:
    """The analysed model (``model`` with the settings' normal uncertainty) and its preloaded
    state: :func:`prepare_analysed` of it. A pure function of its inputs, computed per call;
    a caller-owned :class:`~pinograsp.Session` keeps it per command
    (:meth:`~pinograsp.Session.loading_grasp`)."""
    if not isinstance(model, GraspModel):
        raise InvalidInputError("model", f"expected pinograsp.GraspModel, got {type(model).__name__}")
    analysed = model.with_normal_uncertainty(settings.normal_uncertainty)
    return prepare_analysed(analysed, analysed.command_vector(command), settings, variant, max_segments)


def prepare_analysed(
    analysed: GraspModel, fc: np.ndarray, settings: Settings, variant: str, max_segments: int = MAX_SEGMENTS
) -> Prepared:
    """The preloaded state of the validated commands ``fc`` (na,) on a model that already
    carries the settings' normal uncertainty (a session's model); ``variant``: ``"held"`` or
    ``"settled"``.

    Raises:
        InvalidInputError: ``settings.cone_tolerance`` is set (the path follows the model's own
            friction polygon).
        PreloadNotInEquilibriumError: The preload path does not reach its end.
    """
    if settings.cone_tolerance is not None:
        raise InvalidInputError(
            "cone_tolerance",
            "the quasi-static method follows the model's own friction polygon; refine the model's "
            "pyramids yourself (pinograsp.core.cones.refined) or leave cone_tolerance=None",
        )
    signs = np.where(fc < 0, -1.0, 1.0)
    ratio = float(settings.tangential_ratio)
    m = analysed.with_actuator_signs(signs) if np.any(signs < 0) else analysed
    qm = build_qs_model(m, ratio)
    start, runs = preload_path(qm, np.abs(fc), variant, max_segments)
    return Prepared(m, qm, np.abs(fc), signs, start, tuple(runs), variant, ratio)


__all__ = ["Prepared", "checked_settings", "path_of_variant", "prepare", "prepare_analysed"]
