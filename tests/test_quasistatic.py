"""The quasi-static loading path (pinograsp/analysis/quasistatic): closed forms, invariants,
events, audits and determinism."""

import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples

MU, TAU, L = 0.5, 1.0, 0.1


def _dir(deg: float) -> list[float]:
    t = np.radians(deg)
    return [np.cos(t), np.sin(t), 0.0, 0.0, 0.0, 0.0]


@pytest.fixture(scope="module")
def case1():
    s = pg.load_scene("case1")
    return s.model, s.preload(None)


# ------------------------------------------------------------------ closed forms
@pytest.mark.parametrize("deg", range(0, 360, 15))
def test_pinch_closed_form_24_directions(deg):
    m = examples.pinch()
    r = pg.quasistatic_max_wrench(m, TAU, _dir(deg))
    s = abs(np.sin(np.radians(deg)))
    if s < 1e-9:
        assert r.status == "unbounded" and r.unbounded and np.isinf(r.magnitude)
    else:
        assert r.status == "finite"
        assert r.magnitude == pytest.approx(2 * MU * TAU / (L * s), rel=1e-9)
    assert r.method == "quasistatic" and r.search == "path"
    assert r.response is not None and r.response.resistible and r.response.audit.ok


def test_pinch_3d_closed_form():
    m = examples.pinch(planar=False, edges=4)  # pyramid edges along ±t: the band is exact
    for deg in (30, 90, 135):
        r = pg.quasistatic_max_wrench(m, TAU, _dir(deg))
        assert r.magnitude == pytest.approx(2 * MU * TAU / (L * abs(np.sin(np.radians(deg)))), rel=1e-9)


def test_differential_pinch():
    m = examples.pinch(differential=True)
    for d in ("fy", "-fy"):
        r = pg.quasistatic_max_wrench(m, TAU, d)
        assert r.status == "finite" and r.magnitude == pytest.approx(2 * MU * TAU / L, rel=1e-9)
    for deg in (0, 10, 45, 100, 180, 300):
        r = pg.quasistatic_max_wrench(m, TAU, _dir(deg))
        assert r.status == "below_resolution" and r.magnitude == 0.0


def test_wedge():
    m = examples.wedge()
    up = pg.quasistatic_max_wrench(m, TAU, "fy")
    # the energetic and iterative methods give 2.556 N (free friction); the tangential springs
    # load both contacts alike here, so the path reaches the same limit
    assert up.status == "finite" and up.magnitude == pytest.approx(2.5565233413457, rel=1e-9)
    down = pg.quasistatic_max_wrench(m, TAU, "-fy")
    assert down.status == "unbounded"


def test_case1_named_directions(case1):
    m, fc = case1
    assert pg.quasistatic_max_wrench(m, fc, "fy").magnitude == pytest.approx(4.3354335167, rel=1e-9)
    for d in ("-fy", "fx", "-fx"):
        assert pg.quasistatic_max_wrench(m, fc, d).status == "unbounded"


# ------------------------------------------------------------------ invariants
def _transformed(m, rot=None, shift=None, unit=1.0, cperm=None, jperm=None):
    """``m`` under a world rotation/reflection ``rot``, a translation, a change of length unit
    (lengths x ``unit``) and a reordering of contacts and joints (3D models)."""
    rot = np.eye(3) if rot is None else rot
    shift = np.zeros(3) if shift is None else shift
    det = float(np.linalg.det(rot))
    nc, d = m.nc, m.d
    Q = np.ones(d)
    if det < 0:
        Q[2] = -1.0  # keep right-handed contact frames: t2 flips
    Qfull = np.tile(Q, nc)
    P = np.zeros((6, 6))
    P[:3, :3] = rot
    P[3:, 3:] = det * rot
    G = P @ np.asarray(m.G) * Qfull[None, :]
    G[3:] *= unit
    J = Qfull[:, None] * np.asarray(m.J) * unit
    D = Qfull[:, None] * np.asarray(m.D)
    frames = np.einsum("ab,ibc->iac", rot, np.asarray(m.frames)) * np.array([1.0, 1.0, Q[2]])[None, None, :]
    cperm = np.arange(nc) if cperm is None else np.asarray(cperm)
    jperm = np.arange(m.nq) if jperm is None else np.asarray(jperm)
    rows = np.concatenate([np.arange(i * d, (i + 1) * d) for i in cperm])
    bc = np.asarray(m.beta_contact)
    cols = np.concatenate([np.flatnonzero(bc == i) for i in cperm])
    newbc = np.concatenate([np.full(np.sum(bc == i), k) for k, i in enumerate(cperm)])
    return replace(
        m,
        G=G[:, rows],
        J=J[rows][:, jperm],
        D=D[rows][:, cols],
        beta_contact=newbc,
        k=np.asarray(m.k)[cperm] / unit,
        mu=np.asarray(m.mu)[cperm],
        R=np.asarray(m.R)[jperm] * (unit if False else 1.0),
        C=np.asarray(m.C)[:, jperm],
        points=((np.asarray(m.points) @ rot.T) * unit + shift)[cperm],
        frames=frames[cperm],
        reference_point=(rot @ np.asarray(m.reference_point)) * unit + shift,
        length_scale=m.length_scale * unit,
        contact_names=tuple(m.contact_names[i] for i in cperm),
        joint_names=tuple(m.joint_names[j] for j in jperm),
    ), P


