"""The simulated greenhouse: a MuJoCo model of the MIRTE Master V2 behind the HAL.

MuJoCo must render offscreen on machines with no display (CI, the robot's laptop over SSH),
so EGL is selected here, before any submodule can import mujoco.
"""
import os

os.environ.setdefault("MUJOCO_GL", "egl")
