"""The per-wheel velocity PID (the seed's ``pid_wheels_controller``), vectorised over wheels.

Second stage of the base chain: the mecanum stage (``hw.mecanum``) hands each wheel a reference
angular velocity, and this loop closes it on the encoder-measured velocity before the PWM hits
the motor. Seed gains: p 1.5, i 0.5, d 0.01, anti-windup on, i_clamp +-15, at 10 Hz.

    output = feedforward * reference + p * e + i_term + d * de/dt,     e = reference - measured
    i_term = clamp(i_term + i * e * dt, +-i_clamp)

The feed-forward term (``PidGains.feedforward``, as ros2_control's ``pid_controller`` offers)
carries the nominal command so the slow 10 Hz loop only has to correct model error; see the
field docstring in ``hw.config``.

Anti-windup is *conditional integration*: when the output would exceed ``output_limit`` (the
wheel speed that 100 % duty buys) the integrator does not move further in the saturating
direction, and the output is clamped. A stalled wheel (stuck against a pot, a dropped chassis)
therefore cannot charge the integrator up to i_clamp and fling the robot forward when it frees;
the integral can at most fill the head-room that the feed-forward and proportional terms leave
below saturation. ``i_clamp`` still bounds the integral in every case (seed: +-15).

Units: rad/s in, rad/s command out; the base controller divides by the max wheel speed to get a
duty. Time arrives as ``dt``: nothing here reads a clock.
"""
from __future__ import annotations

import numpy as np

from hw.config import PidGains


class Pid:
    """Independent PIDs, one per element of the vectors given to ``update`` (4 wheels)."""

    def __init__(self, gains: PidGains, output_limit: float | None = None, size: int = 4):
        if output_limit is not None and output_limit <= 0:
            raise ValueError(f"output_limit must be positive, got {output_limit}")
        self.gains = gains
        self.output_limit = output_limit
        self.size = size
        self.i_term = np.zeros(size)
        self._prev_error: np.ndarray | None = None

    def reset(self) -> None:
        """Forget the integral and the derivative history (e-stop, controller inactive)."""
        self.i_term = np.zeros(self.size)
        self._prev_error = None

    def update(self, reference, measured, dt: float) -> np.ndarray:
        """One control step; returns the command (rad/s), clamped to +-output_limit if set.

        The first step after construction or ``reset`` has no derivative (no previous error), and
        a non-positive ``dt`` neither integrates nor differentiates.
        """
        g = self.gains
        ref = np.broadcast_to(np.asarray(reference, dtype=float), (self.size,))
        meas = np.broadcast_to(np.asarray(measured, dtype=float), (self.size,))
        error = ref - meas

        if dt > 0 and self._prev_error is not None:
            d_term = g.d * (error - self._prev_error) / dt
        else:
            d_term = np.zeros(self.size)
        self._prev_error = error.copy()

        base = g.feedforward * ref + g.p * error + d_term
        step = g.i * error * dt if dt > 0 else np.zeros(self.size)
        candidate = np.clip(self.i_term + step, -g.i_clamp, g.i_clamp)

        limit = self.output_limit
        if limit is not None and g.antiwindup:
            unclamped = base + candidate
            rising = candidate > self.i_term
            falling = candidate < self.i_term
            freeze = ((unclamped > limit) & rising) | ((unclamped < -limit) & falling)
            candidate = np.where(freeze, self.i_term, candidate)
        self.i_term = candidate

        output = base + self.i_term
        if limit is not None:
            output = np.clip(output, -limit, limit)
        return output
