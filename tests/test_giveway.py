"""The give-way answer of the default method (docs/giveway.md): closed forms on the pinch, the
paper's case 2 snap, the thresholds shared with the simulation, stiffness as a physical input,
the linearisation bound, paths stopped above ``upper``, and the settings' domains."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.core.giveway import LINEAR_TRANSLATION, giveway_thresholds
from pinograsp.sim.simulate import _options


@pytest.fixture(scope="module")
def pinch():
    return pg.examples.pinch()


@pytest.fixture(scope="module")
def case2():
    return pg.load_scene("case2")


def _dir(deg: float) -> list[float]:
    return [float(np.cos(np.radians(deg))), float(np.sin(np.radians(deg))), 0.0]


@pytest.mark.parametrize("deg, expected", [(90, 10.0), (30, 20.0), (150, 20.0), (45, 10 * np.sqrt(2))])
def test_pinch_sharp_limits_unchanged(pinch, deg, expected):
    """DESIGN §6: F_max = 2 mu tau0 / (L |sin θ|): a sharp give-way at the first limit."""
    mw = pg.max_resistible_wrench(pinch, 1.0, _dir(deg))
    assert mw.status == "finite" and mw.magnitude == pytest.approx(expected, rel=1e-12)
    assert mw.giveway.reason == "limit" and mw.giveway.first_limit == mw.magnitude


def test_pinch_push_gives_way_at_stiffness_times_slip(pinch):
    """Along +x the pushed finger's ratchet holds and the other finger follows at its command:
    the object moves ``F / K`` — the give-way load is ``K * slip`` (closed form), and with the
    default thresholds at 1e6 N/m the push is held (unbounded) up to ``upper``. The path's
    first limit is the ray's buckling, ``2 K a - 20`` (the squeezed pair turning against its
    tangential springs, ``a`` = 50 mm: test_quasistatic), where it lies below twice ``upper``."""
    for K in (1e3, 1e4, 1e5):
        s = pg.Settings(contact_stiffness=K, giveway_slip=1e-3)
        mw = pg.max_resistible_wrench(pinch, 1.0, "fx", upper=1e3, settings=s)
        assert mw.status == "finite" and mw.magnitude == pytest.approx(K * 1e-3, rel=1e-12)
        assert mw.giveway.reason == "translation" and mw.giveway.stiffness == K
        assert mw.giveway.translation == pytest.approx(1e-3, rel=1e-12)
        buckles = 2 * K * 0.05 - 20.0
        first = buckles if buckles <= 2e3 else np.inf
        assert (
            mw.giveway.first_limit == pytest.approx(first, rel=1e-7)
            and mw.first_limit == mw.giveway.first_limit
        )
    held = pg.max_resistible_wrench(pinch, 1.0, "fx", upper=100)
    assert held.status == "unbounded" and held.giveway.reason == "held" and held.upper == 100


def test_linearisation_bound_ends_the_path(pinch):
    """A threshold beyond the linearisation's range (a quarter of the length scale) is not
    reached: the path ends there with reason "linearisation", at ``K * ell / 4``."""
    s = pg.Settings(contact_stiffness=1000.0, giveway_slip=10.0)  # buckling only at 2 K a - 20 = 80 N
    mw = pg.max_resistible_wrench(pinch, 1.0, "fx", upper=100, settings=s)
    bound = LINEAR_TRANSLATION * pinch.length_scale
    assert mw.giveway.reason == "linearisation" and mw.magnitude == pytest.approx(1000.0 * bound, rel=1e-12)
    assert mw.giveway.translation == pytest.approx(bound, rel=1e-12)


def test_case2_finger2_survives_its_snaps(case2):
    """The paper's case 2: the finger-2 preload's first limit (2.83 N) is a µm snap that lands;
    the grasp holds to 18.98 N (simulation, model's pyramid: 18.22 N). Finger 1: 35.74 N at a
    limit with nothing to land on. The ratio moves from 12.6 (first limits) to 1.88."""
    m = case2.model
    f1 = pg.max_resistible_wrench(m, case2.preload("finger1_only"), "fx", upper=50)
    f2 = pg.max_resistible_wrench(m, case2.preload("finger2_only"), "fx", upper=50)
    assert f2.first_limit == pytest.approx(2.8332, rel=1e-4)
    assert f2.magnitude == pytest.approx(18.98165, rel=1e-5) and f2.giveway.reason == "limit"
    assert len(f2.giveway.snaps) == 2 and f2.giveway.snaps[0][0] == pytest.approx(f2.first_limit, rel=1e-12)
    assert f1.magnitude == pytest.approx(35.7359, rel=1e-5) and f1.first_limit == f1.magnitude
    assert f1.magnitude / f2.magnitude == pytest.approx(1.8827, rel=1e-3)
    assert f1.first_limit / f2.first_limit == pytest.approx(12.613, rel=1e-3)
    first = pg.max_resistible_wrench(m, case2.preload("finger2_only"), "fx", upper=50, limit="first")
    assert first.magnitude == f2.first_limit and first.giveway is None


def test_thresholds_are_the_simulations(case2):
    """One definition: the analysis' thresholds equal the simulation's options for the same
    direction, upper and stiffness (and follow the sim's rule: max(1 mm, 20 x deflection))."""
    m = case2.model
    for d, upper, K in (("fx", 50.0, 1e6), ("mz", 5.0, 1e5), ("-fy", 1e3, 1e6)):
        d6 = pg.core.axes.wrench_direction(m, d)
        o = _options(m, d6, upper, {"stiffness": K})
        mw = pg.max_resistible_wrench(m, case2.preload(None), d, upper=upper, contact_stiffness=K)
        assert (mw.giveway.slip, mw.giveway.rotation) == (o.slip, o.rotation)
        assert (o.slip, o.rotation) == giveway_thresholds(m.length_scale, d6, upper, K)
    assert giveway_thresholds(0.1, np.array([1.0, 0, 0, 0, 0, 0]), 1e3, 1e6)[0] == pytest.approx(0.02)
    assert giveway_thresholds(0.1, np.array([1.0, 0, 0, 0, 0, 0]), 10.0, 1e6) == (1e-3, pytest.approx(1e-2))


def test_path_stopped_above_upper_is_above_limit(case2):
    """A path that stops without a verdict (here the segment-count limit) is ``above_limit``
    when it held up to ``upper`` first, and a lower bound without verdict below it."""
    m, cmd = case2.model, case2.preload(None)
    # the count applies to every stage, the preload's too: 7 lets the preload through (a cold
    # call, nothing kept between calls) and stops the load stage at 14.44 N
    with pytest.raises(pg.PreloadNotInEquilibriumError, match="segment_limit"):
        pg.loading_path(m, cmd, "fz", max_segments=3)
    lp = pg.loading_path(m, cmd, "fz", max_segments=7)
    assert lp.status == "segment_limit" and lp.limit == pytest.approx(14.4426, rel=1e-4)
    above = pg.quasistatic_max_wrench(m, cmd, "fz", path=lp, upper=0.5 * lp.limit)
    assert above.status == "above_limit" and above.magnitude == 0.5 * lp.limit and not above.unbounded
    below = pg.quasistatic_max_wrench(m, cmd, "fz", path=lp, upper=2.0 * lp.limit)
    assert below.status == "segment_limit" and below.magnitude == lp.limit


def test_record_is_json_and_in_the_summary(case2):
    mw = pg.max_resistible_wrench(case2.model, case2.preload("finger2_only"), "fx", upper=50)
    data = json.loads(json.dumps(mw.to_dict()))
    assert data["giveway"]["reason"] == "limit" and data["giveway"]["stiffness"] == 1e6
    assert data["giveway"]["first_limit"] == pytest.approx(2.8332, rel=1e-4)
    assert "first limit 2.8332 N; 2 snap(s) survived" in mw.summary()


@pytest.mark.parametrize(
    "field, value",
    [("contact_stiffness", 0.0), ("contact_stiffness", 1e11), ("giveway_slip", -1e-3), ("limit", "last")],
)
def test_settings_domains(field, value):
    with pytest.raises(pg.InvalidInputError) as e:
        pg.Settings(**{field: value}).validated()
    assert e.value.name == field


def test_scene_file_keys(tmp_path):
    """``contact_stiffness``, ``giveway_slip``, ``giveway_rotation_deg`` and ``limit`` in a
    scene's analysis block become its settings (and the simulation's defaults)."""
    src = tmp_path / "s.yaml"
    src.write_text(
        "extends: pinch\nanalysis:\n  contact_stiffness: 2.0e5\n  giveway_slip: 0.002\n"
        "  giveway_rotation_deg: 3\n  limit: first\n"
    )
    s = pg.load_scene(str(src))
    assert s.settings.contact_stiffness == 2e5 and s.settings.giveway_slip == 0.002
    assert s.settings.giveway_rotation == pytest.approx(np.radians(3)) and s.settings.limit == "first"
    from pinograsp.sim.simulate import _scene_defaults

    assert _scene_defaults(s) == {"stiffness": 2e5, "slip": 0.002, "rotation": pytest.approx(np.radians(3))}


def test_flat_bar_mirror_directions_and_push_hold():
    """The flat-pad bar (8 patch corners): pushed along the squeeze axis the pads' four corners
    unload together at 20 N — classified at zero force (their polygons' apex), the grasp then
    holds on the other jaw (unbounded; the simulation holds >= 50 N) instead of stopping
    without a verdict. Mirror directions ±fy and ±fz give way at mu * 20 N = 10 N on both
    sides (simulation 9.986 N), although the −fy/−fz paths' first limits take a wedging branch."""
    bar = pg.load_scene("parallel_jaw_bar")
    m, cmd = bar.model, bar.preload(None)
    push = pg.max_resistible_wrench(m, cmd, "fx", upper=50)
    assert push.status == "unbounded" and push.giveway.first_status == "unbounded"
    for axis in ("fy", "fz"):
        plus = pg.max_resistible_wrench(m, cmd, axis, upper=50)
        minus = pg.max_resistible_wrench(m, cmd, "-" + axis, upper=50)
        assert plus.status == minus.status == "finite"
        assert plus.magnitude == pytest.approx(10.0, rel=1e-4) and minus.magnitude == pytest.approx(
            10.0, rel=2e-3
        )


def test_builtin_snap_scene_gives_way_past_its_landing_snaps():
    """The built-in ``case2_snap`` scene: its default answer depends on snaps that land."""
    s = pg.load_scene("case2_snap")
    mw = s.max_resistible_wrench("push")
    assert mw.magnitude == pytest.approx(18.98165, rel=1e-5) and mw.first_limit == pytest.approx(
        2.8332, rel=1e-4
    )
    assert [round(a, 4) for a, _ in mw.giveway.snaps][0] == pytest.approx(2.8332, rel=1e-4)
    first = s.max_resistible_wrench("push", limit="first")
    assert first.magnitude == mw.first_limit


def test_first_crossing_skips_only_segments_inside_every_threshold():
    """``first_crossing`` examines only the segments with an end near a threshold (speed): the
    same point, bit for bit, as every segment examined in turn, on random walks whose
    breakpoints graze the thresholds (ends within 1e-12 of them, either side), joints included."""
    from pinograsp.analysis.quasistatic import giveway as gw

    def brute(tr, th, x0, q0):
        for j in range(len(tr.loads) - 1):
            hit = gw._first_on_segment(th, x0, q0, tr.x[j], tr.x[j + 1], tr.q[j], tr.q[j + 1], 1.0)
            if hit is not None:
                s, reason = hit
                return float(tr.loads[j] + s * (tr.loads[j + 1] - tr.loads[j])), reason, j, s
        return None

    rng = np.random.default_rng(7)
    th = gw.Thresholds(slip=1e-3, rotation=0.02, joint=0.05, scale=2.0, length_scale=0.05)
    found = grazed = 0
    for _ in range(300):
        k = int(rng.integers(2, 40))
        x = np.cumsum(rng.normal(scale=2e-5, size=(k, 6)), axis=0)
        q = np.cumsum(rng.normal(scale=1e-3, size=(k, 3)), axis=0)
        j = int(rng.integers(1, k))  # one breakpoint on a threshold, to rounding
        v = x[j, :3] - x[0, :3]
        x[j, :3] = x[0, :3] + v * (th.slip / th.scale) / np.linalg.norm(v) * (
            1.0 + rng.choice([-1e-12, 0.0, 1e-12])
        )
        tr = gw.Trace(np.cumsum(rng.uniform(0.1, 1.0, size=k)), x, q)
        got = gw.first_crossing(tr, th, x[0], q[0], 0, None, 0)
        want = brute(tr, th, x[0], q[0])
        assert (got is None) == (want is None)
        if got is not None:
            assert (got.load, got.reason, got.index, got.step) == want
            found += 1
            grazed += got.index == j - 1 and got.step > 1.0 - 1e-9
    assert found > 50 and grazed > 10  # the comparison is not vacuous: crossings, at a grazing end too
