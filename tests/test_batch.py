"""Batch evaluation (pg.evaluate_grasps): rows, errors per row, local executors, files, CLI."""

import math
import re
import sys

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.batch.evaluate import BASE_COLUMNS, TAIL_COLUMNS, TIMING_COLUMNS
from pinograsp.cli import main

pd = pytest.importorskip("pandas")

BOX = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))
CASE1_Q = {"bh_j11": math.pi / 2, "bh_j12": math.pi / 3, "bh_j13": math.pi / 9}
CASE1_Q.update({"bh_j22": math.pi / 3, "bh_j23": math.pi / 9})
FAST = pg.WorstAxisScore(upper=20, steps=4)


def _small_batch():
    """Fast grasps of every kind: scenes, a fixed-q Barrett spec, and two that fail."""
    return [
        "pinch",
        {"scene": "wedge", "id": "w"},
        pg.GraspSpec("barrett_bh8_282", BOX, q=CASE1_Q, command={"f1": 0.5, "f2": 0.5}, id="case1-q"),
        pg.GraspSpec("barrett_bh8_282", BOX.with_pose((0, 0, 0.5), (0, 0, 0)), q=CASE1_Q, command=0.5),
        "no_such_scene",
    ]


def same_table(a, b):
    """Equal tables but for the wall times (bit for bit)."""
    cols = [c for c in a.columns if c not in TIMING_COLUMNS]
    pd.testing.assert_frame_equal(a[cols], b[cols], check_exact=True)


@pytest.fixture(scope="module")
def inprocess():
    return pg.evaluate_grasps(_small_batch(), score=FAST, workers=1)


def test_rows_statuses_and_errors(inprocess):
    df = inprocess
    assert list(df.columns[: len(BASE_COLUMNS)]) == list(BASE_COLUMNS)
    assert list(df.columns[-len(TAIL_COLUMNS) :]) == list(TAIL_COLUMNS)
    assert df["id"].tolist() == ["0", "w", "case1-q", "3", "no_such_scene"][:4] + ["4"]
    assert df["status"].tolist() == ["ok", "ok", "ok", "no_grasp", "error"]
    assert df["reason"].tolist() == ["", "", "", "no_contact", "unknown_name"]
    assert df.loc[3, "error_type"] == "NoContactError" and "touches nothing" in df.loc[3, "error_message"]
    # not a grasp: an answer, it resists nothing (0 N on every axis); a real error has no number
    assert df.loc[3, "score"] == 0.0 and df.loc[3, "max_-fz"] == 0.0 and df.loc[3, "unbounded_fraction"] == 0
    assert df.loc[4, "error_type"] == "UnknownNameError"
    assert np.isnan(df.loc[4, "score"]) and df.loc[4, "n_contacts"] == 0
    # pinch: +-fy limit 2 mu tau0 / L = 10 N (below by at most the resolution 20/2**4), +-fx unbounded
    pinch = df.loc[0]
    assert pinch["n_contacts"] == 2 and 10 - 1.25 <= pinch["score"] <= 10
    assert pinch["max_+fx"] == math.inf and pinch["unbounded_fraction"] == 0.5
    assert math.isnan(pinch["max_+fz"])  # planar: force axes fx, fy only
    assert df.loc[2, "n_contacts"] == 4 and df.loc[2, "source"] == "barrett_bh8_282"
    assert df.loc[2, "obj_z"] == pytest.approx(0.0678)
    assert (df["time_total"] > 0).all()


def test_process_pool_identical_to_in_process(inprocess):
    same_table(pg.evaluate_grasps(_small_batch(), score=FAST, workers=2), inprocess)


def test_custom_score_lambda_bad_score_and_progress():
    calls = []
    df = pg.evaluate_grasps(
        ["pinch", "wedge"], score=lambda m, c: {"nc": m.nc, "k": "x" if m.nc > 5 else 1}, workers=2,
        progress=lambda d, t: calls.append((d, t)),
    )  # fmt: skip
    assert df["nc"].tolist() == [2, 2] and calls[0] == (0, 2) and calls[-1] == (2, 2)
    bad = pg.evaluate_grasps(["pinch"], score=lambda m, c: [1.0], workers=1)
    assert bad.loc[0, "status"] == "error" and bad.loc[0, "error_type"] == "InvalidInputError"


