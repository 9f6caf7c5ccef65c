"""Configuration of the MPPI controller (seed: "MPPI for a holonomic base"; ../shared/reference/mppi.md).

The velocity envelope and acceleration limits below are the *source* of the seed's "triple
coupling": the velocity smoother's limits are derived from them (``nav.config``), so changing
the top speed here changes all three sets together. Where the seed is silent the value is
Nav2's default (the reference's table).
"""
from __future__ import annotations

from typing import Literal, Optional

from pydantic import Field

from hw.config import Strict


class GoalCriticConfig(Strict):
    weight: float = 5.0
    """Seed: GoalCritic 5.0 (pull toward the goal once inside threshold_to_consider)."""
    threshold_to_consider: float = 1.4
    """Active within this distance of the goal, m (Nav2 default 1.4)."""


class GoalAngleCriticConfig(Strict):
    weight: float = 3.0
    """Seed: GoalAngleCritic 3.0 (square up the final heading for the tight yaw tolerance)."""
    threshold_to_consider: Optional[float] = None
    """Active within this distance of the goal, m. Unset, it is derived from the motion model
    (``nav.config``): Omni, 1.4 m, with the goal critic: a holonomic base can hold its final
    heading through the whole final approach, so it never has to square up at the end (where
    the seed says 0.12 rad "can bite") and its heading does not wander while it strafes;
    DiffDrive, the goal checker's xy tolerance: a heading pull that starts before the robot can
    turn towards the goal position is Nav2's classic near-goal stall (Nav2's default is 0.5)."""


class PathAlignCriticConfig(Strict):
    weight: float = 14.0
    """Seed: PathAlignCritic 14.0, dominant: hug the global path, the controller's primary job."""
    offset_from_furthest: int = 20
    """Skipped until the trajectories reach this many path points (Nav2 default 20)."""
    trajectory_point_step: int = 4
    """Score every 4th trajectory point (Nav2 default 4)."""
    threshold_to_consider: float = 0.5
    """Inactive within this distance of the goal, m (Nav2 default 0.5)."""
    max_path_occupancy_ratio: float = 0.07
    """Skipped when more than 7 % of the path up to the furthest point is blocked (Nav2: a
    dynamic obstacle on the path should be avoided, not aligned through)."""


class PathFollowCriticConfig(Strict):
    weight: float = 5.0
    """Seed: PathFollowCritic 5.0 (make progress along the path, not just parallel to it)."""
    offset_from_furthest: int = 6
    """Pull toward the path point this far past the furthest reached one (Nav2 default 6)."""
    threshold_to_consider: float = 1.4
    """Inactive within this distance of the goal, m (Nav2 default 1.4)."""


class PathAngleCriticConfig(Strict):
    weight: float = 2.0
    """Seed: PathAngleCritic 2.0 (penalise heading error against the path)."""
    offset_from_furthest: int = 4
    """Aim at the path point this far past the furthest reached one (Nav2 default 4)."""
    threshold_to_consider: float = 0.5
    """Inactive within this distance of the goal, m (Nav2 default 0.5)."""
    max_angle_to_furthest: float = 0.785
    """Only active when the robot's heading is off the bearing to that point by more than this,
    rad (Nav2 default 0.785)."""
    mode: Optional[Literal["forward", "bidirectional", "path_orientation"]] = None
    """Nav2's three modes: forward preference (0), no directional preference (1), consider the
    path's own orientations (2). Unset, it follows the motion model (``nav.config``): Omni uses
    ``path_orientation``, and the controller gives the plan the goal's heading, so the robot
    strafes along the plan holding the heading it must arrive with, as the Omni model intends
    (a holonomic base need not face where it drives); DiffDrive uses ``forward``, Nav2's
    default, because it must face where it drives."""


class ObstaclesCriticConfig(Strict):
    critical_weight: float = 20.0
    """Seed: ObstaclesCritic critical weight 20.0 (near-collision points)."""
    repulsion_weight: float = 1.5
    """Generally prefer trajectories further from obstacles (Nav2 default 1.5)."""
    collision_cost: float = 10000.0
    """Cost of a trajectory that collides (seed: collision 10000)."""
    collision_margin_distance: float = 0.10
    """Points closer than this to an obstacle (past the footprint) are critical, m (Nav2 0.10)."""
    near_goal_distance: float = 0.5
    """No repulsion within this distance of the goal, m (Nav2 0.5): approach poses sit near pots."""