def test_mirror_pairs_of_case1_equal(case1):
    """Case 1 mirrored about the YZ plane, with contacts and joints in another order: every
    direction's mirror gives the same limit to 1e-12 and the same status."""
    m, fc = case1
    mirror = np.diag([-1.0, 1.0, 1.0])
    mm, P = _transformed(m, mirror, cperm=[2, 3, 0, 1], jperm=[2, 3, 0, 1])
    for deg in range(0, 360, 30):
        d = np.array(_dir(deg))
        a = pg.quasistatic_max_wrench(m, fc, d)
        b = pg.quasistatic_max_wrench(mm, fc, P @ d)
        assert a.status == b.status
        if a.status == "finite":
            assert b.magnitude == pytest.approx(a.magnitude, rel=1e-12)
    # the vertices case 1's contacts slide on are ties, broken by the least-norm rule
    assert pg.loading_path(m, fc, "fy").ties > 0


def test_rigid_motion_invariance():
    m = examples.random_grasp(1, 1, contacts_per_finger=2)
    c, s = np.cos(0.7), np.sin(0.7)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ np.array(
        [[1.0, 0.0, 0.0], [0.0, np.cos(0.3), -np.sin(0.3)], [0.0, np.sin(0.3), np.cos(0.3)]]
    )
    mr, P = _transformed(m, rot, shift=np.array([0.3, -0.2, 0.5]))
    rng = np.random.default_rng(5)
    for _ in range(4):
        d = rng.normal(size=6)
        d /= np.linalg.norm(d)
        a = pg.quasistatic_max_wrench(m, 1.0, d)
        b = pg.quasistatic_max_wrench(mr, 1.0, P @ d)
        assert a.status == b.status
        assert b.magnitude == pytest.approx(a.magnitude, rel=1e-9)


def test_unit_change_invariance():
    """Metres to millimetres: forces unchanged, torques x 1000 (commands in N·mm)."""
    m = examples.random_grasp(2, 1, contacts_per_finger=2)
    mm, _ = _transformed(m, unit=1000.0)
    for d, scale in (([0.3, -0.5, 0.8, 0, 0, 0], 1.0), ([0, 0, 0, 0.2, 0.9, -0.4], 1000.0)):
        a = pg.quasistatic_max_wrench(m, 1.0, d)
        b = pg.quasistatic_max_wrench(mm, 1000.0, d)
        assert a.status == b.status
        if a.status == "finite":
            assert b.magnitude == pytest.approx(a.magnitude * scale, rel=1e-9)


def test_stiffness_scaling(case1):
    m, fc = case1
    stiff = replace(m, k=np.asarray(m.k) * 250.0)
    for d in ("fy", "fz", _dir(60)):
        a = pg.quasistatic_max_wrench(m, fc, d)
        b = pg.quasistatic_max_wrench(stiff, fc, d)
        assert a.status == b.status and b.magnitude == pytest.approx(a.magnitude, rel=1e-10)


# ------------------------------------------------------------------ the path record
def test_events_recorded():
    m = examples.pinch()
    lp = pg.loading_path(m, TAU, _dir(45))
    assert lp.status == "finite" and lp.limit == pytest.approx(
        2 * MU * TAU / (L * np.sin(np.pi / 4)), rel=1e-12
    )
    kinds = [(e.kind, e.name, e.before, e.after) for e in lp.events]
    assert ("contact", "left", "sticking", "sliding (face 1)") in kinds
    assert lp.events[-1].kind == "limit" and lp.events[-1].load == lp.limit
    assert lp.contact_states[0] == ("sticking", "sticking")
    assert lp.actuator_modes[0] == ("moving", "holding")  # pushed towards the right finger
    # one segment: stiffness along the direction from the breakpoints
    s = lp.displacement_along
    assert lp.stiffness[0] == pytest.approx((lp.loads[1] - lp.loads[0]) / (s[1] - s[0]), rel=1e-12)


