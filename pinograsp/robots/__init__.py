"""robots layer (docs/design.md)."""
