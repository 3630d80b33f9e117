"""Plots (polar profile, preload comparison, Fig. 1 forces) and the 3D scene view (plotly, PNG)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.viz import comparison_plots, figures, meshes, profile_plots, viewer
from pinograsp.viz.scene_elements import scene_elements
from pinograsp.viz.scene_mpl import scene_axes

MU, TAU = 0.5, 1.0  # the conftest pinch (a = 0.05 m, L = 0.1 m)

plt = figures.pyplot()


pytestmark = pytest.mark.usefixtures("close_figures")


def assert_image(path: Path) -> None:
    """A written, non-empty, non-blank image."""
    from matplotlib.image import imread

    assert path.is_file() and path.stat().st_size > 1000
    img = imread(str(path))[..., :3]
    assert img.std() > 0.05  # not one flat colour
    background = img[0, 0]
    assert np.mean(np.any(np.abs(img - background) > 0.1, axis=-1)) > 0.01  # > 1 % of pixels drawn


def synthetic_profile(
    mags, unbounded=None, plane=("fx", "fy"), normalized_by=None, basis=None
) -> pg.ResistanceProfile:
    mags = np.asarray(mags, dtype=float)
    n = mags.size
    unb = np.zeros(n, bool) if unbounded is None else np.asarray(unbounded, bool)
    angles = 2 * np.pi * np.arange(n) / n
    b = np.eye(6)[[0, 1]] if basis is None else np.asarray(basis, float)
    return pg.ResistanceProfile(
        plane=plane,
        basis=b,
        angles=angles,
        directions=np.cos(angles)[:, None] * b[0] + np.sin(angles)[:, None] * b[1],
        magnitudes=np.where(unb, np.inf, mags),
        unbounded=unb,
        normalized_by=normalized_by,
        results=(),
    )


@pytest.fixture(scope="module")
def profiles(pinch):
    prp = pg.resistance_profile(pinch, TAU, n=8, method="prp", steps=8)
    low_mu = pg.resistance_profile(examples.pinch(mu=0.3), TAU, n=8, method="prp", steps=8)
    return prp, low_mu


def unbounded_wedges(ax):
    return [p for p in ax.patches if p.get_gid() == figures.GID_UNBOUNDED]


# ----------------------------------------------------------------------------- profile
def test_profile_curve_and_unbounded_wedges(profiles, tmp_path):
    p, _ = profiles
    assert p.unbounded.tolist() == [True, False, False, False, True, False, False, False]  # ±fx
    ax = profile_plots.plot_profile(p)
    wedges = unbounded_wedges(ax)
    assert len(wedges) == 2
    rmax = ax.get_ylim()[1]
    finite = p.magnitudes[~p.unbounded]
    assert rmax == pytest.approx(1.15 * finite.max())
    centres = sorted(np.mod(w.get_x() + w.get_width() / 2, 2 * np.pi) for w in wedges)
    np.testing.assert_allclose(centres, [0.0, np.pi], atol=1e-12)
    for w in wedges:
        assert w.get_height() == pytest.approx(rmax)  # reaches the plot edge
        assert w.get_width() == pytest.approx(2 * np.pi / 8)
        assert w.get_hatch()
    # the curve: finite magnitudes at their angles, broken (NaN) where unbounded
    (line,) = [ln for ln in ax.lines if ln.get_label() == "prp"]
    theta, r = np.asarray(line.get_xdata())[:-1], np.asarray(line.get_ydata())[:-1]
    np.testing.assert_allclose(theta, p.angles)
    assert np.isnan(r[p.unbounded]).all()
    np.testing.assert_allclose(r[~p.unbounded], finite)
    # infinity markers at the edge, and a legend entry for them
    marks = [ln for ln in ax.lines if ln.get_gid() == figures.GID_UNBOUNDED]
    np.testing.assert_allclose(np.sort(np.asarray(marks[0].get_xdata())), [0.0, np.pi])
    assert "unbounded (∞)" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert "[N]" in ax.get_title()
    assert_image(figures.save_figure(ax, tmp_path / "profile.png"))


def test_profile_overlay_and_normalisation(profiles, tmp_path):
    p, low = profiles
    ax = profile_plots.plot_profile({"mu 0.5": p, "mu 0.3": low}, normalize=True, title="pinch")
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend[:2] == ["mu 0.5", "mu 0.3"]
    assert len(unbounded_wedges(ax)) == 4
    for label, prof in (("mu 0.5", p), ("mu 0.3", low)):
        (line,) = [ln for ln in ax.lines if ln.get_label() == label]
        r = np.asarray(line.get_ydata())[:-1]
        assert r[2] == pytest.approx(1.0)  # +fy is the reference
        np.testing.assert_allclose(r[~prof.unbounded], prof.magnitudes[~prof.unbounded] / prof.magnitudes[2])
    assert ax.get_title() == "pinch"
    assert_image(figures.save_figure(ax.figure, tmp_path / "nested" / "dir" / "overlay.png"))
    # a numeric normalisation and the unit of a torque plane
    ax = profile_plots.plot_profile(
        synthetic_profile([2.0, 4.0, 2.0, 4.0], plane=("mx", "my")), normalize=2.0
    )
    np.testing.assert_allclose(np.asarray(ax.lines[0].get_ydata())[:-1], [1.0, 2.0, 1.0, 2.0])
    assert "normalised" in ax.get_title()
    assert "[N·m]" in profile_plots.plot_profile(synthetic_profile([1.0] * 4, plane=("mx", "my"))).get_title()


def test_profile_already_normalised_is_not_divided_again():
    pre = synthetic_profile([1.5, 1.0, 1.5, 1.0], normalized_by=10.0)
    ax = profile_plots.plot_profile(pre, normalize=True)
    np.testing.assert_allclose(np.asarray(ax.lines[0].get_ydata())[:-1], [1.5, 1.0, 1.5, 1.0])
    assert "normalised" in ax.get_title()
    raw = synthetic_profile([15.0, 10.0, 15.0, 10.0])
    with pytest.raises(pg.InvalidInputError, match="normalised and others are not"):
        profile_plots.plot_profile([pre, raw])
    ax = profile_plots.plot_profile([pre, raw], normalize=True)  # the raw one is normalised by its +fy
    np.testing.assert_allclose(np.asarray(ax.lines[1].get_ydata())[:-1], [1.5, 1.0, 1.5, 1.0])


def test_profile_all_unbounded_and_single_direction():
    ax = profile_plots.plot_profile(synthetic_profile([1, 1, 1, 1], unbounded=[True] * 4))
    assert len(unbounded_wedges(ax)) == 4
    assert ax.get_ylim()[1] == pytest.approx(1.15)
    ax = profile_plots.plot_profile(synthetic_profile([3.0], unbounded=[True]))
    (w,) = unbounded_wedges(ax)
    assert w.get_width() == pytest.approx(2 * np.pi)


def test_profile_bad_input():
    ok = synthetic_profile([1.0, 2.0, 1.0, 2.0])
    with pytest.raises(pg.InvalidInputError, match="ResistanceProfile"):
        profile_plots.plot_profile("not a profile")
    with pytest.raises(pg.InvalidInputError, match="no profile"):
        profile_plots.plot_profile([])
    with pytest.raises(pg.InvalidInputError, match="profile\\[1\\]"):
        profile_plots.plot_profile([ok, 3.0])
    with pytest.raises(pg.InvalidInputError, match="polar"):
        _, ax = plt.subplots()
        profile_plots.plot_profile(ok, ax=ax)
    with pytest.raises(pg.InvalidInputError, match="one plane"):
        profile_plots.plot_profile(
            [ok, synthetic_profile([1.0] * 4, plane=("fx", "fz"), basis=np.eye(6)[[0, 2]])]
        )
    with pytest.raises(pg.InvalidInputError, match="labels"):
        profile_plots.plot_profile(ok, labels=["a", "b"])
    with pytest.raises(pg.InvalidInputError, match="no direction along \\+fy"):
        profile_plots.plot_profile(synthetic_profile([1.0, 2.0, 3.0]), normalize=True)
    with pytest.raises(pg.InvalidInputError, match="unbounded along \\+fy"):
        profile_plots.plot_profile(
            synthetic_profile([1.0] * 4, unbounded=[False, True, False, False]), normalize=True
        )
    with pytest.raises(pg.InvalidInputError, match="normalize"):
        profile_plots.plot_profile(ok, normalize=-1.0)
    with pytest.raises(pg.InvalidInputError, match="rmax"):
        profile_plots.plot_profile(ok, rmax=0.0)


# ----------------------------------------------------------------------------- preloads
@pytest.fixture(scope="module")
def preload_results(pinch):
    kw = {"method": "prp", "upper": 100.0, "steps": 10}
    return {
        "tau0 = 1": pg.max_resistible_wrench(pinch, 1.0, "fy", **kw),
        "tau0 = 0.5": pg.max_resistible_wrench(pinch, 0.5, "fy", **kw),
        "along fx": pg.max_resistible_wrench(pinch, 1.0, "fx", **kw),
    }


def test_preload_comparison_bars(preload_results, tmp_path):
    two = {k: preload_results[k] for k in ("tau0 = 1", "tau0 = 0.5")}
    m1, m2 = (r.magnitude for r in two.values())
    assert m1 == pytest.approx(2 * MU * 1.0 / 0.1, abs=0.1) and m2 == pytest.approx(
        2 * MU * 0.5 / 0.1, abs=0.1
    )
    ax = comparison_plots.plot_preload_comparison(two)
    heights = [p.get_height() for p in ax.patches]
    np.testing.assert_allclose(heights, [m1, m2])
    assert f"= {m1 / m2:.3g}" in ax.get_title() and "+fy" in ax.get_title()
    assert ax.get_ylabel() == "max resistible magnitude [N]"
    assert_image(figures.save_figure(ax, tmp_path / "bars.png"))
    # with an unbounded direction: hatched bar above the finite ones, labelled ∞
    ax = comparison_plots.plot_preload_comparison(preload_results)
    (inf_bar,) = unbounded_wedges(ax)
    assert inf_bar.get_hatch() == "//" and inf_bar.get_height() > max(m1, m2)
    assert "∞" in [t.get_text() for t in ax.texts]
    ticks = [t.get_text() for t in ax.get_xticklabels()]
    assert ticks[2] == "along fx\n+fx"  # directions differ: named per bar
    assert_image(figures.save_figure(ax, tmp_path / "bars_inf.png"))


def test_preload_comparison_profiles_and_bad_input(profiles, preload_results):
    p, low = profiles
    ax = comparison_plots.plot_preload_comparison({"a": p, "b": low})
    assert ax.name == "polar" and len(unbounded_wedges(ax)) == 4
    with pytest.raises(pg.InvalidInputError, match="only MaxWrench or only ResistanceProfile"):
        comparison_plots.plot_preload_comparison({"a": p, "b": preload_results["along fx"]})
    with pytest.raises(pg.InvalidInputError, match="non-empty"):
        comparison_plots.plot_preload_comparison({})
    with pytest.raises(pg.InvalidInputError, match="rectilinear"):
        _, ax = plt.subplots(subplot_kw={"projection": "polar"})
        comparison_plots.plot_preload_comparison({"a": preload_results["along fx"]}, ax=ax)


# ----------------------------------------------------------------------------- Fig. 1
def test_force_comparison_marks_contacts_outside_their_cone(pinch, tmp_path):
    w = [12.0, 8.0, 0.0]  # (fx, fy, mz): resisted (|fy| < 2 mu tau0 / L = 10 N)
    passive = pg.passive_response(pinch, TAU, w, method="prp")
    preload = pg.passive_response(pinch, TAU, [0.0, 0.0, 0.0], method="prp")
    lc = pg.linear_compliance(pinch, w, preload.contact_forces)
    assert passive.resistible
    # linear compliance: fx shifts 6 N of normal force from left to right, fy adds 4 N each
    np.testing.assert_allclose(lc.contact_forces[:, :2], [[4.0, -4.0], [16.0, 4.0]], atol=1e-6)
    assert lc.friction_violations == ("left",)
    ax = comparison_plots.plot_force_comparison(pinch, passive, lc)
    (marks,) = [c for c in ax.collections if c.get_gid() == comparison_plots.GID_OUTSIDE_CONE]
    bad = [pinch.contact_names.index(n) for n in lc.friction_violations]
    expected = np.column_stack(
        [lc.contact_forces[bad, 0], np.linalg.norm(lc.contact_forces[bad, 1:], axis=1)]
    )
    np.testing.assert_allclose(marks.get_offsets(), expected)  # (4, 4): |c_t| = 4 > mu c_n = 2
    # the passive forces are plotted and all inside their cone
    pas = [c for c in ax.collections if c.get_label() == "passive analysis"][0]
    pts = np.asarray(pas.get_offsets())
    np.testing.assert_allclose(pts[:, 0], passive.normal_forces, atol=1e-9)
    assert np.all(pts[:, 1] <= MU * pts[:, 0] + 1e-9)
    (cone,) = [ln for ln in ax.lines if ln.get_label() == f"|c_t| = {MU:g} c_n"]
    x, y = np.asarray(cone.get_xdata()), np.asarray(cone.get_ydata())
    np.testing.assert_allclose(y, MU * x)
    red = [t.get_text() for t in ax.texts if t.get_color() == "red"]
    assert red == ["left"]
    assert "1 of 2 contacts outside" in ax.get_title()
    assert_image(figures.save_figure(ax, tmp_path / "fig1.png"))
    np.testing.assert_array_equal(comparison_plots.outside_cone(pinch, lc.contact_forces), [True, False])


def test_force_comparison_bad_input(pinch):
    passive = pg.passive_response(pinch, TAU, [0.0, 0.0, 0.0], method="prp")
    palm = examples.palm_pinch()
    lc_palm = pg.linear_compliance(palm, [0.0, 1.0, 0.0])
    with pytest.raises(pg.InvalidInputError, match="compliance.*3 contacts|2 contacts"):
        comparison_plots.plot_force_comparison(pinch, passive, lc_palm)
    with pytest.raises(pg.InvalidInputError, match="passive"):
        comparison_plots.plot_force_comparison(pinch, object(), lc_palm)


def test_save_figure_errors(tmp_path):
    _, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    with pytest.raises(pg.InvalidInputError, match="suffix"):
        figures.save_figure(ax, tmp_path / "noext")
    with pytest.raises(pg.InvalidInputError, match="Figure or Axes"):
        figures.save_figure("figure", tmp_path / "x.png")
    out = figures.save_figure(ax.figure, tmp_path / "a" / "b.svg", close=True)
    assert out.suffix == ".svg" and out.stat().st_size > 0


# ----------------------------------------------------------------------------- 3D view
def test_importing_pinograsp_loads_no_plotting_library():
    code = (
        "import sys, pinograsp as pg; pg.plot_profile; "
        "assert 'matplotlib' not in sys.modules and 'plotly' not in sys.modules, sorted(sys.modules)"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_geometry_meshes_of_primitives(tmp_path):
    import coal
    import trimesh

    cases = {
        "box": (coal.Box(0.02, 0.04, 0.06), [[-0.01, -0.02, -0.03], [0.01, 0.02, 0.03]]),
        "sphere": (coal.Sphere(0.05), [[-0.05] * 3, [0.05] * 3]),
        "cylinder": (coal.Cylinder(0.01, 0.1), [[-0.01, -0.01, -0.05], [0.01, 0.01, 0.05]]),
        "capsule": (coal.Capsule(0.01, 0.1), [[-0.01, -0.01, -0.06], [0.01, 0.01, 0.06]]),
        "cone": (coal.Cone(0.01, 0.1), [[-0.01, -0.01, -0.05], [0.01, 0.01, 0.05]]),
        "ellipsoid": (coal.Ellipsoid(0.01, 0.02, 0.03), [[-0.01, -0.02, -0.03], [0.01, 0.02, 0.03]]),
    }
    for name, (geom, bounds) in cases.items():
        np.testing.assert_allclose(meshes.geometry_mesh(geom).bounds, bounds, atol=1e-9, err_msg=name)
    trimesh.creation.box(extents=[0.01, 0.02, 0.03]).export(tmp_path / "box.stl")
    trimesh.creation.annulus(0.01, 0.02, 0.01).export(tmp_path / "ring.stl")
    convex = pg.RigidObject.from_mesh(tmp_path / "box.stl", convex=True)
    bvh = pg.RigidObject.from_mesh(tmp_path / "ring.stl", convex=False)
    assert bvh.kind == "mesh"
    np.testing.assert_allclose(
        meshes.geometry_mesh(convex.geometry).bounds, [[-0.005, -0.01, -0.015], [0.005, 0.01, 0.015]]
    )
    assert len(meshes.geometry_mesh(bvh.geometry).faces) == bvh.geometry.num_tris
    assert meshes.geometry_mesh(coal.Halfspace(np.array([0.0, 0.0, 1.0]), 0.0)) is None


def test_scene_figure_of_explicit_contacts(pinch, tmp_path):
    pytest.importorskip("plotly")
    w = [0.0, 5.0, 0.0]
    r = pg.passive_response(pinch, TAU, w, method="prp")
    fig = viewer.scene_figure(pinch, r, cone_scale=0.02, force_scale=0.002)
    names = {t.name for t in fig.data}
    assert r.contact_states == ("sticking", "sticking")  # one trace per contact state
    assert names == {
        "contacts: sticking",
        "contact normals",
        "friction cones",
        "contact forces",
        "external force",
    }
    (cones,) = [t for t in fig.data if t.name == "friction cones"]
    v = np.column_stack([cones.x, cones.y, cones.z]).reshape(2, -1, 3)  # per contact: apex + ring
    for k in range(2):
        apex, ring = v[k, 0], v[k, 1:]
        np.testing.assert_allclose(apex, pinch.points[k])
        axis = ring.mean(axis=0) - apex
        n = pinch.frames[k, :, 0]
        np.testing.assert_allclose(axis, -0.02 * n, atol=1e-12)  # on the hand side, height cone_scale
        radius = np.linalg.norm(ring - ring.mean(axis=0), axis=1)
        np.testing.assert_allclose(radius / 0.02, MU)  # half-angle atan(mu)
    # force arrows end at the contact points, parallel to the forces, 2 mm per newton
    (shafts,) = [t for t in fig.data if t.name == "contact forces" and t.type == "scatter3d"]
    (heads,) = [t for t in fig.data if t.name == "contact forces" and t.type == "mesh3d"]
    seg = np.column_stack([shafts.x, shafts.y, shafts.z]).reshape(-1, 3, 3)[:, :2]
    tips = np.column_stack([heads.x, heads.y, heads.z]).reshape(2, -1, 3)[:, 0]
    np.testing.assert_allclose(tips, pinch.points, atol=1e-12)
    f = r.contact_forces_world
    np.testing.assert_allclose(seg[:, 0], pinch.points - 0.002 * f, atol=1e-12)
    for k in range(2):
        d = seg[k, 1] - seg[k, 0]
        assert np.linalg.norm(np.cross(d, f[k])) < 1e-12 and d @ f[k] > 0
    out = viewer.save_html(fig, tmp_path / "html" / "pinch.html")
    html = out.read_text()
    embedded = "Plotly.newPlot" in html and '<script src="http' not in html and len(html) > 1_000_000
    assert embedded  # plotly.js is inside the file: works offline
    missing = [name for name in names if f'"name":"{name}"' not in html]
    assert not missing
    assert_image(viewer.save_png(pinch, r, path=tmp_path / "png" / "pinch.png"))


@pytest.fixture(scope="module")
def barrett_grasp():
    hand = pg.Hand.builtin("barrett_bh8_282")
    obj = pg.RigidObject.box((0.05, 0.06, 0.08), pose=[0.0, 0.0, 0.04])
    q = hand.close_on(obj)
    model = pg.grasp_model_from_scene(hand, q, obj, mu=0.5, patches=False)  # one point per link
    response = pg.passive_response(model, hand.commands, [0.0, 0.0, -5.0, 0.0, 0.0, 0.0], method="prp")
    return SimpleNamespace(model=model, hand=hand, q=q, object=obj, response=response)


def test_scene_figure_with_hand_and_object(barrett_grasp, tmp_path):
    pytest.importorskip("plotly")
    g = barrett_grasp
    assert g.response.resistible and g.model.nc == 4
    fig = viewer.scene_figure(g.model, g.response, hand=g.hand, q=g.q, obj=g.object)
    traces = {t.name: t for t in fig.data}
    states = {f"contacts: {state}" for state in g.response.contact_states}
    assert {"hand", "object", "friction cones", "contact forces"} | states <= set(traces)
    hand = traces["hand"]
    assert set(hand.hovertext) == set(g.hand.contact_link_names)  # every collision link drawn
    obj = np.column_stack([traces["object"].x, traces["object"].y, traces["object"].z])
    np.testing.assert_allclose(obj.min(axis=0), [-0.025, -0.03, 0.0], atol=1e-12)
    np.testing.assert_allclose(obj.max(axis=0), [0.025, 0.03, 0.08], atol=1e-12)
    assert "resisted" in fig.layout.title.text
    # a scene object (duck-typed: .model, .hand, .q, .object) gives the same figure
    fig2 = viewer.scene_figure(g, g.response)
    assert [t.name for t in fig2.data] == [t.name for t in fig.data]
    np.testing.assert_allclose(np.asarray(fig2.data[0].x), np.asarray(hand.x))
    html = viewer.save_html(fig2, tmp_path / "barrett.html").read_text()
    found = '"name":"hand"' in html and "bh_finger_13_link" in html
    assert found
    assert_image(viewer.save_png(g, g.response, path=tmp_path / "barrett.png", elev=25, azim=-50))


def test_scene_view_bad_input(barrett_grasp, pinch, monkeypatch, tmp_path):
    g = barrett_grasp
    with pytest.raises(pg.InvalidInputError, match="needs its configuration q"):
        scene_elements(g.model, hand=g.hand)
    with pytest.raises(pg.InvalidInputError, match="GraspModel"):
        scene_elements(SimpleNamespace(hand=g.hand))
    with pytest.raises(pg.InvalidInputError, match=r"shape \(4, 3\)"):
        scene_elements(g.model, np.zeros((2, 3)))
    with pytest.raises(pg.InvalidInputError, match="joint values"):
        scene_elements(g.model, hand=g.hand, q=[0.0, 1.0])
    with pytest.raises(pg.InvalidInputError, match="force_scale"):
        pg.scene_figure(pinch, force_scale=-1.0)
    with pytest.raises(pg.InvalidInputError, match="plotly Figure"):
        viewer.save_html("fig", tmp_path / "x.html")
    with pytest.raises(pg.InvalidInputError, match="3D Axes"):
        _, ax = plt.subplots()
        scene_axes(pinch, ax=ax)
    # a response that did not resist (NaN forces) draws no arrows rather than failing
    bad = pg.passive_response(pinch, TAU, [0.0, 50.0, 0.0], method="prp")
    assert not bad.resistible
    el = scene_elements(pinch, bad)
    assert "contact forces" not in [s.name for s in el.segments]
    # plotly missing -> a pinograsp error naming the extra
    monkeypatch.setitem(sys.modules, "plotly.graph_objects", None)
    with pytest.raises(pg.MissingDependencyError, match=r'pip install "pinograsp\[viz\]"') as exc:
        viewer.scene_figure(pinch)
    assert isinstance(exc.value, ImportError) and exc.value.extra == "viz"


def test_scene_view_in_a_scene_analysis_frame(barrett_grasp):
    """Hand and object are re-expressed in the model's frame (a scene's ``frame``)."""
    g = barrett_grasp
    T = np.eye(4)
    T[:3, :3] = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]  # paper axes: y_a = z_base
    T[:3, 3] = [0.0, 0.0, 0.01]
    scene = SimpleNamespace(model=g.model, hand=g.hand, q=g.q, object=g.object, frame=T)
    el = scene_elements(scene)
    (obj,) = [m for m in el.meshes if m.name == "object"]
    # box (0.05, 0.06, 0.08) centred at z_base = 0.04 -> y_a in [-0.01, 0.07], z_a = -y_base
    np.testing.assert_allclose(obj.vertices.min(axis=0), [-0.025, -0.01, -0.03], atol=1e-12)
    np.testing.assert_allclose(obj.vertices.max(axis=0), [0.025, 0.07, 0.03], atol=1e-12)
    with pytest.raises(pg.InvalidInputError, match="frame"):
        scene_elements(g.model, frame=np.ones((4, 4)))
    scenes = pytest.importorskip("pinograsp.scenes.loading")
    case1 = scenes.load_scene("case1")
    el = scene_elements(case1)
    (obj,) = [m for m in el.meshes if m.name == "object"]
    lo, hi = obj.vertices.min(axis=0), obj.vertices.max(axis=0)
    for p in case1.model.points:  # every contact lies on the drawn box's surface (1 mm tolerance)
        assert np.all(p >= lo - 1e-3) and np.all(p <= hi + 1e-3)
        assert np.min(np.minimum(np.abs(p - lo), np.abs(p - hi))) < 1e-3
