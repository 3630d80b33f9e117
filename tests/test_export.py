"""Outputs: to_dict / summary / repr of the result records, values printed to their resolution,
CSV and pandas tables of profiles and batches, and ``pinograsp profile --csv``."""

from __future__ import annotations

import csv
import json
import math
import sys
from dataclasses import replace

import numpy as np
import pytest
from support.grasps import MU, L

import pinograsp as pg
from pinograsp.cli import main
from pinograsp.core import tables
from pinograsp.core.results import format_max_wrench
from pinograsp.core.serialize import decimals, format_magnitude
from pinograsp.core.tables import PROFILE_COLUMNS, RESULT_COLUMNS

# the analytic pinch (conftest ``pinch`` fixture): +Y limit 2 MU tau0 / L = 10 N at tau0 = 1


@pytest.fixture(scope="module")
def profile(pinch):
    return pg.resistance_profile(pinch, 1.0, plane=("fx", "fy"), n=72, method="prp", upper=100.0, steps=8)


@pytest.fixture(scope="module")
def max_y(pinch):
    return pg.max_resistible_wrench(pinch, 1.0, "fy", "prp", 100.0, 10)


def _read_csv(path):
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.DictReader(fh)
        return reader.fieldnames, list(reader)


# ---------------------------------------------------------------------------- resolution formatter
@pytest.mark.parametrize(
    ("value", "resolution", "unit", "text"),
    [
        (1.3672, 0.2, "N", "1.4 N"),
        (4.29893, 4.8e-06, "N", "4.298930 N"),
        (9.9609375, 100 / 2**10, "N", "9.96 N"),
        (12.3456, 50.0, None, "12"),
        (0.0854, 1e-3, "N·m", "0.085 N·m"),
        (1.0, 1e-12, "N", "1.000000 N"),  # at most 6 decimals
        (0.5, 0.0, None, "0.5000"),  # no usable resolution: 4 decimals
        (math.inf, 0.1, "N", "unbounded"),
        (math.nan, 0.1, None, "nan"),
    ],
)
def test_format_magnitude(value, resolution, unit, text):
    assert format_magnitude(value, resolution, unit) == text


def test_decimals():
    cases = (10.0, 1.0, 0.2, 0.01, 4.8e-6, 1e-9, -1.0, math.nan)
    assert [decimals(r) for r in cases] == [0, 0, 1, 2, 6, 6, 4, 4]


def test_format_max_wrench_by_status(max_y):
    assert format_max_wrench(max_y, unit="N") == "9.96 N"
    assert format_max_wrench(max_y, scale=max_y.magnitude) == "1.000"  # resolution 0.0098 relative
    assert format_max_wrench(replace(max_y, status="unbounded", unbounded=True)) == "unbounded"
    assert format_max_wrench(replace(max_y, status="above_limit"), unit="N") == ">= 100 N"
    assert format_max_wrench(replace(max_y, status="below_resolution", floor=0.0977)) == "< 0.098"


# ---------------------------------------------------------------------------- to_dict
def test_max_wrench_to_dict_round_trip(max_y):
    d = json.loads(json.dumps(max_y.to_dict()))
    assert d["magnitude"] == max_y.magnitude == pytest.approx(10.0, abs=max_y.resolution)
    assert d["status"] == "finite" and d["unbounded"] is False
    assert d["label"] == "+fy" and d["unit"] == "N"
    assert d["direction"] == max_y.direction.tolist()
    assert d["resolution"] == max_y.resolution == 100 / 2**10
    assert d["evidence"] == [[m, ok] for m, ok in max_y.evidence]
    r = d["response"]
    assert [c["name"] for c in r["contacts"]] == ["left", "right"]
    assert [c["mu"] for c in r["contacts"]] == [MU, MU]
    assert np.allclose([c["force"] for c in r["contacts"]], max_y.response.contact_forces)
    assert np.allclose([c["force_world"] for c in r["contacts"]], max_y.response.contact_forces_world)
    assert [a["kind"] for a in r["actuators"]] == ["non-backdrivable"] * 2
    assert r["audit"]["ok"] is True and r["audit"]["energy"]["energy_ok"] is True
    assert "response" not in max_y.to_dict(response=False)


