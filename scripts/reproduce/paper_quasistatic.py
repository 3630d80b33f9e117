"""The quasi-static column of ``scripts/reproduce/paper_results.py``: the paper's questions answered
by ``method="quasistatic"`` beside the paper's methods.

The same case functions run with the method overridden (``RunSettings.method``), their plots going
to a temporary folder; each row's answer and verdict become the ``quasistatic`` cell of the row
with the same case and question. ``--only quasistatic`` merges the column into the summary table
already published in ``docs/results.md`` and the README (the other columns' numbers kept as they
are, not recomputed): a fast path, seconds instead of the paper's methods' minutes.
"""

from __future__ import annotations

import argparse
import re
import tempfile
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from .paper_common import Case, Row

#: The summary table's first header cells (both the old six-column and the new layout).
HEADER = "| case | question | paper | pinograsp |"
#: Heading of the quasi-static section of docs/results.md.
SECTION = "## The quasi-static column"


def run_quasistatic(
    run: Callable[[argparse.Namespace, Path], list[Case]], args: argparse.Namespace
) -> tuple[list[Case], float]:
    """The cases run with ``method="quasistatic"`` (plots into a temporary folder); and the time [s]."""
    qs_args = argparse.Namespace(**{**vars(args), "method": "quasistatic"})
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pinograsp-qs-results-") as tmp:
        cases = run(qs_args, Path(tmp))
    return cases, time.perf_counter() - t0


def cell(r: Row) -> str:
    """One row's quasi-static answer with its verdict against the paper."""
    return f"{r.ours} (agrees: {r.agrees})"


def merge(rows: list[Row], qs_cases: list[Case]) -> list[Row]:
    """``rows`` with the quasi-static cell of the row with the same case and question ("—" where
    the quasi-static run has no such row)."""
    qs = {(r.case, r.question): cell(r) for c in qs_cases for r in c.rows}
    return [replace(r, quasistatic=qs.get((r.case, r.question), "—")) for r in rows]


def merge_cases(cases: list[Case], qs_cases: list[Case]) -> None:
    """Fill in the quasi-static cells of ``cases``' rows in place."""
    for c in cases:
        c.rows = merge(c.rows, qs_cases)


# ---------------------------------------------------------------------------- the published table
def _cells(line: str) -> list[str]:
    """The cells of one markdown table row (escaped pipes ``\\|`` kept inside cells)."""
    parts = re.split(r"(?<!\\)\|", line.strip())
    return [p.strip() for p in parts[1:-1]]


def table_span(lines: list[str]) -> tuple[int, int]:
    """First and one-past-last line index of the summary table in ``lines``."""
    start = next((i for i, ln in enumerate(lines) if ln.startswith(HEADER)), None)
    if start is None:
        raise SystemExit(f"no summary table (a line starting {HEADER!r}) found")
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return start, end


def parse_rows(text: str) -> list[Row]:
    """The summary table's rows as published (six columns, or seven with the quasi-static one)."""
    lines = text.splitlines()
    start, end = table_span(lines)
    head = _cells(lines[start])
    rows = []
    for ln in lines[start + 2 : end]:
        c = dict(zip(head, _cells(ln)))
        t = c.get("time [s]", "")
        rows.append(
            Row(c["case"], c["question"], c["paper"], c["pinograsp"], c["agrees"], float(t) if t else 0.0)
        )
    return rows


def replace_table(text: str, table: list[str]) -> str:
    """``text`` with its summary table replaced by ``table``."""
    lines = text.splitlines()
    start, end = table_span(lines)
    return "\n".join([*lines[:start], *table, *lines[end:]]) + ("\n" if text.endswith("\n") else "")


def section(qs_cases: list[Case], seconds: float, only: bool) -> list[str]:
    """The quasi-static section of docs/results.md."""
    how = (
        "merged into the published table by `python -m scripts.reproduce.paper_results --only "
        "quasistatic` (the other columns were not recomputed)"
        if only
        else "computed in the same run"
    )
    lines = [
        SECTION,
        "",
        'The column "quasi-static" answers each question with `method="quasistatic"`, the default: the '
        "load at which the object gives way along the loading path, snaps that land followed "
        "([`giveway.md`](giveway.md); the path's first limit λ* is `MaxWrench.first_limit`): the same "
        "scenes, preloads, directions and "
        "`upper`, no bisection (the scene's `steps` do not apply), the held preload as the scene's "
        "(`preload-first`) and the settled one (`settled-preload`) where the row compares them. A "
        "finite λ* above `upper` is reported as it is (the paper's methods stop at `upper`). "
        f"{seconds:.0f} s for every row; {how}. What the simulation says about the rows where the"
        " quasi-static answer differs from the paper's: [`validation_quasistatic.md`]"
        "(validation_quasistatic.md).",
        "",
    ]
    for c in qs_cases:
        settings = re.sub(r", \d+ bisection steps \([^)]*\)", "", c.settings)
        lines += ["", f"### {c.name} (quasi-static)", "", f"Settings: {settings}.", ""]
        for ln in c.details:
            if "![" in ln or ln.startswith("Scene `"):  # plots of the temporary run; the scene line is above
                continue
            lines.append("#" + ln if ln.startswith("### ") else ln)
    return lines


def put_section(text: str, block: list[str]) -> str:
    """``text`` with its quasi-static section (to the next ``## `` heading or the end) replaced,
    or appended."""
    lines = text.rstrip("\n").splitlines()
    if SECTION in lines:
        i = lines.index(SECTION)
        j = next((k for k in range(i + 1, len(lines)) if lines[k].startswith("## ")), len(lines))
        lines = [*lines[:i], *block, *([""] + lines[j:] if j < len(lines) else [])]
    else:
        lines = [*lines, "", *block]
    return "\n".join(lines).rstrip("\n") + "\n"


#: The sentence the quasi-static column adds to the README's "Generated by" line.
NOTE = ' Column quasi-static: `method="quasistatic"`, {:.0f} s (docs/results.md, its last section).'


def readme_note(text: str, seconds: float) -> str:
    """The README's ``_Generated by `python -m scripts.reproduce.paper_results` ..._`` line with the
    quasi-static column's note (replaced if present)."""
    out = []
    for ln in text.splitlines():
        if ln.startswith("_Generated by `python -m scripts.reproduce.paper_results") and ln.endswith("_"):
            ln = re.sub(r" Column quasi-static: .*$", "", ln[:-1]) + NOTE.format(seconds) + "_"
        out.append(ln)
    return "\n".join(out) + ("\n" if text.endswith("\n") else "")
