"""Invariants: rigid motion, change of length unit, stiffness scaling, mirror symmetry,
contact permutation, and agreement of the two iterative variants on the analytic cases."""

import numpy as np
import pytest
from support.grasps import pinch_contacts

import pinograsp as pg
from pinograsp import examples

UPPER, STEPS = 100.0, 14


def rot_z(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


RES = UPPER / 2**STEPS
TAU = 1.0


def build(contacts, **kw):
    return pg.GraspModel.from_contacts(contacts, joint_names=("left", "right"), **kw)


def maxw(m, d, method, command=TAU, **kw):
    return pg.max_resistible_wrench(m, command, d, method=method, upper=UPPER, steps=STEPS, **kw)


@pytest.mark.parametrize("method", ["prp", "iterative"])
def test_rigid_motion_rotates_the_answers(method):
    """Rotating and translating the whole 3D scene (object reference point included)."""
    cs = pinch_contacts()
    base = build(cs)
    Rm = rot_z(0.7) @ np.array([[1, 0, 0], [0, np.cos(0.4), -np.sin(0.4)], [0, np.sin(0.4), np.cos(0.4)]])
    t = np.array([0.3, -0.2, 0.5])
    moved = build(
        [
            pg.Contact(
                Rm @ c.point + t,
                Rm @ c.normal,
                mu=c.mu,
                jacobian=Rm @ c.jacobian,
                tangent=Rm @ c.tangent,
                name=c.name,
            )
            for c in cs
        ],
        reference_point=t,
    )
    dirs = [[0, 1, 0, 0, 0, 0], [0, 0.8, 0.6, 0, 0, 0], [0.6, 0.8, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0]]
    for d in dirs[: 2 if method == "iterative" else 4]:
        d = np.array(d, float)
        dm = np.concatenate([Rm @ d[:3], Rm @ d[3:]])
        a, b = maxw(base, d, method), maxw(moved, dm, method)
        assert a.unbounded == b.unbounded
        if not a.unbounded:
            assert abs(a.magnitude - b.magnitude) <= RES + 1e-9
    r0 = pg.passive_response(base, TAU, [0, 3, 1, 0, 0, 0.05], method=method)
    r1 = pg.passive_response(moved, TAU, np.concatenate([Rm @ [0, 3, 1], Rm @ [0, 0, 0.05]]), method=method)
    assert r0.resistible and r1.resistible
    np.testing.assert_allclose(r1.normal_forces, r0.normal_forces, atol=1e-6)
    np.testing.assert_allclose(r1.contact_forces_world, r0.contact_forces_world @ Rm.T, atol=1e-6)


@pytest.mark.parametrize("method", ["prp", "iterative"])
def test_metres_to_millimetres(method):
    """Lengths x1000, stiffness /1000 (N/mm), torque commands and moments x1000: forces equal."""
    cs = pinch_contacts(h=0.01)
    m_m = build(cs, planar=True)
    cs_mm = [
        pg.Contact(
            1e3 * c.point,
            c.normal,
            mu=c.mu,
            jacobian=1e3 * c.jacobian,
            stiffness=c.stiffness / 1e3,
            name=c.name,
        )
        for c in cs
    ]
    m_mm = build(cs_mm, planar=True)
    for d in ("fy", [1, 1, 0]):
        a, b = maxw(m_m, d, method), maxw(m_mm, d, method, command=1e3 * TAU)
        assert a.unbounded == b.unbounded
        if not a.unbounded:
            assert abs(a.magnitude - b.magnitude) <= RES + 1e-9
    # a pure moment scales by 1000
    a = maxw(m_m, "mz", method)
    b = pg.max_resistible_wrench(m_mm, 1e3 * TAU, "mz", method=method, upper=1e3 * UPPER, steps=STEPS)
    assert a.unbounded == b.unbounded
    if not a.unbounded:
        assert abs(1e3 * a.magnitude - b.magnitude) <= 1e3 * RES + 2e-3


def test_uniform_stiffness_scaling_keeps_prp_feasibility():
    cs = pinch_contacts(h=0.01)
    for k in (1e-3, 1e3):
        scaled = build(
            [
                pg.Contact(c.point, c.normal, mu=c.mu, jacobian=c.jacobian, stiffness=k, name=c.name)
                for c in cs
            ],
            planar=True,
        )
        ref = build(cs, planar=True)
        for w in ([0, 9.0, 0], [0, 11.0, 0], [3.0, 4.0, 0.1], [0, 0, 2.0]):
            a = pg.passive_response(ref, TAU, w, method="prp")
            b = pg.passive_response(scaled, TAU, w, method="prp")
            assert a.resistible == b.resistible
            if a.resistible:  # displacements scale with 1/k, forces do not
                np.testing.assert_allclose(b.normal_forces, a.normal_forces, atol=1e-6)


@pytest.mark.parametrize("method", ["prp", "iterative"])
def test_mirror_symmetric_profile(pinch, method):
    p = pg.resistance_profile(pinch, TAU, ("fx", "fy"), n=12, method=method, upper=UPPER, steps=STEPS)
    n = len(p.angles)
    for i in range(n):
        j = (n // 2 - i) % n  # angle pi - a
        assert p.unbounded[i] == p.unbounded[j]
        if not p.unbounded[i]:
            assert abs(p.magnitudes[i] - p.magnitudes[j]) <= RES + 2e-3


def test_contact_permutation(pinch):
    cs = pinch_contacts(h=0.01)
    a = build(cs, planar=True)
    b = pg.GraspModel.from_contacts(cs[::-1], joint_names=("left", "right"), planar=True)
    for w in ([0, 5.0, 0], [2.0, -3.0, 0.05]):
        ra = pg.passive_response(a, {"left": 1.0, "right": 2.0}, w, method="iterative")
        rb = pg.passive_response(b, {"left": 1.0, "right": 2.0}, w, method="iterative")
        assert ra.resistible == rb.resistible
        np.testing.assert_allclose(ra.normal_forces, rb.normal_forces[::-1], atol=1e-6)


@pytest.mark.parametrize("variant", ["single-step", "preload-first"])
@pytest.mark.parametrize("case", ["pinch", "palm", "coupled"])
def test_iterative_variants_agree_on_analytic_cases(variant, case):
    m = {"pinch": examples.pinch(), "palm": examples.palm_pinch(), "coupled": examples.coupled_finger()}[case]
    ref = {"pinch": 10.0, "palm": 10.0, "coupled": 2 * 0.5 / (0.1 + 0.04 / 3)}[case]
    r = pg.max_resistible_wrench(m, TAU, "fy", method="iterative", upper=UPPER, steps=STEPS, variant=variant)
    assert abs(r.magnitude - ref) <= RES + 2e-3
    r = pg.max_resistible_wrench(m, TAU, "fx", method="iterative", upper=UPPER, steps=STEPS, variant=variant)
    assert r.unbounded
    # the PRP also accepts both variants
    r = pg.max_resistible_wrench(m, TAU, "fy", method="prp", upper=UPPER, steps=STEPS, variant=variant)
    assert ref - RES <= r.magnitude <= ref + 1e-9
