"""Issue 33, the smaller items: distributed addresses time out with a named error (a fake
connection: ray and dask need not be installed), a thread-pool executor gives each row its own
grasp's warnings, direction strings take one sign, YAML keys come once, paths stay confined and
error messages never quote a file that failed to parse."""

import threading
import warnings
from concurrent.futures import ThreadPoolExecutor

import pytest

import pinograsp as pg
from pinograsp.batch.executors import connect


def test_an_unreachable_cluster_is_a_named_error():
    never = threading.Event()
    with pytest.raises(
        pg.InvalidInputError, match=r"address: no Ray cluster answered at '10.0.0.1:6379' within 0.05 s"
    ):
        connect("Ray", "10.0.0.1:6379", never.wait, seconds=0.05)  # a connection that never returns

    def refused():
        raise OSError("Timed out during handshake while connecting to tcp://10.0.0.1:8786 after 30 s")

    with pytest.raises(pg.InvalidInputError, match=r"cannot reach the Dask cluster .*OSError: Timed out"):
        connect("Dask", "tcp://10.0.0.1:8786", refused)
    assert connect("Dask", "tcp://here:8786", lambda: "client") == "client"


class _WarnWithCommand:
    """A score warning with the grasp's own command (preload tau0: the pinch scenes differ)."""

    columns = ("score",)

    def __call__(self, model, command):
        tau = max(command.values())
        warnings.warn(f"grasp at tau0={tau:g}", UserWarning, stacklevel=1)
        return {"score": 2 * 0.5 * tau / 0.1}  # the pinch's closed form, 2 mu tau0 / L [N]


def test_a_thread_pool_attributes_warnings_to_their_own_grasp():
    grasps = [pg.load_scene("pinch", preload=float(k)) for k in range(1, 13)]
    with ThreadPoolExecutor(4) as pool:
        df = pg.evaluate_grasps(grasps, score=_WarnWithCommand(), executor=pool)
    for k, (w, s) in enumerate(zip(df["warnings"], df["score"]), start=1):
        assert w == f"UserWarning: grasp at tau0={k:g}"  # its own, and only its own
        assert s == pytest.approx(10.0 * k, rel=1e-12)


@pytest.mark.parametrize("bad", ["+-fy", "--fy", "-+fy", "++fy"])
def test_a_direction_takes_one_sign(bad):
    with pytest.raises(pg.UnknownNameError, match="wrench axis"):
        pg.max_resistible_wrench(pg.examples.pinch(), 1.0, bad)
    assert pg.max_resistible_wrench(pg.examples.pinch(), 1.0, bad[-3:]).magnitude == 10.0


def test_duplicated_yaml_keys_are_an_error(tmp_path):
    text = (pg.load_scene("pinch").path).read_text()
    p = tmp_path / "s.yaml"
    p.write_text(text + "friction: 0.9\n")  # the file says 0.5 first: neither silently wins
    with pytest.raises(
        pg.SceneError, match=r"s.yaml: malformed YAML at line \d+, column 1: duplicated key 'friction'"
    ):
        pg.load_scene(p)
    p.write_text("grasps:\n  - {scene: pinch, id: a, id: b}\n")
    with pytest.raises(pg.SceneError, match="duplicated key 'id'"):
        pg.load_grasps(p)


SECRET = "root:x:0:0:SECRET-TOKEN-1234"


@pytest.mark.parametrize(
    "content", [SECRET + "\n", f"{SECRET}: 1\n", "{{{" + SECRET, "key: [" + SECRET, SECRET + ": [1, 2\n"]
)
def test_extends_never_quotes_another_file(tmp_path, content):
    outside = tmp_path / "private"
    outside.mkdir()
    (outside / "secret").write_text(content)
    folder = tmp_path / "upload"
    folder.mkdir()
    for ref in [str(outside / "secret"), "../private/secret"]:
        (folder / "s.yaml").write_text(f"extends: {ref}\n")
        with pytest.raises(pg.SceneError) as info:
            pg.load_scene(folder / "s.yaml")
        assert "SECRET" not in str(info.value) and "outside the folder" in str(info.value)
    (folder / "secret.yaml").write_text(content)  # inside the folder: read, still not quoted
    (folder / "s.yaml").write_text("extends: secret.yaml\n")
    with pytest.raises(pg.SceneError) as info:
        pg.load_scene(folder / "s.yaml")
    assert "SECRET" not in str(info.value)


def test_the_allow_list_opens_a_folder(tmp_path, monkeypatch):
    shared = tmp_path / "shared"
    shared.mkdir()
    (shared / "base.yaml").write_text((pg.load_scene("pinch").path).read_text())
    folder = tmp_path / "scenes"
    folder.mkdir()
    (folder / "s.yaml").write_text(f"extends: {shared / 'base.yaml'}\n")
    with pytest.raises(pg.SceneError, match="PINOGRASP_ALLOWED_PATHS"):
        pg.load_scene(folder / "s.yaml")
    monkeypatch.setenv("PINOGRASP_ALLOWED_PATHS", str(shared))
    scene = pg.load_scene(folder / "s.yaml")
    assert pg.max_resistible_wrench(scene.model, scene.command, "fy").magnitude == 10.0


@pytest.mark.parametrize("name", ["../scenes/pinch", "../../data/scenes/pinch", ".hidden", "sub/pinch"])
def test_builtin_scene_names_stay_in_the_data_folder(tmp_path, name):
    (tmp_path / "s.yaml").write_text(f"extends: {name}\n")
    with pytest.raises(pg.SceneError, match="extends"):
        pg.load_scene(tmp_path / "s.yaml")


URDF = """<robot name="r"><link name="base"><collision><geometry><mesh filename="{mesh}"/></geometry>
</collision></link></robot>"""


@pytest.mark.parametrize(
    "mesh", ["package://../../etc/x.stl", "../outside.stl", "/etc/x.stl", "file:///etc/x.stl"]
)
def test_urdf_meshes_stay_inside_their_folders(tmp_path, mesh):
    p = tmp_path / "hand.urdf"
    p.write_text(URDF.format(mesh=mesh))
    with pytest.raises(pg.UrdfError, match="outside the URDF's folder"):
        pg.Hand.from_urdf(p)


def test_a_urdf_with_too_many_links_is_refused_before_pinocchio(tmp_path):
    from pinograsp.robots.urdf import MAX_LINKS

    p = tmp_path / "big.urdf"
    p.write_text(
        '<robot name="r">' + "".join(f'<link name="l{i}"/>' for i in range(MAX_LINKS + 1)) + "</robot>"
    )
    with pytest.raises(pg.UrdfError, match=f"{MAX_LINKS + 1} links, more than the {MAX_LINKS}"):
        pg.Hand.from_urdf(p)
