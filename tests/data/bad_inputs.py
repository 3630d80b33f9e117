"""The bad-input table (issue 26, docs/errors.md "Input domains"): designed inputs across the API,
the CLI, scene/hand/batch files and the simulation, each with its expected named error (a type
and a fragment of the message) or verdict. ``tests/test_bad_inputs.py`` runs every row.

A row is ``Case(id, area, run, error, match)``: ``run(tmp)`` gets a fresh folder; with ``error``
the call must raise exactly that pinograsp error with ``match`` in the message; with
``error=None`` it must return something for which ``verdict`` holds. CLI rows return
``(exit code, stderr)`` and expect exit code 2 and ``match`` on stderr (or a verdict).
"""

from __future__ import annotations

import contextlib
import io
import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pinograsp as pg
from pinograsp import examples


@dataclass(frozen=True)
class Case:
    id: str
    area: str  # api, cli, scene, hand, batch, sim
    run: Callable[[Path], Any]
    error: type | None = pg.InvalidInputError
    match: str = ""
    verdict: Callable[[Any], bool] | None = None


CASES: list[Case] = []


#: The bisection's domains (steps <= 60, upper within the grasp's force scale) are the searching
#: methods'; the default quasi-static path does not bisect (the method table, core/methods.py:
#: not bounded by upper and steps).
IT = "iterative"


def case(id: str, area: str, run: Callable[[Path], Any], error: type | None = pg.InvalidInputError,
         match: str = "", verdict: Callable[[Any], bool] | None = None) -> None:  # fmt: skip
    CASES.append(Case(id, area, run, error, match, verdict))


def pinch() -> pg.GraspModel:
    return examples.pinch()


def mw(**kw: Any) -> Callable[[Path], Any]:
    args = dict(command=1.0, direction="fy", upper=100.0, steps=4) | kw
    return lambda tmp: pg.max_resistible_wrench(pinch(), args.pop("command"), args.pop("direction"), **args)


def cli(*argv: str) -> Callable[[Path], Any]:
    """The CLI in-process: ``(exit code, stderr)`` (stdout is kept as ``json`` when asked)."""

    def run(tmp: Path) -> tuple[int, str]:
        from pinograsp.cli import main

        out, err = io.StringIO(), io.StringIO()
        argv2 = [a.replace("{tmp}", str(tmp)) for a in argv]
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            rc = main(argv2)
        return rc, err.getvalue() + out.getvalue()

    return run


