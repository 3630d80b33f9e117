"""Traps a new user fell into on example-robot-data hands the package does not ship (issue 27).

Each test uses the exact input that triggered the bug and asserts numbers.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

import pinograsp as pg

TALOS_JOINTS = [
    "gripper_left_joint",
    "gripper_left_inner_double_joint",
    "gripper_left_fingertip_1_joint",
    "gripper_left_fingertip_2_joint",
    "gripper_left_motor_single_joint",
    "gripper_left_inner_single_joint",
    "gripper_left_fingertip_3_joint",
]


def robots_dir():
    return pg.example_robot_data_dir() / "example-robot-data" / "robots"


@functools.cache
def talos_gripper() -> pg.Hand:
    """Talos' left gripper: one motor, ``gripper_left_joint``, drives six ``<mimic>`` joints."""
    return pg.Hand.from_urdf(
        robots_dir() / "talos_data/robots/talos_full_v2.urdf",
        {
            "joints": TALOS_JOINTS,
            "base_link": "gripper_left_base_link",
            "closing": {"gripper_left_joint": -1, "gripper_left_inner_double_joint": -1},
        },
        package_dirs=[pg.example_robot_data_dir()],
    )


def talos_model(y: float = 0.0) -> pg.GraspModel:
    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, y, -0.135])
    hand = talos_gripper()
    return pg.grasp_model_from_scene(hand, hand.close_on(box), box, mu=0.5)


# ------------------------------------------------------------------ 1. pruning keeps the motor
def test_talos_motor_survives_pruning_and_balances_both_jaws():
    # before: "3 contacts, 5 joints, 0 actuators, 0 couplings" (the motor's link touches nothing)
    m = talos_model()
    assert m.contact_names == (
        "gripper_left_fingertip_1_link",
        "gripper_left_fingertip_2_link",
        "gripper_left_fingertip_3_link",
    )
    assert m.nq == 7 and m.actuator_names == ("gripper_left_joint",) and m.ncp == 6
    assert not m.pruned
    # the motor's own link moves no contact: its Jacobian column is zero
    assert not np.any(m.J[:, m.joint_names.index("gripper_left_joint")])
    choice = pg.equilibrium_preload(m)
    assert choice.status == "found" and choice.command == {"gripper_left_joint": 1.0}
    r = pg.passive_response(m, choice.command, np.zeros(6))
    assert r.status == "resisted"
    # closed form 1: both jaws press equally (the double jaw's two tips against the single one)
    cn = np.asarray(r.normal_forces)
    np.testing.assert_allclose(cn[0] + cn[1], cn[2], rtol=1e-6)
    assert cn[2] > 1.0
    # closed form 2 (virtual work): with every mimic ratio +1 in closing coordinates, the motor
    # torque equals the contact forces' work along the common closing motion (all joints +1)
    e = np.ones(m.nq)
    c = np.concatenate([np.asarray(f) for f in r.contact_forces])
    np.testing.assert_allclose(e @ (m.J.T @ c), 1.0, rtol=1e-6)


def test_talos_one_jaw_touching_has_no_preload_and_says_why():
    # before: raw TypeError "ufunc 'bitwise_and' not supported" (0 actuators after pruning)
    m = talos_model(-0.001)
    assert m.contact_names == ("gripper_left_fingertip_3_link",)
    assert m.actuator_names == ("gripper_left_joint",)
    choice = pg.equilibrium_preload(m)
    assert choice.status == "infeasible" and choice.command is None
    assert choice.unloadable_contacts == ("gripper_left_fingertip_3_link",)


def test_preload_of_a_model_without_actuators_is_an_answer():
    # before: raw TypeError from analysis/preload.py (empty float arrays combined with '&')
    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, 0.0, -0.135])
    hand = talos_gripper()
    m = pg.grasp_model_from_scene(hand, hand.close_on(box), box, mu=0.5, actuators=[])
    assert m.na == 0
    with pytest.raises(pg.ModelError, match="no actuator reaches a contact"):
        pg.equilibrium_preload(m)


