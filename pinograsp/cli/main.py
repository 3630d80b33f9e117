"""Command-line interface ``pinograsp`` (see ``docs/cli.md``): the entry point and dispatch.

Sub-commands::

    pinograsp demo [--scene case1] [-n 24] [--out ./pinograsp-out]
    pinograsp scenes [SCENE]
    pinograsp analyze SCENE --wrench fx,fy,fz,mx,my,mz
    pinograsp max-wrench SCENE --direction fy|-fy|1,0,0,0,0,0|<scene direction name>
    pinograsp profile SCENE [--plane fx,fy] [-n 72] [--normalize]
    pinograsp compare-preloads SCENE [--direction NAME ...]
    pinograsp resistance-set SCENE [-n 500] [--csv FILE]
    pinograsp preload SCENE [--objective balanced|least_norm]
    pinograsp optimal-preload SCENE -w W [-w W ...] [--budget B]
    pinograsp batch GRASPS.yaml [--executor local|ray|dask] [--workers N] [--out results.parquet]
                    [--resume] [--timeout SECONDS]
    pinograsp simulate SCENE -d DIRECTION [--compare] [--upper N] [--preload NAME]
    pinograsp path SCENE -d DIRECTION [--png FILE] [--csv FILE] [--json]

``SCENE`` is a built-in scene name (``pinograsp scenes``) or the path of a scene YAML file.
Common options: ``--method`` (a name of the method table, :mod:`pinograsp.core.methods`),
``--upper``, ``--steps``,
``--normal-uncertainty`` and ``--cone-tolerance`` [deg], ``--json`` (the result as JSON on stdout
and nothing else), ``--out DIR`` (plots and JSON files), ``--debug`` (full tracebacks). Errors
are one line ``pinograsp: error: ...`` on stderr; bad input
(:class:`~pinograsp.errors.PinograspError`, bad options) exits with code 2.

The parser is in :mod:`.parse`, the commands in :mod:`.commands`, :mod:`.sweep_commands` and
:mod:`.sim_commands` (heavy modules imported inside them), text output in :mod:`.report`.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import warnings
from collections.abc import Callable, Iterator, Sequence

from ..errors import PinograspError
from . import commands, path_command, plan_command, sim_commands, sweep_commands
from .parse import UsageError, build_parser, join_dash_values

#: Sub-command -> its function (parsed arguments -> exit code).
COMMANDS: dict[str, Callable[..., int]] = {
    "demo": sweep_commands.cmd_demo,
    "scenes": commands.cmd_scenes,
    "analyze": commands.cmd_analyze,
    "max-wrench": commands.cmd_max_wrench,
    "profile": sweep_commands.cmd_profile,
    "compare-preloads": sweep_commands.cmd_compare_preloads,
    "resistance-set": sweep_commands.cmd_resistance_set,
    "preload": commands.cmd_preload,
    "optimal-preload": commands.cmd_optimal_preload,
    "batch": commands.cmd_batch,
    "simulate": sim_commands.cmd_simulate,
    "path": path_command.cmd_path,
    "plan": plan_command.cmd_plan,
}


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:  # noqa: ANN001
    text = " ".join(str(message).split())
    print(f"pinograsp: warning: {text} ({category.__name__})", file=sys.stderr)


@contextlib.contextmanager
def _stdout_to_stderr(enabled: bool) -> Iterator[None]:
    """Send everything written to file descriptor 1 (e.g. SCIP's C-level messages) to stderr,
    so that ``--json`` leaves nothing but the JSON document on stdout."""
    if not enabled:
        yield
        return
    try:
        sys.stdout.flush()
        saved = os.dup(1)
        os.dup2(2, 1)
    except (OSError, ValueError, AttributeError):  # no real fd 1: nothing to protect
        yield
        return
    try:
        yield
    finally:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _run(args: argparse.Namespace, debug: bool) -> int:
    """Run the chosen command; errors become one line on stderr and an exit code."""
    try:
        with _stdout_to_stderr(bool(getattr(args, "json", False))):
            code = int(COMMANDS[args.cmd](args))
        text = getattr(args, "json_text", None)
        if text is not None:
            sys.stdout.write(text)
            sys.stdout.flush()
        return code
    except PinograspError as exc:
        if debug:
            raise
        msg = " ".join(str(exc).split())
        print(f"pinograsp: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:
        if debug:
            raise
        print("\npinograsp: interrupted", file=sys.stderr)
        return int(getattr(exc, "exit_code", 130))
    except BrokenPipeError:  # pragma: no cover - e.g. `pinograsp ... | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    except Exception as exc:
        if debug:
            raise
        msg = " ".join(f"{type(exc).__name__}: {exc}".split())
        print(
            f"pinograsp: error: unexpected failure: {msg} (run with --debug for the traceback)",
            file=sys.stderr,
        )
        return 1


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; returns the exit code (0 ok, 2 bad input or usage, 1 unexpected failure,
    130 interrupted)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(join_dash_values(argv))
    except UsageError as exc:
        print(f"pinograsp: error: {exc} (see 'pinograsp --help')", file=sys.stderr)
        return 2
    except SystemExit as exc:  # --help, --version
        return int(exc.code or 0) if not isinstance(exc.code, str) else 2
    debug = bool(getattr(args, "debug", False)) or "--debug" in argv
    with warnings.catch_warnings():
        if not debug:
            warnings.showwarning = _show_warning
        return _run(args, debug)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
