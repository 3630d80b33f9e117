"""Grippers of any shape: a prismatic parallel jaw with a mimic coupling (closed forms) and
example-robot-data's one-joint SO-101 (Pinocchio returns its 6x1 frame Jacobian as shape (6,))."""

import warnings

import numpy as np
import pytest

import pinograsp as pg

MU, F, R = 0.5, 20.0, 0.02  # friction, motor force [N], ball radius [m]


@pytest.fixture(scope="module")
def jaw():
    hand = pg.Hand.builtin("parallel_jaw")
    ball = pg.RigidObject.sphere(R, pose=[0.0, 0.04, 0.0])
    q = hand.close_on(ball)
    return hand, q, pg.grasp_model_from_scene(hand, q, ball, mu=MU)


def test_parallel_jaw_model(jaw):
    hand, q, m = jaw
    assert hand.joint_names == ("pj_left", "pj_right") and q[0] == pytest.approx(q[1], abs=1e-12)  # mimic
    assert m.nc == 2 and m.nq == 2 and m.na == 1 and m.C.shape == (1, 2)
    np.testing.assert_allclose(m.C @ [1.0, 1.0], 0.0)  # q_right = q_left
    # prismatic Jacobians: closing the left jaw moves its contact along +x by 1 m per m
    np.testing.assert_allclose(m.frames[0][:, 0], [1, 0, 0], atol=1e-9)
    assert m.J[0, 0] == pytest.approx(1.0) and m.J[0, 1] == 0.0


@pytest.mark.parametrize("method", ["iterative", "prp"])
def test_parallel_jaw_closed_forms(jaw, method):
    """Each jaw presses with F/2 (one motor, a rigid mimic); a load across the jaws (y, z) is
    resisted up to 2 mu F/2 = mu F = 10 N; a torque about y or z up to 2 a mu F/2 (a = contact
    distance from the centre); about the jaws' common normal (x) not at all (point contacts
    have no torsional friction); along x the non-backdrivable motor holds: unbounded."""
    _, _, m = jaw
    a = abs(m.points[0, 0])
    r = pg.passive_response(m, F, np.zeros(6), method)
    np.testing.assert_allclose(r.normal_forces, [F / 2, F / 2], rtol=1e-6)
    upper, steps = 100.0, 14
    res = upper / 2**steps
    slack = res + (2e-3 if method == "iterative" else 1e-6)  # the iterative tolerance eps'
    for d, limit in (("fy", MU * F), ("-fz", MU * F), ("mz", a * MU * F), ("-my", a * MU * F)):
        mw = pg.max_resistible_wrench(m, F, d, method, upper=upper, steps=steps)
        assert mw.status == "finite" and limit - res - 1e-6 <= mw.magnitude <= limit + slack, (
            d,
            mw.magnitude,
        )
    for d in ("fx", "-fx"):
        assert pg.max_resistible_wrench(m, F, d, method, upper=upper, steps=steps).status == "unbounded"
    assert pg.max_resistible_wrench(m, F, "mx", method, upper=upper, steps=steps).status == "below_resolution"


@pytest.fixture(scope="module")
def so101():
    hand = pg.Hand.builtin("so101")
    ball = pg.RigidObject.sphere(0.012, pose=[0.00175, 0.0, -0.08])  # touching the fixed jaw
    q = hand.close_on(ball)
    return hand, q, ball


