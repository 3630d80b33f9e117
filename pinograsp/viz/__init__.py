"""Visualisation layer: profile, comparison and resistance-set plots (matplotlib) and the 3D
scene view (plotly), imported only when used (docs/plots.md)."""
