"""SLAM configuration (seed: ../shared/seeds/001_*, "SLAM configuration", "Resetting the map").

Override in YAML under ``nav.slam`` or with ``LUPIN_NAV__SLAM__...``.
"""
from __future__ import annotations

from typing import Optional

from pydantic import Field, model_validator

from hw.config import BlindRule, Strict


class SlamConfig(Strict):
    resolution: float = Field(0.05, gt=0)
    """Map cell size, m (seed: slam_toolbox resolution 0.05, the map file's resolution). The map
    has no set size: it grows as the robot explores (``nav.slam.grid``)."""
    min_range: float = Field(0.25, ge=0)
    """Returns closer than this are dropped, m (seed: below 0.25 m the lidar sees the robot's own
    gripper and arm; filtered in AMCL, slam_toolbox and both costmaps alike)."""
    max_range: float = Field(12.0, gt=0)
    """Returns beyond this are dropped, m (seed: the C1's effective 12 m)."""
    blind: BlindRule = BlindRule()
    """When a scan is too blind to register (``hw.scan_trust``, the collision monitor's rule and
    numbers): a cart pushed over the robot covers half the lidar's view, and what is left, the
    cart's faces a hand's width off, dragged ICP round by 8 deg in a second (held-out seed 4 of
    ``safety.people``, 928.5-929.5 s); the map drawn at that heading was wrong from then on and
    the patrol lost 26 pots. A scan too blind to steer by is too blind to map by: the pose goes
    on by wheel odometry alone until scans can be trusted again (``nav.slam.mapper``)."""
    voxel_size: float = Field(0.10, gt=0)
    """kiss-icp's local-map voxel, m (kiss-icp sizes it at ~1 % of the range it sees: 0.1 m at
    the C1's 12 m). Measured on the greenhouse survey: 0.10 m gives 6 mm trajectory error at
    2 ms a scan, 0.05 m 8 mm at 3 ms, 0.03 m 14 mm (too few points per voxel to average noise),
    with the registered scan thinned to 1.5 voxels as kiss-icp does; it is now the scan
    registered as it goes into the local map, at half a voxel (``nav.slam.lidar_odometry``: at
    1.5 the heading drifted and the 180-pot map bent)."""
    max_points_per_voxel: int = Field(3, gt=0)
    """kiss-icp's points kept per voxel. Its default 20 is for 3D voxels a surface crosses; a 2D
    scan's voxel is crossed by a line, and each drive past a spot adds points to its voxels until
    they hold 20, so the registration's neighbour search grew with the patrol: on the 180-pot
    patrol, where the robot drives the aisles by the dock again and again, the per-scan update's
    p95 in the last tenth was 1.7-2.4x the first's. With 3 a voxel is full after a pass or two.
    Measured, 20 -> 3: the 180-pot patrol's scans replayed, last tenth over first 1.55 -> 1.22
    (median) and 1.69 -> 1.27 (p95); the survey's trajectory error 5.5 -> 5.2 mm, the generated
    surveys' worst 11.7 -> 5.8 mm, map recall 0.982 both; the two-bay survey's pots 0.0224 ->
    0.018 m at worst. (4 and 5 put the two-bay survey's worst pot at 0.050 and 0.022 m, 6 left the
    p95 ratio at 1.59: what a setting does to one long survey is chaotic, so it was judged on all
    of these together.)"""
    local_map_range: float = Field(12.0, gt=0)
    """Local voxel map radius around the robot, m (kiss-icp's max_distance: the sensor's range,
    the C1's 12 m): points the lidar could still see stay in the map."""
    initial_threshold: float = Field(0.3, gt=0)
    """kiss-icp adaptive threshold before any motion, m (its default 2.0 m is lidar-car scale; a
    2 m correspondence gate would pair a pot with its neighbour 1 m down the aisle, the slip
    the reference warns of). It then adapts to the odometry's own prediction error."""
    min_motion: float = Field(0.02, gt=0)
    """Motion below which the adaptive threshold is not updated, m (kiss-icp min_motion_th)."""
    keyframe_distance: float = Field(0.25, gt=0)
    """A scan becomes a pose-graph node after this much travel, m (slam_toolbox's
    minimum_travel_distance is 0.5; half that suits 1 m pot spacing)."""
    keyframe_angle: float = Field(0.25, gt=0)
    """... or after this much rotation, rad."""
    loop_closure: bool = True
    """Look for revisits and optimise the pose graph (off: lidar odometry alone, for comparison)."""
    loop_search_radius: float = Field(1.0, gt=0)
    """Look for revisits among keyframes this close to the current estimate, m
    (slam_toolbox loop_search_maximum_distance is 3 m at house scale)."""
    loop_min_travel: float = Field(4.0, gt=0)
    """... that were left at least this much travel ago, m (so the recent chain is not a 'loop')."""
    loop_fitness: float = Field(0.8, gt=0, le=1)
    """Share of the scan's points that must land within ``loop_inlier_distance`` of the matched
    submap for a loop closure to be accepted (a wrong match in a row of identical pots fails this)."""
    loop_inlier_distance: float = Field(0.05, gt=0)
    """Inlier distance for the loop check, m (one map cell)."""
    loop_max_correction: float = Field(0.5, gt=0)
    """A loop match may move the current pose at most this far, m; more is a false match
    (half the pot spacing, so a match onto the neighbouring pot is rejected)."""
    transform_publish_period: float = Field(0.10, gt=0)
    """map -> odom publish period, s (seed: 10 Hz, down from slam_toolbox's 50 Hz: one of the two
    bandwidth levers that kept the Pi's bridge below its silent-wedge threshold)."""
    map_update_interval: float = Field(1.0, gt=0)
    """How often the worker hands back the map for the global costmap's static layer, s (the
    global costmap updates at 1 Hz)."""
    respawn_delay: float = Field(1.0, gt=0)
    """Seconds from a killed or crashed worker to its replacement (seed: respawn_delay 1.0)."""
    reply_timeout: float = Field(5.0, gt=0)
    """A worker that has not replied counts as wedged, and is killed and respawned, after this
    many seconds without using any CPU (hung) or this many CPU seconds on one scan (spinning):
    a wedged SLAM never stalls the control loop, and a worker only starved of CPU on a busy
    machine keeps its map (``nav.slam.liveness``)."""
    startup_timeout: float = Field(30.0, gt=0)
    """Seconds a fresh worker may take to answer its first scan, in place of ``reply_timeout``:
    it starts a new interpreter and imports numpy, casadi and kiss-icp first (~0.5 s here,
    several seconds on a cold Pi)."""
    lockstep: Optional[bool] = None
    """Exchange every scan with the worker in lock-step on the runtime clock, so runs stay
    deterministic for a seed; or free-running, never waiting: a scan that finds the worker busy
    is dropped and the latest reply is used. Unset: lock-step on the sim's clock, free-running
    on the robot's wall clock."""

    @model_validator(mode="after")
    def _ranges(self) -> "SlamConfig":
        if self.min_range >= self.max_range:
            raise ValueError(f"slam.min_range {self.min_range} must be below max_range {self.max_range}")
        return self
