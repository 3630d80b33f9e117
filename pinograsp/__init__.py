"""pinograsp: passive reaction analysis for robot grasps.

The curated public API (docs/design.md). The core layer (NumPy only: models, contacts,
settings, results) is imported here; every other layer — the solvers and analyses, the URDF
side (Pinocchio, Coal), scenes, batches, simulation and plots — is imported on first use of one
of its names, so ``import pinograsp`` loads neither a solver, cvxpy, Pinocchio nor Coal.
"""

from typing import TYPE_CHECKING

from .core.actuation import ACTUATOR_KINDS, Actuator, Coupling
from .core.axes import WRENCH_AXES, plane_directions, wrench_direction
from .core.contact import Contact, friction_edges
from .core.model import GraspModel, PruneRecord
from .core.query import Query
from .core.results import Audit, MaxWrench, PassiveResponse, ResistanceProfile, format_max_wrench
from .core.serialize import format_magnitude
from .core.settings import Backend, Method, Search, Settings, Variant
from .core.tables import results_rows, results_table, results_to_csv
from .errors import (
    AuditWarning,
    BigMWarning,
    ConditioningWarning,
    ContactDetectionError,
    InvalidInputError,
    MissingDependencyError,
    ModelError,
    ModelFileError,
    NoContactError,
    NoPreloadError,
    PenetrationError,
    PinograspError,
    PinograspWarning,
    PreloadNotInEquilibriumError,
    RefinementWarning,
    SceneError,
    SolverError,
    SolverNotAvailableError,
    SolverTimeoutError,
    UnknownNameError,
    UrdfError,
)

__version__ = "0.1.0"

# For type checkers (py.typed): the lazily imported names with their real types, as explicit
# re-exports. tests/test_imports.py checks that this block and _LAZY name the same things.
if TYPE_CHECKING:
    from .analysis.baseline import LinearComplianceResult as LinearComplianceResult
    from .analysis.baseline import linear_compliance as linear_compliance
    from .analysis.max_wrench import max_resistible_wrench as max_resistible_wrench
    from .analysis.metrics import GraspScore as GraspScore
    from .analysis.metrics import ferrari_canny as ferrari_canny
    from .analysis.metrics import grasp_score as grasp_score
    from .analysis.metrics import hull_reach as hull_reach
    from .analysis.optimal import DisturbanceCheck as DisturbanceCheck
    from .analysis.optimal import OptimalPreload as OptimalPreload
    from .analysis.optimal import optimal_preload as optimal_preload
    from .analysis.preload import PreloadChoice as PreloadChoice
    from .analysis.preload import equilibrium_preload as equilibrium_preload
    from .analysis.profile import resistance_profile as resistance_profile
    from .analysis.quasistatic import LoadingPath as LoadingPath
    from .analysis.quasistatic import PathEvent as PathEvent
    from .analysis.quasistatic import loading_path as loading_path
    from .analysis.quasistatic import quasistatic_max_wrench as quasistatic_max_wrench
    from .analysis.quasistatic import quasistatic_response as quasistatic_response
    from .analysis.resistance_set import ResistanceSet as ResistanceSet
    from .analysis.resistance_set import resistance_set as resistance_set
    from .analysis.resistance_set import sphere_points as sphere_points
    from .analysis.response import Session as Session
    from .analysis.response import passive_response as passive_response
    from .batch.disturbances import DisturbanceScore as DisturbanceScore
    from .batch.disturbances import Gravity as Gravity
    from .batch.evaluate import WorstAxisScore as WorstAxisScore
    from .batch.evaluate import evaluate_grasps as evaluate_grasps
    from .batch.evaluate import save_results as save_results
    from .batch.files import GraspBatch as GraspBatch
    from .batch.files import load_grasps as load_grasps
    from .batch.grasps import GraspSpec as GraspSpec
    from .batch.grasps import ObjectSpec as ObjectSpec
    from .batch.grasps import sample_grasps as sample_grasps
    from .batch.rows import reason_counts as reason_counts
    from .core import examples as examples
    from .planning.plan import plan_grasps as plan_grasps
    from .planning.records import GraspPlan as GraspPlan
    from .planning.records import GraspPlans as GraspPlans
    from .planning.records import PlanCheck as PlanCheck
    from .robots.autoclose import close_on as close_on
    from .robots.closing import ClosingCheck as ClosingCheck
    from .robots.closing import JointClosing as JointClosing
    from .robots.closing import check_closing as check_closing
    from .robots.collision import detect_contacts as detect_contacts
    from .robots.collision import link_distances as link_distances
    from .robots.description import HandDescription as HandDescription
    from .robots.description import example_robot_data_dir as example_robot_data_dir
    from .robots.grasp import grasp_model_from_scene as grasp_model_from_scene
    from .robots.hand import Hand as Hand
    from .robots.objects import RigidObject as RigidObject
    from .scenes.loading import builtin_scenes as builtin_scenes
    from .scenes.loading import load_scene as load_scene
    from .scenes.schema import Scene as Scene
    from .sim.result import SimulationResult as SimulationResult
    from .sim.simulate import simulate_max_wrench as simulate_max_wrench
    from .solvers import available_miqp_solvers as available_miqp_solvers
    from .viz.comparison_plots import plot_force_comparison as plot_force_comparison
    from .viz.comparison_plots import plot_preload_comparison as plot_preload_comparison
    from .viz.figures import save_figure as save_figure
    from .viz.path_plots import plot_loading_path as plot_loading_path
    from .viz.plan_plots import plot_plan as plot_plan
    from .viz.profile_plots import plot_profile as plot_profile
    from .viz.scene_inputs import SceneStyle as SceneStyle
    from .viz.set_plots import plot_resistance_set as plot_resistance_set
    from .viz.viewer import save_html as save_html
    from .viz.viewer import save_png as save_png
    from .viz.viewer import scene_figure as scene_figure

#: Public names of the lazily imported layers -> their module (below ``pinograsp``).
_LAZY = {
    # analysis: passive response, max wrench, profiles, sets, scores, preloads, baseline
    "Session": "analysis.response",
    "passive_response": "analysis.response",
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
    "close_on": "robots.autoclose",
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
    "DisturbanceScore": "batch.disturbances",
    "Gravity": "batch.disturbances",
    "save_results": "batch.evaluate",
    "reason_counts": "batch.rows",
    "GraspSpec": "batch.grasps",
    "ObjectSpec": "batch.grasps",
    "sample_grasps": "batch.grasps",
    "load_grasps": "batch.files",
    "GraspBatch": "batch.files",
    # grasp planning
    "plan_grasps": "planning.plan",
    "GraspPlan": "planning.records",
    "GraspPlans": "planning.records",
    "PlanCheck": "planning.records",
    # plots and the 3D scene view
    "plot_profile": "viz.profile_plots",
    "plot_plan": "viz.plan_plots",
    "plot_preload_comparison": "viz.comparison_plots",
    "plot_force_comparison": "viz.comparison_plots",
    "plot_resistance_set": "viz.set_plots",
    "plot_loading_path": "viz.path_plots",
    "save_figure": "viz.figures",
    "scene_figure": "viz.viewer",
    "SceneStyle": "viz.scene_inputs",
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
    "Query",
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
    "ContactDetectionError",
    "InvalidInputError",
    "MissingDependencyError",
    "ModelError",
    "ModelFileError",
    "NoContactError",
    "NoPreloadError",
    "PenetrationError",
    "PinograspError",
    "PinograspWarning",
    "PreloadNotInEquilibriumError",
    "RefinementWarning",
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
