"""Command-line interface layer: ``pinograsp`` and ``python -m pinograsp.cli`` (docs/cli.md)."""

from .main import main

__all__ = ["main"]
