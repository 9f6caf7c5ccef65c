"""Configuration of the arm: trajectory controller, gripper path, stall handling, IK.

Every default is a number from the hardware seed (../shared/seeds/000_*); field docstrings say
which and why. Override in YAML or ``LUPIN_ARM__...``.
"""
from __future__ import annotations

from hw.config import Strict


class ArmConfig(Strict):
    """The 4-DOF Hiwonder arm and its gripper."""
