"""batch layer (docs/design.md)."""
