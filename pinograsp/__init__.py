"""pinograsp: passive reaction analysis for robot grasps."""

from .actuation import ACTUATOR_KINDS, Actuator, Coupling
from .contact import Contact, friction_edges
from .errors import (
    BigMWarning,
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

__version__ = "0.1.0"

__all__ = [
    "ACTUATOR_KINDS",
    "Actuator",
    "BigMWarning",
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