def cli_json(*argv: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> dict:
        rc, text = cli(*argv, "--json")(tmp)
        assert rc == 0, text
        return json.loads(text)

    return run


# ------------------------------------------------------------------------------ API: searches
case("upper-1e300", "api", mw(upper=1e300), match="upper: must be in [1e-06, 1e+12]")
case("upper-1e200-steps-20", "api", mw(upper=1e200, steps=20), match="upper")
case("upper-1e12-pinch", "api", mw(upper=1e12, method=IT), match="times the grasp's force scale")
case("upper-negative", "api", mw(upper=-1.0), match="upper")
case("upper-nan", "api", mw(upper=float("nan")), match="upper: must be finite")
case("upper-zero", "api", mw(upper=0.0), match="upper")
case("upper-string", "api", mw(upper="100"), match="upper")
case("steps-1024", "api", mw(steps=1024, method=IT), match="steps: must be an integer in [1, 60]")
case("steps-1e6", "api", mw(steps=10**6, method=IT), match="steps")
# the default path does not bisect: steps and upper do not apply (the closed form 2 mu tau0 / L = 10 N)
case("steps-1024-path", "api", mw(steps=1024, upper=1e12), None, verdict=lambda r: r.magnitude == 10.0)
case("steps-zero", "api", mw(steps=0), match="steps")
case("steps-float", "api", mw(steps=2.5), match="steps")
case("eps-1e300", "api", mw(eps=1e300), match="eps")
case("eps-above-force-scale", "api", mw(eps=50.0, method="iterative"), match="every net wrench would count")
case("tolerance-1", "api", mw(tolerance=1.0), match="tolerance: must be in [1e-12, 0.01]")
case("tolerance-1e-300", "api", mw(tolerance=1e-300), match="tolerance")
case("gamma-1e300", "api", mw(gamma=1e300), match="gamma")
case("max-iterations-1e12", "api", mw(max_iterations=10**12), match="max_iterations")
case("max-nodes-1e12", "api", mw(max_nodes=10**12), match="max_nodes")
case("time-limit-1e300", "api", mw(time_limit=1e300), match="time_limit")
case("bigm-1e300", "api", mw(bigm=1e300), match="bigm")
case("command-1e300", "api", mw(command=1e300), match="command: must be within")
case("command-negative", "api", mw(command=-1.0), match="negative command")
case("command-nan", "api", mw(command=float("nan")), match="command: contains NaN")
case("direction-zero", "api", mw(direction=[0.0, 0.0, 0.0]), match="direction")
# ------------------------------------------------------------------------------ API: responses
case("wrench-1e12-pinch", "api", lambda t: pg.passive_response(pinch(), 1.0, [1e12, 0, 0]),
     match="times the grasp's force scale")  # fmt: skip
case("wrench-1e300", "api", lambda t: pg.passive_response(pinch(), 1.0, [0, 1e300, 0]), match="exceeds 1e+12")
case("wrench-inf", "api", lambda t: pg.passive_response(pinch(), 1.0, [0, float("inf"), 0]), match="wrench")
case("wrench-4-numbers", "api", lambda t: pg.passive_response(pinch(), 1.0, [0, 1, 0, 0]), match="wrench")
case("preload-1e300", "api", lambda t: pg.passive_response(pinch(), 1e300, [0, 1, 0]), match="command")
case(
    "pinch-x-unbounded-forces-physical", "api",
    lambda t: pg.passive_response(pinch(), 1.0, [20.0, 0, 0]), None,
    verdict=lambda r: r.resistible and r.audit.ok
    and (r.contact_forces[:, 0] >= -r.audit.tolerance).all(),
)  # fmt: skip
case("audit-pulling-contact", "api", lambda t: pg.Audit(0.0, 0.0, 0.0, 0.0, pull=5.9), None,
     verdict=lambda a: not a.ok and "PULLS" in a.summary())  # fmt: skip
case("audit-overflow", "api", lambda t: pg.Audit(0.0, 0.0, 0.0, 0.0, finite=False), None,
     verdict=lambda a: not a.ok and "non-finite" in a.summary())  # fmt: skip
case("compliance-ragged-kt", "api",
     lambda t: pg.linear_compliance(pinch(), [0, 1, 0], tangential_stiffness=[[1.0, 2.0], [3.0]]),
     match="tangential_stiffness")  # fmt: skip
case("compliance-kt-1e300", "api",
     lambda t: pg.linear_compliance(pinch(), [0, 1, 0], tangential_stiffness=1e300),
     match="tangential_stiffness")  # fmt: skip
# ------------------------------------------------------------------------------ API: sizes
case("profile-n-1e12", "api", lambda t: pg.resistance_profile(pinch(), 1.0, n=10**12), match="n: must be")
case("profile-n-zero", "api", lambda t: pg.resistance_profile(pinch(), 1.0, n=0), match="n")
case("profile-upper-1e300", "api", lambda t: pg.resistance_profile(pinch(), 1.0, n=4, upper=1e300),
     match="upper")  # fmt: skip
case("set-n-1e9", "api", lambda t: pg.resistance_set(pinch(), 1.0, n=10**9), match="n: must be")
case("set-length-1e-300", "api", lambda t: pg.resistance_set(pinch(), 1.0, n=4, length=1e-300),
     match="length: must be in")  # fmt: skip
case("set-length-1e300", "api", lambda t: pg.resistance_set(pinch(), 1.0, n=4, length=1e300), match="length")
case("score-length-1e-300", "api", lambda t: pg.grasp_score(pinch(), 1.0, n=4, length=1e-300),
     match="length")  # fmt: skip
case("score-length-1.35e154", "api", lambda t: pg.grasp_score(pinch(), 1.0, n=4, length=1.35e154),
     match="length")  # fmt: skip
case("score-steps-1024", "api", lambda t: pg.grasp_score(pinch(), 1.0, n=4, steps=1024, method=IT),
     match="steps")  # fmt: skip
case("score-quantile-1.5", "api", lambda t: pg.grasp_score(pinch(), 1.0, n=4, quantile=1.5), match="quantile")
case("ferrari-canny-length-1e-17", "api", lambda t: pg.ferrari_canny(pinch(), 1e-17), match="length")
case("ferrari-canny-length-1e200", "api", lambda t: pg.ferrari_canny(pinch(), 1e200), match="length")
case("ferrari-canny-length-ok", "api", lambda t: pg.ferrari_canny(pinch(), 0.05), None,
     verdict=lambda v: abs(v - pg.ferrari_canny(pinch())) < 1e-12 and v > 0)  # fmt: skip
# ------------------------------------------------------------------------------ API: preloads
case("optimal-grid-1e9", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], grid=10**9), match="grid")
case("optimal-max-command-1e300", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], max_command=1e300),
     match="max_command")  # fmt: skip
case("optimal-refine-1e6", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], refine=10**6), match="refine")
case("optimal-upper-1e300", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], upper=1e300), match="upper")
case("optimal-steps-1000", "api",
     lambda t: pg.optimal_preload(pinch(), ["fy"], steps=1000, method=IT), match="steps")  # fmt: skip
case("optimal-budget-1e300", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], budget=1e300),
     match="budget")  # fmt: skip
case("preload-max-command-1e300", "api", lambda t: pg.equilibrium_preload(pinch(), max_command=1e300),
     match="max_command")  # fmt: skip
case("preload-max-command-zero", "api", lambda t: pg.equilibrium_preload(pinch(), max_command=0.0),
     match="max_command")  # fmt: skip
case("preload-grip-1e300", "api",
     lambda t: pg.equilibrium_preload(pinch(), objective="least_norm", grip=1e300), match="grip")  # fmt: skip


def _no_actuator(t: Path) -> Any:
    c = pg.Contact.revolute([-0.05, 0, 0], [1, 0, 0], {0: ([-0.05, -0.1, 0], [0, 0, -1])}, nq=2)
    d = pg.Contact.revolute([0.05, 0, 0], [-1, 0, 0], {1: ([0.05, -0.1, 0], [0, 0, 1])}, nq=2)
    return pg.equilibrium_preload(pg.GraspModel.from_contacts([c, d], actuators=[], planar=True))


case("preload-no-actuator", "api", _no_actuator, pg.ModelError, "no actuator reaches a contact")
case("preload-pinch-bound-2", "api", lambda t: pg.equilibrium_preload(pinch(), max_command=2.0), None,
     verdict=lambda c: c.status == "found" and c.command == {"left": 2.0, "right": 2.0})  # fmt: skip
