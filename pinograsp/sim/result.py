"""The record of one simulated give-way test (:func:`pinograsp.simulate_max_wrench`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

#: ``"gave_way"``: a sharp break: at the largest load it holds the object is still within a
#: tenth of a threshold; ``"gradual"``: at that load it has already moved more (it sways under
#: a growing load, e.g. through a differential: no sharp break load); ``"held"``: it held up to
#: the upper load.
SimulationStatus = Literal["gave_way", "held", "gradual"]

#: Statuses of a prediction (:class:`~pinograsp.MaxWrench`) that mean "resisted up to the upper
#: load", the class of the simulation's ``"held"``.
PREDICTED_HOLDS = ("unbounded", "above_limit")


@dataclass(frozen=True)
class SimulationTrace:
    """Samples of the load phase (every ``trace_every`` steps), each (ns,).

    Attributes:
        time: Time since the load started [s].
        applied: Applied load along the direction [N or N·m].
        resisted: Load the contacts resist along the direction, ``-d · (contact wrench)``
            [N or N·m] (equal to ``applied`` at rest).
        translation: Distance of the reference point from its preloaded position [m].
        rotation: Rotation angle of the object from its preloaded orientation [rad].
    """

    time: np.ndarray
    applied: np.ndarray
    resisted: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray

    def to_dict(self) -> dict[str, list[float]]:
        """The samples as plain lists."""
        return {k: [float(x) for x in getattr(self, k)] for k in self.__dataclass_fields__}


@dataclass(frozen=True)
class SimulationResult:
    """Outcome of ramping a load along one direction on the simulated, preloaded grasp.

    Attributes:
        status: :data:`SimulationStatus`.
        load: Largest constant load under which the object comes to rest within the thresholds
            (to ``tolerance``) [N or N·m along ``direction``]; ``None`` when ``"held"``. For
            ``"gradual"`` the upper end of the give-way range ``[onset_load, load]``.
        onset_load: Applied load of the ramp when the object had first moved a tenth of a
            threshold (at most ``load``) [N or N·m]; ``None`` when it never did.
        applied_load: Applied load when the ramp stopped [N or N·m] (above ``load`` by the
            sliding object's inertia).
        direction: Unit load direction (6,) (plain Euclidean norm of force [N] and torque [N·m]).
        unit: ``"N"``, ``"N·m"`` or ``"N, N·m"``.
        upper: Largest applied load [N or N·m]; held there for ``hold_time``.
        start: First load of the ramp as a fraction of ``upper``; ``load`` is 0 when the object
            does not hold even that.
        slip_threshold: Translation of the reference point that counts as giving way [m].
        rotation_threshold: Rotation that counts as giving way [rad].
        tolerance: Relative resolution of ``load``.
        stiffness: Contact stiffness of the stiffest contact [N/m].
        mass: Object mass [kg] (inertia ``mass * length_scale**2`` about every axis).
        timestep: Integration step [s].
        ramp_time: e-folding time of the exponential load ramp [s].
        preload: ``"held"`` (object held still while the motors close) or ``"settled"``.
        friction: ``"cone"`` (Coulomb's circular cone) or ``"pyramid"`` (the model's pyramid).
        release_time: Time over which a held object was released [s] (0: at once).
        finger_mass: Each hand joint's effective mass at its farthest contact, as a multiple of
            ``mass``.
        steps: Integration steps taken (preload and load phases).
        sim_time: Simulated time [s].
        wall_time: Wall time of the run, model building included [s].
        trace: Samples of the load ramp.
        evidence: Every constant-load test ``(load, held)`` of the refinement, in order.
        command: Actuator commands of the preload, (na,) [N·m or N].
        predicted: The analysis' prediction along the same direction [N or N·m] (``inf`` when
            unbounded), when asked for (:func:`pinograsp.sim.simulate.simulate_command`).
        predicted_status: Its status (``"finite"``, ``"unbounded"``, ...), when asked for.
    """

    status: SimulationStatus
    load: float | None
    onset_load: float | None
    applied_load: float
    direction: np.ndarray
    unit: str
    upper: float
    start: float
    slip_threshold: float
    rotation_threshold: float
    tolerance: float
    stiffness: float
    mass: float
    timestep: float
    ramp_time: float
    preload: str
    friction: str
    release_time: float
    finger_mass: float
    steps: int
    sim_time: float
    wall_time: float
    trace: SimulationTrace = field(repr=False)
    evidence: tuple[tuple[float, bool], ...] = field(repr=False)
    command: np.ndarray = field(repr=False)
    predicted: float | None = None
    predicted_status: str | None = None

    @property
    def agreement(self) -> float | None:
        """``load / predicted - 1`` when both are finite numbers, else ``None``."""
        if self.load is None or self.predicted is None or not np.isfinite(self.predicted):
            return None
        return self.load / self.predicted - 1.0 if self.predicted else None

    @property
    def same_class(self) -> bool | None:
        """Whether simulation and prediction agree on the class: both hold up to ``upper``
        (``"held"`` and ``"unbounded"`` or ``"above_limit"``) or both give way; ``None``
        without a prediction."""
        if self.predicted_status is None:
            return None
        return (self.status == "held") == (self.predicted_status in PREDICTED_HOLDS)

    def to_dict(self, trace: bool = False) -> dict[str, Any]:
        """Plain JSON-ready data (``None`` for missing or infinite numbers); the trace when
        ``trace`` is true."""
        out: dict[str, Any] = {}
        for name in self.__dataclass_fields__:
            value = getattr(self, name)
            if name == "trace":
                if trace:
                    out[name] = value.to_dict()
            elif name == "evidence":
                out[name] = [[float(x), bool(ok)] for x, ok in value]
            elif isinstance(value, np.ndarray):
                out[name] = [float(x) for x in value]
            elif isinstance(value, float) and not np.isfinite(value):
                out[name] = None
            else:
                out[name] = value
        out["agreement"] = self.agreement
        out["same_class"] = self.same_class
        return out

    def summary(self) -> str:
        """One line: status, load, thresholds and time."""
        u = self.unit
        if self.status == "held":
            head = f"held up to {self.upper:g} {u}"
        elif self.status == "gradual":
            head = f"gave way gradually between {self.onset_load:.4g} and {self.load:.4g} {u}"
        elif self.load == 0.0:
            head = f"gave way below the first load of the ramp, {self.upper * self.start:.3g} {u}"
        else:
            head = f"gave way at {self.load:.4g} {u}"
        if self.predicted is not None:
            head += f" (predicted {self.predicted:.4g} {u}, {self.predicted_status})"
        return (
            f"{head}; thresholds {self.slip_threshold * 1e3:.3g} mm, "
            f"{np.degrees(self.rotation_threshold):.3g}°;"
            f" {self.steps} steps of {self.timestep:g} s, {self.wall_time:.2f} s"
        )
