"""Argument definitions shared by several ``pinograsp`` commands (one home per option text)."""

from __future__ import annotations

import argparse

PRELOAD_HELP = "one of the scene's named preloads (default: the scene's preload)"


def add_direction(p: argparse._ActionsContainer, *, required: bool = True) -> None:
    """``--direction/-d``: an axis with sign, a wrench vector or a scene direction name."""
    p.add_argument(
        "--direction",
        "-d",
        required=required,
        help="an axis with sign (fy, -fy, mx), a wrench vector 1,0,0,0,0,0, or a scene direction name",
    )
