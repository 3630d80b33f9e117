"""Contact states and slip directions in the 3D view (plotly, matplotlib) and in the summaries.

Closed forms used:

* wedge (faces at 20° from the y axis, normals ``n = (±cos 20°, sin 20°, 0)``): a slip along a
  face is ``±(sin 20°, -cos 20°, 0)``;
* palm pinch (fingers at ``x = ±0.05`` with ``c_n = 10`` N, ``mu = 0.5``, a palm below):
  under ``fy = -20`` N the fingers slide down, ``(0, -1, 0)``, each resisting ``mu c_n = 5`` N
  against the slip, and the palm sticks carrying the other 10 N; under ``fx = 2`` N the palm is
  separated.
"""

from __future__ import annotations

import dataclasses
import warnings
from types import SimpleNamespace

import numpy as np
import pytest
from matplotlib.colors import to_rgba

import pinograsp as pg
from pinograsp import examples
from pinograsp.viz import figures, viewer
from pinograsp.viz.scene_elements import COLORS, SLIP_FRACTION, SLIP_NAME, STATE_STYLES, scene_elements
from pinograsp.viz.scene_mpl import GID_CONTACTS, scene_axes

plt = figures.pyplot()
S20, C20 = np.sin(np.radians(20.0)), np.cos(np.radians(20.0))


pytestmark = pytest.mark.usefixtures("close_figures")


@pytest.fixture(scope="module")
def wedge_stick(wedge):
    return pg.passive_response(wedge, 1.0, [0.0, 2.0, 0.0], method="energetic")


@pytest.fixture(scope="module")
def wedge_slide(wedge):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pg.AuditWarning)  # PRP's wedging artefact, flagged by the audit
        return pg.passive_response(wedge, 1.0, [0.0, 3.0, 0.0], method="prp")


@pytest.fixture(scope="module")
def palm():
    return examples.palm_pinch()


@pytest.fixture(scope="module")
def palm_slide(palm):
    return pg.passive_response(palm, 1.0, [0.0, -20.0, 0.0], method="energetic")


def _stateless(r):
    """The response as an older one would be: no states, no slip."""
    return dataclasses.replace(r, contact_states=(), contact_slip=None)


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _slip_shafts(el):
    found = [s for s in el.segments if s.name == SLIP_NAME]
    return found[0].segments if found else np.zeros((0, 2, 3))


# ----------------------------------------------------------------------------- elements
def test_sliding_contacts_get_arrows_along_the_normalised_slip(wedge, wedge_slide):
    r = wedge_slide
    assert r.contact_states == ("sliding", "sliding")
    el = scene_elements(wedge, r)
    assert el.contact_states == r.contact_states
    u = _unit(r.contact_slip)
    np.testing.assert_allclose(u, [[S20, -C20, 0.0], [-S20, -C20, 0.0]], atol=1e-9)  # along the faces
    np.testing.assert_allclose(np.einsum("ij,ij->i", u, wedge.frames[:, :, 0]), 0.0, atol=1e-12)
    np.testing.assert_allclose(el.slip_directions, u, atol=1e-12)
    shafts = _slip_shafts(el)
    assert shafts.shape == (2, 2, 3)
    np.testing.assert_allclose(shafts[:, 0], wedge.points, atol=1e-15)  # from the contact points
    np.testing.assert_allclose(_unit(shafts[:, 1] - shafts[:, 0]), u, atol=1e-9)
    # fixed length: SLIP_FRACTION x the scene size (contacts 6 cm apart), the head's apex at the tip
    assert el.size == pytest.approx(0.06, abs=1e-12)
    assert el.slip_length == pytest.approx(SLIP_FRACTION * 0.06, abs=1e-15)
    (heads,) = [m for m in el.meshes if m.name == SLIP_NAME]
    apexes = heads.vertices.reshape(2, -1, 3)[:, 0]
    np.testing.assert_allclose(apexes, wedge.points + el.slip_length * u, atol=1e-15)
    assert el.title == "2 contacts — resisted: 2 sliding"
    assert (
        "state: sliding" in el.point_labels[0]
        and "slip direction = [0.342, -0.94, 0.0]" in el.point_labels[0]
    )
    assert np.all(el.bounds[0] <= apexes.min(axis=0)) and np.all(el.bounds[1] >= apexes.max(axis=0))


def test_sticking_contacts_get_no_arrow(wedge, wedge_stick, pinch):
    assert wedge_stick.contact_states == ("sticking", "sticking")
    el = scene_elements(wedge, wedge_stick)
    assert el.contact_states == ("sticking", "sticking") and SLIP_NAME not in [s.name for s in el.segments]
    np.testing.assert_array_equal(el.slip_directions, np.zeros((2, 3)))
    assert el.title == "2 contacts — resisted: 2 sticking"
    r = pg.passive_response(pinch, 1.0, [0.0, 5.0, 0.0], method="energetic")
    assert r.contact_states == ("sticking", "sticking")  # c_t = 2.5 N < mu c_n = 5 N
    el = scene_elements(pinch, r)
    assert [k for k, _ in el.state_groups()] == ["sticking"] and not len(_slip_shafts(el))


