"""Closed-form planar grasps: the pinch and the other cases derived in docs/analytic_cases.md.

Forces at a given load must match closed form to 1e-6; bisection magnitudes to the bisection
resolution for PRP, and within ``eps + resolution`` (the iterative scheme accepts a net wrench
below ``eps``) for the iterative scheme.
"""

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples

A, L, MU, TAU = 0.05, 0.1, 0.5, 1.0
UPPER, STEPS = 100.0, 16
RES = UPPER / 2**STEPS
EPS = 1e-3
METHODS = ["prp", "iterative"]


def tol(method):
    return RES if method == "prp" else RES + 2 * EPS


def fmax_pinch(theta):
    s = abs(np.sin(theta))
    return np.inf if s < 1e-12 else 2 * MU * TAU / (L * s)


def check_max(m, command, direction, method, expected):
    r = pg.max_resistible_wrench(m, command, direction, method=method, upper=UPPER, steps=STEPS)
    if np.isinf(expected):
        assert r.unbounded and np.isinf(r.magnitude)
    else:
        assert not r.unbounded
        if method == "prp":
            assert expected - RES <= r.magnitude <= expected + 1e-9
        else:
            assert abs(r.magnitude - expected) <= tol(method)
    assert r.monotone
    return r


# ----------------------------------------------------------------------------- pinch
@pytest.mark.parametrize("method", METHODS)
def test_pinch_preload_forces(pinch, method):
    r = pg.passive_response(pinch, TAU, np.zeros(3), method=method)
    assert r.resistible
    np.testing.assert_allclose(r.normal_forces, [TAU / L, TAU / L], atol=1e-6)
    np.testing.assert_allclose(r.contact_forces[:, 1:], 0.0, atol=1e-6)
    np.testing.assert_allclose(r.joint_torques, [TAU, TAU], atol=1e-6)
    assert r.audit.equilibrium < 1e-6 and r.audit.complementarity < 1e-6 and r.audit.polished


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("theta", [0.3, 1.2, 2.0, -0.7])
def test_pinch_forces_at_given_load(pinch, method, theta):
    F = 0.9 * fmax_pinch(theta)
    w = F * np.array([np.cos(theta), np.sin(theta), 0.0])
    r = pg.passive_response(pinch, TAU, w, method=method)
    assert r.resistible and r.status == "resisted"
    # the pushed finger holds and takes the x load, the other keeps c_n = tau0/L
    fx = F * np.cos(theta)
    cn = np.array([TAU / L + max(-fx, 0.0), TAU / L + max(fx, 0.0)])
    np.testing.assert_allclose(r.normal_forces, cn, atol=1e-6)
    # both contacts carry half the tangential load (world y)
    np.testing.assert_allclose(r.contact_forces_world[:, 1], [-w[1] / 2, -w[1] / 2], atol=1e-6)
    held = "right" if fx > 0 else "left"
    assert r.actuator_modes[r.actuator_names.index(held)] == "holding"
    np.testing.assert_allclose(r.net_wrench, 0.0, atol=EPS)


@pytest.mark.parametrize("method", METHODS)
def test_pinch_load_above_limit_is_not_resisted(pinch, method):
    r = pg.passive_response(pinch, TAU, [0, 1.01 * fmax_pinch(np.pi / 2), 0], method=method)
    assert not r.resistible and r.status == "not_resisted"


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("theta", [np.pi / 2, -np.pi / 2, np.pi / 4, 3 * np.pi / 4, 0.0, np.pi])
def test_pinch_max_wrench(pinch, method, theta):
    check_max(pinch, TAU, [np.cos(theta), np.sin(theta), 0], method, fmax_pinch(theta))


# ------------------------------------------------------------------- differential
@pytest.mark.parametrize("method", METHODS)
def test_differential_pinch(method):
    m = examples.pinch(a=A, L=L, mu=MU, differential=True)
    r0 = pg.passive_response(m, TAU, np.zeros(3), method=method)
    np.testing.assert_allclose(r0.normal_forces, [TAU / L, TAU / L], atol=1e-6)
    check_max(m, TAU, "fy", method, 2 * MU * TAU / L)
    check_max(m, TAU, "-fy", method, 2 * MU * TAU / L)
    # any x component: the fingers shift together, F_max = 0 (iterative: below eps)
    for d in ([1, 0, 0], [-1, 1, 0]):
        r = check_max(m, TAU, d, method, 0.0)
        # iterative: a net wrench below eps + eps_rel * F (F ~ the 10 N preload forces) counts as
        # resisted, and along (-1, 1) that admits |w| up to ~sqrt(2) times the tolerance
        assert r.magnitude <= (0.0 if method == "prp" else 2 * EPS)