def test_so101_one_joint_gripper(so101):
    hand, q, ball = so101
    assert hand.nq == 1 and hand.closing_signs.tolist() == [-1.0]
    m = pg.grasp_model_from_scene(hand, q, ball)
    assert m.nc == 2 and m.J.shape == (6, 1)
    assert set(m.contact_names) == {"gripper_link", "moving_jaw_so101_v1_link"}
    fixed = m.contact_names.index("gripper_link")
    assert np.all(m.J[3 * fixed : 3 * fixed + 3] == 0.0)  # the fixed jaw does not move
    # the preload: two contacts in equilibrium push equal and opposite along the line joining
    # them, and the moving jaw's force balances the motor torque (J^T c = f, 1 N·m)
    r = pg.passive_response(m, 1.0, np.zeros(6))
    c = r.contact_forces_world
    np.testing.assert_allclose(c[0], -c[1], atol=1e-9)
    line = m.points[1] - m.points[0]
    assert np.linalg.norm(np.cross(c[0], line)) <= 1e-9 * np.linalg.norm(c[0]) * np.linalg.norm(line)
    np.testing.assert_allclose(r.joint_torques, [1.0], rtol=1e-9)
    np.testing.assert_allclose(r.actuator_forces, [1.0], rtol=1e-9)
    # pushing the ball towards the palm is held by the fingers' passive reaction up to upper;
    # past it the compressed two-point grasp buckles (quasistatic.buckling), above upper
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)
        mw = pg.max_resistible_wrench(m, 1.0, "-fz", upper=50, steps=10)
    assert mw.status == "above_limit" and mw.magnitude == 50.0
    assert mw.giveway.reason == "limit" and mw.giveway.load > 50.0
    # held only while nothing drives the spin about the two contacts' chord: the answer says so
    chord = (m.points[1] - m.points[0]) / np.linalg.norm(m.points[1] - m.points[0])
    assert mw.note.startswith("held while nothing drives the free rotation about the axis (")
    axis = np.array([float(x) for x in mw.note.split("axis (")[1].split(")")[0].split(",")])
    assert abs(axis @ chord) / np.linalg.norm(axis) == pytest.approx(1.0, abs=1e-3)


def test_jacobian_of_a_one_joint_hand_matches_finite_differences(so101):
    """The contact Jacobian column equals the finite-difference motion of the contact point on
    the moving jaw when the joint closes (closing sign -1)."""
    import pinocchio as pin

    from pinograsp.robots.grasp import contact_jacobian
    from pinograsp.robots.kinematics import HandConfiguration

    hand, q, _ = so101
    jid = hand.model.getJointId("gripper")
    p = np.array([0.012, 0.0, -0.086])  # a point on the moving jaw [m]
    J = contact_jacobian(hand, q, jid, p)
    assert J.shape == (3, 1)
    local = HandConfiguration.at(hand, q).data.oMi[jid].actInv(p)
    h = 1e-6
    moved = []
    for dq in (h, -h):
        data = hand.model.createData()
        pin.forwardKinematics(hand.model, data, q + hand.closing_signs * dq)
        moved.append(data.oMi[jid].act(local))
    np.testing.assert_allclose(J[:, 0], (moved[0] - moved[1]) / (2 * h), atol=1e-8)


@pytest.fixture(scope="module")
def tilted_cylinder():
    """A 30 mm cylinder, 40 mm long, axis along y, in the parallel jaw: each jaw touches it along
    a line, modelled by its 2 end points (4 contacts, each F/4 under the preload)."""
    hand = pg.Hand.builtin("parallel_jaw")
    pose = np.eye(4)
    pose[:3, :3] = [[1, 0, 0], [0, 0, 1], [0, -1, 0]]
    pose[:3, 3] = [0.0, 0.040, 0.0]
    cyl = pg.RigidObject.cylinder(0.015, 0.040, pose=pose)
    q = hand.close_on(cyl)
    return pg.grasp_model_from_scene(hand, q, cyl, mu=MU)


