"""scripts/reproduce/validate_hands.py: the cached hands' validation on 24 directions per hand
(the simulation in all, the paper's methods in the 12 at multiples of 30°, "not run" in the others:
``--extend``), and the report's counts per method over the directions it was run on."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pinograsp as pg
from scripts.reproduce import validate_hands as vh

PAPER = ("iterative", "prp", "energetic")


def _cache(name: str) -> dict:
    return json.loads((vh.CACHE / f"{name}.json").read_text())


@pytest.mark.parametrize("name", vh.HANDS)
def test_cache_holds_24_directions_with_the_paper_methods_on_every_other_one(name):
    data = _cache(name)
    rows, meta = data["rows"], data["meta"]
    scene = pg.load_scene(name)
    dirs = vh.VM._directions(scene, 24)
    assert meta["n"] == 24 and len(rows) == len(dirs) == 24
    assert all(vh._matches(label, row) for (label, _), row in zip(dirs, rows))
    for i, row in enumerate(rows):
        not_run = [row[m]["verdict"] == "not run" for m in PAPER]
        assert all(not_run) if i % 2 else not any(not_run), row["direction"]
        assert row["sim"]["status"] in ("held", "gave_way", "gradual")
    # the simulated-only directions are the odd multiples of 15°, named as the run recorded them
    assert meta["extended"]["simulated only"] == [f"{15 * (2 * k + 1)}°" for k in range(12)]
    # every named direction is among the directions the paper's methods were run on
    named = [r for r in rows if "(" in r["direction"]]
    assert len(named) == 3 and all(r["iterative"]["verdict"] != "not run" for r in named)


def test_extend_simulates_only_the_missing_directions(monkeypatch):
    """The cached rows are kept as they are (the same objects, in the order of the 24
    directions); only the 12 missing ones are simulated, their paper methods "not run"."""
    rows = [r for r in _cache("ezgripper")["rows"] if r["iterative"]["verdict"] != "not run"]
    assert len(rows) == 12
    calls = []

    def fake_simulate(scene, d):
        calls.append(np.asarray(d))
        return {"status": "held", "load": float("nan"), "onset": None, "upper": 50.0, "t": 0.0, "steps": 1}

    monkeypatch.setattr(vh.VM, "_simulate", fake_simulate)
    out = vh.extend_hand("ezgripper", 24, rows)
    assert len(out) == 24 and len(calls) == 12
    assert all(out[2 * k] is rows[k] for k in range(12))
    assert [r["direction"] for r in out[1::2]] == [f"{15 * (2 * k + 1)}°" for k in range(12)]
    assert all(r[m]["verdict"] == "not run" and r[m]["status"] == "not_run" for r in out[1::2] for m in PAPER)
    # a complete cache is left alone; a cached direction outside -n is refused
    assert vh.extend_hand("ezgripper", 24, out) == out and len(calls) == 12
    with pytest.raises(ValueError, match="not among -n 8"):
        vh.extend_hand("ezgripper", 8, rows)


def _row(label: str, ran: bool, verdict: str) -> dict:
    pred = {"status": "unbounded", "magnitude": float("inf"), "upper": 50.0, "wedging": False,
            "wedge_from": None, "t": 0.1, "verdict": verdict, "rel": None}  # fmt: skip
    paper = dict(pred) if ran else dict(vh.NOT_RUN)
    sim = {"status": "held", "load": float("nan"), "onset": None, "upper": 50.0, "t": 1.0, "steps": 1}
    return {"direction": label, "sim": sim, vh.LIVE: dict(pred), **{m: dict(paper) for m in PAPER}}


def test_report_counts_each_method_over_the_directions_it_ran_on(monkeypatch):
    monkeypatch.setattr(vh.VM, "METHODS", (vh.LIVE, *PAPER))
    rows = [_row(f"{15 * i}°", i % 2 == 0, "both hold" if i != 3 else "predicted holds") for i in range(24)]
    by = {s["method"]: s for s in vh.summarize_all({"hand": rows})}
    assert (by[vh.LIVE]["directions"], by[vh.LIVE]["same"], by[vh.LIVE]["pred_holds"]) == (24, 23, 1)
    assert all((by[m]["directions"], by[m]["same"]) == (12, 12) for m in PAPER)
    table = "\n".join(vh._scene_table("hand", rows))
    assert table.count("not run") == 36 and table.count("(class differs)") == 1
    assert vh._pred_text(rows[1]["iterative"]) == "not run"


def test_the_live_column_is_the_default_answer_itself():
    """The quasi-static column is ``scene.max_resistible_wrench(d)`` at its defaults (the give-way
    answer), its verdict the plain comparison with the cached simulation (no threshold rescue),
    and λ* (``giveway.first_limit``) is a column of its own."""
    rows = vh.add_live("ezgripper", _cache("ezgripper")["rows"], 24)
    scene = pg.load_scene("ezgripper")
    label, d = vh.VM._directions(scene, 24)[1]  # 15°: λ* unbounded, gives way gradually in rotation
    mw = scene.max_resistible_wrench(d)
    live, first = rows[1][vh.LIVE], rows[1][vh.FIRST]
    assert label == "15°" and mw.method == "quasistatic" and mw.giveway is not None
    assert (live["status"], live["magnitude"]) == ("finite", pytest.approx(float(mw.magnitude)))
    assert live["giveway"]["reason"] == "rotation" and first["status"] == "unbounded"
    assert (live["verdict"], first["verdict"]) == ("both give way", "predicted holds")
    assert live["rel"] == pytest.approx(rows[1]["sim"]["load"] / mw.magnitude - 1.0)
    assert "via" not in live


@pytest.mark.parametrize(
    ("name", "default", "first"),
    [  # (same class, finite pairs, within 10 %) of the default answer and of λ*, 24 directions
        ("ezgripper", (24, 23, 5), (15, 14, 5)),
        ("talos_gripper", (15, 8, 4), (7, 0, 0)),
        ("hey5", (24, 15, 11), (24, 15, 12)),
    ],
)
def test_measured_counts_of_the_default_and_of_lambda_star(name, default, first):
    """The counts documented in docs/validation.md ("Built-in hands") and
    docs/validation_quasistatic.md."""
    rows = vh.add_live(name, _cache(name)["rows"], 24)
    for m, want in ((vh.LIVE, default), (vh.FIRST, first)):
        c = vh.qs_counts(rows, m)
        assert (c["same"], c["finite"], c["within"]) == want, m
