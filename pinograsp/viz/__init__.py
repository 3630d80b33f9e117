"""viz layer (docs/design.md)."""
