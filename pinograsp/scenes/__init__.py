"""scenes layer (docs/design.md)."""
