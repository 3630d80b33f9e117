"""The gravity disturbance set (``pg.Gravity``, pinograsp/batch/disturbances.py, docs/planning.md):
its wrenches, its score against the unit forces' closed form, its home in GRASPS files, the
planner and the CLI, and the sphere lattice behind a number of orientations."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from support.clirun import run

import pinograsp as pg
from pinograsp.batch.disturbances import disturbance_set
from pinograsp.batch.grasps import build_grasp
from pinograsp.core.axes import cube_directions, sphere_directions

pytest.importorskip("pandas")

SPHERE = pg.ObjectSpec("sphere", radius=0.02)
F = 20.0  # the parallel jaw's force [N]: each jaw presses 10 N
#: The planner's small configuration of tests/test_planning.py.
SMALL = dict(n=8, top=3, preload=F, refine=1, rounds=1, standoff=(0.4, 1.0))


@pytest.fixture(scope="module")
def jaw_grasp():
    spec = pg.GraspSpec("parallel_jaw", SPHERE.with_pose((0, 0.045, 0), (0, 0, 0)), command=F)
    model, command, _ = build_grasp(spec)
    return model, command


def test_sphere_directions_are_an_even_unit_lattice():
    d = sphere_directions(100)
    assert d.shape == (100, 6) and not d[:, 3:].any()
    np.testing.assert_allclose(np.linalg.norm(d[:, :3], axis=1), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(d[:, 2], 1.0 - (2.0 * np.arange(100) + 1.0) / 100, rtol=0, atol=1e-15)
    assert abs(d[:, 2].sum()) < 1e-12  # heights symmetric about the equator
    assert np.linalg.norm(d[:, :3].mean(axis=0)) < 0.01  # no side favoured
    # every direction has a neighbour within 2.5 x the mean spacing sqrt(4 pi / n)
    cos = d[:, :3] @ d[:, :3].T
    np.fill_diagonal(cos, -1.0)
    assert np.arccos(cos.max(axis=1)).max() < 2.5 * math.sqrt(4 * math.pi / 100)
    assert np.array_equal(sphere_directions(100), d)


def test_gravity_is_the_weight_times_the_margin_along_each_orientation():
    g = pg.Gravity(0.2, margin=0.5)
    labels, w = g.wrenches()
    names, units = cube_directions()
    assert labels == tuple(f"g{a}" for a in names) and g.weight == 1.5 * 0.2 * 9.81
    np.testing.assert_array_equal(w[:, :3], g.weight * units[:, :3])
    assert not w[:, 3:].any()
    off = pg.Gravity(0.2, margin=0.0, orientations=40, offset=(0.01, 0.0, -0.02), g=9.8)
    labels, w = off.wrenches()
    assert labels == tuple(f"g{i}" for i in range(40))
    np.testing.assert_allclose(np.linalg.norm(w[:, :3], axis=1), 0.2 * 9.8, rtol=1e-15)
    np.testing.assert_array_equal(w[:, 3:], np.cross([0.01, 0.0, -0.02], w[:, :3]))
    assert pg.Gravity.of(off.to_dict()) == off
    assert disturbance_set({"gravity": off.to_dict()})[1].tolist() == w.tolist()


def test_gravity_values_are_the_unit_forces_over_the_weight(jaw_grasp):
    model, command = jaw_grasp
    unit = pg.DisturbanceScore()(model, command)
    g = pg.Gravity(0.1, margin=1.0)
    grav = pg.DisturbanceScore(disturbances=g)(model, command)
    for label in pg.DisturbanceScore().labels:
        assert grav[f"max_g{label}"] == pytest.approx(unit[f"max_{label}"] / g.weight, rel=1e-13)
    # the jaws' closed form (tests/test_planning.py): the corners first, 9.048 N = 4.61 weights
    assert grav["score"] == pytest.approx(unit["score"] / g.weight, rel=1e-13)
    assert grav["score"] * g.weight == pytest.approx(9.048367651, rel=1e-8)
    assert grav["epsilon"] == unit["epsilon"]


def test_more_orientations_find_a_worse_one_than_the_cube(jaw_grasp):
    model, command = jaw_grasp
    g26, g40 = pg.Gravity(0.1), pg.Gravity(0.1, orientations=40)
    cube = pg.DisturbanceScore(disturbances=g26)(model, command)["score"]
    fine = pg.DisturbanceScore(disturbances=g40)(model, command)
    assert fine["score"] < cube
    # each of the 40 is the jaws' first slip, mu F / (b + mu a) (tests/test_planning.py), with the
    # model's friction pyramid of 8 edges at 0, 45, ... deg of the tangents (y, z): along a
    # tangential angle theta it holds mu cos(pi / 8) / cos(theta - the nearest face's centre)
    _, w = g40.wrenches()
    half = math.pi / model.edges
    for i, row in enumerate(w):
        u = row[:3] / np.linalg.norm(row[:3])
        a, b = abs(u[0]), math.hypot(u[1], u[2])
        mu = 0.5 * math.cos(half) / math.cos(math.atan2(u[2], u[1]) % (2 * half) - half)
        assert fine[f"max_g{i}"] * g40.weight == pytest.approx(mu * F / (b + mu * a), rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "culprit", "says"),
    [
        ({"mass": 0.0}, "mass", "(0, 1e+06] kg"),
        ({"mass": 0.1, "margin": -0.1}, "margin", "[0, 100]"),
        ({"mass": 0.1, "orientations": 5}, "orientations", "[6, 1000]"),
        ({"mass": 0.1, "orientations": "sphere"}, "orientations", "cube26"),
        ({"mass": 0.1, "offset": (0.0, 0.1)}, "offset", "3"),
        ({"mass": 0.1, "g": -9.81}, "g", "m/s²"),
    ],
)
def test_bad_gravity_is_named(kwargs, culprit, says):
    with pytest.raises(pg.InvalidInputError) as exc:
        pg.Gravity(**kwargs)
    assert exc.value.name == culprit and says in str(exc.value)


def test_bad_gravity_mappings_are_named():
    with pytest.raises(pg.InvalidInputError, match="'mass' \\[kg\\] is missing"):
        pg.DisturbanceScore(disturbances={"gravity": {"margin": 1}})
    with pytest.raises(pg.InvalidInputError, match="unknown key\\(s\\) \\['weight'\\]"):
        pg.DisturbanceScore(disturbances={"gravity": {"mass": 1, "weight": 2}})
    with pytest.raises(pg.InvalidInputError, match="names one set"):
        pg.DisturbanceScore(disturbances={"gravity": {"mass": 1}, "cube26": {}})
    with pytest.raises(
        pg.InvalidInputError, match=r"'gravity' is not a named set; give 'cube26', pg.Gravity"
    ):
        pg.DisturbanceScore(disturbances="gravity")


def test_a_grasps_file_scores_gravity(tmp_path, jaw_grasp):
    body = (
        "score:\n  disturbances: {gravity: {mass: 0.1, margin: 1}}\n"
        "grasps:\n  - hand: parallel_jaw\n"
        "    object: {shape: sphere, radius: 0.02, pose: {xyz: [0, 0.045, 0]}}\n"
        "    command: 20\n"
    )
    path = tmp_path / "g.yaml"
    path.write_text(body)
    batch = pg.load_grasps(path)
    assert batch.score["disturbances"] == {"gravity": pg.Gravity(0.1, margin=1).to_dict()}
    df = pg.evaluate_grasps(list(batch.grasps), score=pg.DisturbanceScore(**batch.score), workers=1)
    model, command = jaw_grasp
    direct = pg.DisturbanceScore(disturbances=pg.Gravity(0.1, margin=1))(model, command)
    assert df["score"].iloc[0] == direct["score"]
    path.write_text(body.replace("margin: 1", "margin: 1, weight: 2"))
    with pytest.raises(pg.SceneError, match="score.disturbances"):
        pg.load_grasps(path)


def test_the_planner_ranks_the_same_grasps_in_weights():
    g = pg.Gravity(0.05, margin=0.5)
    unit = pg.plan_grasps("parallel_jaw", SPHERE, **SMALL)
    grav = pg.plan_grasps("parallel_jaw", SPHERE, disturbances=g, **SMALL)
    assert [p.id for p in grav.plans] == [p.id for p in unit.plans]
    for p, q in zip(grav.plans, unit.plans):
        assert p.object_pose.tolist() == q.object_pose.tolist()
        assert p.worst == f"g{q.worst}" and p.score == pytest.approx(q.score / g.weight, rel=1e-13)
    assert grav.score_options["disturbances"] == {"gravity": g.to_dict()}
    assert "multiples of the weight x 1.5 (0.7358 N) in 26 orientations" in grav.summary()


def test_cli_plan_gravity(tmp_path, capsys, monkeypatch):
    argv = [
        "plan",
        "parallel_jaw",
        "sphere:0.02",
        "--n",
        "4",
        "--top",
        "1",
        "--preload",
        "20",
        "--refine",
        "0",
    ]
    rc, out, err = run(capsys, *argv, "--gravity", "0.1", "--margin", "1", "--orientations", "40", "--json")
    assert rc == 0, err
    doc = json.loads(out)
    assert doc["score_options"]["disturbances"]["gravity"]["orientations"] == 40
    assert len(doc["labels"]) == 40 and doc["plans"][0]["worst"].startswith("g")
    rc, _, err = run(capsys, *argv, "--margin", "1")
    assert rc == 2 and "--margin" in err and "--gravity MASS" in err
    rc, _, err = run(capsys, *argv, "--gravity", "0.1", "--orientations", "many")
    assert rc == 2 and "--orientations" in err and "[6, 1000]" in err
    rc, _, err = run(capsys, *argv, "--gravity", "-1")  # named by the flag typed, with its range
    assert rc == 2 and "error: --gravity: must be in (0, 1e+06] kg, got -1.0" in err
    # the pictures' value axis says weights, not newtons
    drawn = []
    monkeypatch.setattr(pg, "plot_plan", lambda plan, path, **kw: drawn.append(kw))
    rc, _, err = run(capsys, *argv, "--gravity", "0.1", "--margin", "1", "--out", str(tmp_path / "g"))
    assert rc == 0, err
    assert drawn == [{"ylabel": "largest resisted multiple of 1.962 N (the weight x 2)"}]


def _ability_box_plan5() -> pg.GraspSpec:
    """Issue 34's Ability × box plan 5 (docs/planning.md, "Acceptance"; tests/data)."""
    from pathlib import Path

    spec = json.loads((Path(__file__).parent / "data" / "ability_box_plan5_spec.json").read_text())["spec"]
    return pg.GraspSpec(**{**spec, "object": pg.ObjectSpec(**spec["object"])})


