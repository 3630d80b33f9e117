"""Rigid poses: URDF roll-pitch-yaw angles and rotation matrices (the one home of both
conversions; scenes, hand descriptions and grasp records use them). Angles [rad]."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def rotation_rpy(rpy: Sequence[float] | np.ndarray) -> np.ndarray:
    """URDF roll-pitch-yaw [rad] -> rotation ``Rz(yaw) Ry(pitch) Rx(roll)``, (3, 3)."""
    r, p, y = (float(v) for v in rpy)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def rpy_of(R: np.ndarray) -> tuple[float, float, float]:
    """Inverse of :func:`rotation_rpy`: roll, pitch, yaw [rad] of a rotation (3, 3); pitch in
    ``[-pi/2, pi/2]`` (at ``|pitch| = pi/2`` roll is taken 0)."""
    pitch = -math.asin(max(-1.0, min(1.0, float(R[2, 0]))))
    if abs(math.cos(pitch)) < 1e-12:
        return 0.0, pitch, math.atan2(-float(R[0, 1]), float(R[1, 1]))
    return math.atan2(float(R[2, 1]), float(R[2, 2])), pitch, math.atan2(float(R[1, 0]), float(R[0, 0]))