def test_response_to_dict_matches_model_lookup(pinch, max_y):
    r = max_y.response
    assert r.to_dict() == r.to_dict(pinch)  # the record carries mu and kinds itself
    assert r.to_dict()["wrench"] == pytest.approx([0.0, max_y.magnitude, 0, 0, 0, 0])


def test_unresisted_response_to_dict_has_none(pinch):
    r = pg.passive_response(pinch, 1.0, [0.0, 50.0, 0.0], method="prp")
    d = json.loads(json.dumps(r.to_dict()))
    assert d["resistible"] is False
    assert d["contacts"][0]["force"] == [None, None, None] and d["contacts"][0]["mode"] is None
    assert "NOT RESISTED" in r.summary()


def test_profile_to_dict(profile):
    d = json.loads(json.dumps(profile.to_dict()))
    assert d["n"] == 72 and d["plane"] == ["fx", "fy"]
    assert d["magnitudes"] == [None if np.isinf(m) else m for m in profile.magnitudes]
    assert d["unbounded"] == profile.unbounded.tolist()
    assert d["angles_deg"] == pytest.approx(np.degrees(profile.angles))
    assert d["unbounded_runs_deg"] == [[0.0, 0.0], [180.0, 180.0]]
    assert d["normalized_by"] is None and d["normalized"] is None
    ref = profile.magnitudes[18]
    dn = profile.to_dict(ref)
    assert dn["normalized"][18] == pytest.approx(1.0) and dn["normalized_by"] == ref
    full = profile.to_dict(results=True)
    assert [r["status"] for r in full["results"]] == list(profile.statuses)


def test_normalized_profile_keeps_absolute_magnitudes(pinch):
    p = pg.resistance_profile(pinch, 1.0, ("fx", "fy"), 8, "prp", 100.0, 8, normalize=True)
    d = p.to_dict()
    absolute = [r.magnitude for r in p.results]
    assert d["magnitudes"] == [None if np.isinf(m) else m for m in absolute]
    assert d["normalized"] == [None if np.isinf(m) else m for m in p.magnitudes]
    assert d["normalized_by"] == p.normalized_by == pytest.approx(10.0, abs=0.4)


def test_audit_energy_and_baseline_to_dict(pinch, max_y):
    a = max_y.response.audit
    assert a.to_dict()["energy"] == a.energy.to_dict()
    assert a.energy.to_dict()["spring_energy"] == a.energy.spring_energy
    assert "audit: ok" in a.summary() and "spring energy" in a.energy.summary()
    lc = pg.linear_compliance(pinch, [0, 5, 0, 0, 0, 0], max_y.response.contact_forces * 0.5)
    d = json.loads(json.dumps(lc.to_dict()))
    assert d["contact_names"] == ["left", "right"]
    assert np.allclose(d["contact_forces"], lc.contact_forces)
    assert d["friction_violations"] == list(lc.friction_violations) and d["valid"] is lc.valid
    assert "linear compliance" in lc.summary()


# ---------------------------------------------------------------------------- summary / repr
def test_repr_is_compact(profile, max_y):
    text = repr(profile)
    assert len(text) < 400 and "array" not in text
    assert text.startswith("ResistanceProfile(plane=('fx', 'fy'), n=72, method='prp', finite=")
    assert "unbounded=2" in text
    for obj in (max_y, max_y.response):
        assert len(repr(obj)) < 400 and "array" not in repr(obj)
    assert "magnitude=9.961" in repr(max_y) and "status='finite'" in repr(max_y)