class ConstraintCriticConfig(Strict):
    weight: float = 4.0
    """Seed: ConstraintCritic 4.0 (respect the velocity envelope)."""


class PreferForwardCriticConfig(Strict):
    weight: float = 1.0
    """Seed: PreferForwardCritic 1.0, dropped from the diff-drive default 5.0 so MPPI does not
    bias away from a cleanly shorter sideways approach."""
    threshold_to_consider: float = 0.5
    """Inactive within this distance of the goal, m (Nav2 default 0.5)."""


CRITICS = ("constraint", "obstacles", "goal", "goal_angle", "path_align", "path_follow", "path_angle",
           "prefer_forward")
"""Nav2's ConstraintCritic, ObstaclesCritic, GoalCritic, GoalAngleCritic, PathAlignCritic,
PathFollowCritic, PathAngleCritic and PreferForwardCritic, in snake case (config keys)."""


class CriticsConfig(Strict):
    goal: GoalCriticConfig = GoalCriticConfig()
    """GoalCritic: pull toward the goal."""
    goal_angle: GoalAngleCriticConfig = GoalAngleCriticConfig()
    """GoalAngleCritic: square up the final heading."""
    path_align: PathAlignCriticConfig = PathAlignCriticConfig()
    """PathAlignCritic: hug the global path (dominant)."""
    path_follow: PathFollowCriticConfig = PathFollowCriticConfig()
    """PathFollowCritic: progress along the path."""
    path_angle: PathAngleCriticConfig = PathAngleCriticConfig()
    """PathAngleCritic: heading against the path."""
    obstacles: ObstaclesCriticConfig = ObstaclesCriticConfig()
    """ObstaclesCritic: avoid lethal cells, keep a margin."""
    constraint: ConstraintCriticConfig = ConstraintCriticConfig()
    """ConstraintCritic: respect the velocity envelope."""
    prefer_forward: PreferForwardCriticConfig = PreferForwardCriticConfig()
    """PreferForwardCritic: a weak bias against reversing."""


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

    batch_size: int = Field(2000, ge=1)
    """Sampled trajectories per iteration (seed: batch_size 2000; Nav2 default 1000)."""
    time_steps: int = Field(56, ge=9)
    """Steps per trajectory (seed: time_steps 56): 2.8 s of horizon at model_dt."""
    model_dt: float = Field(0.05, gt=0)
    """Rollout step, s (seed: model_dt 0.05, equal to the control period)."""
    frequency: float = Field(20.0, gt=0)
    """Controller rate, Hz (seed: controller_frequency 20.0)."""
    iteration_count: int = Field(1, ge=1)
    """Optimisation iterations per cycle (Nav2 default 1)."""
    temperature: float = Field(0.3, gt=0)
    """Softmax temperature lambda over trajectory costs (Nav2 default 0.3)."""
    gamma: float = Field(0.015, ge=0)
    """Control-cost weight (Nav2 default 0.015)."""
    vx_std: float = Field(0.2, gt=0)
    """Sampling noise std, m/s (Nav2 default 0.2)."""
    vy_std: float = Field(0.2, gt=0)
    """Sampling noise std, m/s (Nav2 default 0.2)."""
    wz_std: float = Field(0.4, gt=0)
    """Sampling noise std, rad/s (Nav2 default 0.4; large values make the heading oscillate)."""
    min_y_velocity_threshold: float = Field(0.001, ge=0)
    """Measured lateral speeds below this are read as zero, m/s (seed: 0.001 so lateral motion is
    never gated as noise; the diff-drive default 0.5 would hide every strafe)."""
    retry_attempt_limit: int = Field(1, ge=0)
    """Resets and retries when every trajectory collides, before 'no valid control' (Nav2: 1)."""
    regenerate_noises: bool = False
    """Draw fresh noise every cycle instead of reusing one draw (Nav2 default false)."""
    seed: int = 0
    """Seed of the noise generator: same seed, same commands."""
    motion_model: Literal["omni", "diff"] = "omni"
    """Seed: motion_model Omni, so the noised distribution is 3-DOF (vx, vy, wz) and sideways
    trajectories are candidates. ``diff`` pins vy to zero (the lateral shortcut is then
    structurally absent, as the seed explains)."""
    critics: tuple[str, ...] = CRITICS
    """Critics that run, in order (seed: all eight)."""
    critic: CriticsConfig = CriticsConfig()
    """Per-critic weights and parameters."""
