"""pinograsp: passive reaction analysis for robot grasps."""

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
    ConvergenceWarning,
    InvalidInputError,
    ModelError,
    PinograspError,
    PinograspWarning,
    PreloadNotInEquilibriumError,
    SolverError,
    SolverNotAvailableError,
    SolverTimeoutError,
    UnknownNameError,
)

# --- the solver side: imported on first use, so that `import pinograsp`, the URDF side and
# `pinograsp scenes` / `--help` load neither the solvers nor cvxpy.
_LAZY = {
    "max_resistible_wrench": "analysis.max_wrench",
    "resistance_profile": "analysis.max_wrench",
    "LinearComplianceResult": "analysis.baseline",
    "linear_compliance": "analysis.baseline",
    "PreloadChoice": "analysis.preload",
    "equilibrium_preload": "analysis.preload",
    "OptimalPreload": "analysis.optimal",
    "DisturbanceCheck": "analysis.optimal",
    "optimal_preload": "analysis.optimal",
    "PassiveSolver": "analysis.response",
    "Session": "analysis.response",
    "passive_response": "analysis.response",
    "solver_for": "analysis.response",
    "available_miqp_solvers": "solvers",
    "resistance_set": "analysis.resistance_set",
    "ResistanceSet": "analysis.resistance_set",
    "sphere_points": "analysis.resistance_set",
    "grasp_score": "analysis.metrics",
    "GraspScore": "analysis.metrics",
    "ferrari_canny": "analysis.metrics",
    "hull_reach": "analysis.metrics",
}

__version__ = "0.1.0"

__all__ = [
    "Backend",
    "Method",
    "Search",
    "Variant",
    "plane_directions",
    "Audit",
    "LinearComplianceResult",
    "MaxWrench",
    "PassiveResponse",
    "PassiveSolver",
    "ResistanceProfile",
    "Session",
    "Settings",
    "available_miqp_solvers",
    "equilibrium_preload",
    "PreloadChoice",
    "optimal_preload",
    "OptimalPreload",
    "DisturbanceCheck",
    "format_magnitude",
    "format_max_wrench",
    "linear_compliance",
    "max_resistible_wrench",
    "passive_response",
    "resistance_profile",
    "results_rows",
    "results_table",
    "results_to_csv",
    "solver_for",
    "wrench_direction",
    "ACTUATOR_KINDS",
    "Actuator",
    "AuditWarning",
    "BigMWarning",
    "ConditioningWarning",
    "Contact",
    "ConvergenceWarning",
    "Coupling",
    "GraspModel",
    "InvalidInputError",
    "ModelError",
    "PinograspError",
    "PinograspWarning",
    "PreloadNotInEquilibriumError",
    "PruneRecord",
    "SolverError",
    "SolverNotAvailableError",
    "SolverTimeoutError",
    "UnknownNameError",
    "WRENCH_AXES",
    "friction_edges",
]

# --- URDF side (issue 3): hands, objects, contact detection; imported lazily so that solvers and
# analytic models never load Pinocchio or Coal.
from .errors import ModelFileError, NoContactError, PenetrationError, UrdfError  # noqa: E402

_URDF_SIDE = {
    **_LAZY,
    "Hand": "robots.hand",
    "HandDescription": "robots.hand",
    "example_robot_data_dir": "robots.hand",
    "RigidObject": "robots.objects",
    "detect_contacts": "robots.collision",
    "link_distances": "robots.collision",
    "grasp_model_from_scene": "robots.grasp",
}
__all__ += ["ModelFileError", "NoContactError", "PenetrationError", "UrdfError"]
__all__ += [k for k in _URDF_SIDE if k not in __all__]

# --- plots and the 3D scene view (issue 5): matplotlib / plotly are imported only when used.
from .errors import MissingDependencyError  # noqa: E402

_URDF_SIDE.update(
    {
        "plot_profile": "viz.plots",
        "plot_preload_comparison": "viz.plots",
        "plot_force_comparison": "viz.plots",
        "plot_resistance_set": "viz.set_plots",
        "save_figure": "viz.plots",
        "scene_figure": "viz.viewer",
        "save_html": "viz.viewer",
        "save_png": "viz.viewer",
    }
)
__all__ += ["MissingDependencyError", *[k for k in _URDF_SIDE if k not in __all__]]

# --- scene files (issue 5): YAML scenes and the built-in paper scenes.
from .errors import SceneError  # noqa: E402

_URDF_SIDE.update(
    {"load_scene": "scenes.loading", "Scene": "scenes.schema", "builtin_scenes": "scenes.loading"}
)
__all__ += ["SceneError", "load_scene", "Scene", "builtin_scenes"]

# --- "check my description": closing signs against the geometry (no contact needed).
_URDF_SIDE.update(
    {"check_closing": "robots.closing", "ClosingCheck": "robots.closing", "JointClosing": "robots.closing"}
)
__all__ += ["check_closing", "ClosingCheck", "JointClosing"]

# --- batches of grasps (local processes, Ray, Dask): records, sampling, evaluation, tables.
_URDF_SIDE.update(
    {
        "evaluate_grasps": "batch.evaluate",
        "WorstAxisScore": "batch.evaluate",
        "save_results": "batch.evaluate",
        "GraspSpec": "batch.grasps",
        "ObjectSpec": "batch.grasps",
        "sample_grasps": "batch.grasps",
        "load_grasps": "batch.files",
        "GraspBatch": "batch.files",
    }
)
__all__ += ["evaluate_grasps", "WorstAxisScore", "save_results", "GraspSpec", "ObjectSpec"]
__all__ += ["sample_grasps", "load_grasps", "GraspBatch"]


def __getattr__(name: str) -> object:
    import importlib

    if name == "examples":  # the analytic and synthetic example grasps (a module)
        return importlib.import_module(".core.examples", __name__)
    if name in _URDF_SIDE:
        return getattr(importlib.import_module(f".{_URDF_SIDE[name]}", __name__), name)
    raise AttributeError(f"module 'pinograsp' has no attribute {name!r}")