# ------------------------------------------------------ 3. energetic "finite" at upper
@pytest.mark.parametrize("backend", ["bnb", "miqp"])
def test_energetic_limit_at_upper_is_not_finite(pinch, backend):
    # before: backend="miqp" gave +fx "finite 49.99994 N" at upper=50 (the bound binding within
    # the MIQP gap) and +fy "finite 4.99997 N" at upper=5; the PRP says unbounded / above_limit
    cmd = {"left": 1.0, "right": 1.0}
    r = pg.max_resistible_wrench(pinch, cmd, "fx", "energetic", upper=50, backend=backend)
    assert r.status == "unbounded" and r.magnitude == float("inf")
    r = pg.max_resistible_wrench(pinch, cmd, "fy", "energetic", upper=5, backend=backend)
    assert r.status == "above_limit" and r.magnitude == 5.0
    # a finite limit well inside the bound is untouched: F = 2 mu f / L = 10 N
    r = pg.max_resistible_wrench(pinch, cmd, "fy", "energetic", upper=50, backend=backend)
    assert r.status == "finite" and abs(r.magnitude - 10.0) < 1e-5


# ------------------------------------------- 4. energetic on a plain 7-contact Allegro grasp
ALLEGRO_DESCRIPTION = {
    "name": "allegro_left",
    "base_link": "palm_link",
    "actuators": [
        {
            "name": f"joint_{j}.0",
            "kind": "locked" if j in (0, 4, 8, 12) else "non-backdrivable",
            "transmission": {f"joint_{j}.0": 1.0},
        }
        for j in range(16)
    ],
    "open_configuration": {"joint_12.0": 1.2},
}


@functools.cache
def allegro_left_grasp() -> tuple[pg.Hand, np.ndarray, pg.RigidObject, pg.GraspModel]:
    """example-robot-data's Allegro left hand (the shipped right hand's description) on the
    README's ball: 7 contacts."""
    hand = pg.Hand.from_urdf(
        robots_dir() / "allegro_hand_description/urdf/allegro_left_hand.urdf",
        ALLEGRO_DESCRIPTION,
        package_dirs=[pg.example_robot_data_dir()],
    )
    ball = pg.RigidObject.sphere(0.04, pose=[0.07, 0.0, 0.03])
    q = hand.close_on(ball, {"joint_12.0": 1.2})
    return hand, q, ball, pg.grasp_model_from_scene(hand, q, ball, mu=0.5)


def test_energetic_zero_load_on_allegro_left_is_resisted():
    # before: "NOT RESISTED (status failed)" with a net wrench of 1.04e-4 N and "audit: ok", and
    # max_resistible_wrench raised "SolverError: solver failed at magnitude 0": the energetic load
    # stage carries the held-still preload's residual (<= eps = 1e-3 N) and was then checked
    # against 1e-6 of the force scale
    _, _, _, m = allegro_left_grasp()
    assert m.nc == 7
    choice = pg.equilibrium_preload(m, max_command=0.5, method="iterative")  # the preload it checks
    assert choice.status == "found"
    r = pg.passive_response(m, choice.command, np.zeros(6), "energetic")
    assert r.status == "resisted" and r.audit.ok
    assert r.audit.equilibrium < 1e-3 <= r.audit.equilibrium_tolerance
    # with no load the energetic answer is the held-still preload (to its residual, eps)
    it = pg.passive_response(m, choice.command, np.zeros(6), "iterative")
    np.testing.assert_allclose(r.normal_forces, it.normal_forces, atol=5e-3)
    assert abs(float(np.sum(r.normal_forces)) - 22.07) < 0.01


@pytest.mark.slow
def test_energetic_max_wrench_on_allegro_left():
    _, _, _, m = allegro_left_grasp()
    choice = pg.equilibrium_preload(m, max_command=0.5)
    r = pg.max_resistible_wrench(m, choice.command, "-fz", "energetic", upper=20)
    assert r.status == "finite" and abs(r.magnitude - 6.498) < 0.01


