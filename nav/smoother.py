"""The velocity smoother between the controller and the twist_mux's ``auto`` source.

Seed ("The cmd_vel chain"): Nav2's controller output goes through velocity_smoother and only
then to ``/cmd_vel_auto``, the mux's autonomy input; autonomy never bypasses the mux. Its
limits are the MPPI envelope mirrored (``nav.config`` derives them, the "triple coupling").

Per axis, as Nav2's smoother does it open-loop: the commanded change is clipped to
``max_accel * dt`` while speeding up (|v| growing, same sign) and to ``|max_decel| * dt`` while
slowing down or reversing, after the target was clamped to the velocity limits. ``reset()``
(after a cancel or an e-stop) makes the next command start from rest.
"""
from __future__ import annotations

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from nav.config import SmootherConfig


class VelocitySmoother:
    def __init__(self, config: SmootherConfig):
        self._vmax = np.asarray(config.max_velocity, dtype=float)
        self._vmin = np.asarray(config.min_velocity, dtype=float)
        self._accel = np.asarray(config.max_accel, dtype=float)
        self._decel = np.abs(np.asarray(config.max_decel, dtype=float))
        self.last: Twist = ZERO_TWIST

    def reset(self) -> None:
        self.last = ZERO_TWIST

    def smooth(self, target: Twist, dt: float) -> Twist:
        """The command to send now, given the wanted one and the time since the last."""
        cur = np.array((self.last.vx, self.last.vy, self.last.wz))
        want = np.clip((target.vx, target.vy, target.wz), self._vmin, self._vmax)
        speeding_up = (np.abs(want) >= np.abs(cur)) & (want * cur >= 0)
        step = np.where(speeding_up, self._accel, self._decel) * max(dt, 0.0)
        out = cur + np.clip(want - cur, -step, step)
        self.last = Twist(float(out[0]), float(out[1]), float(out[2]))
        return self.last
