"""Core layer: NumPy only, the hinge between the URDF side and the solvers (docs/design.md).

``GraspModel`` and its building from contacts, contacts, actuation, wrench axes, settings and
option vocabularies, validation, result records, the energy audit, serialisation and the
example grasps. Nothing here imports Pinocchio, Coal or a solver.
"""