case("preload-case1-bound-0.5", "api",
     lambda t: pg.equilibrium_preload(pg.load_scene("case1").model, max_command=0.5), None,
     verdict=lambda c: c.status == "found" and max(c.command.values()) == 0.5)  # fmt: skip
# ------------------------------------------------------------------------------ API: constructors
case("revolute-nq-1e9", "api", lambda t: pg.Contact.revolute([0, 0, 0], [1, 0, 0], {}, nq=10**9),
     match="nq: must be an integer in [0, 10000]")  # fmt: skip
case(
    "revolute-nq-negative", "api", lambda t: pg.Contact.revolute([0, 0, 0], [1, 0, 0], {}, nq=-1), match="nq"
)
case(
    "contact-mu-1e6",
    "api",
    lambda t: pg.Contact([0, 0, 0], [1, 0, 0], mu=1e6),
    match="mu: must be in [0, 100]",
)
case("contact-mu-negative", "api", lambda t: pg.Contact([0, 0, 0], [1, 0, 0], mu=-0.1), match="mu")
case("contact-stiffness-1e300", "api", lambda t: pg.Contact([0, 0, 0], [1, 0, 0], stiffness=1e300),
     match="stiffness")  # fmt: skip
case("contact-stiffness-1e-300", "api", lambda t: pg.Contact([0, 0, 0], [1, 0, 0], stiffness=1e-300),
     match="stiffness")  # fmt: skip
case("box-size-1e-300", "api", lambda t: pg.RigidObject.box((1e-300, 0.05, 0.05)), match="size[0]")
case("sphere-radius-1e300", "api", lambda t: pg.RigidObject.sphere(1e300), match="radius")
case("cylinder-length-zero", "api", lambda t: pg.RigidObject.cylinder(0.02, 0.0), match="length")
case("sample-n-1e10", "api",
     lambda t: pg.sample_grasps("underactuated_2f", pg.ObjectSpec("box", size=(0.05, 0.05, 0.05)), 10**10),
     match="n: must be an integer in [1, 1000000]")  # fmt: skip
case("sample-n-zero", "api",
     lambda t: pg.sample_grasps("underactuated_2f", pg.ObjectSpec("box", size=(0.05, 0.05, 0.05)), 0),
     match="n")  # fmt: skip
case("settings-eps-1e300", "api", lambda t: pg.Settings(eps=1e300).validated(), match="eps: must be in")
case("settings-max-nodes-1e12", "api", lambda t: pg.Settings(max_nodes=10**12).validated(), match="max_nodes")


def hand_and_box() -> tuple[Any, Any]:
    return pg.Hand.builtin("underactuated_2f"), pg.RigidObject.box((0.05, 0.05, 0.02), [0.0, 0.07, 0.0])


def close(**kw: Any) -> Callable[[Path], Any]:
    return lambda t: (lambda h, o: h.close_on(o, **kw))(*hand_and_box())


case("close-tolerance-1e300", "api", close(tolerance=1e300), match="tolerance: must be in (0, 0.05] m")
case("close-step-1e-300", "api", close(step=1e-300), match="step: must be in")
case("close-max-steps-1e12", "api", close(max_steps=10**12), match="max_steps")
case("detect-tolerance-1e300", "api",
     lambda t: pg.detect_contacts(*hand_and_box()[:1], None, hand_and_box()[1], tolerance=1e300),
     match="tolerance")  # fmt: skip
case("hand-q-1e300", "api",
     lambda t: pg.link_distances(hand_and_box()[0], {"uf_j11": 1e300}, hand_and_box()[1]),
     match="within ±1000")  # fmt: skip
case("object-pose-1e300", "api", lambda t: pg.RigidObject.box((0.05, 0.05, 0.02), [1e300, 0, 0]),
     match="pose translation")  # fmt: skip

# ------------------------------------------------------------------------------ CLI
case("cli-preload-pinch-2", "cli", cli_json("preload", "pinch", "--max-command", "2"), None,
     verdict=lambda d: d["status"] == "found" and d["preload"] == {"left": 2.0, "right": 2.0})  # fmt: skip
case("cli-preload-case1-0.5", "cli", cli_json("preload", "case1", "--max-command", "0.5"), None,
     verdict=lambda d: d["status"] == "found")  # fmt: skip
case("cli-preload-fig1-0.6", "cli", cli_json("preload", "fig1", "--max-command", "0.6"), None,
     verdict=lambda d: d["status"] == "found")  # fmt: skip
case("cli-preload-max-command-1e300", "cli", cli("preload", "pinch", "--max-command", "1e300"), None,
     verdict=lambda r: r[0] == 2 and "max_command" in r[1])  # fmt: skip
case("cli-upper-1e300", "cli", cli("max-wrench", "pinch", "-d", "fy", "--upper", "1e300"), None,
     verdict=lambda r: r[0] == 2 and "--upper" in r[1])  # fmt: skip
case("cli-steps-1024", "cli",
     cli("max-wrench", "pinch", "-d", "fy", "--steps", "1024", "--method", IT), None,
     verdict=lambda r: r[0] == 2 and "--steps" in r[1])  # fmt: skip
case("cli-upper-beyond-force-scale", "cli",
     cli("max-wrench", "pinch", "-d", "fy", "--upper", "1e9", "--method", IT), None,
     verdict=lambda r: r[0] == 2 and "force scale" in r[1])  # fmt: skip
case("cli-profile-n-1e12", "cli", cli("profile", "pinch", "-n", "1000000000000"), None,
     verdict=lambda r: r[0] == 2 and "n: must be" in r[1])  # fmt: skip
