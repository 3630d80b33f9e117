"""The quasi-static validation harness's rules (scripts/reproduce/validate_quasistatic.py) on
synthetic records (classes, ≈ 0, the refinement rule; gradual give-ways compared with the answer
itself, no rescue), and the default answer itself as the compared prediction."""

from __future__ import annotations

import numpy as np
import pytest

import pinograsp as pg
from scripts.reproduce import qs_cases, qs_references
from scripts.reproduce import validate_quasistatic as vq


def _sim(status: str, load: float | None, onset: float | None = None, upper: float = 50.0) -> dict:
    return {"status": status, "load": load, "onset": onset, "upper": upper, "slip_threshold": 1e-3,
            "rotation_threshold": 0.02, "stiffness": 1e6}  # fmt: skip


def _pred(status: str, magnitude: float) -> dict:
    return {"status": status, "magnitude": magnitude}


def test_sharp_give_way_relative_difference() -> None:
    c = vq.classify(_pred("finite", 10.0), _sim("gave_way", 10.5))
    assert c["verdict"] == "same class" and c["rel"] == pytest.approx(0.05)


def test_limit_at_or_above_upper_holds() -> None:
    assert vq.classify(_pred("finite", 50.0), _sim("held", None))["verdict"] == "same class"
    c = vq.classify(_pred("unbounded", np.inf), _sim("gave_way", 20.0))
    assert c["verdict"] == "wrong class" and c["why"] == "predicted holds"


def test_gradual_give_way_is_compared_with_the_answer_itself() -> None:
    """No rescue: a gradual simulated give-way against the answer's own load; an unbounded
    answer is the wrong class however far its path moves."""
    sim = _sim("gradual", 30.0, onset=12.0)
    c = vq.classify(_pred("finite", 28.0), sim)
    assert c["verdict"] == "same class" and not c["sharp"] and c["rel"] == pytest.approx(30.0 / 28.0 - 1.0)
    c = vq.classify(_pred("unbounded", np.inf), sim)
    assert c["verdict"] == "wrong class" and c["why"] == "predicted holds" and c["rel"] is None


def test_headline_counts() -> None:
    rows = [
        {"friction": "pyramid", "cmp": {"quasistatic": vq.classify(_pred(st, m), _sim(ss, sl))}}
        for st, m, ss, sl in [("finite", 10.0, "gave_way", 10.5), ("finite", 10.0, "gradual", 13.0),
                              ("unbounded", np.inf, "held", None), ("unbounded", np.inf, "gave_way", 5.0)]
    ]  # fmt: skip
    h = vq.headline(rows, "quasistatic", "pyramid")
    assert (h["directions"], h["same"], h["wrong"], h["finite"], h["within"]) == (4, 3, 1, 2, 1)
    assert h["median"] == pytest.approx(0.5 * (0.05 + 0.3))


def test_zero_is_its_own_class() -> None:
    c = vq.classify(_pred("below_resolution", 0.0), _sim("gave_way", 26.4))
    assert c["verdict"] == "wrong class" and c["why"] == "predicted ≈ 0"
    c = vq.classify(_pred("below_resolution", 0.0), _sim("gave_way", 0.01))
    assert c["verdict"] == "same class" and c["zero"]


def test_no_verdict_and_not_run() -> None:
    assert vq.classify(_pred("node_limit", np.nan), _sim("held", None))["verdict"] == "no verdict"
    assert vq.classify(None, _sim("held", None))["verdict"] == "not run"


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
    # 1e-5 m reached halfway (in displacement) from 2 N to 4 N
    assert vq.trace_load(sim, 1e-5, 1.0) == pytest.approx(np.exp(0.5 * (np.log(2.0) + np.log(4.0))))


def test_the_default_answer_itself_is_compared() -> None:
    """The live record is ``pg.max_resistible_wrench(model, command, d, upper=...)`` at its
    defaults (the give-way answer), not a load read off the path by hand; λ* is its first limit.
    Case 2 at -X: the first limit 12.49 N is a snap the grasp survives."""
    case = next(c for c in qs_cases.cases(["scenes"]) if c.key == "scenes/case2/-fx")
    _, model, command = case.build()
    mw = pg.max_resistible_wrench(model, command, np.asarray(case.direction), upper=case.upper)
    rec = vq.run_quasistatic(case, {"pyramid": {"upper": 12.5}})
    assert rec["answer"] == "giveway" and rec["method"] == "quasistatic"
    assert (rec["status"], rec["magnitude"]) == (str(mw.status), float(mw.magnitude))
    assert vq.first_limit(rec)["magnitude"] == pytest.approx(12.49, abs=0.01) == mw.giveway.first_limit
    assert rec["giveway"]["snaps"] and rec["magnitude"] != rec["giveway"]["first_limit"]
    # the answer at a simulation record's own upper (a refinement pass) is computed there
    at = vq.at_upper(rec, {"upper": 12.5})
    again = pg.max_resistible_wrench(model, command, np.asarray(case.direction), upper=12.5)
    assert (at["status"], at["magnitude"]) == (str(again.status), float(again.magnitude))


