"""Time against error of the magnitude search settings, on grasps with a closed form."""

from __future__ import annotations

import math
import warnings

import pinograsp as pg
from pinograsp import examples

#: name -> (factory, direction, closed-form limit [N] per method family): docs/analytic_cases.md
MODELS = {
    "pinch, +fy": (examples.pinch, "fy", {"prp": 10.0, "iterative": 10.0, "energetic": 10.0}),
    "pinch, (1, 1)": (
        examples.pinch,
        [1.0, 1.0, 0.0],
        {"prp": 10 * math.sqrt(2), "iterative": 10 * math.sqrt(2)},
    ),
    "pinch, fingers 1 cm apart in z, +fy": (
        lambda: examples.pinch(h=0.01),
        "fy",
        {"iterative": 6.0, "energetic": 6.0},
    ),
}
#: name -> (method, keyword arguments of pg.max_resistible_wrench), upper 1000 N
CONFIGS = {
    "PRP bisection, 10 steps": ("prp", dict(steps=10)),
    "PRP bisection, 20 steps": ("prp", dict(steps=20)),
    "PRP direct": ("prp", dict(search="direct")),
    "iterative secant, 10 steps": ("iterative", dict(steps=10)),
    "iterative secant, 20 steps": ("iterative", dict(steps=20)),
    "iterative bisection, 20 steps": ("iterative", dict(steps=20, search="bisection")),
    "energetic, 20 steps": ("energetic", dict(steps=20)),
}


class TimeVsError:
    """One direction query per search setting; ``relative_error``: ``|answer - closed form| /
    closed form``; ``resolution``: the reported resolution over the closed form (the error is
    below it where resistibility is monotone along the ray)."""

    params = [list(MODELS), list(CONFIGS)]
    param_names = ["grasp", "setting"]

    def setup(self, grasp: str, setting: str) -> None:
        factory, self.direction, closed = MODELS[grasp]
        self.method, self.kw = CONFIGS[setting]
        if self.method not in closed:
            raise NotImplementedError(f"no closed form for {self.method} on {grasp}")
        self.model, self.closed = factory(), closed[self.method]

    def _answer(self) -> pg.MaxWrench:
        if getattr(self, "answer", None) is None:
            self.answer = self._query()
        return self.answer

    def _query(self) -> pg.MaxWrench:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", pg.AuditWarning)
            return pg.max_resistible_wrench(
                self.model, 1.0, self.direction, method=self.method, upper=1e3, **self.kw
            )

    def time_query(self, grasp: str, setting: str) -> None:
        self._query()

    def track_relative_error(self, grasp: str, setting: str) -> float:
        return abs(self._answer().magnitude - self.closed) / self.closed

    def track_resolution(self, grasp: str, setting: str) -> float:
        return self._answer().resolution / self.closed

    def track_solves(self, grasp: str, setting: str) -> int:
        return self._answer().n_solves
