"""pinograsp: passive reaction analysis for robot grasps."""

from .actuation import ACTUATOR_KINDS, Actuator, Coupling
from .contact import Contact, friction_edges
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
from .model import WRENCH_AXES, GraspModel, PruneRecord
from .results import Audit, MaxWrench, PassiveResponse, ResistanceProfile
from .serialize import format_magnitude, format_max_wrench
from .tables import results_rows, results_table, results_to_csv

# --- the solver side: imported on first use, so that `import pinograsp`, the URDF side and
# `pinograsp scenes` / `--help` load neither the solvers nor cvxpy.
_LAZY = {
    "max_resistible_wrench": "analysis",
    "resistance_profile": "analysis",
    "wrench_direction": "analysis",
    "LinearComplianceResult": "baseline",
    "linear_compliance": "baseline",
    "PreloadChoice": "preload",
    "equilibrium_preload": "preload",
    "OptimalPreload": "optimal",
    "DisturbanceCheck": "optimal",
    "optimal_preload": "optimal",
    "PassiveSolver": "response",
    "Session": "response",
    "Settings": "response",
    "passive_response": "response",
    "solver_for": "response",
    "available_miqp_solvers": "solvers",
    "plane_directions": "analysis",
    "resistance_set": "rset",
    "ResistanceSet": "rset",
    "sphere_points": "rset",
    "grasp_score": "metrics",
    "GraspScore": "metrics",
    "ferrari_canny": "metrics",
    "hull_reach": "metrics",
}

__version__ = "0.1.0"

__all__ = [
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
    "Hand": "hand",
    "HandDescription": "hand",
    "example_robot_data_dir": "hand",
    "RigidObject": "objects",
    "detect_contacts": "collision",
    "link_distances": "collision",
    "grasp_model_from_scene": "scene",
}
__all__ += ["ModelFileError", "NoContactError", "PenetrationError", "UrdfError"]
__all__ += [k for k in _URDF_SIDE if k not in __all__]

# --- plots and the 3D scene view (issue 5): matplotlib / plotly are imported only when used.
from .errors import MissingDependencyError  # noqa: E402

_URDF_SIDE.update(
    {
        "plot_profile": "plots",
        "plot_preload_comparison": "plots",
        "plot_force_comparison": "plots",
        "plot_resistance_set": "set_plots",
        "save_figure": "plots",
        "scene_figure": "viewer",
        "save_html": "viewer",
        "save_png": "viewer",
    }
)
__all__ += ["MissingDependencyError", *[k for k in _URDF_SIDE if k not in __all__]]

# --- scene files (issue 5): YAML scenes and the built-in paper scenes.
from .errors import SceneError  # noqa: E402

_URDF_SIDE.update({"load_scene": "scenes", "Scene": "scenes", "builtin_scenes": "scenes"})
__all__ += ["SceneError", "load_scene", "Scene", "builtin_scenes"]

# --- "check my description": closing signs against the geometry (no contact needed).
_URDF_SIDE.update({"check_closing": "inspection", "ClosingCheck": "inspection", "JointClosing": "inspection"})
__all__ += ["check_closing", "ClosingCheck", "JointClosing"]

# --- batches of grasps (local processes, Ray, Dask): records, sampling, evaluation, tables.
_URDF_SIDE.update(
    {
        "evaluate_grasps": "batch",
        "WorstAxisScore": "batch",
        "save_results": "batch",
        "GraspSpec": "grasps",
        "ObjectSpec": "grasps",
        "sample_grasps": "grasps",
        "load_grasps": "grasp_files",
        "GraspBatch": "grasp_files",
    }
)
__all__ += ["evaluate_grasps", "WorstAxisScore", "save_results", "GraspSpec", "ObjectSpec"]
__all__ += ["sample_grasps", "load_grasps", "GraspBatch"]


def __getattr__(name: str) -> object:
    if name in _URDF_SIDE:
        import importlib

        return getattr(importlib.import_module(f".{_URDF_SIDE[name]}", __name__), name)
    raise AttributeError(f"module 'pinograsp' has no attribute {name!r}")
