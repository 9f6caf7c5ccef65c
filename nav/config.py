"""Configuration of navigation: costmaps, planner, MPPI, velocity smoother, goal checker,
navigator (seed: ../shared/seeds/001_*, the navigation page).

Coupled values are derived, not copied: the velocity smoother's limits follow the MPPI envelope
(the seed's "triple coupling": MPPI accel, smoother accel and smoother velocity must all mirror
the MPPI velocity envelope, or the smoother chops the very trajectory MPPI just optimised and
PathAlign drifts). An explicit smoother override stays possible and is validated against the
envelope. Override in YAML or ``LUPIN_NAV__...``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

from pydantic import Field, model_validator

from hw.config import Strict
from nav.amcl.config import AmclConfig
from nav.costmap.config import CostmapsConfig
from nav.mppi.config import MppiConfig
from nav.slam.config import SlamConfig

Triple = tuple[float, float, float]


class PlannerConfig(Strict):
    tolerance: float = Field(0.5, ge=0)
    """When the goal cell is blocked, plan to the nearest reachable cell within this many
    metres of it (seed: NavfnPlanner tolerance 0.5)."""
    allow_unknown: bool = True
    """Plan through unknown space (seed: allow_unknown true): with SLAM the map starts empty."""
    rate: float = Field(1.0, gt=0)
    """Replanning rate, Hz (Nav2's navigate-to-pose tree replans at 1 Hz)."""


class SmootherConfig(Strict):
    """Velocity smoother between the controller and the mux's ``auto`` source (seed:
    velocity_smoother). Leave a field unset to derive it from the MPPI envelope."""

    max_velocity: Optional[Triple] = None
    """(vx, vy, wz) upper limits; default: (vx_max, vy_max, wz_max) of MPPI = (0.5, 0.5, 1.9)."""
    min_velocity: Optional[Triple] = None
    """(vx, vy, wz) lower limits; default: (vx_min, vy_min, -wz_max) = (-0.35, -0.5, -1.9)."""
    max_accel: Optional[Triple] = None
    """(ax, ay, az) acceleration limits; default: MPPI's (2.5, 2.5, 3.2)."""
    max_decel: Optional[Triple] = None
    """(ax, ay, az) deceleration limits, negative; default: the acceleration mirrored."""


class GoalCheckerConfig(Strict):
    xy_tolerance: float = Field(0.25, gt=0)
    """Goal reached within this distance, m (seed: xy_goal_tolerance 0.25)."""
    yaw_tolerance: float = Field(0.12, gt=0)
    """Goal heading tolerance, rad (seed: yaw_goal_tolerance 0.12, ~7 deg). Tight on purpose:
    it frames the AprilTag head-on at each approach pose so the climate read is clean. The seed
    records that it "can bite" on hardware (MPPI iterating near the goal can blow the timeout)
    and that the documented fallback is to loosen it towards ~0.18 rad, trading camera framing
    for approach reliability. We keep 0.12 and measure how often it bites."""
    stopped_velocity: float = Field(0.05, gt=0)
    """The goal counts only once the robot is also at rest inside the tolerances: measured
    translational speed below this, m/s (Nav2's StoppedGoalChecker). Without it the goal ends the
    instant the robot crosses the 0.25 m circle at speed, and the camera frames the pot from
    wherever that was; with it MPPI's GoalCritic brings the robot in to the pose itself."""
    stopped_yaw_rate: float = Field(0.15, gt=0)
    """Measured yaw rate below which the robot counts as at rest, rad/s (StoppedGoalChecker)."""


class NavigatorConfig(Strict):
    """Navigate-to-pose behaviour around the planner and the controller."""

    local_costmap_rate: float = Field(5.0, gt=0)
    """Local costmap update rate, Hz (seed: the 3 x 3 m rolling window updates at 5.0 Hz)."""
    global_costmap_rate: float = Field(1.0, gt=0)
    """Global costmap update rate, Hz (Nav2's default update_frequency for the global map)."""
    default_timeout: float = Field(60.0, gt=0)
    """Seconds a goal may take when the caller gives none (the original mission's 60 s per
    navigation attempt, reference/upstream.md)."""
    max_recoveries: int = Field(3, ge=0)
    """Recoveries (clear the local costmap, back off, retry) before a goal fails with 'no valid
    control'. Bounded so a wedged robot reports instead of trying forever."""
    max_plan_failures: int = Field(3, ge=1)
    """Consecutive planning failures (at the replan rate) before a goal fails: the first may be
    a costmap not yet cleared of a passing obstacle, three in a row is a blocked route."""
    backoff_speed: float = Field(0.10, gt=0)
    """Recovery back-off speed away from the nearest obstacle, m/s (slow: it drives blind to
    the plan, only the costmap says which way is clear)."""
    backoff_time: float = Field(1.0, gt=0)
    """Recovery back-off duration, s (0.10 m at the default speed)."""
    progress_radius: float = Field(0.5, gt=0)
    """The robot must move this far from its last checkpoint within ``progress_time`` or the
    goal fails for lack of progress, m (Nav2's SimpleProgressChecker required_movement_radius
    0.5): a robot stalled short of a goal it cannot reach reports it instead of waiting out
    the timeout."""
    progress_time: float = Field(10.0, gt=0)
    """Seconds allowed to make that progress (Nav2's movement_time_allowance 10.0)."""
    readiness_timeout: float = Field(20.0, gt=0)
    """Seconds the readiness cascade waits at one stage before it reports that stage as missing
    (seed: bond_timeout raised from 4 s to 20 s, because a cold bring-up over WiFi took longer
    than 4 s and the default aborted a stack that was fine). It keeps waiting after reporting:
    navigation activates as soon as the stage arrives, the cascade never wedges."""
    scan_timeout: float = Field(0.5, gt=0)
    """A goal holds still (zero twist, the clock of its progress check and deadline stopped)
    while the newest lidar scan is older than this, s: five revolutions of the C1 at 10 Hz.
    Driving on a costmap that no longer sees is how a dropped USB link ends in a pot."""
    blocked_wait: float = Field(15.0, gt=0)
    """Seconds (in all, per goal) a goal waits, its progress check and deadline stopped, while
    the collision monitor holds the base for something in its way (a person in a 0.8 m aisle, where there is
    no going round): waiting is what a person expects of a machine, and backing off into
    someone behind is worse. The planner keeps replanning meanwhile (the person is in the
    costmap, so another way round is taken where there is one); past this the goal fails
    ``blocked`` and the patrol comes back to the pot later."""
    person_wait: float = Field(60.0, gt=0)
    """Seconds (in all, per goal, the monitor's holds counted with them) a goal waits for people:
    one on its goal, one in the only way, one close by. People move on, where a crate does not:
    a grower working or walking the aisle the robot needs takes a minute more often than 15 s.
    On a generated greenhouse with six walkers (seed 101, not a benchmark seed) 15 s made the
    robot give up 14 of 24 pots after four tries each; 60 s, one."""
    lidar_mount: tuple[float, float, float] = (0.115, 0.0, 0.0)
    """Lidar pose in base_link (x, y, yaw): the MIRTE model's lidar post (sim model README)."""


class NavConfig(Strict):
    """Navigation stack."""

    costmap: CostmapsConfig = CostmapsConfig()
    """Local and global costmaps (seed: narrow-aisle costmaps)."""
    planner: PlannerConfig = PlannerConfig()
    """NavFn-style Dijkstra global planner."""
    mppi: MppiConfig = MppiConfig()
    """The MPPI controller with the Omni motion model."""
    smoother: SmootherConfig = SmootherConfig()
    """Velocity smoother; limits derived from ``mppi`` unless given."""
    goal_checker: GoalCheckerConfig = GoalCheckerConfig()
    """SimpleGoalChecker tolerances."""
    navigator: NavigatorConfig = NavigatorConfig()
    """Navigate-to-pose: rates, timeout, recovery."""
    slam: bool = True
    """True: SLAM owns ``map -> odom`` and maps as it goes; false: localisation on the saved map
    ``map_file`` (the original's ``slam:=`` launch argument; there SLAM was the live mode and
    AMCL the dormant one, kept warm for a saved-map workflow: here both are live)."""
    map_file: Optional[Path] = None
    """The saved map (map_server YAML) to localise on when ``slam`` is false."""
    mapping: SlamConfig = SlamConfig()
    """SLAM: lidar odometry, grid, loop closure, worker process and its respawn."""
    amcl: AmclConfig = AmclConfig()
    """Localisation on a saved map: particle filter, Omni motion model, likelihood field."""

    @model_validator(mode="after")
    def _localisation_source(self) -> "NavConfig":
        if not self.slam and self.map_file is None:
            raise ValueError("slam is false (localisation on a saved map) but map_file is not set")
        return self

    @model_validator(mode="after")
    def _derive_coupled(self) -> "NavConfig":
        m, s = self.mppi, self.smoother
        envelope_max = (m.vx_max, m.vy_max, m.wz_max)
        envelope_min = (m.vx_min, m.vy_min, -m.wz_max)
        accel = (m.ax_max, m.ay_max, m.az_max)
        derived = {
            "max_velocity": envelope_max if s.max_velocity is None else s.max_velocity,
            "min_velocity": envelope_min if s.min_velocity is None else s.min_velocity,
            "max_accel": accel if s.max_accel is None else s.max_accel,
        }
        derived["max_decel"] = (tuple(-a for a in derived["max_accel"]) if s.max_decel is None
                                else s.max_decel)
        axes = ("vx", "vy", "wz")
        for i, axis in enumerate(axes):
            if derived["max_velocity"][i] < envelope_max[i] - 1e-9:
                raise ValueError(f"smoother.max_velocity {axis} {derived['max_velocity'][i]} is below the MPPI "
                                 f"envelope {envelope_max[i]}: the smoother would chop MPPI's trajectories")
            if derived["min_velocity"][i] > envelope_min[i] + 1e-9:
                raise ValueError(f"smoother.min_velocity {axis} {derived['min_velocity'][i]} is above the MPPI "
                                 f"envelope {envelope_min[i]}: the smoother would chop MPPI's trajectories")
            if derived["max_accel"][i] <= 0 or derived["max_decel"][i] >= 0:
                raise ValueError(f"smoother accel/decel {axis}: max_accel must be > 0 and max_decel < 0")
        object.__setattr__(self, "smoother", SmootherConfig.model_construct(**derived))
        self._derive_from_motion_model()
        return self

    def _derive_from_motion_model(self) -> None:
        """GoalAngle's reach and PathAngle's mode follow the motion model (see their configs)."""
        critic, omni = self.mppi.critic, self.mppi.motion_model == "omni"
        if critic.goal_angle.threshold_to_consider is None:
            reach = critic.goal.threshold_to_consider if omni else self.goal_checker.xy_tolerance
            object.__setattr__(critic.goal_angle, "threshold_to_consider", reach)
        if critic.path_angle.mode is None:
            object.__setattr__(critic.path_angle, "mode", "path_orientation" if omni else "forward")
