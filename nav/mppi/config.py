"""Configuration of the MPPI controller (seed: "MPPI for a holonomic base"; ../shared/reference/mppi.md).

The velocity envelope and acceleration limits below are the *source* of the seed's "triple
coupling": the velocity smoother's limits are derived from them (``nav.config``), so changing
the top speed here changes all three sets together.
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict


class MppiConfig(Strict):
    """MPPI with the Omni motion model."""

    vx_max: float = Field(0.5, gt=0)
    """Forward speed limit, m/s (seed: vx_max 0.5)."""
    vx_min: float = Field(-0.35, le=0)
    """Reverse speed limit, m/s (seed: vx_min -0.35; asymmetric forward/back)."""
    vy_max: float = Field(0.5, ge=0)
    """Strafe limit, m/s (seed: vy_max 0.5)."""
    vy_min: float = Field(-0.5, le=0)
    """Strafe limit the other way, m/s (seed: vy_min -0.5: *symmetric*, or the noised
    distribution could only push one way and left-strafe samples would collapse)."""
    wz_max: float = Field(1.9, gt=0)
    """Yaw-rate limit, rad/s, both ways (seed: wz_max 1.9)."""
    ax_max: float = Field(2.5, gt=0)
    """Longitudinal acceleration limit, m/s^2 (seed: ax_max 2.5)."""
    ay_max: float = Field(2.5, gt=0)
    """Lateral acceleration limit, m/s^2 (seed: ay_max 2.5)."""
    az_max: float = Field(3.2, gt=0)
    """Yaw acceleration limit, rad/s^2 (seed: az_max 3.2)."""
