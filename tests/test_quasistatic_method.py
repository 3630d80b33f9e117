"""``method="quasistatic"`` through every entry point that chooses a method (issue #25, Deliver 5):
the registry row, passive_response, max_resistible_wrench, profiles, resistance sets, scores,
preloads, scenes' analysis blocks, batch rows and the CLI, with the pinch's closed form
``2 mu tau0 / (L |sin θ|)`` and its exactly unbounded ±X."""

import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from support.clirun import run, run_json

import pinograsp as pg
from pinograsp import examples
from pinograsp.analysis.registry import get_method
from pinograsp.cli import main
from pinograsp.core.methods import bounded, search_text

MU, TAU, L = 0.5, 1.0, 0.1
QS = "quasistatic"


def closed_form(theta: float) -> float:
    """The pinch's largest force along ``(cos θ, sin θ)`` [N] (inf along ±x)."""
    s = abs(np.sin(theta))
    return np.inf if s < 1e-12 else 2 * MU * TAU / (L * s)


@pytest.fixture(scope="module")
def pinch():
    return examples.pinch()


# ------------------------------------------------------------------------------ the row
def test_registry_row_and_its_vocabulary():
    rules = get_method(QS)
    assert rules.name == pg.Method.QUASISTATIC and rules.searches == (pg.Search.PATH,)
    assert rules.load_kind is None and rules.load_factor_kind is None and not rules.refines
    assert not bounded(QS) and bounded("iterative")
    assert "exact" in search_text(QS, 1e3, 20) and "upper 1000" in search_text("prp", 1e3, 20)
    assert pg.Query(QS).search is pg.Search.AUTO and pg.Query(QS, search="path").search is pg.Search.PATH


# ------------------------------------------------------------------------------ max wrench
@pytest.mark.parametrize("deg", range(0, 360, 15))
def test_max_resistible_wrench_is_the_closed_form(pinch, deg):
    t = np.radians(deg)
    mw = pg.max_resistible_wrench(pinch, TAU, [np.cos(t), np.sin(t), 0.0], QS)
    expected = closed_form(t)
    if np.isinf(expected):
        assert mw.status == "unbounded" and mw.unbounded and np.isinf(mw.magnitude)
    else:
        assert mw.status == "finite" and mw.magnitude == pytest.approx(expected, rel=1e-9)
    assert mw.method == QS and mw.search == "path" and mw.floor == 0.0 and mw.resolution == 0.0
    assert mw.response is not None and mw.response.resistible and mw.response.audit.ok
    assert mw.response.variant == "preload-first"


def test_steps_do_not_apply_and_upper_caps(pinch):
    """``steps`` do not apply; ``upper`` is the largest load of interest: a give-way above it is
    ``above_limit`` at ``upper`` (as the searches and the simulation say), the exact load kept
    in ``giveway.load``; an unbounded path stays unbounded."""
    ref = pg.max_resistible_wrench(pinch, TAU, "fy", QS)
    for upper, steps in ((1.0, 1), (5.0, 30), (1e6, 3)):
        mw = pg.max_resistible_wrench(pinch, TAU, "fy", QS, upper, steps)
        assert mw.giveway.load == ref.magnitude == pytest.approx(10.0, rel=1e-12)
        if upper > 10.0:
            assert mw.status == "finite" and mw.magnitude == ref.magnitude
        else:
            assert mw.status == "above_limit" and mw.magnitude == upper and not mw.unbounded
    assert pg.max_resistible_wrench(pinch, TAU, "fx", QS, upper=1e-3).status == "unbounded"
    q = pg.max_resistible_wrench(pinch, TAU, "fy", query=pg.Query(QS, 7.0, 2, "path"))
    assert q.status == "above_limit" and q.magnitude == 7.0 and q.giveway.load == ref.magnitude


