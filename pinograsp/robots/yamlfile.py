"""Reading pinograsp's YAML files (scenes, hand descriptions, grasp batches) safely.

``yaml.safe_load`` builds no objects, but it still expands aliases: a few lines of nested
``*alias`` references ("a billion laughs") become an exponentially large document, and an error
message that prints it never ends. pinograsp's files need no aliases, so the loader refuses
them (and anchors), and refuses files above :data:`MAX_BYTES`, before building anything
(docs/errors.md, "Input domains").
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

#: Largest YAML file read [bytes] (a scene or a batch of 10^4 grasps is well below 1 MB).
MAX_BYTES = 16 * 2**20


def _loader() -> type:
    import yaml

    class NoAliasLoader(yaml.SafeLoader):
        """A safe loader that refuses anchors and aliases (no expansion, no bomb)."""

        def compose_node(self, parent: Any, index: Any) -> Any:  # noqa: ANN401
            event = self.peek_event()
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
                raise yaml.composer.ComposerError(
                    None,
                    None,
                    "anchors and aliases (&name / *name) are not allowed in pinograsp files: "
                    "write the values out",
                    event.start_mark,
                )
            return super().compose_node(parent, index)

    return NoAliasLoader


def load_text(text: str) -> Any:  # noqa: ANN401
    """The YAML document ``text`` (``yaml.YAMLError`` for malformed YAML or an alias)."""
    import yaml

    return yaml.load(text, Loader=_loader())  # noqa: S506 - a SafeLoader subclass


def load_file(path: Path) -> Any:  # noqa: ANN401
    """The YAML document in ``path``; ``ValueError`` when the file exceeds :data:`MAX_BYTES`
    (``OSError``/``UnicodeDecodeError``/``yaml.YAMLError`` as reading and parsing raise them)."""
    size = path.stat().st_size
    if size > MAX_BYTES:
        raise ValueError(
            f"the file has {size} bytes, more than the {MAX_BYTES} bytes a pinograsp file may have"
        )
    return load_text(path.read_text())