case("cli-set-n-1e12", "cli", cli("resistance-set", "pinch", "-n", "1000000000000"), None,
     verdict=lambda r: r[0] == 2 and "n: must be" in r[1])  # fmt: skip
case("cli-set-length-1e-300", "cli", cli("resistance-set", "pinch", "-n", "4", "--length", "1e-300"), None,
     verdict=lambda r: r[0] == 2 and "length" in r[1])  # fmt: skip
case("cli-optimal-grid-1e9", "cli",
     cli("optimal-preload", "pinch", "-w", "fy=3", "--grid", "1000000000"), None,
     verdict=lambda r: r[0] == 2 and "grid" in r[1])  # fmt: skip
case("cli-analyze-wrench-1e12", "cli", cli("analyze", "pinch", "--wrench", "0,1e12,0"), None,
     verdict=lambda r: r[0] == 2 and "force scale" in r[1])  # fmt: skip


def _out_under_a_file(t: Path) -> tuple[int, str]:
    (t / "file").write_text("x")
    return cli("max-wrench", "pinch", "-d", "fy", "--steps", "3", "--out", str(t / "file" / "sub"))(t)


case("cli-out-under-a-file", "cli", _out_under_a_file, None,
     verdict=lambda r: r[0] == 2 and "--out" in r[1])  # fmt: skip
case("cli-simulate-timestep-1e-300", "cli",
     cli("simulate", "pinch", "-d", "fy", "--timestep", "1e-300"), None,
     verdict=lambda r: r[0] == 2 and "timestep" in r[1])  # fmt: skip
case("cli-simulate-upper-1e300", "cli", cli("simulate", "pinch", "-d", "fy", "--upper", "1e300"), None,
     verdict=lambda r: r[0] == 2 and "upper" in r[1])  # fmt: skip
case("cli-simulate-stiffness-1e300", "cli",
     cli("simulate", "pinch", "-d", "fy", "--stiffness", "1e300"), None,
     verdict=lambda r: r[0] == 2 and "stiffness" in r[1])  # fmt: skip

# ------------------------------------------------------------------------------ scene files
BOMB = "\n".join(
    [
        'a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]',
        *[f"{c}: &{c} [{', '.join(['*' + p] * 9)}]" for p, c in zip("abcdefgh", "bcdefghi")],
    ]
)
PINCH = (Path(pg.__file__).parent / "data" / "scenes" / "pinch.yaml").read_text()