def test_refusals_name_the_valid_choices(pinch):
    with pytest.raises(pg.InvalidInputError, match=r"variant: 'single-step' does not apply.*preload-first"):
        pg.max_resistible_wrench(pinch, TAU, "fy", QS, variant="single-step")
    with pytest.raises(pg.InvalidInputError, match="cone refinement applies to method='prp' or 'energetic'"):
        pg.passive_response(pinch, TAU, [0, 1, 0], QS, cone_tolerance=0.1)
    with pytest.raises(pg.InvalidInputError, match="'path' exists for method='quasistatic' only"):
        pg.resistance_profile(pinch, TAU, n=4, method="prp", search="path")
    with pytest.raises(pg.InvalidInputError, match="no one-solve load-factor problem"):
        pg.Session(pinch).max_load_factor(TAU, np.array([0, 1.0, 0, 0, 0, 0]), 50.0, QS)


def test_passive_response_is_the_state_on_the_path(pinch):
    held = pg.passive_response(pinch, TAU, [0, 9.999, 0], QS)
    assert held.status == "resisted" and held.method == QS and held.variant == "preload-first"
    np.testing.assert_allclose(held.normal_forces, [10.0, 10.0], rtol=1e-12)
    assert np.linalg.norm(held.net_wrench) < 1e-12 and held.audit.ok
    gone = pg.passive_response(pinch, TAU, [0, 10.001, 0], QS)
    assert gone.status == "not_resisted" and not gone.resistible
    np.testing.assert_allclose(gone.net_wrench[:2], [0.0, 0.001], atol=1e-9)  # stopped at the limit 10 N
    settled = pg.passive_response(pinch, TAU, [0, 5.0, 0], QS, variant="settled-preload")
    assert settled.resistible and settled.variant == "settled-preload"


def test_preload_without_equilibrium(pinch):
    """Backdrivable fingers at 1 and 0.5 N·m push the object along +x: no preloaded state."""
    m = examples.pinch(kind="backdrivable")
    with pytest.raises(pg.PreloadNotInEquilibriumError, match="quasistatic"):
        pg.max_resistible_wrench(m, [1.0, 0.5], "fy", QS)
    r = pg.passive_response(m, [1.0, 0.5], [0, 1.0, 0], QS)
    assert r.status == "not_resisted" and np.isnan(r.contact_forces).all()
    with pytest.raises(pg.PreloadNotInEquilibriumError):
        pg.loading_path(m, [1.0, 0.5], "fy")
    fixed = pg.equilibrium_preload(m, QS)
    assert fixed.found and fixed.command == {"left": 1.0, "right": 1.0} and fixed.method == QS
    np.testing.assert_allclose(fixed.response.normal_forces, [10.0, 10.0], rtol=1e-9)


def test_optimal_preload_searches_with_the_path(pinch):
    """5 N along +y needs a grip of 5 N per finger: tau0 = F L / (2 mu) = 0.5 N·m (exact)."""
    r = pg.optimal_preload(pinch, [[0.0, 5.0, 0.0]], QS)
    assert r.status == "optimal" and r.method == QS and r.value == pytest.approx(0.5, rel=1e-9)


# ------------------------------------------------------------------------------ profiles, sets, scores
def test_profile_set_and_score_are_the_closed_form(pinch):
    p = pg.resistance_profile(pinch, TAU, n=24, method=QS)
    expected = np.array([closed_form(a) for a in p.angles])
    np.testing.assert_allclose(p.magnitudes, expected, rtol=1e-9)
    assert list(p.unbounded) == list(np.isinf(expected)) and not p.failures
    s = pg.Session(pinch)
    again = pg.resistance_profile(pinch, TAU, n=24, query=pg.Query(QS), session=s)
    np.testing.assert_array_equal(again.magnitudes, p.magnitudes)
    pooled = pg.resistance_profile(pinch, TAU, n=24, method=QS, workers=2)
    np.testing.assert_array_equal(pooled.magnitudes, p.magnitudes)
    dirs = [[0, 1, 0], [1, 1, 0], [1, 0, 0], [-1, -2, 0]]
    rs = pg.resistance_set(pinch, TAU, directions=dirs, method=QS)
    force = [closed_form(np.arctan2(d[1], d[0])) for d in dirs]
    np.testing.assert_allclose(rs.magnitudes, force, rtol=1e-9)
    assert list(rs.statuses) == ["finite", "finite", "unbounded", "finite"] and rs.method == QS
    score = pg.grasp_score(pinch, TAU, method=QS, n=24)
    full = pg.resistance_set(pinch, TAU, 24, QS)
    assert score.value == full.quantile(0.05, capped=True) and score.rset.method == QS


