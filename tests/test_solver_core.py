"""The exact solver core: determinism across processes and call history, mirror symmetry,
unbounded directions decided by the model, the branch-and-bound against the reference MIQP, and
the secant search against the paper's bisection."""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import pinograsp as pg
from pinograsp import examples
from pinograsp.core.examples import random_grasp
from pinograsp.solvers import BranchAndBound, Formulation, ScaledData, available_miqp_solvers, build_problem

HAS_SCIP = "scip" in available_miqp_solvers()

#: The three queries of the issue, as code run in a fresh interpreter.
QUERIES = textwrap.dedent(
    """
    import json, sys
    import numpy as np
    import pinograsp as pg
    from pinograsp import examples
    from pinograsp.core.examples import random_grasp

    def record(r):
        resp = r.response
        forces = resp.contact_forces.tobytes().hex() if resp is not None else ""
        return [float(r.magnitude).hex(), bool(r.unbounded), forces,
                [(float(m).hex(), ok) for m, ok in r.evidence]]

    s = pg.load_scene("case1")
    out = [record(pg.max_resistible_wrench(s.model, s.command, d, upper=1e3)) for d in ("fx", "-fx")]
    out.append(record(pg.max_resistible_wrench(examples.wedge(), 1.0, "-fy", upper=1e3)))
    out.append(record(pg.max_resistible_wrench(examples.wedge(), 1.0, "fy", upper=1e3)))
    g = random_grasp(3, n_pairs=2)
    out.append(record(pg.max_resistible_wrench(g, 1.0, [0.3, -0.2, 0.5, 0.0, 0.0, 0.0], upper=50)))
    a = np.radians(30.0)
    out.append(record(pg.max_resistible_wrench(
        s.model, s.command, [np.cos(a), np.sin(a), 0, 0, 0, 0], method="energetic", upper=50)))
    b = np.radians(80.0)
    out.append(record(pg.max_resistible_wrench(
        examples.pinch(planar=False), 1.0, [0, np.cos(b), np.sin(b), 0, 0, 0], method="energetic",
        upper=50, cone_tolerance=np.radians(2.0))))
    json.dump(out, sys.stdout)
    """
)