def test_energetic_slip_arrows_oppose_friction(palm, palm_slide):
    r = palm_slide
    assert r.contact_states == ("sliding", "sliding", "sticking")
    el = scene_elements(palm, r)
    shafts = _slip_shafts(el)
    assert shafts.shape == (2, 2, 3)  # the two fingers, not the palm
    u = _unit(shafts[:, 1] - shafts[:, 0])
    np.testing.assert_allclose(u, [[0.0, -1.0, 0.0], [0.0, -1.0, 0.0]], atol=1e-9)
    np.testing.assert_allclose(u, _unit(r.contact_slip[:2]), atol=1e-9)
    # maximum dissipation: the friction on the object is mu c_n = 5 N against the drawn slip
    np.testing.assert_allclose(np.einsum("ij,ij->i", r.contact_forces_world[:2], u), -5.0, atol=1e-6)
    np.testing.assert_allclose(r.contact_forces_world[2], [0.0, 10.0, 0.0], atol=1e-6)
    assert el.title == "3 contacts — resisted: 1 sticking, 2 sliding"
    groups = dict(el.state_groups())
    assert groups["sliding"].tolist() == [0, 1] and groups["sticking"].tolist() == [2]


def test_states_of_a_max_wrench_are_its_responses(palm):
    mw = pg.max_resistible_wrench(palm, 1.0, [0.0, -1.0, 0.0], method="energetic")
    assert mw.unbounded and mw.response.contact_states == ("sliding", "sliding", "sticking")
    el = scene_elements(palm, mw)
    assert el.contact_states == mw.response.contact_states
    np.testing.assert_allclose(el.slip_directions[:2], [[0.0, -1.0, 0.0]] * 2, atol=1e-9)


# ----------------------------------------------------------------------------- no states: as before
def test_responses_without_states_draw_as_before(wedge, wedge_slide):
    r = wedge_slide
    old = _stateless(r)
    el, el_old = scene_elements(wedge, r), scene_elements(wedge, old)
    assert el_old.contact_states == () and el_old.slip_directions is None and el_old.slip_length == 0.0
    assert el_old.title == "2 contacts — resisted"
    assert [s.name for s in el_old.segments] == ["contact normals", "contact forces", "external force"]
    assert [m.name for m in el_old.meshes] == ["friction cones", "contact forces", "external force"]
    # everything else is what the stateful view draws, minus the slip arrows and the state text
    kept = [s for s in el.segments if s.name != SLIP_NAME]
    for a, b in zip(kept, el_old.segments, strict=True):
        assert a.name == b.name and a.color == b.color and np.array_equal(a.segments, b.segments)
    for a, b in zip([m for m in el.meshes if m.name != SLIP_NAME], el_old.meshes, strict=True):
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    for new, before in zip(el.point_labels, el_old.point_labels, strict=True):
        assert new.startswith(before) and "state" not in before
    # forces given as an array, or a states tuple that does not fit, carry no states either
    assert scene_elements(wedge, r.contact_forces_world).contact_states == ()
    for bad in (("sliding",), ("sliding", "slipping"), None, "sliding"):
        fake = SimpleNamespace(
            contact_forces_world=r.contact_forces_world, wrench=r.wrench, contact_states=bad
        )
        assert scene_elements(wedge, fake).contact_states == ()
    # a non-finite slip keeps the states but draws no arrow
    nan_slip = dataclasses.replace(r, contact_slip=np.full((2, 3), np.nan))
    el_nan = scene_elements(wedge, nan_slip)
    assert el_nan.contact_states == r.contact_states and not len(_slip_shafts(el_nan))


def test_matplotlib_without_states_is_one_scatter(wedge, wedge_slide):
    ax = scene_axes(wedge, _stateless(wedge_slide))
    points = [c for c in ax.collections if hasattr(c, "_offsets3d")]
    assert len(points) == 1 and points[0].get_gid() is None
    np.testing.assert_allclose(points[0].get_facecolor()[0], to_rgba(COLORS["contacts"]))
    labels = [h.get_label() for h in ax.get_legend().legend_handles]
    assert labels == ["friction cones", "contact normals", "contact forces", "external force", "contacts"]
    assert not [c for c in ax.collections if "slip" in str(c.get_gid())]


# ----------------------------------------------------------------------------- matplotlib
def _state_scatters(ax):
    return {
        c.get_gid()[len(GID_CONTACTS) :]: c
        for c in ax.collections
        if str(c.get_gid()).startswith(GID_CONTACTS)
    }