# ------------------------------------------------------------------------------ scenes, batch, CLI
@pytest.fixture()
def qs_scene(tmp_path):
    """The built-in pinch scene with ``analysis.method: quasistatic``."""
    text = (Path(pg.__file__).parent / "data" / "scenes" / "pinch.yaml").read_text()
    lines = [ln for ln in text.splitlines() if not ln.startswith("  method:")]
    text = "\n".join(lines).replace("analysis:\n", "analysis:\n  method: quasistatic\n")
    assert "method: quasistatic" in text
    path = tmp_path / "pinch_qs.yaml"
    path.write_text(text + "\n")
    return path


def test_scene_analysis_block(qs_scene):
    scene = pg.load_scene(qs_scene)
    assert (
        scene.analysis.method is pg.Method.QUASISTATIC
        and scene.analysis.query.method is pg.Method.QUASISTATIC
    )
    assert scene.max_resistible_wrench("up").magnitude == pytest.approx(10.0, rel=1e-12)
    assert scene.max_resistible_wrench("right").status == "unbounded"
    assert scene.passive_response([0, 5.0, 0]).method == QS


def test_batch_row_scores_with_the_path():
    t = pg.evaluate_grasps(["pinch"], score=pg.WorstAxisScore(method=QS), workers=1)
    row = t.iloc[0]
    assert row["status"] == "ok" and row["score"] == pytest.approx(10.0, rel=1e-12)
    assert row["max_+fx"] == row["max_-fx"] == np.inf and row["unbounded_fraction"] == 0.5


def test_batch_file_with_score_method(tmp_path):
    path = tmp_path / "grasps.yaml"
    path.write_text("score: {method: quasistatic}\ngrasps:\n  - {scene: pinch}\n")
    out = tmp_path / "res.csv"
    assert main(["batch", str(path), "--out", str(out), "--workers", "1", "--no-progress"]) == 0
    df = pd.read_csv(out)
    assert df["status"].tolist() == ["ok"] and df["score"].iloc[0] == pytest.approx(10.0, rel=1e-12)


def test_cli_every_analysis_command(capsys, qs_scene):
    mw = run_json(capsys, "max-wrench", "pinch", "-d", "fy", "--method", QS)
    assert mw["method"] == QS and mw["search"] == "path" and mw["magnitude"] == pytest.approx(10.0, rel=1e-12)
    rc, out, _ = run(capsys, "max-wrench", "pinch", "-d", "fx", "--method", QS)
    assert (
        rc == 0
        and "UNBOUNDED: the loading path has no limit and stays within the give-way thresholds" in out
        and "upper limit" not in out
    )
    prof = run_json(capsys, "profile", "pinch", "-n", "8", "--method", QS)
    assert prof["magnitudes"][2] == pytest.approx(10.0, rel=1e-12) and prof["magnitudes"][0] is None
    assert prof["resolution"] == 0.0  # exact: no search grid
    rs = run_json(capsys, "resistance-set", "pinch", "-n", "20", "--method", QS)
    assert rs["method"] == QS
    an = run_json(capsys, "analyze", "pinch", "-w", "0,5,0", "--method", QS)
    assert an["status"] == "resisted" and an["method"] == QS and an["variant"] == "preload-first"
    from_scene = run_json(capsys, "max-wrench", str(qs_scene), "-d", "fy")
    assert from_scene["method"] == QS and from_scene["magnitude"] == mw["magnitude"]
    rc, _, err = run(capsys, "max-wrench", "pinch", "-d", "fy", "--method", QS, "--variant", "single-step")
    assert rc != 0 and "preload-first" in err


