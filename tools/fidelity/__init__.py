"""rdsim against pybullet on the same URDFs: see docs/fidelity.md.

``tools/fidelity/report.py`` prints the tables; tests/python/test_fidelity.py runs short versions.
"""
from .arms import PyBulletArm, RdsimArm, make_pair
from .compare import (action_sequence, inverse_kinematics, joint_targets, link_inertias, move, pybullet_sensitivity,
                      recipe_search)
from .robots import CASES, RobotCase

__all__ = ["CASES", "PyBulletArm", "RdsimArm", "RobotCase", "action_sequence", "inverse_kinematics", "pybullet_sensitivity",
           "joint_targets", "link_inertias", "make_pair", "move", "recipe_search"]