def test_matplotlib_colours_markers_and_legend_per_state(palm, palm_slide):
    ax = scene_axes(palm, palm_slide)
    sc = _state_scatters(ax)
    assert set(sc) == {"sliding", "sticking"}
    for state, idx in (("sliding", [0, 1]), ("sticking", [2])):
        np.testing.assert_allclose(np.column_stack(sc[state]._offsets3d), palm.points[idx], atol=1e-15)
        np.testing.assert_allclose(sc[state].get_facecolor()[0], to_rgba(STATE_STYLES[state][0]))
    labels = [h.get_label() for h in ax.get_legend().legend_handles]
    assert labels[-3:] == [SLIP_NAME, "contacts: sticking", "contacts: sliding"]
    (shafts,) = [c for c in ax.collections if c.get_gid() == "pinograsp-slip-directions"]
    segs = np.array([np.asarray(s) for s in shafts._segments3d])
    np.testing.assert_allclose(_unit(segs[:, 1] - segs[:, 0]), _unit(palm_slide.contact_slip[:2]), atol=1e-9)
    np.testing.assert_allclose(shafts.get_color()[0], to_rgba(COLORS["slip"]))
    assert [c for c in ax.collections if c.get_gid() == "pinograsp-slip-directions-heads"]
    assert ax.get_title() == "3 contacts — resisted: 1 sticking, 2 sliding"


def test_matplotlib_separated_contact_is_an_open_marker(palm):
    r = pg.passive_response(palm, 1.0, [2.0, 0.0, 0.0], method="energetic")
    assert r.contact_states == ("sticking", "sticking", "separated")
    np.testing.assert_allclose(r.contact_forces[2], 0.0, atol=1e-9)  # the palm carries nothing
    assert np.linalg.norm(r.contact_slip[2]) > 0  # it moves, but a separated contact gets no arrow
    ax = scene_axes(palm, r)
    sc = _state_scatters(ax)
    np.testing.assert_allclose(np.column_stack(sc["separated"]._offsets3d), palm.points[[2]], atol=1e-15)
    fill = sc["separated"].get_facecolor()
    assert len(fill) == 0 or np.all(fill[:, 3] == 0.0)  # open: no fill
    np.testing.assert_allclose(sc["separated"].get_edgecolor()[0], to_rgba(COLORS["separated"]))
    assert not [c for c in ax.collections if "slip" in str(c.get_gid())]


# ----------------------------------------------------------------------------- plotly
def test_plotly_traces_per_state_and_slip_arrows(wedge, wedge_slide, palm, palm_slide):
    pytest.importorskip("plotly")
    fig = viewer.scene_figure(palm, palm_slide)
    traces = {(t.name, t.type): t for t in fig.data}
    for state, idx in (("sliding", [0, 1]), ("sticking", [2])):
        t = traces[(f"contacts: {state}", "scatter3d")]
        np.testing.assert_allclose(np.column_stack([t.x, t.y, t.z]), palm.points[idx], atol=1e-15)
        assert t.marker.color == STATE_STYLES[state][0] and t.marker.symbol == STATE_STYLES[state][3]
        assert all(f"state: {state}" in h for h in t.hovertext)
    shafts = traces[(SLIP_NAME, "scatter3d")]
    seg = np.column_stack([shafts.x, shafts.y, shafts.z]).reshape(-1, 3, 3)[:, :2]
    np.testing.assert_allclose(_unit(seg[:, 1] - seg[:, 0]), _unit(palm_slide.contact_slip[:2]), atol=1e-9)
    assert (SLIP_NAME, "mesh3d") in traces and ("contacts", "scatter3d") not in traces
    # without states: the single "contacts" trace and the same traces as before
    old = viewer.scene_figure(wedge, _stateless(wedge_slide))
    assert [t.name for t in old.data] == [
        "friction cones",
        "contact forces",
        "external force",
        "contact normals",
        "contact forces",
        "external force",
        "contacts",
    ]
    assert old.data[-1].marker.color == COLORS["contacts"]
    new = viewer.scene_figure(wedge, wedge_slide)
    assert [t.name for t in new.data if t.name not in (SLIP_NAME, "contacts: sliding")] == [
        t.name for t in old.data if t.name != "contacts"
    ]


# ----------------------------------------------------------------------------- summaries
def test_summaries_list_the_state_per_contact(wedge, wedge_slide, palm_slide):
    text = palm_slide.summary()
    assert (
        "contact states: left sliding (slip direction (0, -1, 0)), "
        "right sliding (slip direction (0, -1, 0)), palm sticking"
    ) in text.splitlines()
    assert "contact states: left sliding (slip direction (0.342, -0.9397, 0)), " in wedge_slide.summary()
    assert "contact states" not in _stateless(palm_slide).summary()
    mw = pg.max_resistible_wrench(wedge, 1.0, [0.0, 1.0, 0.0], method="energetic")
    assert "contact states at 2.55652 N: left sticking, right sticking" in mw.summary()
