"""Snap-landing study (issue 34(a)'s last miss): notes_snap_study.md."""
