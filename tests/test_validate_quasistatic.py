"""The quasi-static validation harness's rules (scripts/reproduce/validate_quasistatic.py) on
synthetic records: classes, the threshold rule for gradual give-ways, ≈ 0, the refinement rule."""

from __future__ import annotations

import numpy as np
import pytest

from scripts.reproduce import qs_cases, qs_references
from scripts.reproduce import validate_quasistatic as vq


def _sim(status: str, load: float | None, onset: float | None = None, upper: float = 50.0) -> dict:
    return {"status": status, "load": load, "onset": onset, "upper": upper, "slip_threshold": 1e-3,
            "rotation_threshold": 0.02, "stiffness": 1e6}  # fmt: skip


def _pred(status: str, magnitude: float, **lad: float) -> dict:
    return {"status": status, "magnitude": magnitude, "lad": {"pyramid": lad} if lad else {}}


def test_sharp_give_way_relative_difference() -> None:
    c = vq.classify(_pred("finite", 10.0), _sim("gave_way", 10.5), "pyramid")
    assert c["verdict"] == "same class" and c["rel"] == pytest.approx(0.05)


def test_limit_at_or_above_upper_holds() -> None:
    assert vq.classify(_pred("finite", 50.0), _sim("held", None), "pyramid")["verdict"] == "same class"
    c = vq.classify(_pred("unbounded", np.inf), _sim("gave_way", 20.0), "pyramid")
    assert c["verdict"] == "wrong class" and c["why"] == "predicted holds"


def test_gradual_give_way_at_a_tenth_of_the_thresholds() -> None:
    sim = _sim("gradual", 30.0, onset=12.0)
    c = vq.classify(_pred("unbounded", np.inf, thr=80.0, onset=12.6), sim, "pyramid")
    assert c["verdict"] == "same class" and c["via"] == "threshold"
    assert c["rel_onset"] == pytest.approx(12.0 / 12.6 - 1.0)
    assert c["rel_lad"] == pytest.approx(30.0 / 80.0 - 1.0)
    # the path does not move a tenth of the thresholds below upper: it holds
    c = vq.classify(_pred("unbounded", np.inf, thr=800.0, onset=60.0), sim, "pyramid")
    assert c["verdict"] == "wrong class"


def test_zero_is_its_own_class() -> None:
    c = vq.classify(_pred("below_resolution", 0.0), _sim("gave_way", 26.4), "pyramid")
    assert c["verdict"] == "wrong class" and c["why"] == "predicted ≈ 0"
    c = vq.classify(_pred("below_resolution", 0.0), _sim("gave_way", 0.01), "pyramid")
    assert c["verdict"] == "same class" and c["zero"]


def test_no_verdict_and_not_run() -> None:
    assert vq.classify(_pred("node_limit", np.nan), _sim("held", None), "pyramid")["verdict"] == "no verdict"
    assert vq.classify(None, _sim("held", None), "pyramid")["verdict"] == "not run"


def test_refinement_rule() -> None:
    assert qs_references.refine_upper({"status": "gave_way", "load": 1.9, "upper": 50.0}) == pytest.approx(
        7.6
    )
    assert (
        qs_references.refine_upper({"status": "gave_way", "load": 10.0, "upper": 50.0}) is None
    )  # > upper / 8
    assert qs_references.refine_upper({"status": "gave_way", "load": 0.01, "upper": 50.0}) is None  # ≈ 0
    assert qs_references.refine_upper({"status": "held", "load": None, "upper": 50.0}) is None
    assert (
        qs_references.refine_upper({"status": "gave_way", "load": 1.9, "upper": 7.6, "refined": True}) is None
    )


def test_trace_load_interpolates_the_first_crossing() -> None:
    sim = _sim("gradual", 5.0)
    sim["trace"] = {
        "applied": [1.0, 2.0, 4.0],
        "translation": [0.0, 5e-6, 1.5e-5],
        "rotation": [0.0, 0.0, 0.0],
    }
    # 1 % of the 1 mm threshold = 1e-5 m, reached halfway (in displacement) from 2 N to 4 N
    assert vq.trace_load(sim) == pytest.approx(np.exp(0.5 * (np.log(2.0) + np.log(4.0))))


def test_case_keys_are_unique_and_directions_unit() -> None:
    cs = list(qs_cases.cases())
    assert len({c.key for c in cs}) == len(cs)
    assert max(abs(np.linalg.norm(c.direction) - 1.0) for c in cs) < 1e-12
    assert sum(c.set != "scenes" for c in cs) == 108  # 72 random + 18 backdrivable + 18 low mu
