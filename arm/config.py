"""Configuration of the arm: trajectory controller, gripper path, stall handling, calibration, IK.

Every default is a number from the hardware seed (../shared/seeds/000_*) or the robot model
(sim/models/mirte_master/README.md, which cites the vendor URDF); field docstrings say which
and why, and say so plainly where a number is Lupin's own choice. The joint windows are not
here: they are the seed's fixed table in ``arm.limits``. Override in YAML or ``LUPIN_ARM__...``.
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict


class ReassertConfig(Strict):
    """The vendor HW interface's write loop (seed: "The dead-band re-assert mechanism")."""

    rate: float = Field(10.0, gt=0)
    """Write-loop rate, Hz (seed: MirteMasterArmHWInterface::write runs at the 10 Hz
    controller_manager rate)."""
    command_deadband: float = Field(0.05, gt=0)
    """SERVO_COMMAND_DIFF, rad (seed: 0.05 rad, ~2.9 deg): re-send a joint when its command
    changed by more than this since it was last sent."""
    moved_deadband: float = Field(0.05, gt=0)
    """SERVO_MOVED_DIFF, rad (seed: 0.05 rad): re-send when the measured position drifted more
    than this since the joint was last sent (gravity sag, a raw write that bypassed us)."""
    settle_time: float = Field(0.3, ge=0)
    """After a write's ramp ends the joint is still settling this long, s; until then its
    anchor follows it, so "since it last moved" means where it came to rest (Lupin's choice:
    ~3 ticks, the sim servos settle in ~0.2 s)."""
    stuck_after: float = Field(1.0, gt=0)
    """Stuck guard, s (issue 7): a joint still off target this long after its command stopped
    changing is commanded to where it is, once, instead of pushing (the lift's stall trip)."""
    stuck_factor: float = Field(2.0, gt=1)
    """Stuck guard threshold in dead-bands (issue 7: more than twice the dead-band off target)."""


class MotionConfig(Strict):
    max_joint_speed: float = Field(0.6, gt=0)
    """Fastest joint in a preset or IK move, rad/s. Lupin's choice, far below an LX-16A's
    ~6 rad/s no-load speed: slow lifts keep shoulder_lift under the current it trips at (seed)."""
    min_duration: float = Field(0.5, gt=0)
    """Shortest move, s, so a tiny correction is still a ramp and not a jerk (Lupin's choice)."""
    idle_timeout: float = Field(120.0, gt=0)
    """With no arm command for this long, the arm parks at ``home`` (seed: "Never park the arm
    extended"; the minute count is Lupin's choice)."""


class StallConfig(Strict):
    """shoulder_lift's trips (seed: it stalls against gravity and unloads or latches)."""

    joints: tuple[str, ...] = ("shoulder_lift",)
    """Joints watched for unload / latch (seed: the LX-series shoulder_lift servo trips)."""
    reload_attempts: int = Field(2, ge=1)
    """Re-load + re-command tries before an unloaded servo that stays unloaded is treated as
    latched (seed: an unloaded servo re-loads with set_enable true; a latch needs a power cycle)."""


class GripperConfig(Strict):
    goal_tolerance: float = Field(0.03, gt=0)
    """Jaw within this of its goal, rad, counts as reached (Lupin's choice: under the 0.05 rad
    dead-band, above the +-1 count read noise of 0.004 rad)."""
    stall_timeout: float = Field(1.0, gt=0)
    """No jaw motion for this long short of the goal is a stall, s (GripperActionController's
    stall detection; the duration is Lupin's choice)."""
    stall_velocity: float = Field(0.02, gt=0)
    """Jaw slower than this, rad/s, counts as not moving (Lupin's choice)."""


