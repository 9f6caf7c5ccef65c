"""AMCL configuration: the seed's dormant AMCL path (../shared/seeds/001_*: OmniMotionModel,
alpha1..alpha5 0.2, laser_min_range 0.25 m, 12 m max range, set_initial_pose) with Nav2's amcl
defaults where the seed is silent, and the names Nav2 uses where it has one, so a Nav2
parameter file reads across. Override under ``nav.amcl`` or ``LUPIN_NAV__AMCL__...``."""
from __future__ import annotations

from pydantic import Field, model_validator

from hw.config import BlindRule, Strict

Triple = tuple[float, float, float]


class AmclConfig(Strict):
    particles: int = Field(1000, ge=50)
    """Particles, a fixed count. Nav2 adapts between min_particles 500 and max_particles 2000
    by KLD sampling to save CPU once converged; a fixed count keeps the cloud one numpy array
    and a run repeatable for a seed, and an update of 1000 particles x 60 beams takes ~2 ms, so
    there is little to save. 1000 rather than Nav2's floor of 500 (see ``sigma_hit`` for the
    trials): with 500 one start of 24 locked onto the neighbouring pot, 1 m out (under an
    earlier convergence test), with 1000 none of 72 did, and it was ready sooner (4.4 s worst
    against 7.9 s)."""
    blind: BlindRule = BlindRule()
    """When a scan is too blind to weigh the particles by (``hw.scan_trust``, the collision
    monitor's rule): its few returns left are whatever covers the lidar (a cart pushed over
    the robot), so the filter skips it and the pose follows odometry until scans can be trusted
    (the same as ``SlamConfig.blind``)."""
    alphas: tuple[float, float, float, float, float] = (0.2, 0.2, 0.2, 0.2, 0.2)
    """alpha1..alpha5 of Nav2's OmniMotionModel (seed: all five 0.2): rotation noise from
    rotation (alpha1) and from translation (alpha2), translation noise from translation
    (alpha3) and from rotation (alpha4), strafe noise from translation (alpha5; rotation feeds
    the strafe through alpha4 too, as in Nav2)."""
    laser_min_range: float = Field(0.25, ge=0)
    """Returns closer than this are dropped, m (seed: 0.25 m, applied in AMCL's laser_min_range
    "to filter lidar returns hitting the robot's own body", here mostly the arm)."""
    laser_max_range: float = Field(12.0, gt=0)
    """Returns at or beyond this are dropped, m (seed: 12.0, "the RPLidar A1 effective max");
    also the range of the likelihood field's random term, z_rand / max range."""
    max_beams: int = Field(60, ge=2)
    """Beams of a scan the sensor model evaluates, spread evenly over the usable returns (Nav2
    default 60)."""
    z_hit: float = Field(0.5, ge=0)
    """Weight of the likelihood field's Gaussian hit term (Nav2 default 0.5)."""
    z_rand: float = Field(0.5, ge=0)
    """Weight of its uniform random term (Nav2 default 0.5); with z_hit it keeps a beam that
    hits a plant or a person from zeroing a particle."""
    sigma_hit: float = Field(0.1, gt=0)
    """Std of the hit term, m. Nav2's default 0.2 suits coarse maps and noisy lasers; on a
    0.05 m map with a lidar good to a few cm, 0.1 holds the estimate tighter. Trials (24 starts
    0.5 m / 0.3 rad off in the synthetic greenhouse of tests/nav/test_amcl.py, parked until
    ready, then a 4.5 m drive along the aisle on odometry 3 % long and turning 2.5 deg/m): the
    worst map-pose error while driving was 0.046 m / 0.035 rad at 0.1, 0.072 m / 0.046 rad at
    0.2. Sharper is not safer: 0.08 (with 500 particles) locked onto the neighbouring pot, 1 m
    out, in 1 of 8 starts."""
    laser_likelihood_max_dist: float = Field(2.0, gt=0)
    """Distance to the nearest obstacle at which the likelihood field saturates, m (Nav2 default
    2.0; beyond 5 sigma_hit the hit term is nil anyway)."""
    update_min_d: float = Field(0.05, ge=0)
    """Once converged, the filter updates only after this much travel, m. Nav2's default is
    0.25, but its motion noise is per update and quadratic in the step (alphas 0.2: a 0.25 m
    step spreads a particle ~0.11 m and ~0.11 rad), so the total noise over a drive falls as
    the step shrinks, and an update costs ~2 ms here. In the ``sigma_hit`` trials the worst
    error while driving was 0.081 m / 0.111 rad at 0.25 m / 0.2 rad (Nav2's defaults), 0.061 m
    / 0.048 rad at 0.1 / 0.1 and 0.046 m / 0.035 rad at 0.05 / 0.05. The gate still matters
    standing still: one scan repeated is not new evidence, and would collapse the cloud. Until
    it has converged the filter updates on every scan regardless (see ``roughening``)."""
    update_min_a: float = Field(0.05, ge=0)
    """... or this much rotation, rad (Nav2 default 0.2; see ``update_min_d``)."""
    resample_interval: int = Field(1, ge=1)
    """Filter updates between resamplings (Nav2 default 1); weights multiply in between."""
    recovery_alpha_slow: float = Field(0.0, ge=0, le=1)
    """Decay of the slow average of the measurement likelihood for random-particle recovery
    (Nav2 default 0.0, off; Nav2 suggests 0.001 to turn it on)."""
    recovery_alpha_fast: float = Field(0.0, ge=0, le=1)
    """Decay of the fast average (Nav2 default 0.0, off; Nav2 suggests 0.1). Off because the
    robot starts from a known pose and random particles only cost accuracy when it is right."""
    initial_pose: Triple = (0.0, 0.0, 0.0)
    """Where the robot starts in the saved map (x m, y m, yaw rad). The map frame is the
    robot's start pose, the dock (spec/mission.md), so that is the origin; the original seeded
    the vendor spawn pose (x 1.0527, y 0.509611, yaw 0) with set_initial_pose: true for headless
    restarts. Set it when the robot starts elsewhere; ``reset`` reseeds at runtime (RViz's 2D
    Pose Estimate)."""
    initial_cov: Triple = (0.25, 0.25, 0.0685)
    """Variances of the initial cloud (x m^2, y m^2, yaw rad^2): Nav2's defaults (0.5 m and
    pi/12 rad std). A start 0.5 m / 0.3 rad off the configured pose is inside it."""
    roughening: Triple = (0.015, 0.015, 0.0075)
    """Std of the jitter added to the resampled cloud until it has converged (x m, y m, yaw
    rad). Scans taken standing still carry no motion noise, and resampling alone would collapse
    the cloud onto the few particles that happened to be drawn (Gordon et al. 1993's
    roughening); the jitter is also what lets a tight cloud slide onto the truth. In the
    ``sigma_hit`` trials 0.005 m let a cloud 0.14 m off pass as settled (it slid too slowly
    for ``converged_drift`` to see); 0.02 m did as well as 0.015 m there but held the cloud
    0.067 m wide along the aisle of the simulated greenhouse's survey map, close to
    ``converged_std``. Off once converged: updates then come with motion, and its noise."""
    converged_std: tuple[float, float] = (0.08, 0.05)
    """The cloud has converged (``ready``) when the std of its position along its widest axis is
    below the first, m, and its yaw std below the second, rad ... This is the test that the
    cloud is one mode, not two pots apart; it cannot be much tighter, since the roughening
    keeps the cloud ~0.04 m wide in the synthetic greenhouse and ~0.055 m wide along the aisle
    of the simulated greenhouse's survey map, however right it is."""
    converged_drift: tuple[float, float] = (0.01, 0.01)
    """... and every estimate of the last ``converged_window`` updates, carried to now by the
    odometry since, is within this (m, rad) of the current one: the test that the cloud has
    stopped sliding (while driving too, as long as the filter agrees with the wheels). A cloud
    that repeated scans have made tight can still be sliding onto the truth (measured: 0.07 m
    wide at 0.07 m off, true to 0.012 m eighteen scans later). In the ``sigma_hit`` trials:
    ready in 2.9 s (median; 4.4 s worst) within 0.035 m / 0.026 rad of the truth."""
    converged_window: int = Field(10, ge=1)
    """Updates over which ``converged_drift`` is judged (1 s of scans standing still)."""
    seed: int = 0
    """Seed of the filter's random draws: same seed, same scans, same cloud."""

    @model_validator(mode="after")
    def _ranges(self) -> "AmclConfig":
        if self.laser_min_range >= self.laser_max_range:
            raise ValueError(f"amcl.laser_min_range {self.laser_min_range} must be below laser_max_range "
                             f"{self.laser_max_range}")
        if self.z_hit + self.z_rand <= 0:
            raise ValueError("amcl.z_hit + z_rand must be positive")
        return self