def test_a_failed_equilibrium_never_passes_the_audit():
    # the rule behind "status failed ... audit: ok": the equilibrium bound is part of the audit
    from pinograsp.core.audit import Audit

    bad = Audit(equilibrium=1e-4, hand=0.0, complementarity=0.0, friction=0.0, equilibrium_tolerance=1e-6)
    assert not bad.ok and "NOT OK" in bad.summary()
    good = Audit(equilibrium=1e-4, hand=0.0, complementarity=0.0, friction=0.0, equilibrium_tolerance=1e-3)
    assert good.ok and good.to_dict()["equilibrium_tolerance"] == 1e-3


# ------------------------------------------------- 5. default contact links through locked joints
def test_default_contact_links_include_links_below_locked_joints():
    # before: TIAGo's Hey5 with its three motor joints as hand joints checked only hand_palm_link
    # and the motors' 1 mm spheres: the finger links hang below joints the description locks
    hand = pg.Hand.from_urdf(
        robots_dir() / "tiago_description/robots/tiago.urdf",
        {"joints": ["hand_thumb_joint", "hand_index_joint", "hand_mrl_joint"], "base_link": "hand_palm_link"},
        package_dirs=[pg.example_robot_data_dir()],
    )
    links = hand.contact_link_names
    assert len(links) == 37 and len(hand.geometry.geometryObjects) == 37
    for name in (
        "hand_palm_link",
        "hand_thumb_flex_2_link",
        "hand_index_flex_3_link",
        "hand_little_flex_3_link",
    ):
        assert name in links
    # nothing above or beside the base link (TIAGo's arm, torso, base)
    assert all(n.startswith("hand_") for n in links)


def test_default_contact_links_stop_at_the_base_link():
    # Talos: the whole humanoid is locked; only the left gripper's links are at/below its base
    links = talos_gripper().contact_link_names
    assert len(links) == 8 and all(n.startswith("gripper_left_") for n in links)


# ------------------------------------------------------------------- 6. check_closing advice
def test_check_closing_allegro_locked_joints_and_the_thumb():
    # before: joint_8.0 (a locked abduction) flagged OPENS, and joint_13.0 flagged OPENS with
    # "use closing: {joint_13.0: -1}", contradicting the shipped file (with -1 the thumb misses)
    hand = pg.Hand.builtin("allegro_right")
    ball = pg.RigidObject.sphere(0.04, pose=[0.07, 0.0, 0.03])
    r = pg.check_closing(hand, ball, {"joint_12.0": 1.2})
    assert r.ok and r.wrong == ()
    for j in ("joint_0.0", "joint_4.0", "joint_8.0", "joint_12.0"):
        assert r[j].verdict == "locked" and r[j].suggested_sign == 1
    assert r["joint_13.0"].verdict == "closes"
    assert r["joint_13.0"].distance_after < r["joint_13.0"].distance_other < r["joint_13.0"].distance_before
    assert r.suggested_closing == {j: 1 for j in hand.joint_names}


def test_check_closing_never_suggests_a_sense_a_limit_blocks():
    # before: every Allegro joint at its lower limit that moved away was told "use closing: -1"
    # (joint_9.0: "7.65 mm -> 9.37 mm ... OPENS"), a sense in which it cannot move at all
    hand = pg.Hand.builtin("allegro_right")
    back = pg.RigidObject.sphere(0.02, pose=[-0.04, 0.0, 0.1])
    r = pg.check_closing(hand, back, dict(zip(hand.joint_names, hand.lower)))
    assert r.ok and r.wrong == ()
    j9 = r["joint_9.0"]
    assert j9.verdict == "no effect" and j9.distance_other == float("inf")
    assert j9.distance_after > j9.distance_before and "limit blocks the other sense" in j9.note