def test_summaries(profile, max_y):
    s = max_y.summary()
    assert s.splitlines()[0] == "max resistible wrench along +fy: 9.96 N (finite, resolution 0.098 N)"
    assert "left 10.00000 N, right 10.00000 N" in s
    ps = profile.summary()
    assert "72 directions" in ps and "unbounded at 0°, 180°" in ps
    assert "RESISTED" in max_y.response.summary()


# ---------------------------------------------------------------------------- CSV / DataFrame
def test_profile_csv_rows_equal_magnitudes(profile, tmp_path):
    path = profile.to_csv(tmp_path / "sub" / "profile.csv")
    cols, rows = _read_csv(path)
    assert tuple(cols) == PROFILE_COLUMNS and len(rows) == 72
    assert [float(r["magnitude"]) for r in rows] == profile.magnitudes.tolist()
    assert [float(r["angle_deg"]) for r in rows] == pytest.approx(np.degrees(profile.angles))
    assert [r["status"] for r in rows] == list(profile.statuses)
    assert [r["unbounded"] == "True" for r in rows] == profile.unbounded.tolist()
    dirs = np.array([[float(r[a]) for a in pg.WRENCH_AXES] for r in rows])
    assert dirs == pytest.approx(profile.directions)
    assert rows[0]["magnitude"] == "inf" and rows[0]["normalized"] == ""
    assert [int(r["n_solves"]) for r in rows] == [r.n_solves for r in profile.results]


def test_csv_path_errors(profile, tmp_path):
    with pytest.raises(pg.InvalidInputError, match="is a folder"):
        profile.to_csv(tmp_path)
    with pytest.raises(pg.InvalidInputError, match="file path"):
        profile.to_csv(3)


def test_profile_dataframe(profile):
    df = profile.to_dataframe()
    assert tuple(df.columns) == PROFILE_COLUMNS and len(df) == 72
    assert df["magnitude"].tolist() == profile.magnitudes.tolist()
    assert df["status"].tolist() == list(profile.statuses)
    assert df["normalized"].isna().all()
    assert df.loc[18, "magnitude"] == pytest.approx(10.0, abs=100 / 2**8)