# ------------------------------------------------------------------------------ determinism
SCRIPT = """
import numpy as np, pinograsp as pg
s = pg.load_scene("case1")
p = pg.resistance_profile(s.model, s.command, n=12, method="quasistatic")
print([float(m).hex() for m in p.magnitudes], list(p.statuses))
r = pg.passive_response(s.model, s.command, [0, 2.0, 0, 0, 0, 0], "quasistatic")
print(r.status, [float(x).hex() for x in r.normal_forces])
"""


def test_bit_identical_in_fresh_processes():
    runs = [
        subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, check=True).stdout
        for _ in range(2)
    ]
    assert runs[0] == runs[1] and runs[0].count("\n") == 2


# ------------------------------------------------------------------------------ tangential stiffness
def test_tangential_ratio_reaches_every_entry_point(capsys, tmp_path):
    """``Settings.tangential_ratio`` through the API, a scene's analysis block and the CLI: the
    same numbers as :func:`pinograsp.quasistatic_max_wrench` with that setting."""
    scene = pg.load_scene("case1")
    m, fc = scene.model, scene.command
    direct = {
        r: pg.quasistatic_max_wrench(m, fc, "fy", pg.Settings(tangential_ratio=r)).magnitude for r in (0.1, 1)
    }
    assert abs(direct[0.1] / direct[1] - 1) > 1e-3  # 4.392 vs 4.335 N
    for r in (0.1, 1):
        assert pg.max_resistible_wrench(m, fc, "fy", QS, tangential_ratio=r).magnitude == direct[r]
    data = run_json(capsys, "max-wrench", "case1", "-d", "fy", "--method", QS, "--tangential-ratio", "0.1")
    assert data["magnitude"] == direct[0.1]
    rc, _, err = run(capsys, "max-wrench", "case1", "-d", "fy", "--method", QS, "--tangential-ratio", "0")
    assert rc == 2 and "--tangential-ratio" in err and "[1e-06, 1e+06]" in err
    text = (Path(pg.__file__).parent / "data" / "scenes" / "pinch.yaml").read_text()
    path = tmp_path / "pinch_kt.yaml"
    path.write_text(text.replace("analysis:\n", "analysis:\n  tangential_ratio: 10\n"))
    assert pg.load_scene(path).settings.tangential_ratio == 10.0
    case1 = (Path(pg.__file__).parent / "data" / "scenes" / "case1.yaml").read_text()
    soft = tmp_path / "case1_soft.yaml"
    soft.write_text(case1.replace("analysis:\n", "analysis:\n  tangential_ratio: 0.1\n"))
    assert run_json(capsys, "path", str(soft), "-d", "fy")["limit"] == direct[0.1]
    assert run_json(capsys, "max-wrench", str(soft), "-d", "fy", "--method", QS)["magnitude"] == direct[0.1]


def test_a_path_without_verdict_is_a_failed_direction(pinch, monkeypatch):
    """A path that stops without a verdict (here: forced ``segment_limit`` along +y) is never a
    number: a SolverError for one query, a failed direction (typed status) in a profile."""
    from pinograsp.analysis import method_quasistatic

    real = method_quasistatic.max_wrench_prepared

    def stopped_along_y(*args, **kw):
        mw = real(*args, **kw)
        return replace(mw, status="segment_limit") if abs(mw.direction[1]) > 0.99 else mw

    monkeypatch.setattr(method_quasistatic, "max_wrench_prepared", stopped_along_y)
    with pytest.raises(pg.SolverError, match="without a verdict") as err:
        pg.max_resistible_wrench(pinch, TAU, "fy", QS)
    assert err.value.status == "segment_limit"
    p = pg.resistance_profile(pinch, TAU, n=4, method=QS)
    assert list(p.statuses) == ["unbounded", "failed", "unbounded", "failed"]
    assert [(i, st) for i, _, st in p.failures] == [(1, "segment_limit"), (3, "segment_limit")]
    assert np.isnan(p.magnitudes[[1, 3]]).all()


