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
#: Deepest nesting of mappings and lists (a scene nests 5 deep; Python's recursion ends near 300).
MAX_DEPTH = 64
#: Most values (nodes) in one file (a batch of 5000 written-out grasps has about 1e5; sample blocks
#: are one entry each). Refusing at 2.5e5 values took 15 s on 2 cores under a load of 8 (the 16 MiB
#: cap alone: 258 s, issue 33).
MAX_NODES = 250_000


def _loader() -> type:
    import yaml

    class NoAliasLoader(yaml.SafeLoader):
        """A safe loader that refuses anchors and aliases (no expansion, no bomb), nesting deeper
        than :data:`MAX_DEPTH`, more than :data:`MAX_NODES` values and duplicated keys."""

        depth = 0
        nodes = 0

        def compose_node(self, parent: Any, index: Any) -> Any:  # noqa: ANN401
            event = self.peek_event()
            self.nodes += 1
            if self.depth >= MAX_DEPTH or self.nodes > MAX_NODES:
                what = (
                    f"nested deeper than {MAX_DEPTH}"
                    if self.depth >= MAX_DEPTH
                    else f"more than {MAX_NODES} values"
                )
                raise yaml.composer.ComposerError(
                    None,
                    None,
                    f"{what} (the limit of pinograsp files: MAX_DEPTH, MAX_NODES)",
                    event.start_mark,
                )
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
                raise yaml.composer.ComposerError(
                    None,
                    None,
                    "anchors and aliases (&name / *name) are not allowed in pinograsp files: "
                    "write the values out",
                    event.start_mark,
                )
            self.depth += 1
            try:
                return super().compose_node(parent, index)
            finally:
                self.depth -= 1

        def construct_mapping(self, node: Any, deep: bool = False) -> Any:  # noqa: ANN401, FBT001, FBT002
            seen: set[Any] = set()
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=True)
                if isinstance(key, (str, int, float, bool)) or key is None:
                    if key in seen:
                        raise yaml.constructor.ConstructorError(
                            None,
                            None,
                            f"duplicated key {str(key)[:60]!r} (each key once)",
                            key_node.start_mark,
                        )
                    seen.add(key)
            return super().construct_mapping(node, deep=deep)

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


def yaml_problem(exc: Exception) -> str:
    """What is wrong with a malformed YAML file, and where: never the file's text (a file that
    is not what it claims to be, e.g. ``extends: /etc/shadow``, is not quoted; docs/errors.md)."""
    mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
    where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
    problem = getattr(exc, "problem", None) or getattr(exc, "reason", None) or type(exc).__name__
    return f"malformed YAML{where}: {' '.join(str(problem).split())[:200]}"