def test_unbounded_has_a_ray():
    """Within the load of interest (geometry followed up to twice ``upper``) the pinch along +x
    ends in a ray: held to any load, the ray's evidence at infinity."""
    mw = pg.max_resistible_wrench(examples.pinch(), TAU, "fx")
    assert mw.status == "unbounded" and np.isinf(mw.magnitude) and mw.evidence[-1] == (np.inf, True)
    assert mw.giveway.reason == "held" and mw.note == ""  # no free motion left: nothing to warn of


def test_a_ray_that_buckles_ends_with_a_limit():
    """The pinch along +x is a ray: the pushed right contact carries the load, the left keeps
    its preload (10 N). The pair squeezes the object along its chord, and turning about z has
    only the tangential springs against it, 2 k_t a^2, while the squeeze's geometric stiffness
    takes a (c_R + c_L) = a (20 + lambda) from it: the ray buckles at lambda = 2 k_t a - 20 =
    99980 N (k_t = 1e6 N/m, a = 50 mm), far beyond any load of interest."""
    lp = pg.loading_path(examples.pinch(), TAU, "fx")
    assert lp.status == "finite" and lp.limit == pytest.approx(2 * 1e6 * 0.05 - 20.0, rel=1e-7)
    assert lp.events[-1].kind == "limit" and "buckles" in lp.events[-1].cause
    st = lp.state_at(1e4)
    assert st["contact_forces"][1, 0] == pytest.approx(10.0 + 1e4, rel=1e-12)
    assert st["contact_forces"][0, 0] == pytest.approx(10.0, rel=1e-12)


@pytest.mark.parametrize("name", ["pinch", "wedge", "case1", "random8"])
def test_audit_at_every_breakpoint(name, case1):
    if name == "case1":
        m, fc = case1
        dirs = ["fy", "fz", _dir(30), [0.2, 0.4, -0.3, 0.01, 0.02, -0.005]]
    elif name == "random8":
        m, fc = examples.random_grasp(0, 2, contacts_per_finger=2), 1.0
        rng = np.random.default_rng(0)
        dirs = [rng.normal(size=6) for _ in range(3)]
    else:
        m, fc = getattr(examples, name)(), 1.0
        dirs = [_dir(a) for a in (20, 90, 200)]
    for d in dirs:
        lp = pg.loading_path(m, fc, d)
        force = max(float(np.abs(lp.contact_forces).max()), 1.0)
        assert lp.audit["equilibrium"].max() <= 1e-9 * force
        assert lp.audit["hand"].max() <= 1e-9 * force
        assert lp.audit["friction"].max() <= 1e-9 * force
        # energy: load and actuator work = elastic energy change + friction dissipation
        work = np.abs(lp.loads[1:]).max(initial=1.0) * np.abs(lp.object_displacements).max() + 1.0
        assert np.abs(lp.audit["energy"]).max(initial=0.0) <= 1e-8 * work


def test_response_on_the_path():
    m = examples.pinch()
    r = pg.quasistatic_response(m, TAU, [0.0, 5.0, 0.0])
    assert r.resistible and r.status == "resisted"
    np.testing.assert_allclose(r.contact_forces[:, 0], [10.0, 10.0], rtol=1e-12)
    np.testing.assert_allclose(r.contact_forces[:, 1], [-2.5, 2.5], rtol=1e-12)
    assert r.contact_states == ("sticking", "sticking")
    assert r.audit.ok
    assert not pg.quasistatic_response(m, TAU, [0.0, 10.5, 0.0]).resistible
    assert pg.quasistatic_response(m, TAU, [1e5, 0.0, 0.0]).resistible
    zero = pg.quasistatic_response(m, TAU, np.zeros(3))
    np.testing.assert_allclose(zero.contact_forces[:, 0], [10.0, 10.0], rtol=1e-12)


def test_load_at_displacement_scales_with_stiffness():
    lp = pg.loading_path(examples.pinch(), TAU, _dir(60))
    # sharp give-way: the path's limit when the threshold is not reached before it
    assert lp.load_at_displacement(1.0, stiffness=1e6) == lp.limit
    # soft springs: the elastic displacement reaches the threshold first, linearly in the load
    s1 = lp.load_at_displacement(1e-3, stiffness=1e3)
    s2 = lp.load_at_displacement(2e-3, stiffness=1e3)
    assert s1 < lp.limit and s2 == pytest.approx(2 * s1, rel=1e-12)