def test_batch_row_of_a_urdf_hand():
    """A Barrett grasp closed on a box, its preload chosen ("auto") and verified by the
    quasi-static preload path, scored along the six force axes by the path; the same bits in a
    local pool of two workers."""
    import math

    box = pg.ObjectSpec("box", size=(0.1462, 0.05, 0.10), xyz=(0.0, 0.0, 0.0678))
    g = pg.GraspSpec("barrett_bh8_282", box, q_open={"bh_j11": math.pi / 2}, preload_method=QS)
    score = pg.WorstAxisScore(method=QS)
    df = pg.evaluate_grasps([g, g], score=score, workers=1)
    row = df.iloc[0]
    assert row["status"] == "ok" and row["n_contacts"] == 4, row["error_message"]
    axes = [row[f"max_{s}{a}"] for a in ("fx", "fy", "fz") for s in "+-"]
    assert row["score"] == min(axes) > 0 and row["unbounded_fraction"] == np.mean(np.isinf(axes)) > 0
    pooled = pg.evaluate_grasps([g, g], score=score, workers=2)
    for col in ("score", *score.columns[2:]):
        assert list(df[col]) == list(pooled[col])


def _pinch_right_axis(flipped: bool) -> pg.GraspModel:
    """The pinch; with ``flipped`` the right finger closes for a negative torque of its
    bidirectional actuator."""
    ez = np.array([0.0, 0.0, 1.0])
    left = pg.Contact.revolute(
        [-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], -ez)}, nq=2, mu=MU, name="left"
    )
    right = pg.Contact.revolute(
        [0.05, 0, 0], [-1, 0, 0], {1: ([0.05, -0.1, 0], -ez if flipped else ez)}, nq=2, mu=MU, name="right"
    )
    acts = [pg.Actuator({0: 1.0}, name="left"), pg.Actuator({1: 1.0}, name="right", bidirectional=flipped)]
    return pg.GraspModel.from_contacts(
        [left, right], actuators=acts, planar=True, joint_names=("left", "right")
    )


def test_negative_commands_of_a_bidirectional_actuator():
    ref, neg = _pinch_right_axis(False), _pinch_right_axis(True)
    a = pg.max_resistible_wrench(ref, TAU, "fy", QS)
    b = pg.max_resistible_wrench(neg, {"left": TAU, "right": -TAU}, "fy", QS)
    assert a.magnitude == b.magnitude == pytest.approx(10.0, rel=1e-12)
    r = pg.passive_response(ref, TAU, [2.0, 3.0, 0.0], QS)
    n = pg.passive_response(neg, [TAU, -TAU], [2.0, 3.0, 0.0], QS)
    assert n.status == r.status == "resisted" and n.command.tolist() == [1.0, -1.0]
    np.testing.assert_allclose(n.contact_forces, r.contact_forces, atol=1e-12)
    np.testing.assert_allclose(n.actuator_forces, r.actuator_forces * [1, -1], atol=1e-12)


