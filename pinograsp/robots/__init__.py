"""Robots layer: the URDF side (docs/design.md, docs/hands.md).

Hand descriptions and hands (Pinocchio), hand configurations, objects and contact detection
(Coal), closing a hand on an object, and the grasp model of a configuration touching an object.
Never imports a solver.
"""