def _far_ends_unload(a: float, b: float, c0: float) -> float:
    """The torque [N·m] about the jaws' plane normal to the lines (z) at which the far end
    points unload: all four stick (stiffness 4 k (a^2 + b^2)) until the far ends' friction
    ``k b theta`` reaches ``mu (c0 - k a theta)``; then the far ends slide and the stiffness is
    ``k (4 a^2 + 2 b^2 - 2 mu a b)`` until ``k a theta = c0`` (tangential springs = normal ones;
    ``a``: half the line length, ``b``: the radius, ``c0``: the preload per end point)."""
    k_theta_slide = MU * c0 / (b + MU * a)
    sticking, sliding = 4 * (a * a + b * b), 4 * a * a + 2 * b * b - 2 * MU * a * b
    return sticking * k_theta_slide + sliding * (c0 / a - k_theta_slide)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_cylinder_tilted_out_of_the_jaws_gives_way_where_its_far_ends_unload(tilted_cylinder, sign):
    """Turning the cylinder about z (its end points pressed into one jaw and pulled off the
    other) shifts the jaw forces to the near end points until the far ones unload (closed form
    0.5125 N·m). Then two diagonal points hold it: they wedge it (their normal forces grow, the
    non-backdrivable motor holds), but the spin about their chord, which passes through the
    centre, is free (point contacts carry no torque about the line joining them), and the load
    has a rounding-level part along it (the auto-closed points are 0.4 µm off z = 0): no
    equilibrium is left, the path ends there. The simulation agrees at a slow ramp (0.5125 /
    0.5117 N·m at ramp_time 0.3; at the default ramp its 0.1 s hold is too short for the free
    spin to creep and it reports 4.62 N·m: 0.60 N·m with hold_time 0.5)."""
    m = tilted_cylinder
    a = float(np.ptp(m.points[:, 1])) / 2
    b = float(np.ptp(m.points[:, 0])) / 2
    expected = _far_ends_unload(a, b, F / 4)
    assert expected == pytest.approx(0.5125, rel=1e-5)  # 0.4 N·m of normal couple + friction
    mw = pg.max_resistible_wrench(m, F, [0, 0, 0, 0, 0, sign], upper=50)
    assert mw.status == "finite" and mw.giveway.reason == "limit"
    assert mw.magnitude == pytest.approx(expected, rel=1e-3)
    lp = pg.loading_path(m, F, [0, 0, 0, 0, 0, sign])
    cn = lp.contact_forces[-1][:, 0]
    loaded = cn > 1e-2 * F
    assert loaded.sum() == 2  # a diagonal pair, one point per jaw, F/2 each
    np.testing.assert_allclose(cn[loaded], F / 2, rtol=1e-3)
    p = m.points[loaded]
    assert p[0, 1] != pytest.approx(p[1, 1]) and np.sign(p[0, 0]) != np.sign(p[1, 0])


@pytest.mark.slow
def test_the_tilted_cylinder_gives_way_in_simulation_at_a_slow_ramp(tilted_cylinder):
    """The arbiter at ramp_time 0.3 (a 1.5 s hold: long enough for the free spin about the chord
    of the two remaining points to creep) against the path's answer (~50 s)."""
    m = tilted_cylinder
    sim = pg.simulate_max_wrench(m, "mz", F, upper=50, friction="pyramid", ramp_time=0.3)
    mw = pg.max_resistible_wrench(m, F, "mz", upper=50)
    assert sim.status == "gave_way" and sim.load == pytest.approx(mw.magnitude, rel=1e-2)


@pytest.fixture(scope="module")
def upright_cylinder():
    """A 30 mm cylinder, 150 mm long, axis along z, in the parallel jaw: each jaw touches it
    along a 20 mm line (the jaw's height) at x = +-15 mm, modelled by its 2 end points (4
    contacts, F/4 each under the preload)."""
    hand = pg.Hand.builtin("parallel_jaw")
    cyl = pg.RigidObject.cylinder(0.015, 0.150, pose=[0.0, 0.040, 0.0])
    q = hand.close_on(cyl)
    return pg.grasp_model_from_scene(hand, q, cyl, mu=MU)


