"""The validation cases of the quasi-static method (issue 25): grasps, commands and directions.

One :class:`Case` is one grasp, preload command and load direction; the simulation references
(``qs_references.py sim``), the cached predictions of the paper's methods (``qs_references.py
methods``) and the harness (``validate_quasistatic.py``) all enumerate the same list, keyed by
:attr:`Case.key`, so that a reference computed once is found again.

Sets (every choice below is deterministic: seeds, not time):

- ``scenes``: every built-in scene, 24 directions in its ``analysis.plane`` plus its named
  directions not among them; the scene's preload and ``analysis.upper``.
- ``random``: ``pg.examples.random_grasp(seed, n_pairs, contacts_per_finger=2)`` (non-
  backdrivable fingers, mu 0.5, 8-edge pyramids) with ``n_pairs`` 1–4 (4, 8, 12, 16 contacts),
  seeds 0–5, command 1 N·m per finger, upper 50, 3 random 6D directions per grasp.
- ``backdrivable``: the same grasps with backdrivable fingers (``kind="backdrivable"``), 12 and
  16 contacts, seeds 0–2: random grasps with 12–16 contacts and ratchets surround the object and mostly hold,
  backdrivable fingers give way at finite loads (finite directions where the ``random`` set mostly holds).
- ``lowmu``: mu 0.2 and torque-heavy directions (force part scaled by 0.1 before normalising),
  ``n_pairs`` 2–3, seeds 0–2: more finite and gradual give-ways at 8 and 12 contacts.

Random directions: ``np.random.default_rng(1000 + seed).standard_normal(6)`` normalised (the
plain Euclidean norm of force [N] and torque [N·m], as ``pg.simulate_max_wrench``), three per
seed, the same for every contact count and set of one seed.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import pinograsp as pg

from .validate_mujoco import _label  # the same direction labels as the scene validation

#: Built-in scenes validated (all of them).
SCENES = (
    "pinch",
    "wedge",
    "case1",
    "case2",
    "case3",
    "fig1",
    "parallel_jaw_bar",
    "parallel_jaw_box",
    "talos_torus",
    "case2_snap",
)
#: Directions per scene plane.
N_PLANE = 24
#: Upper load of the random sets [N or N·m], as in the issue.
RANDOM_UPPER = 50.0
#: Bisection steps of the paper's methods on the random sets. The issue's speed table used 10
#: (resolution 50 / 2**10 = 0.05 N), too coarse for the sub-newton limits of 4-contact grasps.
RANDOM_STEPS = 20
#: The random sets: name -> (n_pairs values, seeds, mu, actuator kind, force-part scale).
RANDOM_SETS: dict[str, tuple[tuple[int, ...], tuple[int, ...], float, str, float]] = {
    "random": ((1, 2, 3, 4), tuple(range(6)), 0.5, "non-backdrivable", 1.0),
    "backdrivable": ((3, 4), (0, 1, 2), 0.5, "backdrivable", 1.0),
    "lowmu": ((2, 3), (0, 1, 2), 0.2, "non-backdrivable", 0.1),
}
SETS = ("scenes", *RANDOM_SETS)


@dataclass(frozen=True)
class Case:
    """One grasp, preload and load direction.

    Attributes:
        key: Unique, stable identifier ``set/grasp/direction``.
        set: ``"scenes"`` or a key of :data:`RANDOM_SETS`.
        group: Table row group: the scene name, or ``"<nc> contacts"``.
        grasp: ``scene name`` or ``random_grasp(seed, n_pairs, ...)`` text.
        label: Direction label (``"+fy"``, ``"30°"``, ``"d1"``).
        direction: Unit direction, (6,) [N, N·m].
        upper: Upper load of the simulation and the paper's methods.
        nc: Number of contacts.
        spec: How to rebuild the grasp (``{"scene": name}`` or random_grasp arguments).
        planar: A planar model (its friction polygon is the segment ``[-mu, mu] c_n``, the
            circular cone restricted to the plane: one simulation serves both friction models).
    """

    key: str
    set: str
    group: str
    grasp: str
    label: str
    direction: tuple[float, ...]
    upper: float
    nc: int
    spec: dict[str, Any] = field(hash=False, compare=False)
    planar: bool = False

    def build(self) -> tuple[Any, Any, np.ndarray]:
        """``(scene or None, model, command)`` of the case."""
        if "scene" in self.spec:
            scene = pg.load_scene(self.spec["scene"])
            return scene, scene.model, scene.model.command_vector(scene.preload(None))
        kw = dict(self.spec)
        model = pg.examples.random_grasp(kw.pop("seed"), kw.pop("n_pairs"), **kw)
        return None, model, np.ones(model.na)


def fingerprint(case: Case) -> str:
    """Hash of everything a simulation of the case depends on (model arrays, command, direction,
    upper): fig. 1 is the case-1 grasp with the same preload, so one simulation serves both."""
    import hashlib

    _, m, cmd = case.build()
    h = hashlib.sha256()
    for a in (m.G, m.J, m.D, m.k, m.mu, m.R, m.C, m.frames, m.points, cmd, np.asarray(case.direction)):
        h.update(np.ascontiguousarray(np.asarray(a, dtype=float)).tobytes())
    h.update(repr((m.kinds, m.length_scale, case.upper)).encode())
    return h.hexdigest()[:16]


def scene_cases(name: str, n: int = N_PLANE) -> list[Case]:
    """``n`` directions of the scene's plane, then its named directions not among them."""
    scene = pg.load_scene(name)
    dirs = pg.plane_directions(scene.model, scene.analysis.plane, n)
    basis = (dirs[0], dirs[n // 4]) if n % 4 == 0 else None
    out = [(_label(d, basis), np.asarray(d, dtype=float)) for d in dirs]
    for dname, d in scene.analysis.directions.items():
        d = np.asarray(scene.direction(dname), dtype=float)
        if not any(np.allclose(d, e) for _, e in out):
            out.append((f"{dname} ({_label(d, None)})", d))
    upper = float(scene.analysis.upper)
    return [
        Case(
            f"scenes/{name}/{label}",
            "scenes",
            name,
            name,
            label,
            tuple(float(x) for x in d / np.linalg.norm(d)),
            upper,
            scene.model.nc,
            {"scene": name},
            bool(scene.model.planar),
        )
        for label, d in out
    ]


def random_directions(seed: int, force_scale: float = 1.0, n: int = 3) -> list[np.ndarray]:
    """``n`` seeded random 6D unit directions (force part scaled by ``force_scale`` first)."""
    rng = np.random.default_rng(1000 + seed)
    out = []
    for _ in range(n):
        d = rng.standard_normal(6)
        d[:3] *= force_scale
        out.append(d / np.linalg.norm(d))
    return out


def random_cases(set_name: str) -> list[Case]:
    """The cases of one random set (:data:`RANDOM_SETS`)."""
    pairs, seeds, mu, kind, fscale = RANDOM_SETS[set_name]
    out = []
    for n_pairs in pairs:
        for seed in seeds:
            spec = {"seed": seed, "n_pairs": n_pairs, "contacts_per_finger": 2, "mu": mu, "kind": kind}
            grasp = f"random_grasp({seed}, {n_pairs}, contacts_per_finger=2, mu={mu:g}, kind={kind!r})"
            nc = 4 * n_pairs
            for j, d in enumerate(random_directions(seed, fscale)):
                key = f"{set_name}/n{n_pairs}s{seed}/d{j}"
                out.append(
                    Case(
                        key,
                        set_name,
                        f"{nc} contacts",
                        grasp,
                        f"d{j}",
                        tuple(float(x) for x in d),
                        RANDOM_UPPER,
                        nc,
                        spec,
                    )
                )
    return out


def cases(sets: tuple[str, ...] | list[str] = SETS, scenes: tuple[str, ...] = SCENES) -> Iterator[Case]:
    """Every case of the named sets, in a fixed order."""
    for s in sets:
        if s == "scenes":
            for name in scenes:
                yield from scene_cases(name)
        else:
            yield from random_cases(s)


def parse_sets(text: str) -> list[str]:
    """``"scenes,random"`` -> a checked list of set names."""
    names = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in names if s not in SETS]
    if bad:
        raise SystemExit(f"unknown set(s) {bad}; choose from {list(SETS)}")
    return names
