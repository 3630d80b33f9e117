"""The hand's own finger masses against a physical box: what ``finger_mass`` the Ability hand's
URDF gives on issue 34's plan 5 (Ability × box 4×5×7 cm), and whether the plan holds at it
(docs/simulation.md, "Finger mass", "The hand's own masses").

1. The hand as the package loads it (``Hand.builtin("ability")``, Pinocchio) at the plan's
   configuration ``q`` (the cached spec's, ``grasp_configuration``): per hand joint the
   joint-space inertia ``M_jj(q)`` (``pin.crba``) and its effective mass at its farthest contact
   ``M_jj / reach_j**2``, ``reach_j`` read back from the simulation's own armature at
   ``finger_mass=1`` (``Engine``: ``armature = mass * reach**2``); per contact the effective
   mass along its normal ``1 / (n^T J M^-1 J^T n)``, free (every hand joint moves) and with the
   model's constraints (the linkage couplings ``C q = 0`` and the locked thumb rotation), the
   same for the simulation's diagonal armature; ratios to the box's mass at four densities.
2. ``--simulate``: plan 5 along -fz at the ratios the URDF gives at 700 and 1000 kg/m³ (max and
   median over joints, max over contacts; clipped to the allowed minimum): the snap study's
   settings (pyramid, release 0.05 s, ramp 0.1 s and 0.3 s, upper 70 N), the acceptance call
   (``upper=45``, default friction and ramp) and its slow re-check (ramp 0.3 s, release 0.05 s).
3. ``--directions``: the acceptance call along all 26 cube directions at those ratios
   (``--jobs`` processes); ``--light``: the light-finger checks (:func:`light_tasks`).
4. Whether the acceptance hands' URDFs carry link masses.

    python -m scripts.snapstudy.handmass                      # the tables (seconds)
    nice python -m scripts.snapstudy.handmass --simulate --directions --light --jobs 2
"""

from __future__ import annotations

import argparse
import json
import math
import multiprocessing as mp
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

import pinograsp as pg
from pinograsp.core.axes import cube_directions
from scripts.reproduce.planning_acceptance import CACHE, HOLD, spec_of
from scripts.snapstudy.common import MINUS_FZ

PAIR, PLAN = "ability × box", 4  # plan 5
BOX = (0.04, 0.05, 0.07)  # [m]
DENSITIES = {"300": 300.0, "700 (wood)": 700.0, "1000 (water)": 1000.0, "2700 (aluminium)": 2700.0}
SIMULATED = ("700 (wood)", "1000 (water)")  # the densities whose ratio is simulated
FIXTURE = Path(__file__).resolve().parents[2] / "tests" / "data" / "ability_box_plan5_fz.json"
HANDS = ("parallel_jaw", "barrett_bh8_282", "ability")
#: The snap study's simulation (tests/test_sim_finger_mass.py).
SNAP = {"friction": "pyramid", "release_time": 0.05}


def plan() -> dict:
    """The cached plan (spec, predicted values, simulations)."""
    return json.loads(CACHE.read_text())["pairs"][PAIR]["plans"][PLAN]


def setup():
    """``(hand, q, model, command)`` of plan 5, built as the acceptance builds it; the model is
    checked against the stored fixture of the snap study."""
    from pinograsp.batch.grasps import build_grasp, grasp_configuration

    spec = spec_of(plan()["spec"])
    hand, _, q = grasp_configuration(spec)
    model, command, _ = build_grasp(spec)
    stored = json.loads(FIXTURE.read_text())
    same = np.allclose(model.J, np.asarray(stored["model"]["J"]), rtol=0, atol=1e-12)
    assert same and command == stored["command"], "plan 5 no longer builds the stored fixture"
    assert tuple(hand.joint_names) == tuple(model.joint_names)
    return hand, q, model, command


def joint_inertia(hand, q: np.ndarray) -> np.ndarray:
    """``M(q)`` over the hand joints in the model's order, (nq, nq) [kg m² per rad²]."""
    data = hand.model.createData()
    M = np.array(pin.crba(hand.model, data, q))
    M = np.triu(M) + np.triu(M, 1).T
    idx = [hand.model.joints[hand.model.getJointId(n)].idx_v for n in hand.joint_names]
    return M[np.ix_(idx, idx)]


