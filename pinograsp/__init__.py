"""pinograsp: passive reaction analysis for robot grasps.

The curated public API (docs/design.md). The core layer (NumPy only: models, contacts,
settings, results) is imported here; every other layer — the solvers and analyses, the URDF
side (Pinocchio, Coal), scenes, batches, simulation and plots — is imported on first use of one
of its names, so ``import pinograsp`` loads neither a solver, cvxpy, Pinocchio nor Coal.
"""

from .core.actuation import ACTUATOR_KINDS, Actuator, Coupling
from .core.axes import WRENCH_AXES, plane_directions, wrench_direction
from .core.contact import Contact, friction_edges
from .core.model import GraspModel, PruneRecord
from .core.results import Audit, MaxWrench, PassiveResponse, ResistanceProfile
from .core.serialize import format_magnitude, format_max_wrench
from .core.settings import Backend, Method, Search, Settings, Variant
from .core.tables import results_rows, results_table, results_to_csv
from .errors import (
    AuditWarning,
    BigMWarning,
    ConditioningWarning,
    InvalidInputError,
    MissingDependencyError,
    ModelError,
    ModelFileError,
    NoContactError,
    PenetrationError,
    PinograspError,
    PinograspWarning,
    PreloadNotInEquilibriumError,
    SceneError,
    SolverError,
    SolverNotAvailableError,
    SolverTimeoutError,
    UnknownNameError,
    UrdfError,
)

__version__ = "0.1.0"

#: Public names of the lazily imported layers -> their module (below ``pinograsp``).
_LAZY = {
    # analysis: passive response, max wrench, profiles, sets, scores, preloads, baseline
    "PassiveSolver": "analysis.response",
    "Session": "analysis.response",
    "passive_response": "analysis.response",
    "solver_for": "analysis.response",
    "max_resistible_wrench": "analysis.max_wrench",
    "resistance_profile": "analysis.profile",
    "resistance_set": "analysis.resistance_set",
    "ResistanceSet": "analysis.resistance_set",
    "sphere_points": "analysis.resistance_set",
    "grasp_score": "analysis.metrics",
    "GraspScore": "analysis.metrics",
    "ferrari_canny": "analysis.metrics",
    "hull_reach": "analysis.metrics",
    "equilibrium_preload": "analysis.preload",
    "PreloadChoice": "analysis.preload",
    "optimal_preload": "analysis.optimal",
    "OptimalPreload": "analysis.optimal",
    "DisturbanceCheck": "analysis.optimal",
    "linear_compliance": "analysis.baseline",
    "LinearComplianceResult": "analysis.baseline",
    "available_miqp_solvers": "solvers",
    # the quasi-static loading path
    "loading_path": "analysis.quasistatic",
    "LoadingPath": "analysis.quasistatic",
    "PathEvent": "analysis.quasistatic",
    "quasistatic_max_wrench": "analysis.quasistatic",
    "quasistatic_response": "analysis.quasistatic",
    # robots: the URDF side
    "Hand": "robots.hand",
    "HandDescription": "robots.description",
    "example_robot_data_dir": "robots.description",
    "RigidObject": "robots.objects",
    "detect_contacts": "robots.collision",
    "link_distances": "robots.collision",
    "grasp_model_from_scene": "robots.grasp",
    "check_closing": "robots.closing",
    "ClosingCheck": "robots.closing",
    "JointClosing": "robots.closing",
    # scenes
    "load_scene": "scenes.loading",
    "Scene": "scenes.schema",
    "builtin_scenes": "scenes.loading",
    # simulation (MuJoCo, an optional extra)
    "simulate_max_wrench": "sim.simulate",
    "SimulationResult": "sim.result",
    # batches of grasps
    "evaluate_grasps": "batch.evaluate",
    "WorstAxisScore": "batch.evaluate",
    "save_results": "batch.evaluate",
    "GraspSpec": "batch.grasps",
    "ObjectSpec": "batch.grasps",
    "sample_grasps": "batch.grasps",
    "load_grasps": "batch.files",
    "GraspBatch": "batch.files",
    # plots and the 3D scene view
    "plot_profile": "viz.profile_plots",
    "plot_preload_comparison": "viz.comparison_plots",
    "plot_force_comparison": "viz.comparison_plots",
    "plot_resistance_set": "viz.set_plots",
    "plot_loading_path": "viz.path_plots",
    "save_figure": "viz.figures",
    "scene_figure": "viz.viewer",
    "save_html": "viz.viewer",
    "save_png": "viz.viewer",
}
#: Modules offered as attributes: ``pg.examples`` (the analytic and synthetic example grasps).
_MODULES = {"examples": "core.examples"}

__all__ = [
    # core
    "ACTUATOR_KINDS",
    "Actuator",
    "Audit",
    "Backend",
    "Contact",
    "Coupling",
    "GraspModel",
    "MaxWrench",
    "Method",
    "PassiveResponse",
    "PruneRecord",
    "ResistanceProfile",
    "Search",
    "Settings",
    "Variant",
    "WRENCH_AXES",
    "format_magnitude",
    "format_max_wrench",
    "friction_edges",
    "plane_directions",
    "results_rows",
    "results_table",
    "results_to_csv",
    "wrench_direction",
    # errors and warnings
    "AuditWarning",
    "BigMWarning",
    "ConditioningWarning",
    "InvalidInputError",
    "MissingDependencyError",
    "ModelError",
    "ModelFileError",
    "NoContactError",
    "PenetrationError",
    "PinograspError",
    "PinograspWarning",
    "PreloadNotInEquilibriumError",
    "SceneError",
    "SolverError",
    "SolverNotAvailableError",
    "SolverTimeoutError",
    "UnknownNameError",
    "UrdfError",
    # the lazily imported layers
    *_LAZY,
]


def __getattr__(name: str) -> object:
    import importlib

    if name in _MODULES:
        return importlib.import_module(f".{_MODULES[name]}", __name__)
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'pinograsp' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__, *_MODULES})