def test_missing_pandas(profile, max_y, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(pg.MissingDependencyError, match=r'pip install "pinograsp\[tables\]"'):
        profile.to_dataframe()
    with pytest.raises(pg.MissingDependencyError, match="pandas"):
        pg.results_table([max_y])


def test_results_table_over_preloads(pinch, tmp_path):
    batch = {tau: pg.max_resistible_wrench(pinch, tau, "fy", "prp", 100.0, 10) for tau in (0.5, 1.0, 2.0)}
    df = pg.results_table(batch)
    assert tuple(df.columns) == RESULT_COLUMNS
    assert df["key"].tolist() == [0.5, 1.0, 2.0]
    exact = [2 * MU * tau / L for tau in batch]  # 5, 10, 20 N
    res = 100 / 2**10
    assert all(0 <= e - m <= res for m, e in zip(df["magnitude"], exact))
    assert df["label"].tolist() == ["+fy"] * 3 and df["unit"].tolist() == ["N"] * 3
    path = pg.results_to_csv(batch, tmp_path / "batch.csv")
    cols, rows = _read_csv(path)
    assert tuple(cols) == RESULT_COLUMNS
    assert [float(r["magnitude"]) for r in rows] == [mw.magnitude for mw in batch.values()]
    seq = pg.results_rows(list(batch.values()))
    assert [r["key"] for r in seq] == [0, 1, 2]
    with pytest.raises(pg.InvalidInputError, match="MaxWrench"):
        pg.results_rows([1.0])
    with pytest.raises(pg.InvalidInputError, match="sequence or mapping"):
        pg.results_rows(batch[1.0])


# ---------------------------------------------------------------------------- CLI --csv
def test_cli_profile_csv_matches_api(tmp_path, capsys):
    path = tmp_path / "p.csv"
    args = ["profile", "pinch", "-n", "8", "--steps", "6", "--upper", "100", "--method", "prp"]
    assert main([*args, "--csv", str(path), "--normalize"]) == 0
    out = capsys.readouterr().out
    assert f"wrote {path}" in out
    assert "normalised by the +fy value 9 N\n" in out  # 9.375 N at the resolution 1.56 N
    scene = pg.load_scene("pinch")
    p = pg.resistance_profile(scene.model, scene.preload(), ("fx", "fy"), 8, "prp", 100.0, 6)
    cols, rows = _read_csv(path)
    assert tuple(cols) == PROFILE_COLUMNS
    assert [float(r["magnitude"]) for r in rows] == p.magnitudes.tolist()
    assert [r["status"] for r in rows] == list(p.statuses)
    assert [float(r["normalized"]) for r in rows] == (p.magnitudes / p.magnitudes[2]).tolist()
    # --json leaves stdout to the JSON and still writes the CSV
    path.unlink()
    assert main([*args, "--csv", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert path.exists() and data["magnitudes"][2] == float(_read_csv(path)[1][2]["magnitude"])


def test_cli_csv_bad_path(tmp_path, capsys):
    code = main(["profile", "pinch", "-n", "4", "--steps", "3", "--method", "prp", "--csv", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith("pinograsp: error: --csv:") and "is a folder" in err


def test_bad_arguments_are_pinograsp_errors(max_y):
    for args in (("x", 1.0), (1.0, None), (1.0, 1.0, 3)):
        with pytest.raises(pg.InvalidInputError):
            format_magnitude(*args)
    with pytest.raises(pg.InvalidInputError, match="MaxWrench"):
        format_max_wrench(1.0)
    with pytest.raises(pg.InvalidInputError, match="scale"):
        format_max_wrench(max_y, scale=0.0)
    with pytest.raises(pg.InvalidInputError, match="ResistanceProfile"):
        tables.profile_rows(max_y)


def test_contact_report_to_dict(tmp_path):
    from test_collision import PROBE

    from pinograsp.robots.collision import detect_contacts
    from pinograsp.robots.objects import RigidObject

    f = tmp_path / "probe.urdf"
    f.write_text(PROBE)
    box = RigidObject.box(0.1, pose=[0.1, 0, 0])
    rep = detect_contacts(pg.Hand.from_urdf(f), [0.0395, 0.0], box, links=["slider"])
    d = json.loads(json.dumps(rep.to_dict()))
    assert d["links"] == ["slider"] and d["tolerance"] == rep.tolerance
    assert d["contacts"][0]["distance"] == pytest.approx(0.0005, abs=1e-9)
    assert d["contacts"][0]["normal"] == pytest.approx([1, 0, 0], abs=1e-9)
    assert d["contacts"][0] == rep.contacts[0].to_dict()
    assert rep.summary().startswith("1 contact(s) within") and "slider" in rep.summary()


def test_texts_have_no_signed_zero_and_say_exact_and_how_many():
    """Rounded zeros print unsigned; the path's profile is exact; counts take their number."""
    from pinograsp.core.serialize import signed_text
    from pinograsp.errors import plural

    assert [signed_text(x) for x in (-1e-17, -0.0004, -0.0006, 0.25, np.cos(1.5 * np.pi))] == [
        "+0.000",
        "+0.000",
        "-0.001",
        "+0.250",
        "+0.000",
    ]
    assert (plural("value", 1), plural("value", 3), plural("wrench axis", 2)) == (
        "1 value",
        "3 values",
        "2 wrench axes",
    )
    m = pg.examples.pinch()
    lines = pg.resistance_profile(m, 1.0, plane=("fx", "fy"), n=8).summary().splitlines()
    assert "finite magnitudes 10.0000–14.1421 N (exact)" in lines  # 2 mu tau0 / L; its sqrt(2)
    assert "unbounded at 0°, 180°" in lines
    mixed = pg.resistance_profile(m, 1.0, plane=("fy", "mz"), n=4).summary().splitlines()
    assert "finite 4, unbounded 0" in mixed and "no direction unbounded" in mixed
