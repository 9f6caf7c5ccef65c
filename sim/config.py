"""Configuration of the simulated greenhouse and the simulated MIRTE Master V2.

Numbers marked *untuned* are plausible approximations, not measurements; the robot model's
README (sim/models/mirte_master/README.md) says where each dimension came from.
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict as _Strict


class PhysicsConfig(_Strict):
    timestep: float = Field(0.005, gt=0, le=0.02)
    """MuJoCo step, s. 5 ms with the implicitfast integrator keeps the stiff velocity servos
    stable while leaving room for the >= 20x real-time goal."""
    drive_update: float = Field(0.01, gt=0)
    """How often the wheels' forward kinematics re-target the body's traction servos, s."""


class DriveConfig(_Strict):
    motor_tau: float = Field(0.15, gt=0)
    """Wheel speed first-order time constant, s (untuned). Must exceed ~62 ms or the seed's
    p 1.5 at 10 Hz with feed-forward would oscillate (pole 2.5a - 1.5, a = exp(-dt/tau))."""
    dead_zone: float = Field(0.10, ge=0, lt=1)
    """|duty| below which the motor does not turn (hardware reference: 10 % dead-zone)."""
    slip: tuple[float, float, float] = (0.005, 0.012, 0.008)
    """Mean fraction of the wheels' forward-kinematic twist lost to roller slip, (vx, vy, wz) in
    the body frame. Mecanum strafing is lossier than driving straight (untuned, ~1 %)."""
    slip_jitter: float = Field(0.02, ge=0)
    """Std of the random, seeded variation of that slip per drive update (floor texture, dust):
    odometry error then wanders a little from run to run, and a seed pins it down. Each update's
    slip is drawn from a gamma distribution of that mean and std: never negative (rollers never
    push the body past the wheels) and, unlike a normal clipped at 0, its mean is the configured
    slip (a clipped normal of this jitter lost twice the configured 0.5 % driving straight)."""
    traction_force: float = Field(25.0, gt=0)
    """Largest horizontal force the wheels can push with, N (~0.6 * m * g for 4.2 kg): beyond
    it the wheels spin and odometry diverges from truth, as on the robot."""
    traction_torque: float = Field(4.0, gt=0)
    """Largest yaw torque the wheels can apply, N m."""


class LidarConfig(_Strict):
    rate: float = Field(10.0, gt=0)
    """Revolutions per second (RPLidar C1 Standard mode, ~10 Hz)."""
    points: int = Field(500, gt=8)
    """Points per revolution (~5000 samples/s at 10 Hz)."""
    range_min: float = 0.05
    """C1 minimum range, m (the robot filters < 0.25 m downstream: its own arm)."""
    range_max: float = 12.0
    """C1 effective max, m (seed: laser_max_range 12)."""
    noise_std: float = Field(0.01, ge=0)
    """Gaussian range noise, m (untuned; C1 datasheet accuracy is ~1-2 %)."""


class CameraConfig(_Strict):
    width: int = 640
    """Astra Mini Pro colour stream width (seed: 640x480)."""
    height: int = 480
    """Astra Mini Pro colour stream height."""
    front_fovy_deg: float = 49.5
    """Astra Mini Pro vertical field of view, deg (60 x 49.5 deg colour FOV)."""
    wrist_fovy_deg: float = 50.0
    """USB gripper camera vertical field of view, deg (untuned)."""
    wrist_pitch: float = 0.40
    """Gripper camera pitch below the wrist link, rad (seed: gripper_camera_joint ~0.40 rad)."""
    draw_distance: float = Field(4.0, gt=0)
    """The robot's cameras draw what lies within this many metres of them, like a far clipping
    plane, m. Nothing perception can use lies beyond it: a bloom there is under 9 px across (the
    detector's 150 px2 least blob is ~14 px, nearer than 2.3 m), a 0.10 m tag's cells are 1.3 px
    (unreadable; reads are used to 1.5 m). Drawing farther only costs: a 180-pot greenhouse's
    front frame took 87 ms at 8 m and 56 ms at 4 m (49 ms in the built-in one), and with it the
    large patrol's real-time factor over robot seconds 60-260 went from 4.6 to 5.0. The built-in
    greenhouse (7 x 4 m)
    lies within it from most of it."""


class BatteryConfig(_Strict):
    full_voltage: float = 12.6
    """Resting voltage of a full 3S pack, V."""
    empty_voltage: float = 11.1
    """Voltage at which the pack is empty (seed power_watcher min_voltage 11.1)."""
    capacity_ah: float = Field(2.2, gt=0)
    """Pack capacity, Ah (untuned)."""
    internal_resistance: float = Field(0.08, ge=0)
    """Sag per amp of draw, ohm (untuned)."""
    idle_current: float = Field(0.8, ge=0)
    """Compute + sensors draw, A (untuned)."""
    stall_current: float = Field(2.0, ge=0)
    """Per-motor current at 100 % duty, A (untuned)."""
    charge_current: float = Field(2.0, ge=0)
    """What the dock's charger pushes into the pack in its constant-current phase, A: about 1 C
    for the 2.2 Ah pack, a usual LiPo charge rate (a full charge in a little over an hour)."""
    charge_taper_from: float = Field(0.8, ge=0, le=1)
    """Charge fraction where the charger turns to constant voltage: the current then falls in
    proportion to what is still missing (a LiPo's CC-CV charge), so the last 20 % are slower."""
    dock_reach: float = Field(0.3, gt=0)
    """The dock's contacts touch the robot within this distance of the dock pose, m: the
    navigation goal checker's 0.25 m tolerance and a little (untuned; a real dock's guide
    rails take up the rest)."""


class GreenhouseGeometry(_Strict):
    pot_radius: float = 0.10
    """Pot radius, m (world spec: ~0.10 m)."""
    pot_height: float = 0.25
    """Pot height, m (world spec: ~0.25 m)."""
    tag_size: float = 0.10
    """Black AprilTag square edge, m (world spec: 0.10 m tag, white margin)."""
    plate_size: float = 0.14
    """Tag plate edge including its white margin, m."""
    plate_height: float = 0.15
    """Plate centre height, m: the front camera's optical centre height, so the camera frames
    the tag head-on from the approach pose."""
    wall_height: float = 2.0
    """Greenhouse wall height, m (world spec: walls 2.0 m high)."""
    leaf_pest_share: float = Field(1 / 3, ge=0, le=1)
    """Share of the pests on flowering plants that the sim draws on a leaf rather than on a
    bloom (a plant with no bloom always has its pest on a leaf). Growers' pests (aphids,
    whitefly, thrips) sit on leaves at least as often as on flowers (issue 30), and a detector
    that only looks on blooms must not pass. The world file says only that a plant has a pest
    (spec/world.md); which plant has it where is drawn from the world's name and the pot's id
    (``sim.pests``), so the same file always draws the same plant. 0: every pest of a
    flowering plant on its first bloom."""


class SimConfig(_Strict):
    """The MuJoCo greenhouse backend."""

    realtime: bool = False
    """Hold the physics to the wall clock (``lupin patrol --realtime``): the robot's own pace,
    for watching. Off, the sim runs as fast as the machine allows; the run is the same either
    way (same seed, same trajectory)."""
    seed: int = 0
    """Seed for every random draw in the sim (noise, slip jitter). Same seed, same run."""
    physics: PhysicsConfig = PhysicsConfig()
    """MuJoCo stepping."""
    drive: DriveConfig = DriveConfig()
    """Simulated motors and traction (how the wheels move the body)."""
    lidar: LidarConfig = LidarConfig()
    """Simulated RPLidar C1."""
    camera: CameraConfig = CameraConfig()
    """Simulated front (Astra) and wrist (USB) cameras."""
    battery: BatteryConfig = BatteryConfig()
    """Simulated 3S pack behind the INA226."""
    geometry: GreenhouseGeometry = GreenhouseGeometry()
    """Sizes the world file leaves to the sim (spec/world.md)."""
    led_wiring: str = "BRG"
    """Physical colour order of the simulated strip, as Mirte-247264 is wired (seed: BRG). The
    runtime's ``hw.leds.color_order`` must match it, exactly as on the robot."""
    servo_noise_counts: int = Field(1, ge=0)
    """Position read noise, counts (+-1 count = 0.24 deg, an AS5600/pot-like jitter)."""
    imu_noise: tuple[float, float] = (0.02, 0.002)
    """IMU white noise std: accel m/s^2, gyro rad/s (MPU9250-like, untuned)."""
