"""The energy audit (docs/accuracy.md): springs cannot store more energy than the load and the
actuators supply on the solution's own displacements. The PRP's wedging answers break it (the
seed's §VI artefact; an independent simulation gives way where the audit starts to fail); the
iterative scheme's equilibria and the analytic pinch's closed forms satisfy it."""

import warnings

import numpy as np
import pytest

import pinograsp as pg
from pinograsp.core.audit import MAX_DISPLACEMENT_RATIO, energy_check, friction_use


def _at(deg: float) -> np.ndarray:
    a = np.radians(deg)
    return np.array([np.cos(a), np.sin(a), 0.0, 0.0, 0.0, 0.0])


def test_case1_prp_wedging_is_flagged_where_the_simulation_gives_way(case1):
    """case1 along 30°: the simulation gives way at 35.7 N; the PRP calls 100 N resisted."""
    s = case1
    with pytest.warns(pg.AuditWarning, match="bh_finger_13_link") as rec:
        bad = pg.passive_response(s.model, s.command, 40.0 * _at(30), "prp")
    assert "wedging" in str(rec[0].message)
    e = bad.audit.energy
    assert bad.status == "resisted" and not bad.audit.ok and not e.energy_ok
    assert e.spring_energy > e.load_work + e.actuator_work > 0  # 780 J stored, 635 J supplied
    assert e.contacts == ("bh_finger_13_link",)
    with warnings.catch_warnings():
        warnings.simplefilter("error", pg.AuditWarning)
        for method in ("prp", "iterative"):
            good = pg.passive_response(s.model, s.command, 35.0 * _at(30), method)
            g = good.audit.energy
            assert good.audit.ok and g.energy_ok and g.displacement_ok
            assert 0 < g.spring_energy < g.load_work + g.actuator_work


def test_iterative_equilibria_pass_the_audit_everywhere(case1):
    s = case1
    with warnings.catch_warnings():
        warnings.simplefilter("error", pg.AuditWarning)
        for deg in (0, 30, 60, 90, 135, 270):
            r = pg.passive_response(s.model, s.command, 20.0 * _at(deg))
            if r.status == "resisted":
                e = r.audit.energy
                assert e.energy_ok and e.displacement_ratio < 10.0
                assert e.spring_energy <= 0.7 * (e.load_work + e.actuator_work)


def test_case3_prp_unbounded_pull_rests_on_failed_audits():
    """case3 +Y: the PRP says unbounded, the simulation gives way at 1.49 N; the max-wrench
    result lists the resisted magnitudes whose solutions fail the audit, with one warning."""
    s = pg.load_scene("case3")
    with pytest.warns(pg.AuditWarning, match="uf_proximal") as rec:
        r = s.max_resistible_wrench("fy", method="prp")  # upper 50 N
    assert len(rec) == 1 and "resisted magnitude" in str(rec[0].message)
    assert r.status == "unbounded" and not r.physically_audited
    assert r.audit_failures[0] == 50.0 and r.audit_failures[-1] == np.inf
    it = s.max_resistible_wrench("fy")
    assert it.physically_audited and it.audit_failures == ()


def test_case3_prp_mirror_directions_solve_alike():
    """330° and 345° ended in SolverError while their mirrors 210° and 195° solved."""
    s = pg.load_scene("case3")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        for deg in (330, 345):
            a = pg.max_resistible_wrench(s.model, s.command, _at(deg), "prp", steps=12)
            b = pg.max_resistible_wrench(s.model, s.command, _at(540 - deg), "prp", steps=12)
            assert a.status == b.status == "finite" and a.magnitude == b.magnitude


def test_pinch_closed_form_energy_balance(pinch):
    """Pinch (k = 1 N/m, arm 0.1 m, tau 1 N·m → 10 N preload per finger). Under f_x = 3 N the
    left contact carries 10 N and the right 13 N (the right actuator is pushed back and holds):
    E = (10² + 13²) / 2 = 134.5 J. At the equilibrium reached by the iterative scheme the left
    finger closes by 10 m + 3 m of object travel, the right by 10 m: W_act = 23 · 10 = 230 J,
    and the load works 3 N × 3 m = 9 J."""
    r = pg.passive_response(pinch, 1.0, [3.0, 0.0, 0.0])
    e = r.audit.energy
    assert e.spring_energy == pytest.approx(134.5, rel=1e-9)
    assert e.actuator_work == pytest.approx(230.0, rel=1e-9)
    assert e.load_work == pytest.approx(9.0, rel=1e-9)
    assert e.energy_ok and r.audit.ok
    # pure preload (no load): the springs hold half the actuators' work
    r = pg.passive_response(pinch, 1.0, [0.0, 0.0, 0.0])
    e = r.audit.energy
    assert e.spring_energy == pytest.approx(0.5 * e.actuator_work, rel=1e-9) and e.load_work == 0.0


def test_friction_use_only_for_touching_contacts(case1, pinch):
    r = pg.passive_response(pinch, 1.0, [0.0, 5.0, 0.0])  # 2.5 N per contact, 10 N normal
    np.testing.assert_allclose(r.friction_use, [0.5, 0.5], rtol=1e-9)
    s = case1
    r = pg.passive_response(s.model, s.command, 35.0 * _at(30))
    sep = np.array([m == "separated" for m in r.contact_modes])
    assert sep.any() and np.isnan(r.friction_use[sep]).all()
    assert (r.friction_use[~sep] <= 1.0 + 1e-9).all()
    # the kernel: separated contacts, or touching ones without normal force, use no friction
    cf = np.array([[1e-10, 3e-10, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.0]])
    use = friction_use(cf, np.array([0.5, 0.5, 0.5]), (False, True, True), 1e-8)
    assert np.isnan(use[0]) and use[1] == pytest.approx(1.0) and np.isnan(use[2])


def test_absurd_displacements_are_flagged():
    k = np.array([1.0e3, 1.0e3])
    cn = np.array([1.0, 1.0])  # compressions 1 mm
    args = dict(
        normal_forces=cn,
        stiffness=k,
        wrench=np.zeros(6),
        load_displacement=np.zeros(6),
        command=np.array([1.0]),
        actuator_displacements=np.array([1.0]),
        joint_displacements=np.zeros(1),
        length_scale=0.1,
        levers=np.array([0.1]),
        names=("a", "b"),
    )
    ok = energy_check(object_displacement=np.r_[0.002, 0, 0, 0, 0, 0], **args)
    assert ok.displacement_ratio == pytest.approx(2.0) and ok.displacement_ok
    spin = energy_check(object_displacement=np.r_[0, 0, 0, 0, 0, 2.4e14], **args)
    assert spin.displacement_ratio == pytest.approx(2.4e16) and not spin.displacement_ok
    assert spin.displacement_ratio > MAX_DISPLACEMENT_RATIO
    assert ok.energy_ok and ok.contacts == ("a", "b")