class CalibrationConfig(Strict):
    joints: tuple[str, ...] = ("shoulder_lift", "elbow", "wrist", "gripper")
    """Calibrated servos (seed: shoulder_lift, elbow, wrist and gripper; shoulder_pan omitted)."""
    sample_duration: float = Field(2.0, gt=0)
    """Raw counts are sampled this long on commit, s (seed: ~2 s)."""
    noise_floor_counts: float = Field(3.0, gt=0)
    """A joint whose samples spread (std) more than this, counts, is rejected: it was still
    moving or its encoder is noisy (seed: the noise-floor gate; 3 counts = 0.7 deg is ours)."""
    max_offset_counts: int = Field(40, gt=0, le=125)
    """Safety clamp, counts (1 count = 0.24 deg): a joint needing more is skipped as
    misassembled (seed: "a small safety clamp to skip misassembled servos"; 40 = 9.6 deg is
    ours, inside the servo's +-125)."""


class KinematicsConfig(Strict):
    """The arm chain to the wrist camera, from the robot model (sim/models/mirte_master/
    README.md and mirte_master.xml, after the vendor URDF arm.xacro)."""

    pan_origin: tuple[float, float, float] = (0.06, 0.0, 0.124)
    """shoulder_pan joint origin in base_link, m (model: pan axis x 0.06 on the deck)."""
    lift_height: float = 0.075
    """shoulder_lift axis above the pan origin, m (model: shoulder_lift_link pos; 0.25 m up)."""
    upper_arm: float = 0.138
    """shoulder_lift -> elbow, m (URDF shoulder_lift link, model README)."""
    forearm: float = 0.143
    """elbow -> wrist, m (URDF elbow link, model README)."""
    camera_offset: tuple[float, float] = (-0.064664, 0.032527)
    """Wrist camera optical centre in the wrist link (x across, z along), m (model:
    wrist_camera pos; URDF gripper_camera_joint: 0.027 m along the link, 0.067 m behind)."""
    camera_pitch: float = 0.40
    """Optical axis pitched this far from the wrist link towards the side the wrist bends to,
    rad (seed: gripper_camera_joint pitched ~0.40 rad down)."""


class IkConfig(Strict):
    """Camera aiming: point the wrist camera's optical axis at a bloom from above (issue 7)."""

    min_look_down: float = Field(0.6, gt=0, lt=1.58)
    """The optical axis must point at least this far below horizontal, rad (about 34 deg), so
    the bloom is seen from above. ``inspect`` looks ~0.93 rad down (model README)."""
    min_range: float = Field(0.12, gt=0)
    """Camera-to-target distance bounds, m: nearer than this the bloom overfills the frame."""
    max_range: float = Field(0.45, gt=0)
    """... and beyond this it is too small to classify (``inspect`` sees its bloom ~0.2 m off)."""
    tolerance: float = Field(0.005, gt=0)
    """A solution whose optical axis misses the target by more than this, m, is a failure."""
    max_iter: int = Field(200, gt=0)
    """Ipopt iteration cap; the small problem converges in a few dozen."""
    floor_z: float = -0.051
    """The floor in base_link, m (base_link sits at wheel-axle height, 0.051 m above the floor:
    robot model README). A target below it is no bloom: refused, never aimed at."""
    body_min: tuple[float, float, float] = (-0.165, -0.13, -0.051)
    """Lower corner of the robot's body in base_link, m: the chassis collision envelope
    (0.33 x 0.26 m, up to 0.135 m above the floor; robot model README) down to the floor."""
    body_max: tuple[float, float, float] = (0.165, 0.13, 0.084)
    """Upper corner of the robot's body in base_link, m. A target inside is refused."""


class ArmConfig(Strict):
    """The 4-DOF Hiwonder arm and its gripper."""

    reassert: ReassertConfig = ReassertConfig()
    """The dead-band write loop (vendor HW interface semantics)."""
    motion: MotionConfig = MotionConfig()
    """Preset timing and the idle park."""
    stall: StallConfig = StallConfig()
    """Unload / latch handling for shoulder_lift."""
    gripper: GripperConfig = GripperConfig()
    """The gripper command path (GripperActionController semantics)."""
    calibration: CalibrationConfig = CalibrationConfig()
    """Operator-in-the-loop zero-offset calibration (hardware only)."""
    kinematics: KinematicsConfig = KinematicsConfig()
    """Link lengths and the wrist camera's mount."""
    ik: IkConfig = IkConfig()
    """Camera aiming with casadi."""
