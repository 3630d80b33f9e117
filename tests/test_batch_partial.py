"""Batch rows keep every direction that answered: a direction that raises an error (here a
SolverError injected into ``max_resistible_wrench`` along one axis) makes the row ``"partial"``,
its own columns NaN with a typed ``status_<direction>``, and every other direction's number
bit-identical to the run where nothing fails; ``score`` (the worst case) is NaN there (an upper
bound only), and answers about the grasp (no preload) or a failure of every axis still make the
whole row."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.analysis import max_wrench
from pinograsp.batch.evaluate import TAIL_COLUMNS, TIMING_COLUMNS
from pinograsp.batch.scores import WorstAxisScore
from pinograsp.errors import SolverError

pd = pytest.importorskip("pandas")

SCORE = WorstAxisScore(upper=20, steps=4)  # the default method: the quasi-static path
GRASPS = ["pinch", "case1", {"scene": "wedge", "id": "w"}]
AXES = ("+fx", "-fx", "+fy", "-fy", "+fz", "-fz")


def _failing(monkeypatch, axes: set[str]) -> None:
    """``max_resistible_wrench`` raising a SolverError along ``axes`` (as the score names them:
    ``"fx"``, ``"-fx"``, ...)."""
    real = max_wrench.max_resistible_wrench

    def fake(model, command, direction, *args, **kwargs):
        if direction in axes:
            raise SolverError("the quasi-static path stopped without a verdict (injected)", solver="lemke")
        return real(model, command, direction, *args, **kwargs)

    monkeypatch.setattr(max_wrench, "max_resistible_wrench", fake)


@pytest.fixture(scope="module")
def reference():
    return pg.evaluate_grasps(GRASPS, score=SCORE, workers=1)


def test_complete_rows_say_ok_per_direction(reference):
    df = reference
    assert df["status"].tolist() == ["ok", "ok", "ok"]
    assert list(df.columns[-len(TAIL_COLUMNS) :]) == list(TAIL_COLUMNS)
    cols = list(df.columns)
    assert cols[cols.index("max_-fz") + 1 : cols.index("error_type")] == [f"status_{a}" for a in AXES]
    assert df.loc[1, [f"status_{a}" for a in AXES]].tolist() == ["ok"] * 6  # case 1: 3D
    assert df.loc[0, [f"status_{a}" for a in AXES]].tolist() == ["ok"] * 4 + ["", ""]  # planar pinch


def test_one_failing_direction_keeps_the_others_bit_identical(monkeypatch, reference):
    _failing(monkeypatch, {"-fy"})
    df = pg.evaluate_grasps(GRASPS, score=SCORE, workers=1)
    assert df["status"].tolist() == ["partial"] * 3
    assert df["reason"].tolist() == ["solver_error"] * 3
    assert (df["error_type"] == "SolverError").all()
    assert df["error_message"].str.startswith("-fy: SolverError: the quasi-static path stopped").all()
    assert (df["status_-fy"] == "solver_error").all() and df["max_-fy"].isna().all()
    # the worst case of a partial row is not known: NaN, not the answered axes' minimum
    assert df["score"].isna().all() and df["unbounded_fraction"].isna().all()
    kept = [c for c in df.columns if c.startswith(("max_", "status_")) and not c.endswith("-fy")]
    kept += ["index", "id", "source", "n_contacts", "command"]
    pd.testing.assert_frame_equal(df[kept], reference[kept], check_exact=True)
    # the bound a user can read off a partial row: the answered axes' minimum, an upper bound
    bound = df[[f"max_{a}" for a in AXES]].min(axis=1)
    assert (bound >= reference["score"]).all()
    assert bound[0] == reference.loc[0, "score"]  # pinch: +fy takes the same 10 N limit
    counts = pg.reason_counts(df)
    assert counts[["status", "reason", "rows"]].values.tolist() == [["partial", "solver_error", 3]]


def test_partial_rows_survive_resume(monkeypatch, tmp_path):
    _failing(monkeypatch, {"fx"})
    out = tmp_path / "t.csv"
    first = pg.evaluate_grasps(GRASPS, score=SCORE, workers=1, out=out)
    again = pg.evaluate_grasps(GRASPS, score=SCORE, workers=1, out=out, resume=True)
    cols = [c for c in first.columns if c not in TIMING_COLUMNS]
    pd.testing.assert_frame_equal(first[cols], again[cols], check_exact=True)
    assert (again["status_+fx"] == "solver_error").all() and (again["status"] == "partial").all()


def test_every_direction_failing_is_an_error_row_and_no_preload_stays_an_answer(monkeypatch):
    _failing(monkeypatch, {"fx", "-fx", "fy", "-fy", "fz", "-fz"})
    df = pg.evaluate_grasps(["pinch"], score=SCORE, workers=1)
    assert df.loc[0, "status"] == "error" and df.loc[0, "reason"] == "solver_error"
    assert math.isnan(df.loc[0, "score"]) and df.loc[0, "status_+fx"] == ""
    # an unbalanced preload is an answer about the grasp: the whole row, as before
    monkeypatch.undo()
    m = pg.examples.pinch(kind="backdrivable")
    with pytest.raises(pg.PreloadNotInEquilibriumError):
        SCORE(m, {"left": 1.0, "right": 0.5})


def test_direct_call_reports_failures(monkeypatch):
    _failing(monkeypatch, {"fy"})
    values = SCORE(pg.examples.pinch(), {"left": 1.0, "right": 1.0})
    assert values.statuses == {
        "status_+fx": "ok",
        "status_-fx": "ok",
        "status_+fy": "solver_error",
        "status_-fy": "ok",
    }
    assert [f.direction for f in values.failures] == ["+fy"] and values.failures[0].reason == "solver_error"
    assert math.isnan(values["score"]) and math.isnan(values["max_+fy"])
    assert values["max_-fy"] == pytest.approx(10.0, abs=20 / 2**4)  # 2 mu tau / L, to the resolution
    assert np.isinf(values["max_+fx"])


def test_auto_preload_that_slides_is_kept_with_a_warning(monkeypatch):
    """``command="auto"``: a design in equilibrium whose released state slides is analysed as it
    is (the same commands as when it is "found"), and the row's warnings say so; an unverified
    one is still a ``no_preload`` row."""
    import dataclasses

    from pinograsp.analysis import preload

    box = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))
    q = {"bh_j11": math.pi / 2, "bh_j12": math.pi / 3, "bh_j13": math.pi / 9}
    q.update({"bh_j22": math.pi / 3, "bh_j23": math.pi / 9})
    spec = pg.GraspSpec("barrett_bh8_282", box, q=q, command="auto", id="auto")
    found = pg.evaluate_grasps([spec], score=SCORE, workers=1)
    assert found.loc[0, "status"] == "ok" and "equilibrium_preload" not in found.loc[0, "warnings"]
    real = preload.equilibrium_preload
    for status, row in (("slides", "ok"), ("unverified", "no_grasp")):

        def fake(*args, _status=status, **kwargs):
            return dataclasses.replace(real(*args, **kwargs), status=_status, reason="(injected)")

        monkeypatch.setattr(preload, "equilibrium_preload", fake)
        df = pg.evaluate_grasps([spec], score=SCORE, workers=1)
        assert df.loc[0, "status"] == row
        if row == "ok":
            assert "PinograspWarning: equilibrium_preload: slides: (injected)" in df.loc[0, "warnings"]
            assert df.loc[0, "command"] == found.loc[0, "command"]
            assert df.loc[0, "score"] == found.loc[0, "score"]
        else:
            assert df.loc[0, "reason"] == "no_preload"
