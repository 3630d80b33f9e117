"""Trial: own hand descriptions (YAML here), balls, boxes and a trimesh torus, auto-close, a
designed preload, 9 grasps x 6 directions, the default method against the simulation.

Deterministic: fixed candidate poses tried in order, the first 9 that close and give a preload
are kept. ``python -m scripts.reproduce.ownhands [--hands a,b] [--report] [--refresh-answers]``
(``--refresh-answers``: the cached grasps' default answers recomputed with the current code,
their simulations kept).
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings
from pathlib import Path

import numpy as np

import pinograsp as pg

HERE = Path(__file__).resolve().parent
CACHE = HERE / "results.json"
TORUS = HERE / "torus_30_10.stl"
UPPER = 20.0
DIRS = ("fx", "-fx", "fy", "-fy", "fz", "-fz")
ROBOTS = "example-robot-data/robots"
#: hand -> (URDF under example-robot-data, description YAML here, max_command, nominal centre [m],
#: closing axis (unit, base frame) along which candidate poses are spread)
HANDS = {
    "romeo_left": ("romeo_description/urdf/romeo.urdf", "romeo_left.yaml", 1.0, (0.07, 0.0, -0.03)),
    "tiago_pro_left": (
        "tiago_pro_description/robots/tiago_pro.urdf",
        "tiago_pro_left.yaml",
        1.0,
        (0.0, 0.0, 0.13),
    ),
    "z1": ("z1_description/urdf/z1.urdf", "z1.yaml", 1.0, (0.12, 0.0, 0.0)),
    "baxter_left": ("baxter_description/urdf/baxter.urdf", "baxter_left.yaml", 20.0, (0.0, 0.0, 0.115)),
}
#: Hands on which a grasp without a designed preload (infeasible) is kept, at the description's
#: commands, when it has at least 3 contacts.
FALLBACK = {"romeo_left"}
OFFSETS = [
    (0, 0, 0),
    (0.01, 0, 0),
    (-0.01, 0, 0),
    (0, 0.01, 0),
    (0, -0.01, 0),
    (0, 0, 0.01),
    (0, 0, -0.01),
    (0.02, 0, 0),
    (-0.02, 0, 0),
    (0, 0, 0.02),
    (0, 0, -0.02),
    (0, 0.02, 0),
    (0, -0.02, 0),
]
OBJECTS = [
    ("ball", 0.015),
    ("ball", 0.02),
    ("ball", 0.01),
    ("ball", 0.025),
    ("box", (0.03, 0.03, 0.03)),
    ("box", (0.02, 0.04, 0.03)),
    ("box", (0.04, 0.02, 0.05)),
    ("torus", 0.0),
    ("torus", 1.0),
]


def _torus() -> Path:
    if not TORUS.exists():
        import trimesh

        trimesh.creation.torus(0.03, 0.01, major_sections=48, minor_sections=24).export(TORUS)
    return TORUS


def _object(kind: str, size: object, pose: np.ndarray) -> pg.RigidObject:
    if kind == "ball":
        return pg.RigidObject.sphere(float(size), pose=pose)  # type: ignore[arg-type]
    if kind == "box":
        return pg.RigidObject.box(tuple(size), pose=pose)  # type: ignore[arg-type]
    T = np.eye(4)
    T[:3, 3] = pose
    if size:  # torus turned 90 deg about x (its hole along y)
        T[:3, :3] = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], dtype=float)
    return pg.RigidObject.from_mesh(_torus(), pose=T)


def load_hand(name: str) -> pg.Hand:
    urdf, yaml, _, _ = HANDS[name]
    return pg.Hand.from_urdf(pg.example_robot_data_dir() / ROBOTS / urdf, HERE / yaml)


def grasp(hand: pg.Hand, name: str, kind: str, size: object, pose: np.ndarray) -> dict:
    """Close, build the model, design the preload: the exact input and what each stage said."""
    obj = _object(kind, size, pose)
    q = hand.close_on(obj)
    model = pg.grasp_model_from_scene(hand, q, obj, mu=0.5)
    pre = pg.equilibrium_preload(model, max_command=HANDS[name][2])
    return {
        "hand": name,
        "kind": kind,
        "size": size,
        "pose": [float(x) for x in pose],
        "q": [float(x) for x in q],
        "nc": int(model.nc),
        "contacts": list(model.contact_names) if hasattr(model, "contact_names") else None,
        "preload_status": pre.status,
        "command": pre.command,
        "preload_reason": pre.reason,
        "model": model,
    }


def find_grasps(hand: pg.Hand, name: str) -> list[dict]:
    out: list[dict] = []
    centre = np.array(HANDS[name][3])
    for kind, size in OBJECTS:
        for off in OFFSETS:
            try:
                g = grasp(hand, name, kind, size, centre + np.array(off))
            except pg.PinograspError as exc:
                print(f"  {kind} {size} {off}: {type(exc).__name__}: {str(exc)[:120]}", flush=True)
                continue
            if g["command"] is None and name in FALLBACK and g["nc"] >= 3:
                g["command"] = dict(hand.commands)  # no designed preload: the description's command
            if g["command"] is None or g["nc"] < 2:
                print(f"  {kind} {size} {off}: nc {g['nc']} preload {g['preload_status']}", flush=True)
                continue
            out.append(g)
            print(
                f"  {kind} {size} {off}: nc {g['nc']} preload {g['preload_status']} {g['command']}",
                flush=True,
            )
            break
    return out


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else float(x)


def compare(g: dict, d: str) -> dict:
    row = answer(g["model"], g["command"], d)
    return {**row, **simulated(g["model"], g["command"], d)}


def answer(model: pg.GraspModel, cmd: object, d: str) -> dict:
    """The default answer's fields of a pair (status, load, first limit, give-way record)."""
    row: dict = {"direction": d}
    try:
        mw = pg.max_resistible_wrench(model, cmd, d, upper=UPPER)
        gw = mw.giveway
        row.update(
            qs_status=mw.status,
            qs=_finite(mw.magnitude),
            first_limit=_finite(mw.first_limit),
            giveway=None
            if gw is None
            else {
                "reason": gw.reason,
                "load": _finite(gw.load),
                "first_limit": _finite(gw.first_limit),
                "snaps": [list(s) for s in gw.snaps],
                "translation": gw.translation,
                "turned": gw.turned,
            },
        )
    except pg.PinograspError as exc:
        row.update(qs_status=type(exc).__name__, qs=None, error=str(exc)[:300])
    return row


