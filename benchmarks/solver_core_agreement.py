"""Section 5 of ``benchmarks/solver_core.py``: step optima of the branch-and-bound against SCIP."""

from __future__ import annotations

import json
import statistics
import time
from collections import Counter

import numpy as np
from solver_core_common import ABS, REL, SCIP_TIME_LIMIT, q
from solver_core_measure import force_scale, rand_wrench


def agreement_instances(quick: bool) -> list[dict]:
    """Grasps of the agreement test: (id, label, factory, command)."""
    import pinograsp as pg
    from pinograsp import examples
    from pinograsp.core.examples import random_grasp

    combos = [(npairs, 1, pl) for npairs in range(1, 7) for pl in (True, False)]
    combos += [(npairs, 2, pl) for npairs in range(1, 4) for pl in (True, False)]
    per = 1 if quick else 12
    out = []
    gid = 0
    for _ in range(per):
        for npairs, cpf, planar in combos:
            seed = 5000 + gid
            link = "two" if cpf == 2 else "one"
            space = "planar" if planar else "3D"
            label = f"random seed {seed}: {2 * npairs * cpf} contacts, {link}-link, {space}"
            out.append(
                dict(
                    id=f"g{gid:03d}",
                    label=label,
                    factory=(
                        lambda s=seed, a=npairs, b=cpf, c=planar: random_grasp(
                            s, n_pairs=a, contacts_per_finger=b, planar=c
                        )
                    ),
                    command=1.0,
                    code=(
                        f"random_grasp({seed}, n_pairs={npairs}, contacts_per_finger={cpf}, planar={planar})"
                    ),
                )
            )
            gid += 1
    scenes = {}
    for name in ("case1", "case3"):
        sc = pg.load_scene(name)
        scenes[name] = (lambda sc=sc: sc.model, sc.command, f'pg.load_scene("{name}").model')
    scenes["pinch"] = (examples.pinch, 1.0, "examples.pinch()")
    scenes["wedge"] = (examples.wedge, 1.0, "examples.wedge()")
    for rep in range(1 if quick else 8):
        for name, (fac, cmd, code) in scenes.items():
            out.append(
                dict(id=f"g{gid:03d}", label=f"{name} (draw {rep})", factory=fac, command=cmd, code=code)
            )
            gid += 1
    return out