def test_check_closing_mimic_followers_and_the_printed_distances():
    # before: with the right signs the followers fingertip_1/2/3 were judged alone and flagged
    # OPENS; with gripper_left_joint's sign wrong the report printed
    # "gripper_left_motor_double_link 54.42 mm -> 52.85 mm ... OPENS" (a decrease called opening)
    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, 0.0, -0.135])
    r = pg.check_closing(talos_gripper(), box)
    assert r.ok
    assert [j.verdict for j in r.joints].count("follows") == 6
    assert r["gripper_left_joint"].verdict == "closes"
    assert abs(r["gripper_left_joint"].distance_after - 0.01721) < 2e-4
    wrong = pg.Hand.from_urdf(
        robots_dir() / "talos_data/robots/talos_full_v2.urdf",
        {"joints": TALOS_JOINTS, "base_link": "gripper_left_base_link"},
        package_dirs=[pg.example_robot_data_dir()],
    )
    w = pg.check_closing(wrong, box)
    assert w.wrong == ("gripper_left_joint",) and w.suggested_closing["gripper_left_joint"] == -1
    line = w["gripper_left_joint"].line()
    assert "closing sense blocked by a joint limit, other sense 17.21 mm" in line and "OPENS" in line


# ------------------------------------------------------------- 7. max_penetration in close_on
def sake_hand() -> pg.Hand:
    return pg.Hand.from_urdf(
        robots_dir() / "alex_description/urdf/alex_sake_hands.urdf",
        {"joints": ["Right_GRIPPER_X1", "Right_GRIPPER_X2"], "base_link": "RightSakePalmLink"},
        package_dirs=[pg.example_robot_data_dir()],
    )


def test_close_on_accepts_max_penetration_and_defaults_to_5_mm():
    # before: a ball 2.95 mm into the SAKE palm raised PenetrationError "more than 1.000 mm ...
    # raise max_penetration" from close_on, which had no max_penetration (docs: 5 mm)
    from pinograsp.robots.collision import DEFAULT_MAX_PENETRATION

    hand = sake_hand()
    ball = pg.RigidObject.sphere(0.02, pose=[0.0, 0.0, -0.095])
    q = hand.close_on(ball)
    np.testing.assert_allclose(q, [0.0, 0.0])  # both fingers already touch: nothing moves
    m = pg.grasp_model_from_scene(hand, q, ball)
    assert "RightSakePalmLink" in m.contact_names
    assert DEFAULT_MAX_PENETRATION == 5e-3
    with pytest.raises(pg.PenetrationError, match=r"more than 2\.000 mm.*max_penetration.*close_on") as exc:
        hand.close_on(ball, max_penetration=0.002)
    assert exc.value.max_penetration == 0.002
    assert abs(exc.value.depths["RightSakePalmLink"] + 2.947e-3) < 1e-5
    with pytest.raises(pg.InvalidInputError, match="max_penetration"):
        hand.close_on(ball, max_penetration=-1.0)


# --------------------------------------------------------------- 8. a mimic naming no joint
def test_mimic_of_a_missing_joint_points_to_use_mimic_false():
    # before: "joint 'Left_index_q2' mimics 'index_q1' but only one of them is a hand joint; keep
    # both in" -- impossible, the PSYONIC URDF has no joint 'index_q1' (it is 'Left_index_q1')
    urdf = robots_dir() / "alex_description/urdf/alex_psyonic_hands.urdf"
    share = pg.example_robot_data_dir()
    with pytest.raises(
        pg.ModelError, match=r"'index_q1', which is not a movable joint.*use_mimic: false"
    ) as e:
        pg.Hand.from_urdf(urdf, package_dirs=[share])
    assert "ratio: 1.05851" in str(e.value)
    # the advice works: mimics off, the linkage given as a coupling (closing coordinates)
    hand = pg.Hand.from_urdf(
        urdf,
        {
            "use_mimic": False,
            "joints": ["Right_index_q1", "Right_index_q2"],
            "couplings": [{"follower": "Right_index_q2", "leader": "Right_index_q1", "ratio": 1.05851325}],
        },
        package_dirs=[share],
    )
    np.testing.assert_allclose(hand.coupling_matrix(), [[-1.05851325, 1.0]])


# ------------------------------------------------------ 10. audit wording per method
def test_audit_message_names_the_wedging_artefact_only_for_the_prp():
    # before: every method's failed energy balance was called "the wedging artefact", while the
    # PRP's own warning said that iterative and energetic have none
    from pinograsp.core.audit import EnergyCheck, audit_message

    check = EnergyCheck(2.0, 0.5, 0.5, 1.0, ("left",))
    assert not check.energy_ok
    prp = audit_message("prp", check)
    assert "the wedging artefact" in prp and "have no wedging artefact" in prp
    for method in ("iterative", "energetic"):
        text = audit_message(method, check)
        assert "not the PRP's wedging artefact (this method has none)" in text
        assert "simulate_max_wrench" in text and "springs store 2 J" in text