def simulated(model: pg.GraspModel, cmd: object, d: str) -> dict:
    """The simulation's fields of a pair (status, load, onset, wall time)."""
    row: dict = {}
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s = pg.simulate_max_wrench(model, d, cmd, upper=UPPER, friction="pyramid")
        row.update(sim_status=s.status, sim=_finite(s.load), sim_onset=_finite(s.onset_load))
    except pg.PinograspError as exc:
        row.update(sim_status=type(exc).__name__, sim=None, sim_error=str(exc)[:300])
    row["sim_wall"] = time.perf_counter() - t0
    return row


def run(names: list[str]) -> None:
    cache = CACHE if names != ["romeo_left"] else HERE / "results_romeo_left.json"
    data = json.loads(cache.read_text()) if cache.exists() else {}
    for name in names:
        hand = load_hand(name)
        print(name, flush=True)
        rows = []
        for g in find_grasps(hand, name):
            pairs = [compare(g, d) for d in DIRS]
            g = {k: v for k, v in g.items() if k != "model"}
            rows.append({**g, "pairs": pairs})
            print(
                "   ",
                [(p["direction"], p["qs_status"], p.get("qs"), p["sim_status"], p.get("sim")) for p in pairs],
                flush=True,
            )
            data[name] = rows
            cache.write_text(json.dumps(data, indent=1, default=str))


def refresh_answers() -> None:
    """Recompute the default answers of every cached pair with the current code, keeping the
    cached grasps and simulations (the answer takes milliseconds, a simulation seconds)."""
    for cache in (CACHE, HERE / "results_romeo_left.json"):
        if not cache.exists():
            continue
        data = json.loads(cache.read_text())
        for name, rows in data.items():
            hand = load_hand(name)
            for g in rows:
                obj = _object(g["kind"], g["size"], np.asarray(g["pose"], dtype=float))
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    model = pg.grasp_model_from_scene(hand, np.asarray(g["q"], dtype=float), obj, mu=0.5)
                    for p in g["pairs"]:
                        for key in ("qs_status", "qs", "first_limit", "giveway", "error"):
                            p.pop(key, None)
                        p.update(answer(model, g["command"], p["direction"]))
        cache.write_text(json.dumps(data, indent=1, default=str))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--hands", default=",".join(HANDS))
    ap.add_argument("--report", action="store_true")
    ap.add_argument("--refresh-answers", action="store_true", help="recompute the cached pairs' answers only")
    a = ap.parse_args()
    if a.refresh_answers:
        refresh_answers()
    elif not a.report:
        run(a.hands.split(","))
    from scripts.reproduce.ownhands.report import write_report

    write_report()


if __name__ == "__main__":
    main()