# -------------------------------------------------------------------------- wedge
def test_wedge_prp_artefact_and_iterative_finite():
    """Diagonally offset contacts: a clockwise rotation squeezes both locked fingers.

    Alg. 1 wedges the object (rotates it, although the load is a pure force along y) and
    resists any load; the iterative scheme gives F_max = 2 (tau0/L)(mu - h/a).
    """
    h = 0.01
    m = examples.pinch(a=A, L=L, mu=MU, h=h)
    expected = 2 * TAU / L * (MU - h / A)
    for d in ("fy", "-fy"):
        prp = pg.max_resistible_wrench(m, TAU, d, method="prp", upper=UPPER, steps=STEPS)
        assert prp.unbounded
        x = prp.response.object_displacement
        assert x[5] < 0 and abs(x[5]) * h > 10 * abs(x[1])  # rotation, not motion along the load
        assert set(prp.response.actuator_modes) == {"holding"}
        assert not prp.physically_audited and not prp.response.audit.energy.energy_ok  # flagged
        it = check_max(m, TAU, d, "iterative", expected)
        assert not it.unbounded
    # below the limit both methods agree on the forces' normal part
    r = pg.passive_response(m, TAU, [0, 0.9 * expected, 0], method="iterative")
    np.testing.assert_allclose(r.normal_forces, [TAU / L, TAU / L], atol=1e-6)


# --------------------------------------------------------------------------- palm
@pytest.mark.parametrize("method", METHODS)
def test_palm_contact(method):
    m = examples.palm_pinch(a=A, L=L, mu=MU)
    check_max(m, TAU, "-fy", method, np.inf)  # pushed onto the palm: passive, unbounded
    check_max(m, TAU, "fy", method, 2 * MU * TAU / L)  # away from the palm: friction-limited
    check_max(m, TAU, "fx", method, np.inf)


def test_palm_contact_forces_prp():
    """Minimum spring energy: finger friction takes what it can, the palm the rest."""
    m = examples.palm_pinch(a=A, L=L, mu=MU)
    F = 30.0
    r = pg.passive_response(m, TAU, [0, -F, 0], method="prp")
    np.testing.assert_allclose(r.normal_forces, [TAU / L, TAU / L, F - 2 * MU * TAU / L], atol=1e-6)
    np.testing.assert_allclose(r.contact_forces_world[:2, 1], [MU * TAU / L] * 2, atol=1e-6)
    assert r.contact_modes == ("touching", "touching", "touching")
    r = pg.passive_response(m, TAU, [0, -5.0, 0], method="prp")  # friction alone suffices
    np.testing.assert_allclose(r.normal_forces[2], 0.0, atol=1e-6)


# ---------------------------------------------------------------- coupled finger
@pytest.mark.parametrize("method", METHODS)
def test_coupled_two_link_finger(method):
    L1, L2, ratio = 0.06, 0.04, 1 / 3
    m = examples.coupled_finger(a=A, L1=L1, L2=L2, ratio=ratio, mu=MU)
    lever = L1 + L2 + ratio * L2
    cn = TAU / lever
    r = pg.passive_response(m, TAU, np.zeros(3), method=method)
    np.testing.assert_allclose(r.normal_forces, [cn, cn], atol=1e-6)
    np.testing.assert_allclose(r.joint_torques, [(L1 + L2) * cn, L2 * cn], atol=1e-6)
    # coupling reaction carries the distal torque; the actuator sees the full command
    np.testing.assert_allclose(np.abs(r.coupling_forces), [L2 * cn], atol=1e-6)
    np.testing.assert_allclose(r.actuator_forces, [TAU], atol=1e-6)
    # distal follows proximal
    q = r.joint_displacements
    assert q[1] == pytest.approx(ratio * q[0], abs=1e-9)
    check_max(m, TAU, "fy", method, 2 * MU * cn)
    check_max(m, TAU, "fx", method, np.inf)
    check_max(m, TAU, "-fx", method, np.inf)


# ------------------------------------------------------------------ backdrivable
def test_backdrivable_fingers_cannot_hold_a_push():
    """Backdrivable joints keep f = f_c: a push along x (unbounded with non-backdrivable
    fingers) is not resisted; along y the pinch limit is unchanged."""
    m = examples.pinch(a=A, L=L, mu=MU, kind="backdrivable")
    for method in METHODS:
        check_max(m, TAU, "fx", method, 0.0)
        check_max(m, TAU, "fy", method, 2 * MU * TAU / L)


def test_profile_pinch_shape_and_normalisation(pinch):
    p = pg.resistance_profile(
        pinch, TAU, ("fx", "fy"), n=8, method="prp", upper=UPPER, steps=STEPS, normalize=True
    )
    assert p.normalized_by == pytest.approx(2 * MU * TAU / L, abs=RES)
    expected = np.array([fmax_pinch(t) for t in p.angles]) / (2 * MU * TAU / L)
    assert np.array_equal(p.unbounded, np.isinf(expected))
    fin = ~p.unbounded
    np.testing.assert_allclose(p.magnitudes[fin], expected[fin], atol=2 * RES / p.normalized_by)
    np.testing.assert_allclose(p.directions[2], [0, 1, 0, 0, 0, 0], atol=1e-15)