@pytest.mark.slow
def test_measured_headline_against_the_cached_simulations() -> None:
    """The documented counts (docs/validation.md, "Headline"): the default answer against the
    pyramid and cone simulations of all 254 directions."""
    refs = vq.load_refs(["pyramid", "cone"])
    sel = [c for c in qs_cases.cases() if c.key in refs]
    preds = vq.collect(["quasistatic"], sel, refs, fresh=False, save=None)["quasistatic"]
    rows = []
    for c in sel:
        for f, sim in refs[c.key].items():
            p = vq.at_upper(preds[c.key], sim)
            rows.append({"friction": f, "cmp": {"quasistatic": vq.classify(p, sim),
                                                 vq.FIRST: vq.classify(vq.first_limit(p), sim)}})  # fmt: skip
    got = {
        (m, f): (h["directions"], h["same"], h["finite"], h["within"])
        for f in ("pyramid", "cone")
        for m in ("quasistatic", vq.FIRST)
        for h in [vq.headline(rows, m, f)]
    }
    assert got == {  # issue 31's goals: same class >= 98 %, finite pairs within 10 % >= 90 %
        ("quasistatic", "pyramid"): (352, 346, 222, 190),
        (vq.FIRST, "pyramid"): (352, 312, 194, 176),
        ("quasistatic", "cone"): (352, 348, 223, 183),
        (vq.FIRST, "cone"): (352, 311, 193, 166),
    }
    # the 254 directions of issue 25 (the scenes before the four new ones) meet both goals:
    # 250 / 254 same class, 134 / 146 within 10 % (docs/validation_quasistatic.md)
    assert got["quasistatic", "pyramid"][1] >= 0.98 * 352
    assert vq.headline(rows, "quasistatic", "pyramid")["median"] == pytest.approx(0.00513, abs=5e-5)


def test_case_keys_are_unique_and_directions_unit() -> None:
    cs = list(qs_cases.cases())
    assert len({c.key for c in cs}) == len(cs)
    assert max(abs(np.linalg.norm(c.direction) - 1.0) for c in cs) < 1e-12
    assert sum(c.set != "scenes" for c in cs) == 108  # 72 random + 18 backdrivable + 18 low mu


def test_settled_reference_takes_the_slowest_settled_ramp(tmp_path, monkeypatch) -> None:
    """``--friction settled``: a direction the ramp study re-simulated is compared with its run
    at the slowest settled ramp (0.3 s here: 0.1 -> 0.3 s moved 2 %), any other with its 0.02 s
    pyramid record; the study's hand directions are ignored."""
    import json

    from scripts.reproduce import ramp_study

    study = tmp_path / "ramp_study.json"
    runs = {"0.02": _sim("gradual", 1.5), "0.1": _sim("gradual", 2.9), "0.3": _sim("gradual", 2.958)}
    answer = {"status": "finite", "magnitude": 3.0, "reason": "rotation", "first_limit": 1.2}
    rows = [
        {"key": "qs/scenes/a/15°", "role": "disagreement", "upper": 50.0, "answer": answer, "sims": runs},
        {"key": "hands/b/15°", "role": "disagreement", "upper": 50.0, "answer": answer, "sims": runs},
    ]
    study.write_text(json.dumps({"meta": {}, "rows": rows}))
    monkeypatch.setattr(ramp_study, "DATA", study)
    refs = {
        "scenes/a/15°": {"pyramid": _sim("gradual", 1.5), "cone": _sim("gradual", 1.6)},
        "scenes/c/30°": {"pyramid": _sim("gave_way", 7.0)},
        "hands/b/15°": {"cone": _sim("gradual", 1.0)},
    }
    vq.settled_refs(refs)
    assert refs["scenes/a/15°"]["settled"]["load"] == 2.958
    assert refs["scenes/a/15°"]["settled"]["ramp_time"] == 0.3
    assert refs["scenes/c/30°"]["settled"] is refs["scenes/c/30°"]["pyramid"]
    assert "settled" not in refs["hands/b/15°"]  # no pyramid record: no settled reference