def test_bad_arguments_name_themselves():
    with pytest.raises(pg.InvalidInputError, match="grasps\\[0\\]"):
        pg.evaluate_grasps([3.5])
    with pytest.raises(pg.InvalidInputError, match="executor"):
        pg.evaluate_grasps(["pinch"], executor="spark")
    with pytest.raises(pg.InvalidInputError, match="workers"):
        pg.evaluate_grasps(["pinch"], workers=-1)
    with pytest.raises(pg.InvalidInputError, match="score"):
        pg.evaluate_grasps(["pinch"], score=3)
    with pytest.raises(pg.InvalidInputError, match="size\\[1\\]"):
        pg.ObjectSpec("box", size=(0.1, -1, 0.1))
    with pytest.raises(pg.InvalidInputError, match="radius"):
        pg.ObjectSpec("box", size=(0.1, 0.1, 0.1), radius=0.1)
    with pytest.raises(pg.InvalidInputError, match="command"):
        pg.GraspSpec("barrett_bh8_282", BOX, command="max")
    with pytest.raises(pg.InvalidInputError, match="mu"):
        pg.GraspSpec("barrett_bh8_282", BOX, mu=-1)


@pytest.mark.parametrize("name", ["ray", "distributed"])
def test_missing_cluster_package(monkeypatch, name):
    monkeypatch.setitem(sys.modules, name, None)
    with pytest.raises(pg.MissingDependencyError, match="pinograsp\\[(ray|dask)\\]"):
        pg.evaluate_grasps(["pinch"], executor="ray" if name == "ray" else "dask")


def test_sample_grasps_deterministic_and_bounded():
    a = pg.sample_grasps("barrett_bh8_282", BOX, 20, seed=3, translation=0.004, rotation=0.1)
    b = pg.sample_grasps("barrett_bh8_282", pg.RigidObject.box(BOX.size, BOX.pose), 20, seed=3,
                         translation=0.004, rotation=0.1)  # fmt: skip
    assert [(g.object.xyz, g.object.rpy) for g in a] == [(g.object.xyz, g.object.rpy) for g in b]
    assert a[0].object == BOX and b[0].object.name == "box"
    assert len({g.object.xyz for g in a}) == 20 and a[5].id == "s3-5"
    for g in a:
        assert np.all(np.abs(np.subtract(g.object.xyz, BOX.xyz)) <= 0.004)
        R = g.object.pose[:3, :3]
        assert math.acos(min(1.0, (np.trace(R) - 1) / 2)) <= 0.1 + 1e-12
    c = pg.sample_grasps("barrett_bh8_282", BOX, 20, seed=4)
    assert c[1].object != a[1].object
    with pytest.raises(pg.InvalidInputError, match="rotation"):
        pg.sample_grasps("barrett_bh8_282", BOX, 2, rotation=-1)
    with pytest.raises(pg.InvalidInputError, match="mu"):
        pg.sample_grasps("barrett_bh8_282", BOX, 2, mu="x")


def test_auto_close_and_auto_preload_row():
    g = pg.GraspSpec("barrett_bh8_282", BOX, q_open={"bh_j11": math.pi / 2}, id="auto")
    df = pg.evaluate_grasps([g], score=FAST, workers=1)
    assert df.loc[0, "status"] == "ok", df.loc[0, "error_message"]
    assert df.loc[0, "n_contacts"] == 4 and df.loc[0, "time_preload"] > 0
    assert '"f1"' in df.loc[0, "command"]


GRASPS_YAML = """
defaults:
  hand: barrett_bh8_282
  q_open: {bh_j11: 90 deg}
score: {upper: 20, steps: 4}
grasps:
  - scene: pinch
    id: pinch
  - id: fixed
    object: {shape: box, size: [0.1462, 0.05, 0.10], pose: {xyz: [0, 0, 0.0678]}}
    q: {bh_j11: 90 deg, bh_j12: 60 deg, bh_j13: 20 deg, bh_j22: 60 deg, bh_j23: 20 deg}
    command: {f1: 0.5, f2: 0.5}
sample:
  - object: {shape: sphere, radius: 0.04, pose: {xyz: [0, 0, 0.5]}}
    n: 2
    seed: 1
    rotation: 5 deg
"""


