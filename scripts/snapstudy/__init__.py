"""Snap-landing study (issue 34(a)'s last miss): docs/giveway.md, "Snaps and the fingers'
mass", and docs/planning.md, "Acceptance"."""
