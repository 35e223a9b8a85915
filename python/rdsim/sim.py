"""``rdsim.sim``: rdsim's simulation level, below the envs.

- :class:`World` -- a Bullet multibody world (``time_step`` s, ``solver_iterations``, ``gravity``,
  ``solver_residual_threshold``); ``add_robot(urdf, position, orientation, drive, position_gain,
  velocity_gain, limit_constraints)`` loads a fixed-base robot, ``add_static_body(urdf, ...)`` a body
  that never moves, ``step(n)`` advances ``n`` fixed steps.
- :class:`Robot` -- joints in rdsim's dof order (``joint_names``, ``lower``, ``upper``, ``effort``,
  ``max_velocity``): ``reset_joints(q)``, ``set_position_targets(q)``, ``set_gains(kp, kd)``,
  ``joint_positions()``, ``joint_velocities()``, ``link_position(link)``, ``link_pose(link)``
  (position, quaternion x y z w), ``link_positions()``, ``state()`` / ``set_state(state)``, and
  ``null_space_ik(link, target, start=None, rest=None, iterations=20, residual_threshold=1e-4)``:
  pybullet-style IK with a rest pose (the env option ik_method "null_space").

Position motors (``drive="position_motor"``) follow pybullet's POSITION_CONTROL: each joint is driven
towards the speed ``kp (target - q) / dt + (1 - kd) qdot`` with at most the URDF effort. Bad arguments
raise :class:`rdsim.Error` with a one-line message. tools/fidelity compares this level with pybullet.
"""
from __future__ import annotations

from ._rdsim import sim as _sim

World = _sim.World
Robot = _sim.Robot

__all__ = ["Robot", "World"]