def test_snap_past_a_softening_limit():
    """Case 2 pushed along +Z: a softening limit at 14.7 N; past it the path (displacement
    control) lands again and stiffens, so the load at 1 mm of motion (the simulation's
    give-way threshold; the simulation gives way gradually at 26.3 N) is far above λ*."""
    s = pg.load_scene("case2")
    lp = pg.loading_path(s.model, s.preload(None), "fz")
    assert lp.status == "finite" and lp.limit == pytest.approx(14.7155, rel=1e-4)
    c = lp.continuation
    assert c is not None and c.snaps and c.loads[c.snaps[0][1]] == pytest.approx(lp.limit, rel=1e-12)
    assert min(c.loads[: c.snaps[0][1]]) < lp.limit  # the load falls past the limit
    # the object turns as it gives way: with its geometry followed, 26.34 N (26.56 N linear);
    # the simulation gives way gradually at 26.3 N
    assert lp.load_at_displacement(1e-3) == pytest.approx(26.3, rel=3e-3)
    # the default answer is that give-way (the scene's upper, 50 N: the simulation's 1 mm
    # threshold), with the first limit beside it
    mw = pg.quasistatic_max_wrench(s.model, s.preload(None), "fz", upper=s.analysis.upper)
    assert mw.magnitude == pytest.approx(lp.load_at_displacement(1e-3), rel=1e-12)
    assert mw.giveway.first_limit == lp.limit and mw.giveway.reason in ("translation", "rotation")
    assert len(mw.giveway.snaps) >= 1 and mw.giveway.snaps[0][0] == pytest.approx(lp.limit, rel=1e-12)
    gw = mw.giveway  # at the threshold it reached: 1 mm, or 1 mm over the length scale
    assert max(gw.translation / gw.slip, gw.turned / gw.rotation) == pytest.approx(1.0, rel=1e-9)
    assert gw.slip == 1e-3 and gw.rotation == pytest.approx(1e-3 / s.model.length_scale, rel=1e-12)
    first = pg.quasistatic_max_wrench(s.model, s.preload(None), "fz", pg.Settings(limit="first"))
    assert first.magnitude == lp.limit and first.giveway is None


def test_to_dict_and_rows():
    import json

    lp = pg.loading_path(examples.pinch(), TAU, _dir(45))
    data = lp.to_dict()
    json.dumps(data)
    assert data["status"] == "finite" and data["method"] == "quasistatic"
    assert len(lp.rows()) == len(lp.loads)
    assert lp.rows()[-1]["load"] == lp.limit


def test_tangential_ratio_setting():
    m = examples.pinch()
    # the pinch's limit does not depend on the tangential stiffness
    for ratio in (0.1, 10.0):
        r = pg.quasistatic_max_wrench(m, TAU, "fy", pg.Settings(tangential_ratio=ratio))
        assert r.magnitude == pytest.approx(10.0, rel=1e-9)
    with pytest.raises(pg.InvalidInputError, match="tangential_ratio"):
        pg.Settings(tangential_ratio=0.0).validated()


def test_bad_inputs():
    m = examples.pinch()
    with pytest.raises(pg.InvalidInputError, match="variant"):
        pg.loading_path(m, TAU, "fy", variant="loose")
    with pytest.raises(pg.InvalidInputError, match="cone_tolerance"):
        pg.loading_path(m, TAU, "fy", settings=pg.Settings(cone_tolerance=0.1))
    with pytest.raises(pg.InvalidInputError):
        pg.loading_path(m, TAU, [np.nan, 0, 0])


def test_segment_limit_is_reported(case1):
    m, fc = case1
    lp = pg.loading_path(m, fc, "fy", max_segments=1)
    assert lp.status == "segment_limit" and lp.segments == 1 and lp.limit == lp.loads[-1] > 0


def test_cli_path(capsys, tmp_path):
    from support.clirun import run, run_json

    data = run_json(capsys, "path", "pinch", "-d", "fy")
    assert data["status"] == "finite" and data["limit"] == pytest.approx(10.0, rel=1e-9)
    assert data["events"][-1]["kind"] == "limit"
    png, csv = tmp_path / "p.png", tmp_path / "p.csv"
    rc, out, _ = run(capsys, "path", "pinch", "-d", "fx", "--png", str(png), "--csv", str(csv))
    assert rc == 0 and "unbounded" in out and png.stat().st_size > 0
    assert csv.read_text().splitlines()[0].startswith("breakpoint,load,displacement_along")
    rc, _, err = run(capsys, "path", "pinch", "-d", "fy", "--tangential-ratio", "0")
    assert rc != 0 and "--tangential-ratio" in err