def test_snap_columns_name_the_first_snap_on_the_way_to_each_answer():
    """Plan 5's -fz answer (>= 50 N) passes the snap at the path's first limit 40.49 N
    (tests/test_sim_finger_mass.py), -fx-fz one at 37.42 N; no other direction snaps below 50 N."""
    from pinograsp.planning.search import score_batch

    spec = _ability_box_plan5()
    model, command, _ = build_grasp(spec)
    score = pg.DisturbanceScore()
    row = score(model, command)
    snapped = {a: row[f"snap_{a}"] for a in score.labels if row[f"snap_{a}"] < math.inf}
    assert set(snapped) == {"-fz", "-fx-fz"}
    assert snapped["-fz"] == pytest.approx(40.495, abs=0.01) and snapped["-fx-fz"] == pytest.approx(
        37.42, abs=0.01
    )
    assert row["score"] == 50.0 and row["snap_free"] == min(snapped.values())
    # each is the loading path's own first snap, from a separate call
    mw = pg.max_resistible_wrench(model, command, [0, 0, -1, 0, 0, 0], upper=50.0)
    assert snapped["-fz"] == mw.giveway.snaps[0][0] == mw.first_limit
    # the planner's record carries them (a batch row read back as a candidate)
    (cand,) = score_batch([spec], score, "sampled", None, {"executor": "local", "workers": 1}, None)
    assert cand.snaps == snapped and cand.values == {a: row[f"max_{a}"] for a in score.labels}


def test_without_a_snap_the_snap_free_worst_is_the_score(jaw_grasp):
    model, command = jaw_grasp
    row = pg.DisturbanceScore()(model, command)
    assert row["snap_free"] == row["score"]
    assert all(row[f"snap_{a}"] == math.inf for a in pg.DisturbanceScore().labels)
    iterative = pg.DisturbanceScore(method="iterative")(model, command)  # no path, no snaps
    assert all(iterative[f"snap_{a}"] == math.inf for a in pg.DisturbanceScore().labels)
