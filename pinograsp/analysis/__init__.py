"""Analysis layer: what users ask of a ``GraspModel`` (docs/design.md).

Passive response (PRP and the iterative scheme), max resistible wrench, profiles, resistance
sets and scores, equilibrium and optimal preloads, the linear-compliance baseline. Imports the
core and the solvers, never the URDF side.
"""