def test_plot_loading_path():
    lp = pg.loading_path(examples.pinch(), TAU, _dir(45))
    ax = pg.plot_loading_path(lp)
    x, y = (
        ax.lines[0].get_data() if ax.lines[0].get_gid() != "pinograsp-unbounded" else ax.lines[1].get_data()
    )
    assert max(y) == pytest.approx(lp.limit, rel=1e-12)
    with pytest.raises(pg.InvalidInputError):
        pg.plot_loading_path("not a path")


SCRIPT = """
import numpy as np, pinograsp as pg
m = pg.examples.random_grasp(0, 2, contacts_per_finger=2)
rng = np.random.default_rng(1)
for _ in range(3):
    lp = pg.loading_path(m, 1.0, rng.normal(size=6))
    print(lp.status, float(lp.limit).hex(), float(np.abs(lp.contact_forces).sum()).hex(), len(lp.loads))
"""


def test_bit_identical_in_fresh_processes():
    runs = [
        subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, check=True).stdout
        for _ in range(2)
    ]
    assert runs[0] == runs[1] and runs[0].count("\n") == 3


# ------------------------------------------------------------------ case 3 mirror pair (validation bug 1)
@pytest.fixture(scope="module")
def case3():
    s = pg.load_scene("case3")
    assert s.analysis.plane == ("fx", "fy")
    return s.model, s.model.command_vector(s.preload(None))


@pytest.mark.parametrize("pair", [(255, 285), (240, 300), (105, 75)])
def test_case3_mirror_pairs_agree(case3, pair):
    """Case 3 is mirror-symmetric about the YZ plane. At the preload its proximal contacts touch
    with zero force and the distal tendon is at its command: pushed with any X component, the
    linearised grasp is a mechanism (object sliding on a zero-force proximal contact, the
    distal tendon paying out at constant force): d(lambda)/ds is 1e-10 to 1e-9 k, rounding of a
    degenerate rate problem. Before the fix 255° gave 0 and 285° accepted 1.3e-9 k as a
    continuation (every rate scaled by about 1e9: object displacement 2e11, friction residual 0.03 N) and
    reported 29.81 N. The model's answer is lambda* = 0 for both; the simulation gives 26.43 N at
    255°/285° (its finite motion engages the proximal contacts, second order) and ~0.02 N at
    240°/300°, which the path matches."""
    m, fc = case3
    a, b = (pg.quasistatic_max_wrench(m, fc, _dir(deg)) for deg in pair)
    assert a.status == b.status == "below_resolution"
    assert a.magnitude == b.magnitude == 0.0
    assert a.magnitude == pytest.approx(b.magnitude, rel=1e-9, abs=0.0)


def test_case3_path_failing_its_audit_is_no_verdict(case3, monkeypatch):
    """With the former mechanism bar (1e-9 k) 285° follows a broken path (its audit fails at
    breakpoint 1): it must stop as ``no_solution`` (reason ``audit``), never ``finite``."""
    from pinograsp.analysis.quasistatic import path as qpath

    m, fc = case3
    monkeypatch.setattr(qpath, "LIMIT_RTOL", 1e-9)
    # a broken segment's huge rates would turn the object past a geometry step at once and be
    # cut there: without geometry updates, the broken path must fail its audit
    monkeypatch.setattr(qpath, "step_to_update", lambda *a: float("inf"))
    lp = pg.loading_path(m, fc, _dir(285), continuation=False)
    assert lp.status == "no_solution" and lp.stop_reason == "audit"
    assert lp.limit == 0.0 and lp.audit["friction"].max() > 1e-3
    r = pg.quasistatic_max_wrench(m, fc, _dir(285), path=lp)
    assert r.status == "no_solution"
    # the answer says the audit cut it short, and how far the path went (the SolverError quotes it)
    assert r.note.startswith(f"the path went on to {lp.loads[-1]:.6g} but its states past 0 fail")
    with pytest.raises(pg.SolverError, match="fail the equilibrium audit"):
        pg.max_resistible_wrench(m, fc, _dir(285))


