"""The hardware abstraction layer (HAL): device-level interfaces.

Everything above this line (wheel PID, mecanum kinematics, arm dead-band logic, e-stop, mux)
runs the same code on the robot and in the MuJoCo greenhouse, because both backends implement
exactly these interfaces. They sit at *device* level on purpose: the sim gets PWM duties and
hands back encoder ticks, so the controllers are exercised rather than bypassed (the original
ROS sim teleported the base and could not test them).

Units are the devices' own where the device has a natural unit (duty fraction, encoder ticks,
Hiwonder position counts and milliseconds, raw pin level, LED bytes in wire order) and SI
elsewhere (lidar metres/radians, IMU m/s^2 and rad/s, volts and amps).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, Sequence, runtime_checkable

import numpy as np

#: Wheel order used everywhere a per-wheel sequence appears (duties, ticks, velocities).
WHEELS: tuple[str, ...] = ("front_left", "front_right", "rear_left", "rear_right")


class DeviceError(RuntimeError):
    """A device did not answer or answered garbage. Callers degrade, they do not crash."""


@dataclass(frozen=True)
class Twist:
    """A body velocity command in base_link (REP-103): m/s forward, m/s left, rad/s CCW."""

    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0


ZERO_TWIST = Twist()


@dataclass(frozen=True)
class LidarScan:
    """One lidar revolution in the lidar frame (REP-103, counter-clockwise angles).

    ``ranges`` holds ``inf`` where there was no return (out of range or dropped).
    """

    stamp: float
    angles: np.ndarray  # float32 radians
    ranges: np.ndarray  # float32 metres


@dataclass(frozen=True)
class ImuReading:
    stamp: float
    accel: tuple[float, float, float]  # m/s^2, body frame, includes gravity (+z up at rest)
    gyro: tuple[float, float, float]  # rad/s


@dataclass(frozen=True)
class PowerReading:
    stamp: float
    voltage: float  # pack voltage, V
    current: float  # A


@dataclass(frozen=True)
class ServoStatus:
    """What one Hiwonder servo reports: raw position counts (0..1000 over 240 deg)."""

    position: int
    vin_mv: int
    temperature_c: int
    loaded: bool


class WheelDriver(Protocol):
    def set_duties(self, duties: Sequence[float]) -> None:
        """Signed PWM duty per wheel in WHEELS order, each in [-1, 1] (1 = 100 %)."""


class WheelEncoders(Protocol):
    def read_ticks(self) -> tuple[int, ...]:
        """Accumulated quadrature ticks per wheel in WHEELS order (4x decoding)."""


class ServoBus(Protocol):
    """The Hiwonder TTL bus, one call per bus transaction. Positions in raw counts."""

    def move(self, servo_id: int, position: int, duration_ms: int) -> None: ...

    def read_position(self, servo_id: int) -> int: ...

    def read_status(self, servo_id: int) -> ServoStatus: ...

    def set_load(self, servo_id: int, loaded: bool) -> None: ...

    def adjust_offset(self, servo_id: int, offset: int) -> None: ...

    def read_offset(self, servo_id: int) -> int: ...


class Lidar(Protocol):
    def latest_scan(self) -> LidarScan | None:
        """The newest complete revolution, or None if none arrived (dropout, not spun up)."""


class Camera(Protocol):
    width: int
    height: int

    def capture(self) -> np.ndarray:
        """One frame on request, uint8 HxWx3 in OpenCV's BGR order."""


class Imu(Protocol):
    def read(self) -> ImuReading: ...


class PowerMonitor(Protocol):
    def read(self) -> PowerReading: ...


class EStopButton(Protocol):
    def read_level(self) -> int:
        """Raw digital level of the button's pin (0 or 1); polarity is config, not code."""


class LedStrip(Protocol):
    num_leds: int

    def write(self, wire: bytes) -> None:
        """Bytes exactly as clocked out on the data line (already in the strip's colour order)."""


@runtime_checkable
class Clock(Protocol):
    """Runtime time source. Sim: deterministic, advances physics. Wall: hardware time."""

    deterministic: bool
    """True when time moves only as the runtime waits (the sim), so a peer process may be waited
    on in lock-step; False for wall time."""

    def now(self) -> float: ...

    def wait_until(self, t: float) -> None: ...


@dataclass
class Hal:
    """One robot's devices, as a backend (sim or hardware) provides them."""

    clock: Clock
    wheels: WheelDriver
    encoders: WheelEncoders
    servos: ServoBus
    lidar: Lidar
    imu: Imu
    power: PowerMonitor
    estop_button: EStopButton
    leds: LedStrip
    cameras: dict[str, Camera] = field(default_factory=dict)
