"""The studied plan (issue 34(a)'s miss): Ability hand x box, plan 5, along -fz."""

from __future__ import annotations

import json

import numpy as np

from scripts.reproduce.planning_acceptance import CACHE, spec_of


def plan_model(pair: str = "ability × box", plan: int = 4):
    """``(model, command)`` of a cached top-5 plan (``plan``: 0-based)."""
    from pinograsp.batch.grasps import build_grasp

    p = json.loads(CACHE.read_text())["pairs"][pair]["plans"][plan]
    model, command, _ = build_grasp(spec_of(p["spec"]))
    return model, command


MINUS_FZ = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 0.0])
