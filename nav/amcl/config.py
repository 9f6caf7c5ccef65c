"""AMCL configuration (seed: ../shared/seeds/001_*, "the dormant AMCL path"; Nav2's amcl
defaults where the seed is silent). Override under ``nav.amcl`` or ``LUPIN_NAV__AMCL__...``."""
from __future__ import annotations

from pydantic import Field, model_validator

from hw.config import Strict

Triple = tuple[float, float, float]


class AmclConfig(Strict):
    particles: int = Field(1000, ge=50)
    """Particles, fixed (Nav2 adapts between 500 and 2000 with KLD sampling; a fixed count keeps
    the filter one vectorised array and its runs deterministic for a seed; 1000 covers the
    initial uncertainty below with ~2 cm spacing in the posterior)."""
    alphas: tuple[float, float, float, float, float] = (0.2, 0.2, 0.2, 0.2, 0.2)
    """alpha1..alpha5 of Nav2's OmniMotionModel (seed: all five at 0.2): rotation's share of the
    translation and strafe noise (alpha1) and of the rotation noise (alpha2), translation's share
    of the translation (alpha3), rotation (alpha4) and strafe (alpha5) noise."""
    laser_min_range: float = Field(0.25, ge=0)
    """Returns closer than this are ignored, m (seed: the robot's own arm, < 0.25 m)."""
    laser_max_range: float = Field(12.0, gt=0)
    """Returns at or beyond this are ignored, m (seed: the C1's 12 m)."""
    max_beams: int = Field(60, ge=4)
    """Beams per scan the sensor model evaluates (Nav2 default 60)."""
    z_hit: float = Field(0.5, ge=0)
    """Weight of the Gaussian hit term (Nav2 default 0.5)."""
    z_rand: float = Field(0.5, ge=0)
    """Weight of the uniform random term (Nav2 default 0.5)."""
    sigma_hit: float = Field(0.08, gt=0)
    """Std of the hit term, m. Nav2's default 0.2 suits house-scale maps; with a 0.05 m SLAM map
    of 1 m-spaced pots and the C1's ~1 cm noise it leaves the cloud ~6 cm wide for good, while
    0.08 settles it to ~3.5 cm (measured from five 0.5 m / 0.3 rad starts in the greenhouse)."""
    likelihood_max_dist: float = Field(2.0, gt=0)
    """Distance to obstacles the likelihood field saturates at, m (Nav2 default 2.0)."""
    update_min_d: float = Field(0.1, ge=0)
    """Once converged, filter only after this much travel, m. Nav2's default is 0.25; with the
    seed's wide alphas a 0.25 m step spreads the cloud ~0.1 m between corrections, and in 0.8 m
    aisles that shows: measured over ten goals in the greenhouse, the worst map-pose error at a
    goal was 4.7 cm at 0.25 m / 0.2 rad and 3.4 cm at 0.1 m / 0.1 rad."""
    update_min_a: float = Field(0.1, ge=0)
    """... or this much rotation, rad (Nav2 default 0.2; see ``update_min_d``)."""
    initial_pose: Triple = (0.0, 0.0, 0.0)
    """Where the robot starts in the saved map (x, y, yaw). The map frame is the dock's (the
    pose the map was made from); the original seeded the vendor spawn pose for headless
    restarts (set_initial_pose: true)."""
    initial_std: Triple = (0.4, 0.4, 0.3)
    """Std of the initial cloud (x m, y m, yaw rad): wide enough that a 0.5 m / 0.3 rad error in
    the initial pose is inside it (Nav2's default initial_cov is 0.5 x 0.5 m, pi/12 rad)."""
    settle_jitter: Triple = (0.01, 0.01, 0.005)
    """Before convergence the filter also updates on scans taken standing still, jittering the
    resampled cloud by this std (x m, y m, yaw rad) so it does not collapse onto a few particles
    (Gordon's roughening). Nav2 waits for motion; a robot that must not move until it knows
    where it is cannot."""
    converged_std: tuple[float, float] = (0.045, 0.035)
    """The cloud counts as converged (``map -> odom`` resolves) when its position std is below
    the first, m, and its yaw std below the second, rad."""
    seed: int = 0
    """Seed of the filter's random draws (same seed, same run)."""

    @model_validator(mode="after")
    def _ranges(self) -> "AmclConfig":
        if self.laser_min_range >= self.laser_max_range:
            raise ValueError(f"amcl.laser_min_range {self.laser_min_range} must be below laser_max_range")
        return self