# ------------------------------------------------------------------------- 13. smaller traps
def test_passive_response_with_no_command_says_so(pinch):
    # before: passive_response(model, None, w) -> "command: contains NaN or inf"
    with pytest.raises(
        pg.InvalidInputError, match=r"command.*is None.*equilibrium_preload returns command=None"
    ):
        pg.passive_response(pinch, None, np.zeros(6))


def test_two_point_grasp_names_the_free_rotation_about_the_contact_chord():
    # before: SO-101's two-jaw grasp of a ball was below_resolution along +fy, mx, mz with no word
    # that the object spins about the line through its two contacts
    hand = pg.Hand.builtin("so101")
    ball = pg.RigidObject.sphere(0.012, pose=[0.00175, 0.0, -0.08])
    m = pg.grasp_model_from_scene(hand, hand.close_on(ball), ball, mu=0.5)
    assert m.nc == 2
    free = m.free_motions()
    assert free.shape == (1, 6)
    chord = m.points[1] - m.points[0]
    np.testing.assert_allclose(abs(free[0, 3:] @ chord) / np.linalg.norm(chord), 1.0, atol=1e-9)
    # the axis passes through both contacts: their velocities vanish
    for p in m.points:
        v = free[0, :3] + np.cross(free[0, 3:], p - m.reference_point)
        assert np.linalg.norm(v) < 1e-9
    r = pg.max_resistible_wrench(m, {"gripper": 1.0}, "fy", upper=10, steps=10)
    assert r.status == "below_resolution"
    assert "free to rotate about the axis" in r.note and "two contacts" in r.note
    assert "note: no contact resists this load" in r.summary() and r.to_dict()["note"] == r.note
    fx = pg.max_resistible_wrench(m, {"gripper": 1.0}, "fx", upper=10, steps=10)
    assert fx.status == "finite" and fx.note == ""


def test_object_inside_a_hand_mesh_says_the_mesh_is_a_surface():
    # before: a ball inside the SAKE palm body: NoContactError "RightSakePalmLink: 7.400 mm", no
    # word that a hand mesh is a surface (Coal BVH)
    hand = sake_hand()
    ball = pg.RigidObject.sphere(0.005, pose=[0.0, 0.0, -0.04])
    with pytest.raises(pg.NoContactError, match=r"RightSakePalmLink: 7\.400 mm.*mesh is a surface") as e:
        hand.close_on(ball)
    assert e.value.surfaces == ("RightSakePalmLink",)
    with pytest.raises(pg.NoContactError) as e:
        pg.grasp_model_from_scene(hand, hand.q_open, ball)
    assert e.value.surfaces == ("RightSakePalmLink",)
    with pytest.raises(pg.NoContactError) as e:  # far below the hand: no such hint
        hand.close_on(pg.RigidObject.sphere(0.005, pose=[0.0, 0.0, -0.3]))
    assert e.value.surfaces == ()


# ------------------------------------------------------------------------------ 12. pictures
def test_big_hand_meshes_are_decimated_into_surfaces_not_slivers():
    # before: the G1 Dex3-1 meshes were cut to every k-th face, drawn as scattered slivers
    import trimesh

    from pinograsp.viz.meshes import geometry_mesh
    from pinograsp.viz.scene_mpl import _decimate

    hand = pg.Hand.from_urdf(
        robots_dir() / "g1_description/urdf/g1_29dof_with_hand_rev_1_0.urdf",
        {"joints": ["left_hand_index_0_joint"], "base_link": "left_hand_palm_link"},
        package_dirs=[pg.example_robot_data_dir()],
    )
    palm = hand.geometry.geometryObjects[hand.contact_link_names.index("left_hand_palm_link")]
    mesh = geometry_mesh(palm.geometry)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    assert len(f) > 4000
    v2, f2 = _decimate(v, f, 4000)
    assert 0 < len(f2) <= 4000
    area = trimesh.Trimesh(v, f, process=False).area
    kept = trimesh.Trimesh(v2, f2, process=False).area
    every_kth = trimesh.Trimesh(v, f[:: int(np.ceil(len(f) / 4000))], process=False).area
    assert abs(kept / area - 1.0) < 0.15  # the decimated surface covers the palm
    assert every_kth / area < 0.6  # what was drawn before: a fraction of it
    np.testing.assert_array_equal(_decimate(v, f, 4000)[1], f2)  # deterministic


