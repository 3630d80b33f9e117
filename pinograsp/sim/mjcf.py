"""The reduced MuJoCo model of a grasp: hand joints, the free object, tendons, limits, motors.

The model is built from the :class:`~pinograsp.GraspModel` arrays alone (docs/simulation.md,
"The reduced model"): one hinge per model joint (its position is the joint displacement ``q``
from the touching configuration, its inertia an armature), one free body for the object (its
centre of mass at the reference point ``o``), one fixed tendon per actuator (length
``u = R^T q``, :mod:`pinograsp.core.model`) carrying a motor and, for non-backdrivable
actuators, a lower limit moved to the running maximum of ``u`` during the simulation; locked
actuators and the rigid couplings ``C q = 0`` are tendon equalities. MuJoCo's own collision
detection is disabled: contact forces come from :mod:`pinograsp.sim.contacts`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import MissingDependencyError

if TYPE_CHECKING:
    from ..core.model import GraspModel

#: Impedance of every limit and equality: constant 0.99 (MuJoCo ``solimp``), so a held actuator
#: yields ~1 % of what an unconstrained joint would (docs/simulation.md).
SOLIMP = "0.99 0.99 0.001 0.5 2"
#: Upper end of a non-backdrivable actuator's range [m or rad]: never reached.
FAR = 1e6


def import_mujoco() -> Any:
    """The ``mujoco`` module, or :class:`~pinograsp.errors.MissingDependencyError`."""
    try:
        import mujoco
    except ImportError as exc:
        raise MissingDependencyError("mujoco", "pinograsp's simulation", extra="mujoco") from exc
    return mujoco


@dataclass(frozen=True)
class ReducedModel:
    """A compiled MuJoCo model of a grasp and the indices the simulation needs.

    Attributes:
        model: The ``mujoco.MjModel``.
        xml: The MJCF text it was compiled from.
        object_body: Body id of the object.
        hand_qpos: ``qpos`` addresses of the hand joints, (nq,).
        hand_dof: ``qvel`` addresses of the hand joints, (nq,).
        limited: Tendon ids of the non-backdrivable actuators (their lower limit moves), (nl,).
        motors: Actuator index (in the GraspModel) of each MuJoCo actuator, (nm,).
    """

    model: Any
    xml: str
    object_body: int
    hand_qpos: np.ndarray
    hand_dof: np.ndarray
    limited: np.ndarray
    motors: np.ndarray


def _vec(v: object) -> str:
    return " ".join(f"{float(x):.17g}" for x in np.asarray(v, dtype=float).reshape(-1))


def _fixed_tendon(name: str, coef: np.ndarray, extra: str = "") -> str:
    joints = "".join(f'<joint joint="q{j}" coef="{c:.17g}"/>' for j, c in enumerate(coef) if c != 0.0)
    return f'<fixed name="{name}"{extra}>{joints}</fixed>'


def mjcf(
    grasp: GraspModel,
    *,
    mass: float,
    inertia: float,
    armature: np.ndarray,
    timestep: float,
) -> str:
    """MJCF text of the reduced model (see the module docstring).

    Args:
        grasp: The :class:`~pinograsp.GraspModel`.
        mass: Object mass [kg].
        inertia: Object's principal moment of inertia about ``o`` (isotropic) [kg·m²].
        armature: Generalised inertia of each hand joint, (nq,) [kg·m² per rad² of ``q``].
        timestep: Integration step [s].

    Returns:
        The MJCF document.
    """
    tc = 2.0 * timestep  # MuJoCo's stiffest admissible constraint time constant
    soft = f'solref="{tc:.17g} 1" solimp="{SOLIMP}"'
    body = [
        f'<body name="object" pos="{_vec(grasp.reference_point)}"><freejoint name="object"/>'
        f'<inertial pos="0 0 0" mass="{mass:.17g}" diaginertia="{_vec([inertia] * 3)}"/></body>'
    ]
    for j in range(grasp.nq):
        body.append(
            f'<body name="joint{j}"><joint name="q{j}" type="hinge" axis="0 0 1" '
            f'armature="{armature[j]:.17g}"/><inertial pos="0 0 0" mass="1e-9" '
            f'diaginertia="1e-12 1e-12 1e-12"/></body>'
        )
    tendons, equalities, motors = [], [], []
    for a, kind in enumerate(grasp.kinds):
        coef = np.asarray(grasp.R[:, a], dtype=float)
        if kind == "locked":
            tendons.append(_fixed_tendon(f"a{a}", coef))
            equalities.append(f'<tendon tendon1="a{a}" {soft}/>')
            continue
        limit = f' limited="true" range="0 {FAR:g}" solreflimit="{tc:.17g} 1" solimplimit="{SOLIMP}"'
        tendons.append(_fixed_tendon(f"a{a}", coef, limit if kind == "non-backdrivable" else ""))
        motors.append(f'<motor name="m{a}" tendon="a{a}" gear="1"/>')
    for i in range(grasp.ncp):
        tendons.append(_fixed_tendon(f"c{i}", np.asarray(grasp.C[i], dtype=float)))
        equalities.append(f'<tendon tendon1="c{i}" {soft}/>')
    return (
        '<mujoco model="pinograsp-reduced">'
        f'<option timestep="{timestep:.17g}" gravity="0 0 0" integrator="Euler">'
        '<flag contact="disable"/></option>'
        f"<worldbody>{''.join(body)}</worldbody>"
        f"<tendon>{''.join(tendons)}</tendon>"
        f"<equality>{''.join(equalities)}</equality>"
        f"<actuator>{''.join(motors)}</actuator></mujoco>"
    )


def build(
    grasp: GraspModel, *, mass: float, inertia: float, armature: np.ndarray, timestep: float
) -> ReducedModel:
    """Compile the reduced model of ``grasp`` (arguments as :func:`mjcf`)."""
    mujoco = import_mujoco()
    xml = mjcf(grasp, mass=mass, inertia=inertia, armature=armature, timestep=timestep)
    m = mujoco.MjModel.from_xml_string(xml)
    ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"q{j}") for j in range(grasp.nq)]
    limited = [
        mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_TENDON, f"a{a}")
        for a, kind in enumerate(grasp.kinds)
        if kind == "non-backdrivable"
    ]
    return ReducedModel(
        model=m,
        xml=xml,
        object_body=mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "object"),
        hand_qpos=np.array([m.jnt_qposadr[i] for i in ids], dtype=int),
        hand_dof=np.array([m.jnt_dofadr[i] for i in ids], dtype=int),
        limited=np.array(limited, dtype=int),
        motors=np.array([a for a, kind in enumerate(grasp.kinds) if kind != "locked"], dtype=int),
    )