def _run_fresh() -> list:
    done = subprocess.run([sys.executable, "-c", QUERIES], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def test_same_query_bit_identical_in_fresh_processes_and_after_other_queries():
    runs = [_run_fresh() for _ in range(3)]
    assert runs[0] == runs[1] == runs[2]
    # in this process, after unrelated queries (another scene, other directions, PRP)
    s = pg.load_scene("case1")
    pg.max_resistible_wrench(s.model, s.command, [1.0, 1.0, 0, 0, 0, 0], upper=50)
    pg.passive_response(examples.wedge(), 1.0, [0, 3.0, 0], method="prp")
    pg.max_resistible_wrench(examples.pinch(), 1.0, "fy", upper=100, steps=10)
    here = json.loads(json.dumps(_in_process()))
    assert here == runs[0]
    # case1 is mirror-symmetric about the YZ plane: +X and -X are the same answer
    assert runs[0][0][:2] == runs[0][1][:2] == [float("inf").hex(), True]


def _in_process() -> list:
    ns: dict = {}
    code = QUERIES.replace("json.dump(out, sys.stdout)", "")
    exec(compile(code, "<queries>", "exec"), ns)  # the same code as in the fresh processes
    return ns["out"]


def _angle_dir(deg: float) -> list[float]:
    a = np.radians(deg)
    return [np.cos(a), np.sin(a), 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("upper", [50.0, 1e3])
@pytest.mark.parametrize("theta", [15, 30, 60, 80])
def test_case1_mirror_pairs_are_identical(theta, upper):
    """(θ, 180° − θ) are mirror images on case1: the iterative scheme's grid-snapped search
    gives identical magnitudes, verdicts and evidence."""
    s = pg.load_scene("case1")
    a = pg.max_resistible_wrench(s.model, s.command, _angle_dir(theta), "iterative", upper=upper)
    b = pg.max_resistible_wrench(s.model, s.command, _angle_dir(180 - theta), "iterative", upper=upper)
    assert a.magnitude == b.magnitude and a.unbounded == b.unbounded
    assert a.evidence == b.evidence
    if not a.unbounded:  # mirrored forces: left/right contacts swap, tangential parts flip
        fa, fb = a.response.contact_forces, b.response.contact_forces
        np.testing.assert_allclose(fa[:, 0], fb[[2, 3, 0, 1], 0], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("theta", [15, 30, 60, 80])
def test_case1_mirror_pairs_agree_on_the_default_path(theta):
    """The default quasi-static path is exact (no grid): on the URDF-built case 1, symmetric
    only to rounding (mirrored contact points differ by 4.6e-12 m of 0.07 m), mirror pairs
    agree to 1.2e-10 relative with the same status (the exactly mirrored model agrees to 1e-12:
    tests/test_quasistatic.py)."""
    s = pg.load_scene("case1")
    a = pg.max_resistible_wrench(s.model, s.command, _angle_dir(theta))
    b = pg.max_resistible_wrench(s.model, s.command, _angle_dir(180 - theta))
    assert a.method == "quasistatic" and a.status == b.status and a.unbounded == (theta == 15)
    assert b.magnitude == pytest.approx(a.magnitude, rel=1e-9)
    if not a.unbounded:
        fa, fb = a.response.contact_forces, b.response.contact_forces
        np.testing.assert_allclose(fa[:, 0], fb[[2, 3, 0, 1], 0], rtol=1e-8, atol=1e-9)


@pytest.mark.parametrize("theta", [0, 180, 195, 240, 270, 300, 345])
def test_case1_unbounded_where_the_paper_says_passively_resisted(theta):
    """Seed paper, case 1: ±X and every XY direction with a −Y component are passively resisted
    without bound (an independent simulation holds them to 1000 N)."""
    s = pg.load_scene("case1")
    r = pg.max_resistible_wrench(s.model, s.command, _angle_dir(theta), upper=1e3)
    assert r.unbounded and r.magnitude == np.inf


@pytest.mark.slow
def test_case1_full_circle_mirror_and_unbounded():
    s = pg.load_scene("case1")
    res = {  # the iterative scheme's grid-snapped search: mirror pairs bit-identical
        t: pg.max_resistible_wrench(s.model, s.command, _angle_dir(t), "iterative", upper=1e3)
        for t in range(0, 360, 5)
    }
    for t in range(0, 91, 5):
        assert res[t].magnitude == res[(180 - t) % 360].magnitude
    for t in list(range(185, 360, 5)) + [0, 180]:
        assert res[t].unbounded, t


def test_known_answers_of_the_core():
    """Closed forms and the simulation-checked values reached by the exact core."""
    s = pg.load_scene("case1")
    it = "iterative"
    # case1 +Y (the same under ±1e-6° turns of the direction; the preload's least-energy
    # friction state); 30°: the give-way load of the independent simulation (35.7 N)
    assert pg.max_resistible_wrench(s.model, s.command, "fy", it, upper=1e3).magnitude == pytest.approx(
        4.2982, abs=1e-3
    )
    assert pg.max_resistible_wrench(
        s.model, s.command, _angle_dir(30), it, upper=1e3
    ).magnitude == pytest.approx(35.73, abs=0.01)
    # the default quasi-static path: +Y 4.3354 N, 30° 35.7136 N (the simulation with the
    # model's pyramid gives way at 4.3287 N and 35.404 N: scripts/reproduce/data/qs_sim.jsonl)
    assert pg.max_resistible_wrench(s.model, s.command, "fy").magnitude == pytest.approx(4.3354, abs=1e-4)
    assert pg.max_resistible_wrench(s.model, s.command, _angle_dir(30)).magnitude == pytest.approx(
        35.7136, abs=1e-4
    )
    # the pinch's band 2 mu tau0 / (L |sin θ|): within the iterative tolerance, exact on the path
    for deg in (90, 45):
        band = 10.0 / np.sin(np.radians(deg))
        r = pg.max_resistible_wrench(examples.pinch(), 1.0, _angle_dir(deg)[:3], it, upper=100, steps=16)
        assert r.magnitude == pytest.approx(band, rel=2e-4)
        r = pg.max_resistible_wrench(examples.pinch(), 1.0, _angle_dir(deg)[:3])
        assert r.magnitude == pytest.approx(band, rel=1e-12)


@pytest.mark.parametrize("direction", ["fy", [1.0, 1.0, 0.0], [-0.3, 1.0, 0.0]])
@pytest.mark.parametrize("model", ["pinch", "wedge", "case1"])
def test_secant_search_finds_the_bisection_cell(model, direction):
    if model == "case1":
        s = pg.load_scene("case1")
        m, cmd = s.model, s.command
        direction = direction if isinstance(direction, str) else list(direction) + [0, 0, 0]
    else:
        m, cmd = getattr(examples, model)(), 1.0
    a = pg.max_resistible_wrench(m, cmd, direction, "iterative", upper=100, steps=16, search="secant")
    b = pg.max_resistible_wrench(m, cmd, direction, "iterative", upper=100, steps=16, search="bisection")
    assert a.magnitude == b.magnitude and a.unbounded == b.unbounded
    assert len(a.evidence) <= 2 * len(b.evidence)


def test_direct_load_factor_by_branch_and_bound_matches_closed_form():
    """Alg. 1's largest load factor in one complementarity solve: the pinch band 2 mu tau0 / L
    along y, 2 mu tau0 / (L sin θ) at θ, unbounded along x (PRP)."""
    m = examples.pinch()
    r = pg.max_resistible_wrench(m, 1.0, "fy", "prp", upper=100, search="direct")
    assert r.magnitude == pytest.approx(10.0, rel=1e-8)
    r = pg.max_resistible_wrench(m, 1.0, [1.0, 1.0, 0], "prp", upper=100, search="direct")
    assert r.magnitude == pytest.approx(10.0 * np.sqrt(2), rel=1e-8)
    assert pg.max_resistible_wrench(m, 1.0, "fx", "prp", upper=100, search="direct").unbounded


@pytest.mark.parametrize(
    ("direction", "sin_theta"),
    [("fy", 1.0), ([1.0, 1.0, 0], np.sqrt(0.5)), ([0.3, -1.0, 0], 1 / np.sqrt(1.09))],
)
def test_fine_bisection_next_to_the_limit_gives_a_verdict(direction, sin_theta):
    """30 halvings of [0, 1e3] test magnitudes ~1e-7 (relative) above the pinch's limit, where
    the node QPs are nearly infeasible: the least row violation decides (no SolverError), and
    the answer is the closed form 2 mu tau0 / (L |sin θ|) to one grid step."""
    m = examples.pinch()
    exact = 10.0 / sin_theta
    r = pg.max_resistible_wrench(m, 1.0, direction, "prp", upper=1e3, steps=30)
    assert r.status == "finite"
    assert abs(r.magnitude - exact) <= 1e3 / 2**30 * 1.0001


def _random_step_problems(seed: int):
    """A random grasp (2-4 pairs of fingers, one- or two-link, 3D or planar) and PRP and
    movement-step data of random loads."""
    rng = np.random.default_rng(seed)
    g = random_grasp(
        seed,
        n_pairs=int(rng.integers(1, 3)),
        contacts_per_finger=int(rng.integers(1, 3)),
        planar=bool(seed % 3 == 0),
    )
    f = Formulation(g)
    out = []
    for _ in range(2):
        w = rng.normal(size=f.nw) * rng.uniform(0.2, 3.0)
        data = f.scale_data(w, np.ones(g.na))
        out.append((f, "prp", data))
        x0, d = rng.normal(size=f.nx) * 0.2, rng.normal(size=f.nx)
        out.append((f, "move", ScaledData(data.F, data.w, data.fc, data.p, x0, d)))
    return g, out


@pytest.mark.skipif(not HAS_SCIP, reason="SCIP missing")
@pytest.mark.parametrize("seed", range(6))
def test_branch_and_bound_never_worse_than_the_reference_miqp(seed):
    """Every optimum agrees with SCIP's to 1e-6 relative or is lower (docs/solver_core.md: 200+
    grasps)."""
    from pinograsp.solvers.miqp import CvxpyMIQP

    _, problems = _random_step_problems(seed)
    for f, kind, data in problems:
        own = BranchAndBound(build_problem(f, kind, data)).solve()
        ref = CvxpyMIQP(f, kind).solve(data, 1e3)
        assert own.status == ref.status, (kind, own.message, ref.message)
        if own.status == "optimal":
            assert own.objective <= ref.objective * (1 + 1e-6) + 1e-12


def test_canonical_optimum_is_feasible_and_complementary():
    _, problems = _random_step_problems(11)
    for f, kind, data in problems:
        P = build_problem(f, kind, data)
        sol = BranchAndBound(P).solve()
        if sol.status != "optimal":
            continue
        assert np.abs(P.A @ sol.z - P.b).max(initial=0) < 1e-8
        v = P.C @ sol.z
        lo, up = P.bounds(P.sides_of(sol.mode))
        assert np.all(v >= lo - 1e-8) and np.all(v <= up + 1e-8)
        assert P.complementarity(sol.z).max(initial=0) < 1e-8


def test_profile_normalisation_has_one_home():
    """The value a profile is normalised by: its own result along the reference when it has
    that direction (``ResistanceProfile.result_along``), else one solve; an unbounded or
    unresisted reference is an InvalidInputError naming ``normalize``."""
    from pinograsp.analysis.profile import reference_magnitude

    m, s = examples.pinch(), pg.Settings()
    p = pg.resistance_profile(m, 1.0, n=8, method="prp", upper=100.0, steps=8)
    along_y = p.result_along(p.basis[1])
    assert along_y is p.results[2] and p.result_along(p.directions[1] + 2e-9) is None
    assert reference_magnitude(m, 1.0, p, True, "prp", 100.0, 8, s) == along_y.magnitude
    pn = pg.resistance_profile(m, 1.0, n=8, method="prp", upper=100.0, steps=8, normalize=True)
    assert pn.normalized_by == along_y.magnitude
    np.testing.assert_array_equal(pn.magnitudes, p.magnitudes / along_y.magnitude)
    # a reference that the profile does not sample is solved on its own
    six = pg.resistance_profile(m, 1.0, n=6, method="prp", upper=100.0, steps=8)
    alone = pg.max_resistible_wrench(m, 1.0, "fy", "prp", 100.0, 8)
    assert reference_magnitude(m, 1.0, six, "fy", "prp", 100.0, 8, s) == alone.magnitude
    with pytest.raises(pg.InvalidInputError, match=r"^normalize: the reference direction \+fx is unbounded"):
        reference_magnitude(m, 1.0, p, "fx", "prp", 100.0, 8, s)
