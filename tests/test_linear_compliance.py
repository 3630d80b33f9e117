"""Linear-compliance baseline against a hand calculation on the pinch."""

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples

A, L, MU, TAU = 0.05, 0.1, 0.5, 1.0


def test_pinch_push_hand_calculation(pinch):
    """Push F along +x. Contacts are springs in series along x with k each: the object moves
    F / 2k, the right contact gains F/2 and the left loses F/2 (no tangential share)."""
    c0 = pg.passive_response(pinch, TAU, np.zeros(3)).contact_forces
    F = 30.0
    r = pg.linear_compliance(pinch, [F, 0, 0], c0)
    np.testing.assert_allclose(r.particular[:, 0], [-F / 2, F / 2], atol=1e-9)
    np.testing.assert_allclose(r.contact_forces[:, 0], [TAU / L - F / 2, TAU / L + F / 2], atol=1e-9)
    np.testing.assert_allclose(r.object_displacement[0], F / 2, atol=1e-9)  # k = 1
    assert r.push_violations == ("left",) and not r.valid
    # the passive analysis resists the same push without bound
    assert pg.max_resistible_wrench(pinch, TAU, "fx", method="prp").unbounded


def test_pinch_lift_hand_calculation(pinch):
    """Lift F along +y: tangential springs k_t = mu k share it equally (F/2 each, pointing
    down in the world); the normal forces are unchanged; friction fails above 2 mu tau0/L."""
    c0 = pg.passive_response(pinch, TAU, np.zeros(3)).contact_forces
    for F, ok in ((8.0, True), (12.0, False)):
        r = pg.linear_compliance(pinch, [0, F, 0], c0)
        np.testing.assert_allclose(r.contact_forces_world[:, 1], [-F / 2, -F / 2], atol=1e-9)
        np.testing.assert_allclose(r.contact_forces[:, 0], [TAU / L] * 2, atol=1e-9)
        np.testing.assert_allclose(r.friction_ratio, [F / 2 / (MU * TAU / L)] * 2, atol=1e-9)
        assert r.valid == ok
        assert r.object_displacement[1] == pytest.approx(F / (2 * MU), rel=1e-9)  # k_t = mu k


def test_palm_push_linear_vs_passive():
    """Seed Fig. 1 in miniature: pushing towards the palm, linear springs load the finger
    contacts tangentially beyond friction, while the passive analysis finds the push resisted
    with the palm taking the rest and no extra internal force."""
    m = examples.palm_pinch(a=A, L=L, mu=MU, mu_palm=MU)
    c0 = pg.passive_response(m, TAU, np.zeros(3)).contact_forces
    F = 60.0
    lin = pg.linear_compliance(m, [0, -F, 0], c0)
    # hand calculation: y-springs in parallel: fingers k_t = mu k each, palm k -> shares F
    share = np.array([MU, MU, 1.0]) / (2 * MU + 1.0) * F
    np.testing.assert_allclose(np.abs(lin.particular[:, 1][:2]), share[:2], atol=1e-9)
    np.testing.assert_allclose(lin.particular[2, 0], share[2], atol=1e-9)
    assert set(lin.friction_violations) == {"left", "right"}
    passive = pg.passive_response(m, TAU, [0, -F, 0])
    assert passive.resistible
    np.testing.assert_allclose(passive.normal_forces[:2], [TAU / L] * 2, atol=1e-6)


def test_baseline_input_errors(pinch):
    with pytest.raises(pg.InvalidInputError, match="internal_forces"):
        pg.linear_compliance(pinch, [1, 0, 0], np.zeros((3, 3)))
    with pytest.raises(pg.InvalidInputError, match="wrench"):
        pg.linear_compliance(pinch, [np.inf, 0, 0])