def simulation_armature(model: pg.GraspModel, command: dict) -> tuple[np.ndarray, float]:
    """The simulation's hand-joint armature at ``finger_mass=1``, (nq,) [kg m²], and its object
    mass [kg] (``Engine``, the default options along -fz)."""
    from pinograsp.sim.integrator import Engine
    from pinograsp.sim.simulate import _options

    opts = _options(model, MINUS_FZ, 45.0, {"finger_mass": 1.0})
    run = Engine(model, model.command_vector(command), opts)
    return run.red.model.dof_armature[run.red.hand_dof].copy(), opts.mass


def constrained_basis(model: pg.GraspModel) -> np.ndarray:
    """Null space of the simulation's equality constraints on the hand joints: the couplings
    ``C q = 0`` and the locked actuators ``R_a^T q = 0``, (nq, k)."""
    R = np.asarray(model.R, dtype=float)
    locked = [a for a, kind in enumerate(model.kinds) if kind == "locked"]
    A = np.vstack([np.asarray(model.C, dtype=float).reshape(-1, model.nq), R[:, locked].T])
    _, s, vt = np.linalg.svd(A)
    rank = int((s > 1e-10 * s.max()).sum())
    return vt[rank:].T


def contact_masses(model: pg.GraspModel, M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Effective mass of each contact along its normal [kg], (nc,): free joints and constrained
    (``inf`` where no joint moves the contact along its normal)."""
    Jn = np.asarray(model.J, dtype=float).reshape(model.nc, model.d, model.nq)[:, 0, :]  # n^T J
    N = constrained_basis(model)
    free = np.einsum("ij,ij->i", Jn, np.linalg.solve(M, Jn.T).T)
    Jc = Jn @ N
    con = np.einsum("ij,ij->i", Jc, np.linalg.solve(N.T @ M @ N, Jc.T).T)
    inv = lambda x: np.where(x > 1e-14 * np.max(x), 1.0 / np.maximum(x, 1e-300), math.inf)  # noqa: E731
    return inv(free), inv(con)


def box_mass(rho: float) -> float:
    return rho * float(np.prod(BOX))


def tables(hand, q, model, command) -> dict:
    M = joint_inertia(hand, q)
    arm, m_sim = simulation_armature(model, command)
    reach = np.sqrt(arm / m_sim)
    eff = np.diag(M) / reach**2
    Jn = np.abs(np.asarray(model.J, dtype=float).reshape(model.nc, model.d, model.nq))
    moves = (np.linalg.norm(Jn, axis=1) > 0).any(axis=0)
    print(f"plan 5 (spec {plan()['spec']['id']}), q = {np.round(q, 4).tolist()} rad")
    print(f"simulation: object mass {m_sim:g} kg (10 nc stiffness timestep²); box "
          + ", ".join(f"{k} kg/m³: {box_mass(v) * 1e3:.0f} g" for k, v in DENSITIES.items()))  # fmt: skip
    print("\n| joint | M_jj [kg m²] | reach [mm] | M_jj / reach² [g] | ratio to the box at "
          + " / ".join(f"{v:g}" for v in DENSITIES.values()) + " kg/m³ |")  # fmt: skip
    print("|---|---:|---:|---:|---|")
    for j, name in enumerate(model.joint_names):
        r = " / ".join(f"{eff[j] / box_mass(v):.3f}" for v in DENSITIES.values())
        note = "" if moves[j] else " (moves no contact: reach = length scale)"
        print(f"| {name}{note} | {M[j, j]:.3e} | {reach[j] * 1e3:.1f} | {eff[j] * 1e3:.2f} | {r} |")
    agg = {}
    for label, sel in (("all joints", np.ones(model.nq, bool)), ("joints moving a contact", moves)):
        mx, md = float(eff[sel].max()), float(np.median(eff[sel]))
        agg[label] = (mx, md)
        r = ", ".join(f"{k}: {mx / box_mass(v):.3f} / {md / box_mass(v):.3f}" for k, v in DENSITIES.items())
        print(f"\n{label}: max {mx * 1e3:.2f} g, median {md * 1e3:.2f} g; ratio max / median: {r}")
    free, con = contact_masses(model, M)
    sfree, scon = contact_masses(model, np.diag(arm))  # the simulation at finger_mass=1
    print("\nPer contact, along its normal (free joints | the linkage and the locked thumb rotation):")
    print("| contact | URDF [g] | simulation at finger_mass 1 [g] | URDF / box at 700, 1000 kg/m³ "
          "| equivalent finger_mass at 700, 1000 kg/m³ |")  # fmt: skip
    print("|---|---|---|---|---|")
    equivalent = {k: [] for k in SIMULATED}
    for i, c in enumerate(model.contact_names):
        if not math.isfinite(free[i]):
            print(f"| {c} | fixed (no hand joint moves it) | | | |")
            continue
        cells = []
        for u, s in ((free[i], sfree[i]), (con[i], scon[i])):
            rb = [u / box_mass(DENSITIES[k]) for k in SIMULATED]
            eq = [x / (s / m_sim) for x in rb]
            cells.append(
                (
                    f"{u * 1e3:.2f}",
                    f"{s * 1e3:.0f}",
                    "{:.3f}, {:.3f}".format(*rb),
                    "{:.3f}, {:.3f}".format(*eq),
                )
            )
        for k, x in zip(SIMULATED, eq):  # the constrained one: the simulation keeps the linkage
            equivalent[k].append(x)
        print(f"| {c} | " + " | ".join(f"{a} \\| {b}" for a, b in zip(*cells)) + " |")
    out = {}
    for k in SIMULATED:
        mb = box_mass(DENSITIES[k])
        out[k] = {
            "max over joints": agg["all joints"][0] / mb,
            "median over joints": agg["all joints"][1] / mb,
            "max over contacts (constrained)": max(equivalent[k]),
        }
    return out


def _run(task: tuple) -> tuple:
    """One simulation ``(what, label, model, command, upper, options)``: ``(what, label, status,
    load, CPU [s])``."""
    what, label, model, command, upper, opts = task
    labels, dirs = cube_directions()
    w = np.zeros(6)
    w[:3] = dirs[labels.index(label)][:3]  # as the acceptance builds it
    t = time.process_time()
    r = pg.simulate_max_wrench(model, w, command, upper=upper, **opts)
    return what, label, r.status, r.load, time.process_time() - t


def _text(status: str, load, upper: float) -> str:
    return f"held {upper:g} N" if load is None else f"{status} {load:.2f} N"


def _ratios(cands: dict) -> list[float]:
    """The distinct finger masses to simulate: each candidate to 3 digits, clipped to the range."""
    from pinograsp.sim.simulate import SIM_FINGER_MASS

    lo, hi = SIM_FINGER_MASS
    print("\nfinger_mass the URDF gives (clipped to the allowed range where outside):")
    out = set()
    for k, c in cands.items():
        for how, r in c.items():
            fm = min(hi, max(lo, float(f"{r:.3g}")))
            out.add(fm)
            print(
                f"  {k} kg/m³, {how}: {r:.3f} -> finger_mass={fm:g}"
                + (" (clipped)" if fm != float(f"{r:.3g}") else "")
            )
    return sorted(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--simulate", action="store_true", help="plan 5 along -fz at the URDF's ratios")
    ap.add_argument("--directions", action="store_true", help="the 26 directions at the URDF's ratios")
    ap.add_argument("--light", action="store_true", help="the light-finger checks (+fz, 26 at 0.12)")
    ap.add_argument("--jobs", type=int, default=2, help="simulations side by side (default 2)")
    a = ap.parse_args()
    hand, q, model, command = setup()
    ratios = _ratios(tables(hand, q, model, command))
    check = HOLD * float(plan()["score"])  # the acceptance's check load
    tasks = []
    if a.simulate:
        runs = {
            "pyramid, release 0.05 s, ramp 0.1 s, upper 70": (70.0, {**SNAP, "ramp_time": 0.1}),
            "pyramid, release 0.05 s, ramp 0.3 s, upper 70": (70.0, {**SNAP, "ramp_time": 0.3}),
            f"acceptance (a): cone, ramp 0.02 s, upper {check:g}": (check, {}),
            f"acceptance --slow: cone, ramp 0.3 s, release 0.05 s, upper {check:g}": (
                check, {"ramp_time": 0.3, "release_time": 0.05}),
        }  # fmt: skip
        for fm in ratios:
            tasks += [
                (f"{fm:g} | {k}", "-fz", model, command, up, {**o, "finger_mass": fm})
                for k, (up, o) in runs.items()
            ]
        tasks += [
            (f"1 (default) | {k}", "-fz", model, command, up, o) for k, (up, o) in list(runs.items())[2:]
        ]
    if a.directions:
        tasks += [
            (f"{fm:g} | 26", lab, model, command, check, {"finger_mass": fm})
            for fm in ratios
            for lab in cube_directions()[0]
        ]
    if a.light:
        tasks += light_tasks(model, command, check)
    if not tasks:
        urdf_masses()
        return
    cpu, done = 0.0, []
    with mp.get_context("fork").Pool(a.jobs) as pool:
        for what, lab, status, load, c in pool.imap(_run, tasks):
            cpu += c
            done.append((what, lab, status, load, c))
            print(f"  {what} {lab}: {_text(status, load, 0)} [{c:.1f} s]", flush=True)
    print("\n| finger_mass | run | direction | result | CPU |\n|---:|---|---|---|---:|")
    for (what, lab, status, load, c), t in zip(done, tasks):
        if not what.endswith("| 26"):
            print(f"| {what} | {lab} | {_text(status, load, t[4])} | {c:.1f} s |")
    if a.directions or a.light:
        print(f"\n26 directions, acceptance call, upper {check:g} N:")
        print("| finger_mass | held | gave way | CPU |\n|---:|---:|---|---:|")
        for fm in sorted({float(d[0].split(" |")[0].split()[-1]) for d in done if d[0].endswith("| 26")}):
            rows = [d for d in done if d[0] in (f"{fm:g} | 26", f"light {fm:g} | 26")]
            gave = ", ".join(f"{d[1]} {_text(d[2], d[3], check)}" for d in rows if d[3] is not None)
            held, c = sum(d[3] is None for d in rows), sum(d[4] for d in rows)
            print(f"| {fm:g} | {held} / {len(rows)} | {gave or '-'} | {c:.0f} s |")
    print(f"\nsimulation CPU: {cpu:.0f} s over {a.jobs} process(es)")
    urdf_masses()


def light_tasks(model, command, check: float) -> list[tuple]:
    """The light-finger checks: +fz with the acceptance call from 0.1 to 0.12 (cone and pyramid),
    at 0.1 with smaller time steps and the gradual release; the 26 directions at 0.12; -fz at
    0.151 with ``upper`` 70 N (the circular cone)."""
    out = []
    for fm in (0.1, 0.102, 0.105, 0.11, 0.12):
        for fr in ("cone", "pyramid"):
            out.append(
                (f"light {fm:g} | {fr}, ramp 0.02 s, upper {check:g}", "+fz", check, {"friction": fr}, fm)
            )
    for dt in (5e-5, 2.5e-5):
        out.append((f"light 0.1 | cone, ramp 0.02 s, timestep {dt:g} s", "+fz", check, {"timestep": dt}, 0.1))
    out.append(("light 0.1 | cone, ramp 0.02 s, release 0.05 s", "+fz", check, {"release_time": 0.05}, 0.1))
    for ramp, rel in ((0.02, 0.0), (0.3, 0.05)):
        what = f"light 0.151 | cone, ramp {ramp} s, release {rel} s, upper 70"
        out.append((what, "-fz", 70.0, {"ramp_time": ramp, "release_time": rel}, 0.151))
    out += [("light 0.12 | 26", lab, check, {}, 0.12) for lab in cube_directions()[0]]
    return [(w, lab, model, command, up, {**o, "finger_mass": fm}) for w, lab, up, o, fm in out]


def urdf_masses() -> None:
    """Step 4: link masses of the acceptance hands, as Pinocchio loads them."""
    from pinograsp.robots.hand import Hand

    print("\n| hand | URDF <inertial> tags | moving bodies with mass > 0 | moving mass [g] | M(q_open) > 0 |")
    print("|---|---:|---|---:|---|")
    for name in HANDS:
        hand = Hand.builtin(name)
        m = hand.model
        tags = hand.urdf_path.read_text().count("<inertial")
        masses = [m.inertias[i].mass for i in range(1, m.njoints)]
        M = joint_inertia(hand, hand.q_open)
        pd = bool(np.linalg.eigvalsh(M).min() > 0)
        heavy = sum(x > 0 for x in masses)
        print(f"| {name} | {tags} | {heavy} of {len(masses)} | {sum(masses) * 1e3:.1f} | {pd} |")


if __name__ == "__main__":
    main()