def test_scene_hand_is_see_through_and_the_external_force_visible():
    # before: Talos' opaque gripper was painted over the box, and the 0.5 N external force next to
    # ~6 N contact forces was an arrow of 2 % of the scene inside the box
    from pinograsp.viz.scene_elements import EXTERNAL_MIN_FRACTION, scene_elements

    box = pg.RigidObject.box((0.1, 0.03, 0.02), pose=[0.0, 0.0, -0.135])
    hand = talos_gripper()
    q = hand.close_on(box)
    m = pg.grasp_model_from_scene(hand, q, box, mu=0.5)
    r = pg.passive_response(m, {"gripper_left_joint": 1.0}, [0, 0, -0.5, 0, 0, 0])
    el = scene_elements(m, r, hand=hand, q=q, obj=box)
    opacity = {mesh.name: mesh.opacity for mesh in el.meshes}
    assert opacity["hand"] < 1.0 and opacity["hand"] <= opacity["object"]
    (shaft,) = [s for s in el.segments if s.name == "external force"]
    head = [mesh for mesh in el.meshes if mesh.name == "external force"][0]
    tip = head.vertices[0]  # the cone's apex is the arrow tip
    length = float(np.linalg.norm(tip - shaft.segments[0][0]))
    np.testing.assert_allclose(length, EXTERNAL_MIN_FRACTION * el.size, rtol=1e-9)
    np.testing.assert_allclose((tip - shaft.segments[0][0]) / length, [0, 0, -1], atol=1e-12)


def test_above_limit_is_drawn_as_a_lower_bound(pinch):
    # before: a direction resisted at upper (above_limit) was a plain profile point at upper,
    # read as a limit; the resistance-set map coloured it like a finite limit
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cmd = {"left": 1.0, "right": 1.0}
    it = "iterative"  # the bisection's above_limit (the default path has none: its limit is exact)
    p = pg.resistance_profile(pinch, cmd, ("fx", "fy"), n=8, method=it, upper=5, steps=8)
    assert p.statuses.count("above_limit") == 6 and p.statuses.count("unbounded") == 2
    ax = pg.plot_profile(p)
    (tri,) = [ln for ln in ax.lines if ln.get_gid() == "pinograsp-above-limit"]
    assert len(tri.get_xdata()) == 6 and tri.get_marker() == "^"
    np.testing.assert_allclose(tri.get_ydata(), 5.0)
    assert "above upper (≥, a lower bound)" in [t.get_text() for t in ax.get_legend().get_texts()]
    plt.close(ax.figure)
    rs = pg.resistance_set(
        pinch, cmd, directions=[[0, 1, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0]], method=it, upper=5, steps=8
    )
    assert rs.statuses == ("above_limit", "unbounded")
    fig = pg.plot_resistance_set(rs)
    gids = [c.get_gid() for a in fig.axes for c in a.collections]
    assert "pinograsp-above-limit" in gids
    (above,) = [c for a in fig.axes for c in a.collections if c.get_gid() == "pinograsp-above-limit"]
    assert len(above.get_offsets()) == 1
    plt.close(fig)


@pytest.mark.slow
def test_talos_motor_joint_simulates():
    # a joint kept only through its mimics moves no contact: the simulation gave it a zero
    # (massless) armature and the object "gave way below the first load of the ramp, 2e-05 N"
    m = talos_model()
    s = pg.simulate_max_wrench(m, "fx", {"gripper_left_joint": 1.0}, upper=20)
    r = pg.max_resistible_wrench(m, {"gripper_left_joint": 1.0}, "fx", upper=20, steps=10)
    assert s.status == "gave_way" and r.status == "finite"
    assert abs(s.load / r.magnitude - 1.0) < 0.1  # 6.3 N simulated, 6.15 N predicted