def _tilt_events(a: float, b: float, c0: float) -> tuple[float, float, float]:
    """Torques [N·m] about the axis normal to the jaws' normal and to the lines (y) at which the
    far end points start to slide, the near ones start to slide, and the far ones unload
    (``a``: half the line length, ``b``: half the jaw gap, ``c0``: preload per end point;
    tangential springs = normal ones, friction along the lines at a pyramid edge, so mu; needs
    ``2 mu a < b``). Tilting by theta presses one end of each line by ``k a theta`` and lifts
    the other, and slides every point along its line by ``b theta``: all stick (stiffness
    ``4 k (a^2 + b^2)``) until the far ends slide (``k b theta = mu (c0 - k a theta)``), then
    ``4 k a^2 + 2 k b^2 - 2 mu k a b`` until the near ones slide too (``k b theta = mu (c0 + k
    a theta)``); with all four sliding the friction moment is ``4 mu c0 b`` and the normal
    couple grows until the far ends carry nothing: ``4 c0 (a + mu b)``."""
    th_far, th_near = MU * c0 / (b + MU * a), MU * c0 / (b - MU * a)  # per k
    far = 4 * (a * a + b * b) * th_far
    near = far + (4 * a * a + 2 * b * b - 2 * MU * a * b) * (th_near - th_far)
    return far, near, 4 * c0 * (a + MU * b)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_tilted_upright_cylinder_ends_on_a_diagonal_pair_where_its_far_ends_unload(upright_cylinder, sign):
    """Tilting the upright cylinder about y (its line ends pressed into one jaw and pulled off
    the other) slides and unloads the line ends at the closed forms 0.1625 / 0.25 / 0.35 N·m.
    Past 0.35 N·m two diagonal points hold it: they wedge it between the non-backdrivable jaws
    (any torque about y), but their chord passes through the centre and nothing resists the
    spin about it (point contacts): the simulation's object spins about that chord at constant
    load (0.395 N·m at ramp_time 0.3, 0.3496 at 1.0: the slow test below), and the path's own
    answer past 0.35 N·m is where its first geometry update meets that spin (1.925 N·m at the
    default 5 mrad step, 0.525 at 1 mrad: not a property of the grasp, see the xfail below)."""
    m = upright_cylinder
    a = float(np.ptp(m.points[:, 2])) / 2
    b = float(np.ptp(m.points[:, 0])) / 2
    far, near, unload = _tilt_events(a, b, F / 4)
    assert (far, near, unload) == pytest.approx((0.1625, 0.25, 0.35), rel=1e-6)
    lp = pg.loading_path(m, F, [0, 0, 0, 0, sign, 0])
    loads = sorted({round(e.load, 9) for e in lp.events if e.kind == "contact"})
    np.testing.assert_allclose(loads[:3], [far, near, unload], rtol=1e-6)
    at = int(np.argmin(np.abs(np.asarray(lp.loads) - unload)))
    cn = lp.contact_forces[at][:, 0]
    loaded = cn > 1e-6 * F
    assert loaded.sum() == 2
    np.testing.assert_allclose(cn[loaded], F / 2, rtol=1e-6)  # a diagonal pair, F/2 each
    p = m.points[loaded] - m.reference_point
    assert np.sign(p[0, 0]) != np.sign(p[1, 0]) and np.sign(p[0, 2]) != np.sign(p[1, 2])
    chord = (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])
    assert np.linalg.norm(np.cross(p[0], chord)) < 1e-9  # through the centre: the spin is free
    assert abs(chord[1]) < 1e-8  # and orthogonal to the load (my): the load leaves it alone


@pytest.mark.xfail(strict=True, reason="past the diagonal pair: the first geometry update")
def test_the_tilted_upright_cylinder_gives_way_where_the_diagonal_pair_is_left(upright_cylinder, monkeypatch):
    """What the arbiter converges to: at slower ramps (longer holds) the simulation gives way
    at the far ends' unloading, 0.395 N·m at ramp_time 0.3 and 0.3496 at 1.0 (closed form
    0.35): from there the diagonal pair leaves a free spin about its chord that a rounding-level
    share of the load drives. The path does not see it: its load-stage solves leave the free
    spin alone (least-norm SVD, ``system.RANGE_RTOL``) until its first geometry update, whose
    LU solve (pivot bar 1e-9 on the pivot, the Cholesky path's is on its square) takes the
    spin with 1e14 rates and stops on a "limit": 0.35 + 175 N·m/rad x (2 step - 0.5 mrad),
    0.875 N·m at a 2 mrad step, 1.925 at 5 mrad (the default), 35.2 at 0.1 rad. A pivot bar
    like the Cholesky one is no fix: the wedge then holds past upper (50, "linearisation")."""
    import functools

    from pinograsp.analysis.quasistatic import api, geometry

    m = upright_cylinder
    unload = _tilt_events(float(np.ptp(m.points[:, 2])) / 2, float(np.ptp(m.points[:, 0])) / 2, F / 4)[2]
    for step in (0.002, 0.005):
        up = functools.partial(geometry.GeometryUpdates, step=step, max_step=step, min_step=step / 20)
        monkeypatch.setattr(api, "GeometryUpdates", up)
        assert pg.max_resistible_wrench(m, F, "my", upper=50).magnitude == pytest.approx(unload, rel=1e-2)