def test_grasps_yaml_and_cli(tmp_path):
    path = tmp_path / "grasps.yaml"
    path.write_text(GRASPS_YAML)
    batch = pg.load_grasps(path)
    assert len(batch.grasps) == 4 and batch.score == {"upper": 20.0, "steps": 4}
    assert batch.grasps[1].q_open == (("bh_j11", math.pi / 2),) and batch.grasps[3].id == "s1-1"
    out = tmp_path / "res.csv"
    assert main(["batch", str(path), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    df = pd.read_csv(out)
    assert df["status"].tolist() == ["ok", "ok", "no_grasp", "no_grasp"]
    assert df["reason"].iloc[2] == "no_contact" and df["score"].iloc[0] > 0 and df["score"].iloc[2] == 0
    assert not (tmp_path / "res.csv.partial.jsonl").exists()  # the journal goes once the table is written
    # the documented Python recipe for a GRASPS file gives the command line's table (but the times)
    py = pg.evaluate_grasps(batch.grasps, score=pg.WorstAxisScore(**batch.score), workers=1)
    pg.save_results(py, tmp_path / "py.csv")
    same_table(pd.read_csv(tmp_path / "py.csv"), df)
    pq = tmp_path / "res.parquet"
    pytest.importorskip("pyarrow")
    pg.save_results(pg.evaluate_grasps(["pinch"], score=FAST, workers=1), pq)
    assert pd.read_parquet(pq)["status"].tolist() == ["ok"]


def test_missing_mesh_of_a_grasps_file_is_named_from_the_file(tmp_path, monkeypatch):
    # a GRASPS file's mesh path is taken from the file's folder, whatever the working directory:
    # the row's message names that path and does not claim the working directory was searched
    (tmp_path / "g").mkdir()
    path = tmp_path / "g" / "grasps.yaml"
    path.write_text(
        "grasps:\n  - id: gone\n    hand: parallel_jaw\n"
        "    object: {shape: mesh, file: gone.stl, pose: {xyz: [0, 0, 0.1]}}\n"
    )
    monkeypatch.chdir(tmp_path)
    df = pg.evaluate_grasps(pg.load_grasps(path).grasps, score=FAST, workers=1)
    row = df.loc[0]
    assert (row["status"], row["reason"], row["error_type"]) == ("error", "bad_file", "ModelFileError")
    want = tmp_path / "g" / "gone.stl"
    assert row["error_message"] == (
        f"{want}: mesh file not found: give the path of an existing STL, OBJ, PLY, OFF or GLB file"
    )


def test_auto_preloads_are_verified_by_the_scoring_method(tmp_path):
    """A file whose score names a method verifies its ``"auto"`` preloads with that method
    (a grasp's own ``preload_method`` wins); without one, the package default."""
    obj = "{shape: sphere, radius: 0.04}"
    body = (
        f"defaults: {{hand: barrett_bh8_282, object: {obj}}}\n"
        f"grasps:\n  - {{id: a}}\n  - {{id: b, preload_method: prp}}\n"
        f"sample: [{{n: 1, seed: 0}}]\n"
    )
    path = tmp_path / "g.yaml"
    path.write_text(body + "score: {method: iterative}\n")
    got = [g.preload_method for g in pg.load_grasps(path).grasps]
    assert got == [pg.Method.ITERATIVE, pg.Method.PRP, pg.Method.ITERATIVE]
    path.write_text(body)
    got = [g.preload_method for g in pg.load_grasps(path).grasps]
    assert got == [pg.Method.QUASISTATIC, pg.Method.PRP, pg.Method.QUASISTATIC]


@pytest.mark.parametrize(
    "text, key",
    [
        ("grasps: [{hand: barrett_bh8_282, object: {shape: box, size: [1, 2]}}]", "grasps[0].object.size"),
        ("grasps: [{object: {shape: sphere, radius: 0.1}}]", "grasps[0].hand"),
        ("grasps: [{hand: x, object: {shape: cone}}]", "grasps[0].object.shape"),
        ("defaults: {hand: x, colour: red}\ngrasps: []", "defaults.colour"),
        ("sample: [{hand: x, object: {shape: sphere, radius: 0.1}}]", "sample[0].n"),
        ("grasps: [{hand: x, object: {shape: sphere, radius: 0.1}, mu: -1}]", "grasps[0].mu"),
        ("grasps: [{scene: pinch}]\nscore: {steps: 0}", "score.steps"),
        ("grasps: []", "grasps"),
    ],
)
def test_grasps_yaml_errors_name_the_key(tmp_path, text, key):
    path = tmp_path / "g.yaml"
    path.write_text(text)
    with pytest.raises(pg.InvalidInputError, match=re.escape(f"g.yaml: {key}:")):
        pg.load_grasps(path)


def test_outputs_and_missing_pyarrow(tmp_path, monkeypatch, capsys):
    df = pd.DataFrame({"a": [1.0]})
    with pytest.raises(pg.InvalidInputError, match="path"):
        pg.save_results(df, tmp_path / "x.xlsx")
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    with pytest.raises(pg.MissingDependencyError, match="pinograsp\\[parquet\\]"):
        pg.save_results(df, tmp_path / "x.parquet")
    assert main(["batch", "nothing.yaml", "--out", "r.parquet"]) == 2
    assert "pinograsp[parquet]" in capsys.readouterr().err


def test_a_grasp_record_chooses_its_friction_pyramid(tmp_path):
    """``GraspSpec.edges``: the jaws on a sphere with 16 pyramid edges follow the 16-edge
    closed form of the first slip, ``mu' F / (b + mu' a)`` with ``mu' = mu cos(pi/16) /
    cos(theta - the nearest face's centre)``, along 40 directions spread over the sphere."""
    from pinograsp.batch.grasps import build_grasp
    from pinograsp.core.axes import sphere_directions
    from pinograsp.planning.records import grasp_entry

    sphere = pg.ObjectSpec("sphere", radius=0.02).with_pose((0, 0.045, 0), (0, 0, 0))
    spec = pg.GraspSpec("parallel_jaw", sphere, command=20.0, edges=16)
    model, command, _ = build_grasp(spec)
    assert model.edges == 16 and model.D.shape[1] == 16 * model.nc
    assert build_grasp(pg.GraspSpec("parallel_jaw", sphere, command=20.0))[0].edges == 8
    half = math.pi / 16
    for w in sphere_directions(40):
        a, b = abs(w[0]), math.hypot(w[1], w[2])
        mu = 0.5 * math.cos(half) / math.cos(math.atan2(w[2], w[1]) % (2 * half) - half)
        mw = pg.max_resistible_wrench(model, command, w, upper=50.0)
        assert mw.magnitude == pytest.approx(mu * 20.0 / (b + mu * a), rel=1e-9)
    for bad in (2, 257, 8.5, True):
        with pytest.raises(pg.InvalidInputError, match=r"edges.*\[3, 256\]|edges: expected"):
            pg.GraspSpec("parallel_jaw", sphere, edges=bad)
    entry = grasp_entry(spec)
    assert entry["edges"] == 16 and "edges" not in grasp_entry(pg.GraspSpec("parallel_jaw", sphere))
    f = tmp_path / "g.yaml"
    f.write_text(
        "defaults: {edges: 16}\ngrasps:\n  - {hand: parallel_jaw, object: {shape: sphere, radius: 0.02}}\n"
    )
    assert pg.load_grasps(f).grasps[0].edges == 16
    f.write_text("grasps:\n  - {hand: parallel_jaw, object: {shape: sphere, radius: 0.02}, edges: 2}\n")
    with pytest.raises(pg.SceneError, match=r"edges.*\[3, 256\]"):
        pg.load_grasps(f)
