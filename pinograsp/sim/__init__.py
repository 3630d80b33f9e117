"""Simulation layer: a MuJoCo cross-check of a scene's prediction (docs/simulation.md).

A reduced MuJoCo model whose generalised coordinates are the hand joints of the
:class:`~pinograsp.GraspModel` and the object's free 6-DOF pose; actuators are tendon motors
with a one-sided limit that follows their running maximum closing displacement; contact forces
(push-only normal spring, exact Coulomb spring–slider) are computed here and applied to the
bodies. MuJoCo is optional (``pip install "pinograsp[mujoco]"``) and imported only when a
simulation is built. The layer ranks between ``scenes`` and ``batch``.
"""