@pytest.mark.slow
def test_the_tilted_upright_cylinder_spins_off_in_simulation_past_the_diagonal_pair(upright_cylinder):
    """The arbiter at ramp_time 0.3 (1.5 s holds, ~40 s): past the far ends' unloading (closed
    form 0.35 N·m) the object, held by the diagonal pair, spins about their chord at constant
    load (a constant angular acceleration from a ~1e-7 share of the load along the spin; the
    translation stays below a micron) and its hold test calls a spin of 3 mrad in the second
    half of a hold a give-way: 0.395 N·m, 13 % above the unloading and 5x below the path's
    1.925 N·m (its first geometry update). At ramp_time 1.0 (5 s holds, ~140 s) 0.3496 N·m; at
    the default 0.02 s (0.1 s holds) the spin is too slow to count and it "holds" to 19.7."""
    m = upright_cylinder
    sim = pg.simulate_max_wrench(m, "my", F, upper=50, friction="pyramid", ramp_time=0.3)
    unload = _tilt_events(float(np.ptp(m.points[:, 2])) / 2, float(np.ptp(m.points[:, 0])) / 2, F / 4)[2]
    assert sim.status == "gave_way" and unload < sim.load < 1.15 * unload
    assert sim.load == pytest.approx(0.395, rel=1e-2)


def test_an_upright_cylinder_pushed_onto_one_jaw_tips_over_where_the_other_lets_go():
    """The 50 mm upright cylinder in the parallel jaw (20 N), pushed across the jaws: the far
    jaw's line unloads at F = 20 N, and from there the cylinder rests on the near jaw's line
    alone, pressed by the load through its axis, 15 mm away: turning about that line has no
    spring against it and the compressed line makes it negative (-F r), so it tips over
    (quasistatic.buckling: the ray past 20 N buckles at once). On the mirror side (-x) the path
    reaches the same state through a geometry update, where the rate problem, with the far
    jaw's ends free to open or stay, provably has no solution (snap.no_continuation). The
    simulation at a slow ramp gives way at 19.97 N; before, the answer was "unbounded" (+x) and
    no verdict (-x)."""
    hand = pg.Hand.builtin("parallel_jaw")
    cyl = pg.RigidObject.cylinder(0.015, 0.05, pose=[0.0, 0.040, 0.0])
    m = pg.grasp_model_from_scene(hand, hand.close_on(cyl), cyl, mu=MU)
    for d in ("fx", "-fx"):
        mw = pg.max_resistible_wrench(m, 20.0, d, upper=50)
        assert mw.status == "finite" and mw.giveway.reason == "limit", d
        assert mw.magnitude == pytest.approx(20.0, rel=1e-6), d
        forces = mw.response.normal_forces
        np.testing.assert_allclose(sorted(forces), [0.0, 0.0, 10.0, 10.0], atol=1e-5)  # one jaw: F/2 each


def test_buckling_of_a_pinch_pushed_onto_one_finger_is_mirror_symmetric_and_past_upper():
    """The pinch along +-x: the path's ray buckles at the same load both ways, far above the
    default upper (1e3 N), so the answer stays "unbounded" there."""
    m = pg.examples.pinch()
    loads = [pg.loading_path(m, 1.0, d).limit for d in ("fx", "-fx")]
    assert loads[0] == pytest.approx(loads[1], rel=1e-12) and loads[0] > 2e3
    assert all(pg.max_resistible_wrench(m, 1.0, d).status == "unbounded" for d in ("fx", "-fx"))