def test_base_link_named_like_a_fixed_joint_loads():
    """z1.urdf names a fixed joint and its child link both ``gripperStator``: Pinocchio's reduction
    (and ``getFrameId``) raised ``ValueError: Several frames match the filter`` (issue 31 trial)."""
    hand = pg.Hand.from_urdf(
        robots_dir() / "z1_description/urdf/z1.urdf",
        {"joints": ["jointGripper"], "base_link": "gripperStator", "closing": {"jointGripper": 1}},
    )
    assert hand.joint_names == ("jointGripper",)
    import pinocchio as pin

    fid = hand.model.getFrameId("gripperStator", pin.FrameType.BODY)
    assert np.allclose(hand.model.frames[fid].placement.homogeneous, np.eye(4), atol=1e-12)
    assert hand.model.frames[fid].parentJoint == 0


def test_open_configuration_of_a_mimic_follower_follows_its_leader():
    """Baxter's electric gripper: ``open_configuration`` gives the leader only; the follower
    (``<mimic multiplier="-1">``) stayed at 0, its upper limit, so auto-close stopped at once
    with both fingertips 3 mm from the ball (issue 31 trial)."""
    hand = pg.Hand.from_urdf(
        robots_dir() / "baxter_description/urdf/baxter.urdf",
        {
            "joints": ["l_gripper_l_finger_joint", "l_gripper_r_finger_joint"],
            "base_link": "left_gripper_base_link",
            "closing": {"l_gripper_l_finger_joint": -1},
            "actuators": [{"name": "gripper", "transmission": {"l_gripper_l_finger_joint": 1.0}}],
            "open_configuration": {"l_gripper_l_finger_joint": 0.020833},
        },
    )
    assert np.allclose(hand.q_open, [0.020833, -0.020833])
    ball = pg.RigidObject.sphere(0.015, pose=[0.0, 0.0, 0.115])
    q = hand.close_on(ball)
    assert q[0] == pytest.approx(-q[1], abs=1e-12)
    assert 0.0 < q[0] < 0.020833 - 0.003  # closed past the old 3 mm stop
    report = pg.detect_contacts(hand, q, ball)
    assert sorted(c.link for c in report.contacts) == ["l_gripper_l_finger_tip", "l_gripper_r_finger_tip"]


def test_failed_profile_directions_are_marked_not_gaps(pinch, monkeypatch):
    """Issue 33: a direction whose query raised (no verdict) was a silent gap — drawn as an
    unbounded wedge, in fact (NaN is not finite). Now it is a red cross at the plot edge with a
    legend entry, and only inf radii are wedges."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pinograsp.analysis import method_quasistatic
    from pinograsp.errors import SolverError

    real = method_quasistatic.QuasistaticMethod.max_load

    def failing(self, session, query):
        if query.direction[1] > 0.9:  # +fy
            raise SolverError("no verdict here", solver="lemke", status="no_solution")
        return real(self, session, query)

    monkeypatch.setattr(method_quasistatic.QuasistaticMethod, "max_load", failing)
    cmd = {"left": 1.0, "right": 1.0}
    p = pg.resistance_profile(pinch, cmd, ("fx", "fy"), n=8)
    assert [f[0] for f in p.failures] == [2] and np.isnan(p.magnitudes[2])
    ax = pg.plot_profile(p)
    (cross,) = [ln for ln in ax.lines if ln.get_gid() == "pinograsp-failed"]
    np.testing.assert_allclose(cross.get_xdata(), [np.pi / 2])
    np.testing.assert_allclose(cross.get_ydata(), ax.get_ylim()[1])
    assert "no verdict (failed)" in [t.get_text() for t in ax.get_legend().get_texts()]
    wedges = [c for c in ax.patches if c.get_gid() == "pinograsp-unbounded"]
    assert p.statuses.count("unbounded") == 2 and len(wedges) == 2  # ±fx only: the failure is no wedge
    plt.close(ax.figure)