def agreement_problems(inst: dict) -> list[tuple[str, str, object, object, float]]:
    """The problems of one grasp: (name, kind, form, data, gamma)."""
    import pinograsp as pg
    from pinograsp.solvers import BranchAndBound, ScaledData, build_problem

    m = inst["factory"]()
    sess = pg.Session(m)
    form, gamma = sess.form, sess.options.gamma
    fc = m.command_vector(inst["command"])
    rng = np.random.default_rng([int(inst["id"][1:]), 7])
    if rng.uniform() < 0.5 and m.na > 1:
        fc = fc * rng.uniform(0.5, 1.5, size=m.na)  # a random (possibly unbalanced) preload
    F0 = force_scale(form, m, fc)
    # the preload's normal forces (spring pre-compression of the preload-first variant)
    pre = BranchAndBound(build_problem(form, "prp", form.scale_data(np.zeros(m.nw), fc))).solve()
    p = (form.E @ pre.z[form.layout("prp")["beta"]]) * F0 if pre.status == "optimal" else np.zeros(m.nc)
    probs = []
    w1 = rand_wrench(rng, m, F0, 0.05, 2.0)
    probs.append(("prp0", "prp", form, form.scale_data(w1, fc), gamma))
    w2 = rand_wrench(rng, m, F0, 0.05, 2.0)
    probs.append(("prp1", "prp", form, form.scale_data(w2, fc, p), gamma))
    w3 = rand_wrench(rng, m, F0, 0.05, 2.0)
    d3 = form.scale_data(w3, fc, p)
    probs.append(
        ("move0", "move", form, ScaledData(d3.F, d3.w, d3.fc, d3.p, np.zeros(form.nx), d3.w.copy()), gamma)
    )
    w4 = rand_wrench(rng, m, F0, 0.05, 2.0)
    d4 = form.scale_data(w4, fc, p)
    x0 = rng.normal(size=form.nx) * 0.3
    dirn = d4.w + rng.normal(size=form.nx) * 0.5 * max(np.linalg.norm(d4.w), 1e-3)
    probs.append(("move1", "move", form, ScaledData(d4.F, d4.w, d4.fc, d4.p, x0, dirn), gamma))
    # PRP just above and just below the exact limit along a random direction (where the late
    # stages of a bisection solve: the nearly degenerate problems)
    lim = None
    for _ in range(4):  # the PRP often resists everything (locked fingers): try a few directions
        d6 = m.expand_wrench(rand_wrench(rng, m, 1.0, 1.0, 1.0))
        d6 /= np.linalg.norm(d6)
        try:
            lf = sess.max_load_factor(fc, d6, 1e3 * F0)
        except Exception:
            continue
        if lf.status == "optimal" and np.isfinite(lf.magnitude) and lf.magnitude > 0:
            lim = lf.magnitude
            break
    if lim is not None and lim > 0:
        for tag, f in (
            ("edge+5", 1 + 1e-5),
            ("edge-5", 1 - 1e-5),
            ("edge+7", 1 + 1e-7),
            ("edge-7", 1 - 1e-7),
        ):
            probs.append(
                (f"prp{tag}", "prp", form, form.scale_data(m.reduce_wrench(lim * f * d6), fc), gamma)
            )
    # real steps of an iterative trajectory (the B&B drives it; the problems are compared)
    w5 = rand_wrench(rng, m, F0, 0.05, 2.0)
    rec = []
    orig = sess.solve

    def capture(kind, data, guess=None):
        rec.append((str(getattr(kind, "value", kind)), data))
        return orig(kind, data, guess)

    sess.solve = capture  # type: ignore[method-assign]
    try:
        sess.response(fc, m.expand_wrench(w5), "iterative")
    except Exception:  # the trajectory's own failure is not this test's subject
        pass
    steps = [d for k, d in rec if k == "move" and np.any(d.w != 0)]
    if steps:
        for j, i in enumerate(sorted({1 % len(steps), len(steps) // 2, len(steps) - 1})):
            probs.append((f"traj{j}", "move", form, steps[i], gamma))
    return probs


def _violation(P, z) -> float:
    v = P.C @ z
    out = max(
        float(np.abs(P.A @ z - P.b).max(initial=0.0)),
        float(np.maximum(P.lo - v, 0).max(initial=0.0)),
        float(np.maximum(v - P.up, 0).max(initial=0.0)),
    )
    return max(out, float(P.complementarity(z).max(initial=0.0)))


def compare_one(kind, form, data, gamma) -> dict:
    """B&B vs SCIP on one problem, with diagnostics."""
    from pinograsp.solvers import BranchAndBound, build_problem
    from pinograsp.solvers.miqp import CvxpyMIQP

    P = build_problem(form, kind, data, gamma)
    out: dict = {}
    t0 = time.perf_counter()
    try:
        bb = BranchAndBound(P)
        rb = bb.solve()
        out.update(
            bnb_status=str(rb.status.value),
            bnb_obj=float(rb.objective),
            bnb_nodes=bb.stats().nodes,
            bnb_viol=_violation(P, rb.z) if rb.z is not None else float("nan"),
            bnb_msg=rb.message,
        )
    except Exception as exc:
        out.update(
            bnb_status="crash",
            bnb_obj=float("nan"),
            bnb_nodes=0,
            bnb_viol=float("nan"),
            bnb_msg=f"{type(exc).__name__}: {exc}",
        )
        rb = None
    out["bnb_time"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    M, tries = 1e3, 0
    try:
        miqp = CvxpyMIQP(form, kind, gamma=gamma, time_limit=SCIP_TIME_LIMIT)
        while True:  # the engine's big-M enlargement
            rs = miqp.solve(data, M)
            if rs.status != "optimal" or rs.bigm_ratio < 0.1 or tries >= 2:
                break
            M, tries = M * 100, tries + 1
        out.update(
            scip_status=str(rs.status.value),
            scip_obj=float(rs.objective),
            scip_bigm=rs.bigm_ratio,
            scip_M=M,
            scip_msg=rs.message,
        )
        if rs.z is not None:
            out["scip_viol"] = _violation(P, rs.z)
            pol = BranchAndBound(P).solve_mode(rs.mode)  # SCIP's mode, solved exactly
            out["scip_mode_exact"] = (
                float(pol.objective) if pol.status == "optimal" else str(pol.status.value)
            )
    except Exception as exc:
        out.update(scip_status="crash", scip_obj=float("nan"), scip_msg=f"{type(exc).__name__}: {exc}")
    out["scip_time"] = time.perf_counter() - t0
    b, s = out["bnb_status"], out["scip_status"]
    if b != s:
        out["cls"] = "status mismatch"
    elif b != "optimal":
        out["cls"] = "same status (both " + b + ")"
    else:
        bo, so = out["bnb_obj"], out["scip_obj"]
        if bo <= so * (1 + REL) + ABS:
            out["cls"] = "B&B lower" if bo < so * (1 - REL) - ABS else "agree"
        else:
            out["cls"] = "B&B higher"
    return out


def section_agreement(quick: bool) -> dict:
    insts = agreement_instances(quick)
    rows = []
    t0 = time.perf_counter()
    for i, inst in enumerate(insts):
        try:
            probs = agreement_problems(inst)
        except Exception as exc:
            rows.append(
                dict(
                    id=inst["id"],
                    label=inst["label"],
                    name="setup",
                    kind="-",
                    cls="crash",
                    bnb_status="crash",
                    scip_status="-",
                    bnb_msg=f"{type(exc).__name__}: {exc}",
                )
            )
            continue
        for name, kind, form, data, gamma in probs:
            r = compare_one(kind, form, data, gamma)
            r.update(id=inst["id"], label=inst["label"], name=name, kind=kind, code=inst["code"])
            rows.append(r)
        if (i + 1) % 20 == 0 or i + 1 == len(insts):
            el = time.perf_counter() - t0
            print(
                f"  agreement: {i + 1}/{len(insts)} grasps, {len(rows)} problems, {el:.0f} s "
                f"(ETA {el / (i + 1) * (len(insts) - i - 1):.0f} s)",
                flush=True,
            )
    return dict(rows=rows, n_grasps=len(insts), wall=time.perf_counter() - t0)


def reproduce(pid: str) -> None:
    gid, name = pid.split("-", 1)
    for inst in agreement_instances(False):
        if inst["id"] == gid:
            break
    else:
        raise SystemExit(f"no grasp {gid}")
    for n, kind, form, data, gamma in agreement_problems(inst):
        if n == name:
            print(inst["label"], inst["code"], kind)
            print(json.dumps(compare_one(kind, form, data, gamma), indent=1, default=str))
            return
    raise SystemExit(f"no problem {name} for {gid}")


def diagnose(r: dict) -> str:
    """Which side a disagreement comes from (B&B feasibility tolerance 1e-9, SCIP's 1e-8)."""
    b, sc_ = r.get("bnb_status"), r.get("scip_status")
    me = r.get("scip_mode_exact")
    bv, sv = r.get("bnb_viol", float("nan")), r.get("scip_viol", float("nan"))
    if b in ("failed", "crash", "node_limit"):
        return f"**B&B {b}**"
    if r["cls"] == "B&B higher":
        mode_same = isinstance(me, float) and me >= r["bnb_obj"] * (1 - 1e-9) - 1e-18
        if sv <= 1e-9:
            what = (
                f"the exact QP of SCIP's mode gives {me:.3g}" if isinstance(me, float) else f"its mode: {me}"
            )
            return (
                "**B&B suboptimal: SCIP's point satisfies every row within the B&B's own 1e-9 and is "
                f"better** ({what}: that convex QP is solved inexactly)"
            )
        if mode_same:
            return (
                f"SCIP's point undercuts only by violating rows by {sv:.0e} (its mode, solved exactly = B&B)"
            )
        return "**B&B missed a better mode**"
    if b == "infeasible" and sc_ == "optimal":
        if me == "infeasible" and sv > 1e-9:
            return f"SCIP accepted a point violating rows by {sv:.0e} (its mode has no exact point)"
        return "**B&B missed a feasible mode**"
    if b == "optimal" and sc_ == "infeasible":
        if bv > 1e-9:
            return f"**B&B accepted a point violating rows by {bv:.1e}** (beyond its 1e-9 tolerance)"
        return "SCIP called a feasible problem infeasible"
    return ""


def _agreement_kind(r: dict) -> str:
    """The problem family of an agreement row (a line of the agreement table)."""
    if r["kind"] == "prp":
        return (
            f"PRP at the exact limit × (1 ± 1e-{r['name'][-1]})"
            if "edge" in r["name"]
            else "PRP, random data"
        )
    return "movement step, real trajectory" if r["name"].startswith("traj") else "movement step, random data"


def _diagnosis_counts(rows: list[dict]) -> Counter:
    return Counter(diagnose(r).split(" by ")[0].split(" (")[0].split(":")[0].replace("**", "") for r in rows)


def _relative_excess(r: dict) -> float:
    return (r["bnb_obj"] - r["scip_obj"]) / max(abs(r["scip_obj"]), 1e-300)


def md_agreement(ag: dict) -> str:
    """The agreement section of the report: counts per problem family, then the details."""
    rows = ag["rows"]
    cls = Counter(r["cls"] for r in rows)
    by_kind: dict[str, Counter] = {}
    for r in rows:
        by_kind.setdefault(_agreement_kind(r), Counter())[r["cls"]] += 1
    cats = ["agree", "B&B lower", "B&B higher", "status mismatch"]
    cats += sorted(c for c in cls if c not in cats)
    L = [
        f"{ag['n_grasps']} grasps, {len(rows)} problems, {ag['wall']:.0f} s. Criterion: both optimal and "
        f'B&B objective ≤ SCIP × (1 + {REL:g}) + {ABS:g} ("agree": within that band both ways; "B&B lower": '
        "below it, i.e. SCIP returned a worse point than its proven optimum claims); the objectives are "
        "SCIP's "
        "own point's (not re-polished).",
        "",
        "| problems | " + " | ".join(cats) + " | total |",
        "|---" + "|---:" * (len(cats) + 1) + "|",
    ]
    for key, c in sorted(by_kind.items()):
        L.append(f"| {key} | " + " | ".join(str(c.get(k, 0)) for k in cats) + f" | {sum(c.values())} |")
    L.append("| **all** | " + " | ".join(f"**{cls.get(k, 0)}**" for k in cats) + f" | **{len(rows)}** |")
    higher = [r for r in rows if r["cls"] == "B&B higher"]
    if higher:
        worst = max(_relative_excess(r) for r in higher)
        L += [
            "",
            f'"B&B higher": {len(higher)} (largest relative excess {worst:.1e}): '
            + "; ".join(f"{k}: {v}" for k, v in _diagnosis_counts(higher).most_common())
            + ". SCIP's point is checked against every row of the problem (max violation) and its own mode "
            "is re-solved exactly by the B&B's convex QP.",
        ]
    L += _loose_text(rows) + _timing_text(rows) + _disagreements(rows) + _lower_table(rows)
    return "\n".join(L)


def _loose_text(rows: list[dict]) -> list[str]:
    """B&B "optimal" answers whose point violates a row beyond the B&B's own tolerance."""
    loose = sorted(
        (r for r in rows if r.get("bnb_status") == "optimal" and r.get("bnb_viol", 0.0) > 1e-9),
        key=lambda r: -r["bnb_viol"],
    )
    nopt = sum(r.get("bnb_status") == "optimal" for r in rows)
    if loose:
        listed = " (" + ", ".join(f"{r['id']}-{r['name']} {r['bnb_viol']:.1e}" for r in loose) + ")"
        if all("edge+" in r["name"] for r in loose):
            listed += ": every one a PRP just beyond the exact limit, which is then called resisted."
        else:
            listed += "."
    else:
        listed = "."
    return [
        "",
        f'B&B answers "optimal" whose point violates some row by more than the B&B\'s own feasibility '
        f"tolerance 1e-9: {len(loose)} of {nopt}" + listed,
    ]


def _timing_text(rows: list[dict]) -> list[str]:
    """Objective differences and times where both solvers are optimal."""
    opt = [r for r in rows if r.get("bnb_status") == "optimal" and r.get("scip_status") == "optimal"]
    if not opt:
        return []
    rel = [
        abs(r["bnb_obj"] - r["scip_obj"]) / max(abs(r["scip_obj"]), 1e-300)
        for r in opt
        if r["scip_obj"] > 1e-9
    ]
    bt = [r["bnb_time"] for r in rows if "bnb_time" in r]
    st = [r["scip_time"] for r in rows if "scip_time" in r]
    return [
        "",
        f"Both optimal: {len(opt)}; relative objective difference where SCIP's objective > 1e-9: median "
        f"{statistics.median(rel):.1e}, max {max(rel):.1e}. Time per problem: B&B median "
        f"{1e3 * statistics.median(bt):.1f} ms (p90 {1e3 * q(bt, 90):.1f}, max {1e3 * max(bt):.0f}); "
        "SCIP median "
        f"{1e3 * statistics.median(st):.1f} ms (p90 {1e3 * q(st, 90):.1f}, max {1e3 * max(st):.0f}). "
        f"Largest B&B node count: {max(r.get('bnb_nodes', 0) for r in rows)}.",
    ]


def _disagreements(rows: list[dict]) -> list[str]:
    """The table of problems where the B&B is higher, the statuses differ or a solver crashed."""
    bad = [r for r in rows if r["cls"] in ("B&B higher", "status mismatch", "crash")]
    if not bad:
        return []
    L = [
        "",
        "Disagreements (reproduce one with `python benchmarks/solver_core.py --reproduce ID`):",
        "",
        "| ID | grasp | class | B&B status / objective | SCIP status / objective | relative excess "
        "| B&B point: max violation | SCIP point: max violation | SCIP's mode solved exactly by the B&B "
        "| diagnosis | B&B message |",
        "|---|---|---|---|---|---:|---:|---:|---|---|---|",
    ]
    for r in bad:
        exc = f"{_relative_excess(r):.2e}" if r["cls"] == "B&B higher" else ""
        me = r.get("scip_mode_exact", "—")
        me = f"{me:.10g}" if isinstance(me, float) else str(me)
        L.append(
            f"| {r['id']}-{r['name']} | {r['label']} | {r['cls']} | {r['bnb_status']} / "
            f"{r.get('bnb_obj', float('nan')):.10g} "
            f"| {r.get('scip_status', '?')} / {r.get('scip_obj', float('nan')):.10g} | {exc} "
            f"| {r.get('bnb_viol', float('nan')):.1e} | {r.get('scip_viol', float('nan')):.1e} | {me} "
            f"| {diagnose(r)} | {r.get('bnb_msg', '')[:80]} |"
        )
    return L + [
        "",
        "Diagnoses: " + "; ".join(f"{k}: {v}" for k, v in _diagnosis_counts(bad).most_common()) + ".",
    ]


def _lower_table(rows: list[dict]) -> list[str]:
    """The five largest "B&B lower" cases."""
    low = [r for r in rows if r["cls"] == "B&B lower"]
    if not low:
        return []
    worst = sorted(low, key=lambda r: -(r["scip_obj"] - r["bnb_obj"]) / max(abs(r["scip_obj"]), 1e-300))[:5]
    L = [
        "",
        "Largest \"B&B lower\" cases (SCIP's point worse than the B&B's optimum):",
        "",
        "| ID | grasp | B&B objective | SCIP objective | SCIP's mode solved exactly |",
        "|---|---|---:|---:|---|",
    ]
    for r in worst:
        me = r.get("scip_mode_exact", "—")
        me = f"{me:.6g}" if isinstance(me, float) else str(me)
        L.append(
            f"| {r['id']}-{r['name']} | {r['label']} | {r['bnb_obj']:.6g} | {r['scip_obj']:.6g} | {me} |"
        )
    return L
