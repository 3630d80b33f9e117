"""Text output of the command line: where results go (stdout, ``--json``, ``--out`` files), the
progress bar, and the tables and lines shared by several commands (docs/cli.md, "Output")."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TextIO

import pinograsp as pg

from ..core.paths import probe_writable
from ..core.serialize import jsonable, vector_text


class Output:
    """stdout for humans, or nothing but JSON with ``--json``; files in ``--out``."""

    def __init__(self, args: argparse.Namespace) -> None:
        self.args = args
        self.json = bool(getattr(args, "json", False))
        self.out = Path(args.out) if getattr(args, "out", None) else None
        self.written: list[Path] = []
        if self.out is not None:  # writable before any work (docs/errors.md)
            try:
                self.out.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise pg.InvalidInputError(
                    "--out", f"cannot create the folder {str(self.out)!r}: {exc.strerror or exc}"
                ) from exc
            if not os.access(self.out, os.W_OK):
                raise pg.InvalidInputError("--out", f"the folder {str(self.out)!r} is not writable")

    def print(self, *lines: str) -> None:
        """Print ``lines`` on stdout, unless ``--json``."""
        if not self.json:
            for line in lines:
                print(line)

    @staticmethod
    def target(value: str | None, option: str) -> Path | None:
        """The file of ``option`` (``--csv``, ``--png``), checked before any work like ``--out``:
        not a folder, its folder created if missing and writable (a probe file is created and
        removed there). ``None`` when not given.

        Raises:
            InvalidInputError: Naming ``option``.
        """
        if value is None:
            return None
        p = Path(value)
        if p.is_dir() or not p.name:
            raise pg.InvalidInputError(option, f"{value!r} is a folder, not a file")
        probe_writable(option, p, str(value))
        return p

    def path(self, name: str) -> Path | None:
        """``--out``/``name`` (the folder created), or ``None`` without ``--out``."""
        if self.out is None:
            return None
        self.out.mkdir(parents=True, exist_ok=True)
        return self.out / name

    def write_json(self, name: str, data: dict) -> None:
        """Write ``data`` as ``--out``/``name`` (nothing without ``--out``)."""
        p = self.path(name)
        if p is not None:
            p.write_text(json.dumps(jsonable(data), indent=2) + "\n")
            self.written.append(p)

    def figure(self, name: str, draw: Callable[[Path], object]) -> None:
        """``draw(path)`` for ``--out``/``name`` (nothing without ``--out``)."""
        p = self.path(name)
        if p is not None:
            draw(p)
            self.written.append(p)

    def finish(self, data: dict) -> None:
        """Keep the JSON document for ``main`` (``--json``), or list the files written."""
        if self.json:  # printed by main() once the solvers' stdout is restored
            self.args.json_text = json.dumps(jsonable(data), indent=2) + "\n"
        elif self.written:
            print("\nwrote " + ", ".join(str(p) for p in self.written))


class ProgressBar:
    """A tiny progress bar with elapsed time and ETA, on one stderr line.

    Called as ``bar(done, total)`` (the ``progress`` callback of the API); ``close()`` ends the
    line.
    """

    def __init__(self, label: str, stream: TextIO | None = None, width: int = 28, enabled: bool = True):
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self.enabled = enabled
        self.t0 = time.perf_counter()
        self._last = ""

    @staticmethod
    def clock(seconds: float) -> str:
        """``mm:ss``, ``h:mm:ss`` from 1 h, ``--:--`` when not finite."""
        if not math.isfinite(seconds):
            return "--:--"
        s = int(round(seconds))
        return (
            f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60:02d}:{s % 60:02d}"
        )

    def text(self, done: int, total: int) -> str:
        """The bar's line after ``done`` of ``total``."""
        elapsed = time.perf_counter() - self.t0
        frac = done / total if total else 1.0
        k = int(round(self.width * frac))
        eta = elapsed / done * (total - done) if done else float("nan")
        return (
            f"{self.label} [{'#' * k}{'.' * (self.width - k)}] {done}/{total} "
            f"{100 * frac:3.0f}%  {self.clock(elapsed)} elapsed, ETA {self.clock(eta)}"
        )

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        line = self.text(done, total)
        pad = " " * max(0, len(self._last) - len(line))
        self.stream.write("\r" + line + pad)
        self.stream.flush()
        self._last = line

    def close(self) -> None:
        """End the bar's line (when anything was drawn)."""
        if self.enabled and self._last:
            self.stream.write("\n")
            self.stream.flush()


def progress_bar(args: argparse.Namespace, label: str) -> ProgressBar:
    """A :class:`ProgressBar` drawn with ``--progress``, or by default when stderr is a terminal."""
    if args.progress is not None:
        enabled = bool(args.progress)
    else:
        try:
            enabled = sys.stderr.isatty()
        except (AttributeError, ValueError):
            enabled = False
    return ProgressBar(label, enabled=enabled)


