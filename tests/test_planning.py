"""pg.plan_grasps (docs/planning.md): determinism, the GRASPS file re-scored by the batch, the
refinement's monotonicity, the epsilon column, and a closed form (a parallel jaw on a sphere)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support.clirun import run

import pinograsp as pg
from pinograsp.batch.grasps import build_grasp

pytest.importorskip("pandas")

SPHERE = pg.ObjectSpec("sphere", radius=0.02)
F, MU = 20.0, 0.5  # gripper force [N] (each jaw presses F / 2), friction
#: The sphere's centre stays clear of the palm (it touches the palm below standoff 0.2).
SMALL = dict(n=8, top=3, preload=F, refine=1, rounds=1, standoff=(0.4, 1.0))


@pytest.fixture(scope="module")
def plans():
    return pg.plan_grasps("parallel_jaw", SPHERE, **SMALL)


def test_same_seed_same_plans_bit_for_bit_on_1_or_2_workers(plans):
    again = pg.plan_grasps("parallel_jaw", SPHERE, workers=2, **SMALL)
    assert again.to_dict(timing=False) == plans.to_dict(timing=False)
    other = pg.plan_grasps("parallel_jaw", SPHERE, **{**SMALL, "seed": 1})
    assert other.plans[0].object_pose.tolist() != plans.plans[0].object_pose.tolist()


def test_the_grasps_file_rescores_to_the_same_numbers(plans, tmp_path):
    batch = pg.load_grasps(plans.write_grasps(tmp_path / "plans.yaml"))
    assert batch.score == {**plans.score_options, "method": pg.Method(plans.score_options["method"])}
    df = pg.evaluate_grasps(list(batch.grasps), score=pg.DisturbanceScore(**batch.score), workers=1)
    assert list(df["status"]) == ["ok"] * len(plans.plans)
    for plan, row in zip(plans.plans, df.to_dict("records")):
        assert row["score"] == plan.score and row["epsilon"] == plan.epsilon
        assert {k: row[f"max_{k}"] for k in plan.values} == plan.values


def test_a_mesh_object_outside_the_output_folder_is_copied_and_rescored(tmp_path):
    # `pinograsp plan HAND mesh.stl --out plans/`, then `pinograsp batch plans/plans.yaml`: the
    # batch reads files inside the GRASPS file's folder only (docs/scenes.md, "Paths"), so the
    # mesh is copied next to plans.yaml and named relatively; the numbers are the plans' own
    trimesh = pytest.importorskip("trimesh")
    (tmp_path / "meshes").mkdir()
    mesh = tmp_path / "meshes" / "ball.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=0.02).export(mesh)
    plans = pg.plan_grasps("parallel_jaw", pg.ObjectSpec("mesh", file=str(mesh)), **{**SMALL, "refine": 0})
    path = plans.write_grasps(tmp_path / "plans" / "plans.yaml")
    assert (tmp_path / "plans" / "ball.stl").read_bytes() == mesh.read_bytes()
    batch = pg.load_grasps(path)  # was: SceneError, '.../meshes/ball.stl' is outside the folder
    assert {g.object.file for g in batch.grasps} == {str(tmp_path / "plans" / "ball.stl")}
    df = pg.evaluate_grasps(list(batch.grasps), score=pg.DisturbanceScore(**batch.score), workers=1)
    assert list(df["status"]) == ["ok"] * len(plans.plans)
    for plan, row in zip(plans.plans, df.to_dict("records")):
        assert row["score"] == plan.score and {k: row[f"max_{k}"] for k in plan.values} == plan.values
    # a different file of the same name already there is kept; the copy gets a content-hashed name
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "ball.stl").write_bytes(b"not this mesh")
    again = pg.load_grasps(plans.write_grasps(tmp_path / "other" / "plans.yaml"))
    (copy,) = {Path(g.object.file).name for g in again.grasps}
    assert copy.startswith("ball-") and copy.endswith(".stl") and copy != "ball.stl"
    assert (tmp_path / "other" / copy).read_bytes() == mesh.read_bytes()


def test_refinement_never_lowers_the_best_score(plans):
    assert plans.best >= plans.best_sampled
    assert plans.plans[0].score == plans.best
    flat = pg.plan_grasps("parallel_jaw", SPHERE, **{**SMALL, "refine": 0})
    assert flat.refined == 0 and flat.best == flat.best_sampled
    for p in plans.plans:
        assert p.score >= 0 and p.sampled_score <= p.score or p.origin == "sampled"


def test_epsilon_and_its_rank_are_the_metrics_epsilon(plans):
    eps = []
    for p in plans.plans:
        model, _, _ = build_grasp(p.spec)
        assert p.epsilon == pg.ferrari_canny(model)
        eps.append(p.epsilon)
    expected = [1 + sum(e > x for e in eps) + sum(e == x for e in eps[:i]) for i, x in enumerate(eps)]
    assert [p.epsilon_rank for p in plans.plans] == expected
    by_eps = pg.plan_grasps("parallel_jaw", SPHERE, **{**SMALL, "rank_by": "epsilon"})
    values = [p.epsilon for p in by_eps.plans]
    assert values == sorted(values, reverse=True)


def _closed_forms() -> tuple[dict[str, float], dict[str, float]]:
    """Per cube direction, the jaws closing along hand x on a sphere with normal forces F/2 each:
    a load t along d = (a along x, b across) leaves the normal forces F/2 -+ a t / 2 (the locked,
    coupled jaws) and shares the tangential b t equally. First slip: b t / 2 = mu (F/2 - a t/2);
    giving way (both sliding): b t = mu F. Pure x: the far jaw lets go at t = F, and the ball,
    pressed onto one point through its centre, tips over (the path's ray buckles there)."""
    labels, dirs = pg.batch.disturbances.cube_directions()
    first, give_way = {}, {}
    for label, d in zip(labels, dirs):
        a, b = abs(d[0]), float(np.hypot(d[1], d[2]))
        first[label] = F if b == 0 else MU * F / (b + MU * a)
        give_way[label] = F if b == 0 else MU * F / b
    return first, give_way


def test_parallel_jaw_on_a_sphere_matches_the_friction_limit(plans):
    first, give_way = _closed_forms()
    best = plans.plans[0]
    assert best.contact_names == ("pj_left_jaw", "pj_right_jaw")
    close = lambda v, ref: v == ref or math.isclose(v, ref, rel_tol=1e-6)  # noqa: E731
    which = first if all(close(best.values[k], first[k]) for k in first) else give_way
    assert all(close(best.values[k], which[k]) for k in which), best.values
    assert math.isclose(best.score, min(which.values()), rel_tol=1e-6)
    assert math.isclose(which[best.worst], min(which.values()), rel_tol=1e-6)
    # first slip: the corners, 2 mu N / (sqrt(2/3) + mu / sqrt(3)) = 9.05 N; giving way: mu F = 10 N
    assert best.worst.count("f") == (3 if which is first else 1) or which[best.worst] == MU * F


def test_disturbance_score_counts_multiples_of_a_wrench():
    model, command, _ = build_grasp(
        pg.GraspSpec("parallel_jaw", SPHERE.with_pose((0, 0.045, 0), (0, 0, 0)), command=F)
    )
    unit = pg.DisturbanceScore()(model, command)
    two = pg.DisturbanceScore(disturbances=[[0, 2.0, 0, 0, 0, 0], [0, 0, -3.0, 0, 0, 0]])(model, command)
    assert two["max_w0"] == unit["max_+fy"] / 2 and two["max_w1"] == unit["max_-fz"] / 3
    assert two["score"] == min(two["max_w0"], two["max_w1"])
    with pytest.raises(pg.InvalidInputError, match="zero wrench"):
        pg.DisturbanceScore(disturbances=[[0, 0, 0, 0, 0, 0]])
    with pytest.raises(pg.InvalidInputError, match="disturbances"):
        pg.DisturbanceScore(disturbances="sphere")


def test_disturbance_score_floor_stops_at_the_first_value_below_it():
    model, command, _ = build_grasp(
        pg.GraspSpec("parallel_jaw", SPHERE.with_pose((0, 0.045, 0), (0, 0, 0)), command=F)
    )
    full = pg.DisturbanceScore()(model, command)
    labels = pg.DisturbanceScore().labels
    vals = {a: full[f"max_{a}"] for a in labels}
    order = sorted(labels, key=lambda a: vals[a])
    cut = pg.DisturbanceScore(floor=math.inf, first=(order[0],))(model, command)
    assert cut["pruned"] == 1.0 and cut["score"] == vals[order[0]]
    assert [a for a in labels if not math.isnan(cut[f"max_{a}"])] == [order[0]]  # one path only
    kept = pg.DisturbanceScore(floor=vals[order[0]])(model, command)  # nothing below the worst
    assert kept["pruned"] == 0.0 and all(kept[f"max_{a}"] == vals[a] for a in labels)
    assert "pruned" not in full
    with pytest.raises(pg.InvalidInputError, match="first"):
        pg.DisturbanceScore(first=("+fq",))


def test_bad_arguments_are_named():
    with pytest.raises(pg.InvalidInputError, match="rank_by"):
        pg.plan_grasps("parallel_jaw", SPHERE, rank_by="force")
    with pytest.raises(pg.InvalidInputError, match="verify"):
        pg.plan_grasps("parallel_jaw", SPHERE, top=2, verify=3)
    with pytest.raises(pg.InvalidInputError, match="budget"):
        pg.plan_grasps("parallel_jaw", SPHERE, preload={"budget": -1})


@pytest.mark.parametrize(
    ("obj", "says"),
    [
        ("cylinder:0.02", "cylinder:R,LENGTH (cylinder:0.02,0.08)"),
        ("cylinder:a,b", "takes 2 comma-separated numbers [m]"),
        ("box:1,2", "box:SX,SY,SZ (box:0.05,0.06,0.08)"),
        ("cyl:0.02,0.08", "no such shape or file"),
        ("no_such_object.stl", "existing mesh file"),
    ],
)
def test_cli_plan_bad_object_shows_the_form_and_an_example(capsys, obj, says):
    rc, _, err = run(capsys, "plan", "parallel_jaw", obj, "--n", "1")
    assert rc == 2
    assert err.startswith("pinograsp: error: OBJECT: ") and says in err and repr(obj) in err


def test_cli_plan_writes_a_grasps_file_that_batch_rescores(tmp_path, capsys):
    out = tmp_path / "plans"
    argv = [
        "plan",
        "parallel_jaw",
        "sphere:0.02",
        "--n",
        "6",
        "--top",
        "2",
        "--preload",
        "20",
        "--refine",
        "1",
    ]
    rc, table, err = run(capsys, *argv, "--out", str(out))
    assert rc == 0, err
    assert {p.name for p in out.iterdir()} == {"plans.yaml", "plans.json", "plan_1.png", "plan_2.png"}
    # the table says which preload each score is for (the jaws' one actuator, 20 N)
    rows = [line for line in table.splitlines() if line.strip().startswith(("1 ", "2 "))]
    assert len(rows) == 2 and all(row.rstrip().endswith(" 20") for row in rows), table
    rc, text, err = run(capsys, "batch", str(out / "plans.yaml"))
    assert rc == 0, err
    assert "2 ok" in text and "worst of 26 disturbances" in text


@pytest.mark.slow
def test_verify_simulates_every_direction_of_the_best_plan():
    pytest.importorskip("mujoco")
    p = pg.plan_grasps("parallel_jaw", SPHERE, **{**SMALL, "verify": 1})
    checks = p.plans[0].checks
    assert len(checks) == 26
    finite = [c for c in checks if math.isfinite(c.predicted)]
    assert all(c.simulated >= 0.9 * c.predicted for c in finite), [c.to_dict() for c in checks]


def test_readme_plan_example_prints_the_closed_form(tmp_path, monkeypatch, capsys):
    """The README's "Plan a grasp" example: its best plan is the jaw-on-sphere closed form."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    code = re.search(r"<!-- readme-example: plan -->\n```python\n(.*?)```", text, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(code, "README:plan", "exec"), ns)
    plans, out = ns["plans"], capsys.readouterr().out
    first, give_way = _closed_forms()
    best = plans.plans[0]
    which = first if math.isclose(best.score, min(first.values()), rel_tol=1e-6) else give_way
    assert math.isclose(best.score, min(which.values()), rel_tol=1e-6)
    assert f"best {best.score:.4g}" in out and best.worst.count("f") == 3  # a cube corner, as printed
    assert pg.load_grasps(tmp_path / "plans.yaml").grasps[0].command == best.spec.command


def test_sampled_approaches_never_start_inside_the_object():
    """Each sampled approach's open hand is clear of the object: the Barrett on a box (whose open
    fingers lie flat beside the palm) comes in along its palm normal to its first touch."""
    from pinograsp.planning.approach import ApproachFrame, OpenHand
    from pinograsp.planning.plan import sample_specs

    box = pg.ObjectSpec("box", size=(0.05, 0.06, 0.08))
    base = pg.GraspSpec("barrett_bh8_282", box)
    hand = pg.Hand.builtin("barrett_bh8_282")
    frame = ApproachFrame.of_hand(hand)
    assert np.allclose(frame.axis, [0, 0, 1], atol=0.1)  # the palm normal
    open_hand = OpenHand(hand, None, box, frame, 1e-3)
    specs = sample_specs(base, frame, 40, 0, (0.0, 1.0), hand)
    gaps = np.array([open_hand.clearance(s.object.pose) for s in specs])
    assert gaps.min() > 0.5e-3  # outside the auto-close's stop distance: no finger starts stopped
    # stopped touching (0.6-0.8 mm), just outside the 1 mm tolerance (1.6-1.8 mm) or at their depth
    assert np.all((gaps < 0.8e-3 + 1e-9) | (gaps > 1.6e-3 - 1e-9))


def test_the_screen_only_drops_approaches_without_a_preload():
    """The screen's linear program is a relaxation of the preload design: an approach it drops
    has no "auto" preload (equilibrium_preload raises), and one that has a preload passes it."""
    from dataclasses import replace

    from pinograsp.planning.approach import ApproachFrame
    from pinograsp.planning.plan import sample_specs
    from pinograsp.planning.screen import PRESSED, internal_force

    box = pg.ObjectSpec("box", size=(0.05, 0.06, 0.08))
    hand = pg.Hand.builtin("barrett_bh8_282")
    specs = sample_specs(
        pg.GraspSpec("barrett_bh8_282", box), ApproachFrame.of_hand(hand), 10, 0, (0, 1), hand
    )
    verdicts = []
    for spec in specs:
        model, _, _ = build_grasp(replace(spec, command=1.0))
        try:
            build_grasp(spec)
            found = True
        except pg.NoPreloadError:
            found = False
        pressed = internal_force(model) > PRESSED
        assert pressed or not found, spec.id
        verdicts.append((pressed, found))
    assert (False, False) in verdicts and (True, True) in verdicts  # both kinds occur here


def test_plans_use_contact_patches_so_flat_jaws_grip():
    """A parallel jaw's flat pads on a box are 4 corner points each (``patches=True``, the
    planner's default): the best plans resist ``mu F`` = 0.5 x 20 N = 10 N along the pads (the
    friction limit, to 0.2 %); with point contacts every plan is 0 (the box spins about the line
    between the two points)."""
    box = pg.ObjectSpec("box", size=(0.04, 0.04, 0.04))
    kw = dict(n=20, top=3, preload=20.0, seed=0, workers=1, refine=0)
    plans = pg.plan_grasps("parallel_jaw", box, **kw)
    best = plans.plans[0]
    assert len(best.points) == 8 and best.score == pytest.approx(10.0, rel=2e-3)
    assert best.values["+fy"] == pytest.approx(10.0, rel=2e-3)
    points = pg.plan_grasps("parallel_jaw", box, patches=False, **kw)
    assert all(p.score == 0.0 and len(p.points) == 2 for p in points.plans)


def test_plot_plan_marks_each_simulated_load(plans):
    """A verified plan's picture: a dot at each load where the simulation gave way, a triangle
    on the bar where it held (the checks here are made up: only the drawing is tested)."""
    pytest.importorskip("matplotlib")
    from dataclasses import replace

    from pinograsp.planning.records import PlanCheck

    best = plans.plans[0]
    labels = list(best.values)
    checks = (
        PlanCheck(labels[0], best.values[labels[0]], 3.5, "gave_way", math.nan),
        PlanCheck(labels[1], best.values[labels[1]], math.inf, "held", math.nan),
    )
    fig = pg.plot_plan(replace(best, checks=checks))
    ax = fig.axes[-1]
    dots, triangles = ax.lines[0], ax.lines[1]
    assert dots.get_xdata().tolist() == [0] and dots.get_ydata().tolist() == [3.5]
    assert triangles.get_xdata().tolist() == [1]
    assert triangles.get_ydata()[0] == pytest.approx(ax.patches[1].get_height())
    assert "simulated worst 3.5" in ax.get_title()


def test_a_plan_names_and_draws_the_directions_past_a_snap(plans):
    """``GraspPlan.snaps`` in the summary and as a tick on the bar (made-up snaps: the drawing)."""
    pytest.importorskip("matplotlib")
    from dataclasses import replace

    best = plans.plans[0]
    assert best.snaps == {} and "past a snap" not in best.summary()  # the jaws on a sphere: none
    labels = list(best.values)
    snapped = replace(best, snaps={labels[2]: 0.5 * best.values[labels[2]], labels[4]: 1.25})
    assert f"(worst {best.worst}, 2 past a snap (from 1.25))" in snapped.summary()
    ax = pg.plot_plan(snapped).axes[-1]
    (ticks,) = [line for line in ax.lines if line.get_label() == "first snap"]
    assert ticks.get_xdata().tolist() == [2, 4]
    assert ticks.get_ydata().tolist() == [0.5 * best.values[labels[2]], 1.25]
    assert snapped.to_dict()["snaps"] == {labels[2]: 0.5 * best.values[labels[2]], labels[4]: 1.25}
    # a snap above every value (an unbounded direction's) stays inside the drawn bars
    high = max(v for v in best.values.values() if math.isfinite(v)) * 3
    ax = pg.plot_plan(replace(best, snaps={labels[0]: high})).axes[-1]
    assert ax.get_ylim()[1] > high
    assert ax.get_ylabel() == "largest resisted multiple of the disturbance [N for unit forces]"
    assert pg.plot_plan(best, ylabel="weights").axes[-1].get_ylabel() == "weights"


def test_plans_use_16_edge_pyramids_unless_told(capsys):
    """``PLAN_EDGES`` (docs/planning.md, "Friction pyramid"): every candidate's spec and model
    carry it; ``--edges`` (``edges=``) chooses another."""
    from support.clirun import run_json

    from pinograsp.planning.plan import PLAN_EDGES

    argv = [
        "plan",
        "parallel_jaw",
        "sphere:0.02",
        "--n",
        "3",
        "--top",
        "1",
        "--preload",
        "20",
        "--refine",
        "0",
    ]
    default = run_json(capsys, *argv)["plans"][0]
    eight = run_json(capsys, *argv, "--edges", "8")["plans"][0]
    assert PLAN_EDGES == 16 and default["spec"]["edges"] == 16 and eight["spec"]["edges"] == 8
    model, _, _ = build_grasp(
        pg.GraspSpec(**{**default["spec"], "object": pg.ObjectSpec(**default["spec"]["object"])})
    )
    assert model.edges == 16
    # the jaws' values along the cube's directions are the same closed forms with 8 or 16 edges
    assert default["values"] == pytest.approx(eight["values"], rel=1e-9)
