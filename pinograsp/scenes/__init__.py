"""Scenes layer: YAML scene files and the built-in paper scenes (docs/scenes.md).

Loading a scene imports no solver; a scene's analysis methods import the analysis layer when
called.
"""