# ---------------------------------------------------------------------------- shared lines
def scene_header(scene: Any) -> dict[str, Any]:
    """The scene's name, file and description (the head of every JSON document)."""
    return {"scene": scene.name, "scene_file": scene.path, "description": scene.description}


def scene_line(scene: Any) -> str:
    """``scene 'name': description``."""
    return f"scene {scene.name!r}: {scene.description}"


def preload_line(command: dict[str, float], name: str | None) -> str:
    """``preload: a=1, b=0.5 (name)`` [N·m or N]."""
    text = f"preload: {', '.join(f'{k}={v:g}' for k, v in command.items())}"
    return text + (f" ({name})" if name else "")


def model_settings(settings: Any) -> tuple[dict[str, Any], str]:
    """The settings that change the contact model, as JSON fields [rad] and as a note for the
    method line (``""`` when both are at their defaults): ``normal_uncertainty`` and
    ``cone_tolerance`` (``None``: the model's pyramids)."""
    data = {"normal_uncertainty": settings.normal_uncertainty, "cone_tolerance": settings.cone_tolerance}
    parts = []
    if settings.normal_uncertainty:
        parts.append(f"normal uncertainty {math.degrees(settings.normal_uncertainty):g}°")
    if settings.cone_tolerance is not None:
        parts.append(f"cone tolerance {math.degrees(settings.cone_tolerance):g}°")
    return data, "".join(f", {t}" for t in parts)


def contact_table(model: Any, r: Any) -> list[str]:
    """Contact forces of a passive response [N]: mode, state (``"sticking"``, ``"sliding"`` or
    ``"separated"``, when the response records states), contact-frame force, friction use, world."""
    d = r.to_dict(model)
    w = max([len("contact"), *(len(c["name"]) for c in d["contacts"])])
    states = any(c["state"] for c in d["contacts"])
    lines = [
        f"  {'contact':{w}s}  {'mode':9s} " + (f"{'state':9s} " if states else "")
        + f"{'c_n [N]':>10s} {'c_t1 [N]':>10s} {'c_t2 [N]':>10s} {'|c_t|/mu c_n':>12s}   world force [N]"
    ]  # fmt: skip
    for i, c in enumerate(d["contacts"]):
        f = r.contact_forces[i]  # NaN (not None) when there is no solution
        use = c["friction_use"]
        use_s = "—" if use is None else f"{use:.3f}"
        state = f"{c['state'] or '—':9s} " if states else ""
        lines.append(
            f"  {c['name']:{w}s}  {c['mode'] or '—':9s} {state}{f[0]:10.4f} {f[1]:10.4f} {f[2]:10.4f}"
            f" {use_s:>12s}   {vector_text(r.contact_forces_world[i])}"
        )
    return lines


def actuator_table(model: Any, r: Any) -> list[str]:
    """Actuators of a passive response: kind, command, force [N·m or N], mode."""
    d = r.to_dict(model)
    w = max([len("actuator"), *(len(a["name"]) for a in d["actuators"])])
    lines = [f"  {'actuator':{w}s}  {'kind':17s} {'command':>10s} {'force':>10s}  mode"]
    for i, a in enumerate(d["actuators"]):
        lines.append(
            f"  {a['name']:{w}s}  {a['kind'] or '':17s} {r.command[i]:10.4f} {r.actuator_forces[i]:10.4f}"
            f"  {a['mode'] or '—'}"
        )
    return lines


def audit_line(r: Any) -> str:
    """The audit of a passive response on one line: verdict, residuals [N], energy [J]."""
    a = r.audit
    if a is None:
        return "audit: none"
    return (
        f"audit: {'ok' if a.ok else 'NOT OK'} (equilibrium {a.equilibrium:.2e} N, hand {a.hand:.2e} N, "
        f"complementarity {a.complementarity:.2e} N, friction {a.friction:.2e} N, "
        f"big-M use {a.bigm_ratio:.1%}{_energy_text(a.energy)})"
    )


def _energy_text(e: Any) -> str:
    if e is None:
        return ""
    text = f"; spring energy {e.spring_energy:.4g} J <= supplied {e.load_work + e.actuator_work:.4g} J"
    if not e.energy_ok:
        text = text.replace("<=", "> (WEDGING)") + f" at {', '.join(e.contacts)}"
    if not e.displacement_ok:
        text += f"; displacements {e.displacement_ratio:.3g}x the spring compressions (ABSURD)"
    return text


def scene_figures(args: argparse.Namespace, out: Output, scene: Any, response: Any, png: str | None) -> None:
    """The scene with ``response``'s forces: ``--out``/``png`` (none when ``png`` is ``None``), and
    ``--html FILE`` (the interactive plotly view, standalone: works offline)."""
    if png is not None:
        out.figure(png, lambda p: pg.save_png(scene, response, path=p, title=f"{scene.name}"))
    if getattr(args, "html", None):
        fig = pg.scene_figure(scene, response, title=f"{scene.name}")
        out.written.append(pg.save_html(fig, args.html))