def test_case2_minus_x_limit_is_a_tiny_snap():
    """Case 2 along −X (validation bug 2): λ* = 12.49 N is a genuine softening limit (no
    load-controlled continuation exists: the 4-item LCP has no solution in any of its 16
    bases), but the snap is tiny — the load falls 0.14 % and lands once bh_finger_12_link
    touches — and the landed branch holds: 1 mm of motion at 71.6 N, where the simulation
    holds to 50 N (docs/methods.md, "Past a softening limit")."""
    s = pg.load_scene("case2")
    lp = pg.loading_path(s.model, s.preload(None), "-fx")
    assert lp.status == "finite" and lp.limit == pytest.approx(12.4902, rel=1e-4)
    c = lp.continuation
    assert c is not None and len(c.snaps) >= 2
    i, j = c.snaps[0]
    assert min(c.loads[i : j + 1]) == pytest.approx(12.4727, rel=1e-4)
    assert c.loads[c.snaps[1][0]] == pytest.approx(13.8414, rel=1e-4)
    # further snaps only at 20x the scene's upper, with the object turned 0.3-0.45 rad
    assert all(c.loads[a] > 20 * 50.0 for a, _ in c.snaps[2:])
    held = lp.load_at_displacement(1e-3)  # 71.64 N before the geometry was followed
    assert held == pytest.approx(72.18, rel=1e-3) and held > 50.0
    mw = s.max_resistible_wrench("-fx")
    assert mw.status == "unbounded" and [a for a, _ in mw.giveway.snaps] == pytest.approx(
        [12.4902, 13.8414], rel=1e-4
    )


def test_case2_finger2_preload_drifts_past_a_neutral_limit():
    """Case 2, finger-2 preload, along +X: the first limit (2.83 N) snaps, lands, and the next
    limit (8.37 N) is neutral — a mechanism along the load with zero stiffness. The grasp
    drifts there at constant load until finger 1's distal link touches, then stiffens again
    and holds up to ≈ 18.98 N without moving 1 mm, where it gives way (the simulation: 18.22 N).
    Before, the continuation stopped at the neutral limit (1 mm "at" 8.37 N)."""
    s = pg.load_scene("case2")
    lp = pg.loading_path(s.model, s.preload("finger2_only"), "fx")
    assert lp.status == "finite" and lp.limit == pytest.approx(2.8332, rel=1e-4)
    c = lp.continuation
    assert c is not None and len(c.snaps) == 2 and c.stop_reason == "mechanism"
    top, land = c.snaps[1]
    assert c.loads[top] == pytest.approx(8.3725, rel=1e-4)
    # the neutral drift keeps the load, and the object moves along +X while it drifts
    assert np.ptp(c.loads[top : land + 1]) <= 1e-9 * c.loads[top]
    assert c.object_displacements[land][0] > c.object_displacements[top][0]
    assert c.status == "finite" and c.limit == pytest.approx(18.98, rel=1e-3)
    assert c.limit == max(c.loads[land:])
    assert lp.load_at_displacement(1e-3) == c.limit


#: Case 1's resistance-set directions 80 and 294 (``pg.resistance_set(..., n=500, seed=0)``)
#: and where ``pg.simulate_max_wrench(scene, d, None, upper=50, friction="pyramid")`` gives
#: way [N] (recorded in stop 39; ~3 s each).
NEAR_DEGENERATE = (
    ((0.7528340465289645, 0.6479950370532315, -0.0864435672551503, -0.002994029863468416,
      -0.030799142524985973, -0.07009485449241477), 2.717),
    ((0.9672335829533052, -0.23434489623938368, 0.08147790357639993, -0.005981561699549111,
      0.007336895196927545, -0.05304156607004288), 12.178),
)  # fmt: skip


@pytest.mark.parametrize("direction, simulated", NEAR_DEGENERATE)
def test_a_nearly_degenerate_rate_problem_is_solved_within_rounding(direction, simulated):
    """Two adjacent pyramid faces of one contact start sliding together: the displacement-
    controlled rate LCP has a solution only within rounding (flows ~300× the problem's scale,
    a slack rate -3e-7), which Lemke's method and principal pivoting reject and the
    certificate cannot exclude. The enumeration's near solution continues the path (these
    directions stopped with a SolverError before): a limit within 10 % of the simulation."""
    s = pg.load_scene("case1")
    r = pg.max_resistible_wrench(s.model, s.command, list(direction), upper=50, settings=s.settings)
    assert r.status == "finite" and r.giveway.reason == "limit"
    assert abs(r.magnitude - simulated) <= 0.1 * simulated
