"""One solve and one direction query per method on the analytic models (docs/analytic_cases.md)."""

from __future__ import annotations

import warnings

import numpy as np

import pinograsp as pg
from pinograsp import examples

#: name -> (model factory, direction of the query): the closed-form grasps of docs/analytic_cases.md
MODELS = {
    "pinch": (examples.pinch, "fy"),
    "palm pinch": (examples.palm_pinch, "fy"),
    "wedge": (examples.wedge, "fy"),
    "pinch 3D": (lambda: examples.pinch(planar=False), "fy"),
}
METHODS = ["prp", "iterative", "energetic"]


class SolveTimes:
    """A passive response at one load (fy = 4 N, preload 1 N·m) and the largest load along +fy
    (upper 100 N, 10 steps), per model and method; ``solves``: complementarity problems solved
    by the direction query."""

    params = [list(MODELS), METHODS]
    param_names = ["model", "method"]

    def setup(self, model: str, method: str) -> None:
        factory, self.direction = MODELS[model]
        self.model = factory()
        w = np.zeros(3 if self.model.planar else 6)
        w[1] = 4.0
        self.wrench = w

    def time_passive_response(self, model: str, method: str) -> None:
        pg.passive_response(self.model, 1.0, self.wrench, method=method)

    def time_max_resistible_wrench(self, model: str, method: str) -> None:
        self._query(method)

    def track_solves(self, model: str, method: str) -> int:
        return self._answer(method).n_solves

    def track_magnitude(self, model: str, method: str) -> float:
        return self._answer(method).magnitude

    track_magnitude.unit = "N"  # type: ignore[attr-defined]

    def _answer(self, method: str) -> pg.MaxWrench:
        if getattr(self, "answer", None) is None:
            self.answer = self._query(method)
        return self.answer

    def _query(self, method: str) -> pg.MaxWrench:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pg.AuditWarning)  # the PRP's wedging artefact on the wedge
            return pg.max_resistible_wrench(
                self.model, 1.0, self.direction, method=method, upper=100.0, steps=10
            )