# ------------------------------------------------------------------------------ one default
def test_every_default_reads_the_one_default_method():
    """Making another method the default is one line (core/settings.py DEFAULT_METHOD,
    /work/notes/qs_default.md): every default below reads it, and the built-in scenes name no
    method of their own."""
    import inspect

    from pinograsp.core.settings import DEFAULT_METHOD

    for f in (
        pg.passive_response,
        pg.max_resistible_wrench,
        pg.resistance_profile,
        pg.resistance_set,
        pg.grasp_score,
        pg.equilibrium_preload,
        pg.optimal_preload,
        pg.Session.response,
    ):
        assert inspect.signature(f).parameters["method"].default == DEFAULT_METHOD, f.__name__
    assert pg.Query().method == DEFAULT_METHOD and pg.WorstAxisScore().method == DEFAULT_METHOD
    spec = pg.GraspSpec("barrett_bh8_282", pg.ObjectSpec("sphere", radius=0.04))
    assert spec.preload_method == DEFAULT_METHOD
    for name in pg.builtin_scenes():
        assert pg.load_scene(name).analysis.method == DEFAULT_METHOD, name


def test_the_preload_path_is_followed_once_per_session(monkeypatch):
    """A profile (one session) follows the preload path once for all its directions; a session
    the caller owns keeps it across queries; a new session follows it again (nothing is kept at
    module level); the answers do not depend on it."""
    from pinograsp.analysis.quasistatic import prepared

    calls = []
    real = prepared.preload_path

    def counted(*args, **kwargs):
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(prepared, "preload_path", counted)
    scene = pg.load_scene("case1")
    model = examples.pinch()
    first = pg.resistance_profile(model, TAU, n=12, method=QS)
    assert len(calls) == 1
    mine = pg.Session(model)
    again = pg.resistance_profile(model, TAU, n=12, method=QS, session=mine)
    assert len(calls) == 2 and np.array_equal(first.magnitudes, again.magnitudes, equal_nan=True)
    pg.max_resistible_wrench(model, TAU, "fy", QS, session=mine)
    assert len(calls) == 2  # the caller's session kept it
    pg.resistance_set(scene.model, scene.command, 6, QS)
    assert len(calls) == 3


def test_a_cold_query_validates_once_prepares_once_and_builds_no_miqp(monkeypatch):
    """One cold quasi-static max_resistible_wrench validates its settings once, prepares the
    grasp once, builds no complementarity formulation (no MIQP objects), and calls at most 360
    of the package's functions (cProfile: 351; comprehension frames aside, 547 with them)."""
    import cProfile
    import pstats

    from pinograsp.analysis import response
    from pinograsp.analysis.quasistatic import prepared

    counts = {"validated": 0, "prepared": 0, "formulation": 0}
    real_validated, real_prepare = pg.Settings.validated, prepared.prepare_analysed
    real_form = response.Formulation

    def validated(self):
        counts["validated"] += 1
        return real_validated(self)

    def prepare_analysed(*args, **kwargs):
        counts["prepared"] += 1
        return real_prepare(*args, **kwargs)

    def formulation(*args, **kwargs):
        counts["formulation"] += 1
        return real_form(*args, **kwargs)

    monkeypatch.setattr(pg.Settings, "validated", validated)
    monkeypatch.setattr(response, "prepare_analysed", prepare_analysed)
    monkeypatch.setattr(response, "Formulation", formulation)
    model = examples.pinch()
    mw = pg.max_resistible_wrench(model, TAU, "fy", tangential_ratio=0.5)
    assert mw.magnitude == pytest.approx(10.0, rel=1e-12)
    assert counts == {"validated": 1, "prepared": 1, "formulation": 0}
    cold = examples.pinch()  # the caller's model; the query is cold (no session yet)
    prof = cProfile.Profile()
    prof.enable()
    pg.max_resistible_wrench(cold, TAU, "fy", tangential_ratio=0.5)
    prof.disable()
    stats = pstats.Stats(prof).stats  # type: ignore[attr-defined]
    ours = {k: v[1] for k, v in stats.items() if "/pinograsp/" in k[0].replace("\\", "/")}
    named = sum(n for k, n in ours.items() if not k[2].startswith("<"))  # not comprehension frames
    # 481 named functions (699 frames with comprehensions) before the session owned its state
    assert named <= 360 and sum(ours.values()) <= 600, (named, sum(ours.values()))
