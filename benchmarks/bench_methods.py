"""Method against method on the paper's scenes: the same directions, each method's time and answer."""

from __future__ import annotations

import math
import warnings

import numpy as np

import pinograsp as pg

SCENES = ["case1", "case3"]
METHODS = ["prp", "iterative", "energetic"]
#: directions in the scene's XY force plane [deg from +fx]
ANGLES = [90, 30, 150, 255]


class MethodVsMethod:
    """``pg.max_resistible_wrench`` along one XY direction of a built-in scene with its preload
    (upper 50 N, 20 steps); ``magnitude`` [N] (``inf``: unbounded) and ``vs_iterative``: the
    relative difference from the iterative scheme's answer (0 where both are unbounded)."""

    params = [SCENES, ANGLES, METHODS]
    param_names = ["scene", "angle [deg]", "method"]

    def setup(self, scene: str, angle: int, method: str) -> None:
        sc = pg.load_scene(scene)
        self.model, self.command = sc.model, sc.command
        a = math.radians(angle)
        d = np.zeros(3 if self.model.planar else 6)
        d[0], d[1] = math.cos(a), math.sin(a)
        self.direction = d
        self.answers: dict[str, pg.MaxWrench] = {}

    def _answer(self, method: str) -> pg.MaxWrench:
        if method not in self.answers:
            self.answers[method] = self._query(method)
        return self.answers[method]

    def _query(self, method: str) -> pg.MaxWrench:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pg.AuditWarning)
            return pg.max_resistible_wrench(
                self.model, self.command, self.direction, method=method, upper=50.0, steps=20
            )

    def time_query(self, scene: str, angle: int, method: str) -> None:
        self._query(method)

    def track_magnitude(self, scene: str, angle: int, method: str) -> float:
        return self._answer(method).magnitude

    track_magnitude.unit = "N"  # type: ignore[attr-defined]

    def track_vs_iterative(self, scene: str, angle: int, method: str) -> float:
        mine, ref = self._answer(method).magnitude, self._answer("iterative").magnitude
        if math.isinf(mine) and math.isinf(ref):
            return 0.0
        return abs(mine - ref) / ref if ref else math.inf