def scene(text: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        p = tmp / "scene.yaml"
        p.write_text(text)
        return pg.load_scene(p)

    return run


def pinch_with(old: str, new: str) -> str:
    assert old in PINCH, old
    return PINCH.replace(old, new)


case("scene-alias-bomb", "scene", scene(BOMB + "\nname: *i\n"), pg.SceneError, "aliases")
case("scene-one-alias", "scene", scene(PINCH + "\nx: &x 1\ny: *x\n"), pg.SceneError, "aliases")
case("scene-upper-1e300", "scene", scene(pinch_with("upper: 1000", "upper: 1.0e+300")), pg.SceneError,
     "analysis.upper: must be in")  # fmt: skip
case("scene-upper-1e200", "scene", scene(pinch_with("upper: 1000", "upper: 1.0e+200")), pg.SceneError,
     "analysis.upper")  # fmt: skip
case(
    "scene-steps-1024",
    "scene",
    scene(pinch_with("steps: 20", f"method: {IT}\n  steps: 1024")),
    pg.SceneError,
    "analysis.steps",
)
case("scene-n-1e12", "scene", scene(pinch_with("n: 72", "n: 1000000000000")), pg.SceneError, "analysis.n")
case("scene-friction-1e6", "scene", scene(pinch_with("friction: 0.5", "friction: 1.0e+6")), pg.PinograspError,
     "mu")  # fmt: skip
case("scene-friction-negative", "scene", scene(pinch_with("friction: 0.5", "friction: -0.5")),
     pg.PinograspError, "")  # fmt: skip
case("scene-stiffness-1e300", "scene", scene(pinch_with("stiffness: 1.0", "stiffness: 1.0e+300")),
     pg.PinograspError, "stiffness")  # fmt: skip
case("scene-preload-1e300", "scene",
     lambda t: scene(pinch_with("preload: 1.0 ", "preload: 1.0e+300 "))(t).passive_response([0, 1, 0]),
     pg.PinograspError, "command")  # fmt: skip
case(
    "scene-eps-1e300",
    "scene",
    scene(pinch_with("  steps: 20", "  steps: 20\n  eps: 1.0e+300")),
    pg.PinograspError,
    "eps",
)
case("scene-not-a-mapping", "scene", scene("[1, 2, 3]"), pg.SceneError, "expected a mapping")

# ------------------------------------------------------------------------------ hand files


def hand_file(text: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        p = tmp / "hand.yaml"
        p.write_text(text)
        return pg.HandDescription.from_yaml(p)

    return run


case("hand-alias-bomb", "hand", hand_file(BOMB + "\njoints: *i\n"), pg.ModelFileError, "aliases")
case("hand-missing-file", "hand", lambda t: pg.HandDescription.from_yaml(t / "none.yaml"), pg.ModelFileError,
     "not found")  # fmt: skip
case("hand-malformed", "hand", hand_file("joints: [a, b\n"), pg.ModelFileError, "malformed YAML")

# ------------------------------------------------------------------------------ batch files
BATCH = """
defaults: {hand: underactuated_2f, mu: 0.5}
score: {upper: 50, steps: 6}
grasps:
  - scene: pinch
sample:
  - object: {shape: box, size: [0.05, 0.05, 0.05], pose: {xyz: [0, 0.07, 0]}}
    n: 2
"""


def batch(text: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        p = tmp / "grasps.yaml"
        p.write_text(text)
        return pg.load_grasps(p)

    return run


def batch_with(old: str, new: str) -> str:
    assert old in BATCH, old
    return BATCH.replace(old, new)


case("batch-alias-bomb", "batch", batch(BOMB + "\nscore: {upper: *i}\n"), pg.SceneError, "aliases")
case("batch-upper-1e300", "batch", batch(batch_with("upper: 50", "upper: 1.0e+300")), pg.SceneError,
     "score.upper")  # fmt: skip
case("batch-steps-1024", "batch", batch(batch_with("steps: 6", f"method: {IT}, steps: 1024")), pg.SceneError,
     "score.steps")  # fmt: skip
case("batch-sample-n-1e10", "batch", batch(batch_with("n: 2", "n: 10000000000")), pg.SceneError, "n")
case("batch-size-1e-300", "batch", batch(batch_with("[0.05, 0.05, 0.05]", "[1.0e-300, 0.05, 0.05]")),
     pg.SceneError, "size")  # fmt: skip
case("batch-mu-negative", "batch", batch(batch_with("mu: 0.5", "mu: -1")), pg.SceneError, "mu")

# ------------------------------------------------------------------------------ simulation


def sim(**kw: Any) -> Callable[[Path], Any]:
    return lambda t: pg.simulate_max_wrench(pg.load_scene("pinch"), "fy", **kw)


case("sim-timestep-1e-300", "sim", sim(timestep=1e-300), match="timestep: must be in [1e-07, 0.01]")
case("sim-timestep-1", "sim", sim(timestep=1.0), match="timestep")
case("sim-tolerance-1e-300", "sim", sim(tolerance=1e-300), match="tolerance: must be in")
case("sim-upper-1e300", "sim", sim(upper=1e300), match="upper")
case("sim-upper-beyond-force-scale", "sim", sim(upper=1e9), match="force scale")
case("sim-stiffness-1e300", "sim", sim(stiffness=1e300), match="stiffness")
case("sim-stiffness-1e-300", "sim", sim(stiffness=1e-300), match="stiffness")
case("sim-start-tiny-budget", "sim", sim(start=1e-300, timestep=1e-6), match="integration steps")
case("sim-ramp-time-1e6", "sim", sim(ramp_time=1e6), match="integration steps")
case("sim-unknown-option", "sim", sim(bogus=1), match="unknown simulation option")

# ------------------------------------------------------------------------------ issue 33: reliability
#: A line of a private file: never quoted by an error message.
SECRET = "root:x:0:0:SECRET-TOKEN"
NEST = "a: " + "[" * 500 + "]" * 500 + "\n"


def in_folder(text: str, name: str = "scene.yaml", loader: Callable[[Path], Any] = pg.load_scene,
              outside: str | None = None) -> Callable[[Path], Any]:  # fmt: skip
    """``text`` as ``tmp/upload/name`` (``{outside}``: a private file ``tmp/private/secret``)."""

    def run(tmp: Path) -> Any:
        (tmp / "private").mkdir(exist_ok=True)
        (tmp / "private" / "secret").write_text(outside or SECRET + "\n")
        (tmp / "upload").mkdir(exist_ok=True)
        p = tmp / "upload" / name
        p.write_text(text.replace("{tmp}", str(tmp)))
        try:
            return loader(p)
        except pg.PinograspError as exc:
            assert "SECRET" not in str(exc), str(exc)
            raise

    return run


case("scene-extends-absolute-file", "scene", in_folder("extends: {tmp}/private/secret\n"), pg.SceneError,
     "outside the folder of scene.yaml")  # fmt: skip
case("scene-extends-dotdot-file", "scene", in_folder("extends: ../private/secret\n"), pg.SceneError,
     "outside the folder")  # fmt: skip
case("scene-extends-secret-mapping", "scene",
     in_folder("extends: ../private/secret\n", outside=SECRET + ": 1\n"), pg.SceneError,
     "outside the folder")  # fmt: skip
case("scene-extends-builtin-dotdot", "scene", in_folder("extends: ../scenes/pinch\n"), pg.SceneError,
     "extends")  # fmt: skip
case("scene-extends-builtin-hidden", "scene", in_folder("extends: .pinch\n"), pg.SceneError, "extends")
case("scene-not-a-mapping-not-quoted", "scene", in_folder(SECRET + "\n"), pg.SceneError,
     "got str (the file is not quoted)")  # fmt: skip
case("scene-malformed-not-quoted", "scene", in_folder("key: [" + SECRET + "\n"), pg.SceneError,
     "malformed YAML at line")  # fmt: skip
case("scene-urdf-outside", "scene", in_folder("hand: {urdf: ../private/hand.urdf}\n"), pg.SceneError,
     "hand.urdf: '../private/hand.urdf' is outside")  # fmt: skip
case("scene-mesh-outside", "scene",
     in_folder("hand: underactuated_2f\nobject: {shape: mesh, file: ../private/secret}\n"), pg.SceneError,
     "object.file: '../private/secret' is outside")  # fmt: skip
case("scene-nested-500", "scene", in_folder(NEST), pg.SceneError, "nested deeper than 64")
case("scene-nested-65", "scene", in_folder("a: " + "[" * 65 + "]" * 65 + "\n"), pg.SceneError,
     "nested deeper")  # fmt: skip
case("scene-nested-62-read", "scene",
     lambda t: __import__("pinograsp.robots.yamlfile").robots.yamlfile.load_text("a: " + "[" * 62 + "]" * 62),
     None, verdict=lambda d: isinstance(d, dict))  # fmt: skip
case("scene-duplicated-key", "scene", in_folder(PINCH + "friction: 0.9\n"), pg.SceneError,
     "duplicated key 'friction'")  # fmt: skip
case("scene-duplicated-nested-key", "scene", in_folder(pinch_with("upper: 1000", "upper: 1000\n  upper: 5")),
     pg.SceneError, "duplicated key 'upper'")  # fmt: skip
case("hand-nested-500", "hand", hand_file(NEST), pg.ModelFileError, "nested deeper than 64")
case("hand-duplicated-key", "hand", hand_file("name: a\nname: b\n"), pg.ModelFileError,
     "duplicated key 'name'")  # fmt: skip
URDF = (
    '<robot name="r"><link name="b"><collision><geometry><mesh filename="{}"/></geometry></collision>'
    "</link></robot>"
)


def urdf(text: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        (tmp / "hand.urdf").write_text(text)
        return pg.Hand.from_urdf(tmp / "hand.urdf")

    return run


case("urdf-package-dotdot", "hand", urdf(URDF.format("package://../../etc/x.stl")), pg.UrdfError,
     "outside the URDF's folder")  # fmt: skip
case("urdf-relative-dotdot", "hand", urdf(URDF.format("../x.stl")), pg.UrdfError, "outside the URDF's folder")
case("urdf-absolute-mesh", "hand", urdf(URDF.format("/etc/x.stl")), pg.UrdfError, "outside the URDF's folder")
case("urdf-file-url-mesh", "hand", urdf(URDF.format("file:///etc/x.stl")), pg.UrdfError, "outside")
case("urdf-20000-links", "hand", urdf('<robot name="r">' + '<link name="l"/>' * 20000 + "</robot>"),
     pg.UrdfError, "20000 links, more than the 2000")  # fmt: skip
case("mesh-text-not-quoted", "hand",
     lambda t: (t / "m.stl").write_text(SECRET) and pg.RigidObject.from_mesh(t / "m.stl"), pg.ModelFileError,
     "m.stl")  # fmt: skip
case("batch-nested-500", "batch", batch(NEST), pg.SceneError, "nested deeper than 64")
case("batch-duplicated-key", "batch", batch(BATCH + "score: {upper: 5}\n"), pg.SceneError,
     "duplicated key 'score'")  # fmt: skip
case("batch-scene-outside", "batch",
     in_folder("grasps:\n  - {scene: ../private/secret}\n", "g.yaml", pg.load_grasps), pg.SceneError,
     "grasps[0].scene: '../private/secret' is outside")  # fmt: skip
case("batch-hand-outside", "batch",
     in_folder("grasps:\n  - {hand: /etc/hand.urdf, object: {shape: sphere, radius: 0.02}}\n", "g.yaml",
               pg.load_grasps), pg.SceneError, "outside")  # fmt: skip
FAST = pg.WorstAxisScore(upper=20, steps=4)


def resumed(records: list, *, score: Any = FAST, then: list | None = None, damage: Callable | None = None,
            interrupt: bool = False) -> Callable[[Path], Any]:  # fmt: skip
    """A finished (or interrupted) batch of ``records`` on ``tmp/r.csv``, ``damage(tmp)``, then
    ``resume=True`` with ``then`` (default the same records) and ``score``."""

    def stop(model: Any, command: Any) -> Any:
        raise KeyboardInterrupt

    def run(tmp: Path) -> Any:
        out = tmp / "r.csv"
        if interrupt:
            with contextlib.suppress(KeyboardInterrupt):
                pg.evaluate_grasps([*records, "wedge"], score=_first_only(), workers=1, out=out)
        else:
            pg.evaluate_grasps(records, score=FAST, workers=1, out=out)
        if damage is not None:
            damage(tmp)
        again = _first_only() if interrupt else score  # the interrupted batch's own score
        return pg.evaluate_grasps(then or records, score=again, workers=1, out=out, resume=True)

    return run


class _first_only:  # noqa: N801 - a score: the first call scores, the second interrupts
    calls = 0

    def __call__(self, model: Any, command: Any) -> Any:
        type(self).calls += 1
        if type(self).calls % 2 == 0:
            raise KeyboardInterrupt
        return FAST(model, command)


def _cut(tmp: Path) -> None:
    data = (tmp / "r.csv").read_bytes()
    (tmp / "r.csv").write_bytes(data[: len(data) - 25])


def _journal_line(line: bytes) -> Callable[[Path], None]:
    def damage(tmp: Path) -> None:
        j = tmp / "r.csv.partial.jsonl"
        lines = j.read_bytes().splitlines(keepends=True)
        j.write_bytes(b"".join([lines[0], line, *lines[1:]]))

    return damage


case("batch-resume-other-method", "batch", resumed(["pinch"], score=pg.WorstAxisScore(20, 4, "iterative")),
     match="another batch")  # fmt: skip
case("batch-resume-other-upper", "batch", resumed(["pinch"], score=pg.WorstAxisScore(21, 4)),
     match="another batch")  # fmt: skip
case("batch-resume-same-ok", "batch", resumed(["pinch", "wedge"]), None,
     verdict=lambda df: df["score"].tolist()[0] == 10.0 and len(df) == 2)  # fmt: skip
case("batch-resume-scene-other-preload", "batch",
     resumed([pg.load_scene("pinch")], then=[pg.load_scene("pinch", preload=5.0)]),
     match="another batch")  # fmt: skip
case("batch-resume-table-cut", "batch", resumed(["pinch", "wedge"], damage=_cut),
     match="edited, cut or damaged")  # fmt: skip
case("batch-resume-no-stamp", "batch",
     resumed(["pinch"], damage=lambda t: (t / "r.csv.batch.json").unlink()),
     match="no readable stamp")  # fmt: skip
case("batch-resume-stamp-garbage", "batch",
     resumed(["pinch"], damage=lambda t: (t / "r.csv.batch.json").write_bytes(b"\xff{")),
     match="no readable stamp")  # fmt: skip
case("batch-resume-journal-list-line", "batch",
     resumed(["pinch"], interrupt=True, then=["pinch", "wedge"], damage=_journal_line(b'["x"]\n')),
     match="line 2 is not a row")  # fmt: skip
case("batch-resume-journal-missing-keys", "batch",
     resumed(["pinch"], interrupt=True, then=["pinch", "wedge"], damage=_journal_line(b'{"index": 0}\n')),
     match="line 2 is not a row")  # fmt: skip
case("batch-resume-journal-not-utf8", "batch",
     resumed(["pinch"], interrupt=True, then=["pinch", "wedge"], damage=_journal_line(b"\xff\xfe\n")),
     match="line 2 is not a JSON line")  # fmt: skip
case("api-direction-plus-minus", "api", mw(direction="+-fy"), pg.UnknownNameError, "'+-fy'")
case("api-direction-minus-minus", "api", mw(direction="--fy"), pg.UnknownNameError, "'--fy'")
case("api-direction-one-sign-ok", "api", mw(direction="-fy"), None, verdict=lambda r: r.magnitude == 10.0)


def _contacts(n: int) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        cs = [pg.Contact.revolute([0.0, 0.01 * i, 0.0], [1.0, 0.0, 0.0], {0: ([0, -0.1, 0], [0, 0, 1])}, nq=1)
              for i in range(n)]  # fmt: skip
        return pg.GraspModel.from_contacts(cs, actuators=[pg.Actuator({0: 1.0}, name="m")], planar=True)

    return run


case("api-contacts-257", "api", _contacts(257), match="257 contacts, more than the 256")
case("api-contacts-256-built", "api", _contacts(256), None, verdict=lambda m: m.nc == 256)
case("api-cluster-unreachable", "api",
     lambda t: __import__("pinograsp.batch.executors").batch.executors.connect(
         "Ray", "10.0.0.1:6379", lambda: __import__("threading").Event().wait(), seconds=0.01),
     match="no Ray cluster answered")  # fmt: skip
case("cli-scenes-json-on-stdout", "cli", cli_json("scenes"), None, verdict=lambda d: "pinch" in d)
case("cli-scene-json-on-stdout", "cli", cli_json("scenes", "pinch"), None,
     verdict=lambda d: set(d["actuators"]) == {"left", "right"})  # fmt: skip
case("cli-direction-plus-minus", "cli", cli("max-wrench", "pinch", "-d", "+-fy"), None,
     verdict=lambda r: r[0] == 2 and "'+-fy'" in r[1])  # fmt: skip


def _under_a_file(*argv: str) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        (tmp / "file").write_text("x")
        return cli(*argv)(tmp)

    return run


case("cli-path-csv-under-a-file", "cli",
     _under_a_file("path", "pinch", "-d", "fy", "--csv", "{tmp}/file/p.csv"), None,
     verdict=lambda r: r[0] == 2 and "--csv: cannot write" in r[1])  # fmt: skip
case("cli-path-png-a-folder", "cli", cli("path", "pinch", "-d", "fy", "--png", "{tmp}"), None,
     verdict=lambda r: r[0] == 2 and "--png" in r[1] and "folder" in r[1])  # fmt: skip
case("cli-profile-csv-under-a-file", "cli",
     _under_a_file("profile", "pinch", "-n", "4", "--csv", "{tmp}/file/a.csv"), None,
     verdict=lambda r: r[0] == 2 and "--csv" in r[1])  # fmt: skip
case("cli-set-csv-under-a-file", "cli",
     _under_a_file("resistance-set", "pinch", "-n", "4", "--csv", "{tmp}/file/a.csv"), None,
     verdict=lambda r: r[0] == 2 and "--csv" in r[1])  # fmt: skip


def _batch_resume_method(tmp: Path) -> Any:
    (tmp / "g.yaml").write_text("score: {upper: 20, steps: 4}\ngrasps:\n  - {scene: pinch}\n")
    argv = ("batch", "{tmp}/g.yaml", "--out", "{tmp}/r.csv", "--workers", "1", "--no-progress")
    assert cli(*argv)(tmp)[0] == 0
    return cli(*argv, "--resume", "--method", "iterative")(tmp)


case("cli-batch-resume-other-method", "cli", _batch_resume_method, None,
     verdict=lambda r: r[0] == 2 and "another batch" in r[1])  # fmt: skip


# ---- issue 33, the rest: numeric domains of the loading path (docs/errors.md, "Input domains")
def qs(**kw: Any) -> Callable[[Path], Any]:
    """The default (quasi-static) max-wrench query on the pinch, ``kw`` as settings or arguments."""
    args = dict(command=1.0, direction="fy", upper=100.0) | kw
    return lambda tmp: pg.max_resistible_wrench(pinch(), args.pop("command"), args.pop("direction"), **args)


def _ten(r: Any) -> bool:
    return r.status == "finite" and abs(r.magnitude - 10.0) < 1e-9


for _tr in (1e-9, 3e-8, 1e-7, 2e6, 1e8, 1e9):
    case(f"api-tangential-ratio-{_tr:g}", "api", qs(tangential_ratio=_tr, limit="first"),
         match="tangential_ratio: must be in [1e-06, 1e+06]")  # fmt: skip
for _tr in (1e-6, 1e6):  # the edges answer the pinch's exact 10 N
    case(
        f"api-tangential-ratio-{_tr:g}-ok", "api", qs(tangential_ratio=_tr, limit="first"), None, verdict=_ten
    )
case("scene-tangential-ratio-1e9", "scene",
     scene(pinch_with("  steps: 20", "  steps: 20\n  tangential_ratio: 1.0e+9")), pg.PinograspError,
     "tangential_ratio")  # fmt: skip
case("scene-tangential-ratio-3e-8", "scene",
     scene(pinch_with("  steps: 20", "  steps: 20\n  tangential_ratio: 3.0e-8")), pg.PinograspError,
     "tangential_ratio")  # fmt: skip
case("cli-tangential-ratio-1e9", "cli", cli("max-wrench", "pinch", "-d", "fy", "--tangential-ratio", "1e9"),
     None, verdict=lambda r: r[0] == 2 and "--tangential-ratio" in r[1] and "1e+06" in r[1])  # fmt: skip
case("cli-path-tangential-ratio-3e-8", "cli", cli("path", "pinch", "-d", "fy", "--tangential-ratio", "3e-8"),
     None, verdict=lambda r: r[0] == 2 and "--tangential-ratio" in r[1] and "1e-06" in r[1])  # fmt: skip
for _c in (1e-300, 1e-12, 1e-10, 1e-7):
    case(
        f"api-command-{_c:g}", "api", qs(command=_c), match="the largest command must be 0 or at least 1e-06"
    )
case("api-command-1e-6-ok", "api", qs(command=1e-6, limit="first"), None,
     verdict=lambda r: r.status == "finite" and abs(r.magnitude - 1e-5) < 1e-14)  # fmt: skip
case("api-command-small-beside-large-ok", "api", qs(command=[1.0, 1e-9], limit="first"), None,
     verdict=lambda r: r.status == "finite" and r.magnitude > 0)  # fmt: skip
case("scene-preload-1e-10", "scene",
     lambda t: scene(pinch_with("preload: 1.0 ", "preload: 1.0e-10 "))(t).max_resistible_wrench("fy"),
     pg.InvalidInputError, "largest command")  # fmt: skip
case("api-budget-1e-300", "api", lambda t: pg.optimal_preload(pinch(), ["fy"], budget=1e-300),
     match="budget: must be in [1e-06")  # fmt: skip
case("api-upper-1e-300", "api", qs(upper=1e-300), match="upper: must be in [1e-06")
case("api-grip-1e-300", "api", lambda t: pg.equilibrium_preload(pinch(), objective="least_norm", grip=1e-300),
     match="grip: must be in [1e-06")  # fmt: skip
case("cli-budget-1e-300", "cli", cli("optimal-preload", "pinch", "-w", "fy=1", "--budget", "1e-300"), None,
     verdict=lambda r: r[0] == 2 and "budget" in r[1])  # fmt: skip


def _arm(value: float) -> Callable[[Path], Any]:
    def run(tmp: Path) -> Any:
        from pinograsp.core.examples import pinch_contacts

        acts = [pg.Actuator({0: value}, name="left"), pg.Actuator({1: 1.0}, name="right")]
        m = pg.GraspModel.from_contacts(pinch_contacts(), actuators=acts, planar=True)
        return pg.max_resistible_wrench(m, 1.0, "fy", upper=100.0, limit="first")

    return run


for _a in (1e300, 1e7, 1e-7, 1e-300):
    case(f"api-moment-arm-{_a:g}", "api", _arm(_a), match="transmission[0]: a moment arm")
case("api-moment-arm-1e6-ok", "api", _arm(1e6), None, verdict=lambda r: r.status == "finite")
case("api-coupling-1e300", "api", lambda t: pg.Coupling({0: 1.0, 1: -1e300}), match="weights[1]")
case("scene-moment-arm-1e300", "scene",
     scene(pinch_with("transmission: {left: 1.0}", "transmission: {left: 1.0e+300}")), pg.PinograspError,
     "moment arm")  # fmt: skip


def _lad(**kw: Any) -> Callable[[Path], Any]:
    return lambda tmp: pg.loading_path(pinch(), 1.0, "fy").load_at_displacement(**({"delta": 1e-3} | kw))


for _r in (-1.0, 0.0, float("nan"), 1e4):
    case(f"api-load-at-displacement-rotation-{_r:g}", "api", _lad(rotation=_r), match="rotation: must be")
for _k in (1e-200, 0.5, 1e11):
    case(
        f"api-load-at-displacement-stiffness-{_k:g}", "api", _lad(stiffness=_k), match="stiffness: must be in"
    )
case("api-load-at-displacement-delta-0", "api", _lad(delta=0.0), match="delta: must be in")
case("api-load-at-displacement-ok", "api", _lad(rotation=1e-2, stiffness=1e6), None,
     verdict=lambda v: 0.0 < v <= 10.0)  # fmt: skip
case("api-continuation-no", "api", lambda t: pg.loading_path(pinch(), 1.0, "fy", continuation="no"),
     match="continuation: expected True or False")  # fmt: skip
case("api-continuation-1", "api", lambda t: pg.loading_path(pinch(), 1.0, "fy", continuation=1),
     match="continuation: expected True or False")  # fmt: skip
