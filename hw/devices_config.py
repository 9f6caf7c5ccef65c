"""Where every real device hangs: addresses, channels, bus numbers, ports, baud rates, scales.

The hardware reference (../shared/reference/hardware.md) says it plainly: vendor configs
differ and the config wins, so nothing below is a constant in a driver. Values marked
UNVERIFIED are the reference's defaults that nobody has yet checked on Mirte-247264; they are
here so they can be flipped in YAML (``hw.devices...``) or ``LUPIN_HW__DEVICES__...``.
"""
from __future__ import annotations

from pydantic import Field

from hw.config import Strict


class I2cBusConfig(Strict):
    bus: int = Field(1, ge=0)
    """Linux I2C bus number, /dev/i2c-N (seed: everything slow hangs off I2C1)."""


class Pca9685Config(Strict):
    address: int = Field(0x41, ge=0x03, le=0x77)
    """Motor PWM driver address (seed: PCA9685 at 0x41, config motorservocontroller)."""
    frequency_hz: float = Field(100.0, ge=24, le=1526)
    """PWM frequency, Hz. The old MIRTE config ran the motors at 100 Hz (reference); its code
    default of 2000 Hz is beyond the chip (prescale 3..255 gives 24..1526 Hz at 25 MHz)."""
    oscillator_hz: float = Field(25e6, gt=0)
    """Internal oscillator, Hz (datasheet: 25 MHz); prescale = round(osc / (4096 f)) - 1."""
    channels: dict[str, tuple[int, int]] = Field(default_factory=lambda: {
        "front_left": (2, 3), "front_right": (1, 0), "rear_left": (6, 7), "rear_right": (5, 4)})
    """H-bridge (A forward, B reverse) channels per wheel (vendor motor wiring in the reference:
    rear_left 6/7, front_left 2/3, rear_right 5/4, front_right 1/0; the vendor was 'not sure
    which is correct': UNVERIFIED)."""
    reversal_pause_s: float = Field(0.010, ge=0, le=0.1)
    """Both H-bridge channels at zero this long on a direction reversal (reference: ~10 ms)."""
    watchdog_s: float = Field(0.5, gt=0.1, le=5.0)
    """Wheels left turning by a write older than this are cut (``hw.wheel_watchdog``: a control
    loop that stalls must not leave the robot driving), s: five 100 ms controller beats."""


class Ina226Config(Strict):
    address: int = Field(0x40, ge=0x03, le=0x77)
    """Power monitor address (reference: vendor firmware uses 0x40)."""
    shunt_ohm: float = Field(0.010, gt=0)
    """Shunt resistance, ohm (reference: vendor 0.010 ohm)."""
    max_expected_current: float = Field(8.3, gt=0)
    """Measurement range, A (vendor 8.3 A); current_lsb = this / 32768."""
    averaging: int = 256
    """Samples averaged per conversion (vendor: 256-sample averaging)."""
    min_voltage: float = 11.1
    """Pack empty, V: 0 % and the power-low threshold (seed power_watcher: min_voltage 11.1)."""
    max_voltage: float = 15.0
    """Pack full, V: 100 % (seed: max_voltage 15.0)."""
    max_current: float = Field(5.0, gt=0)
    """Current above which the policy flags over-current, A (seed: max_current 5.0)."""
    power_low_time: float = Field(20.0, ge=0)
    """Seconds continuously below min_voltage before power-low (seed: power_low_time 20 s)."""
    turn_off_time: float = Field(10.0, ge=0)
    """Seconds of power-low before the policy asks for shutdown (seed: turn_off_time 10 s)."""


class ImuConfig(Strict):
    address: int = Field(0x68, ge=0x03, le=0x77)
    """MPU9250 address (reference: 0x68; 0x69 with AD0 high)."""
    accepted_who_am_i: tuple[int, ...] = (0x71, 0x70, 0x73)
    """WHO_AM_I values taken as an MPU9250 (reference: 0x71; some boards report 0x70/0x73)."""
    accel_range_g: int = 2
    """Accelerometer full scale, g: 2/4/8/16 (16384..2048 LSB/g). 2 g: a ground robot's range."""
    gyro_range_dps: int = 250
    """Gyro full scale, deg/s: 250/500/1000/2000 (131..16.4 LSB per deg/s)."""
    mag_address: int = Field(0x0C, ge=0x03, le=0x77)
    """AK8963 magnetometer address, reached through the MPU's I2C bypass (reference: 0x0C)."""


class ArmEncodersConfig(Strict):
    mux_address: int = Field(0x70, ge=0x70, le=0x77)
    """TCA9548A mux address (reference: 0x70..0x77, seed: as5600 behind a mux)."""
    address: int = 0x36
    """AS5600 address; all five share it, hence the mux (reference)."""
    channels: dict[str, int] = Field(default_factory=lambda: {
        "gripper": 0, "shoulder_pan": 1, "shoulder_lift": 2, "elbow": 3, "wrist": 4})
    """Joint -> mux channel (reference: vendor mapping; the seed only says channels 0-4)."""


class GpioLine(Strict):
    chip: str = "/dev/gpiochip0"
    """GPIO chip device."""
    line: int = Field(ge=0)
    """Line offset on the chip."""


class EncoderGpioConfig(Strict):
    chip: str = "/dev/gpiochip0"
    """GPIO chip of the wheel encoders."""
    lines: dict[str, tuple[int, int]] = Field(default_factory=lambda: {
        "front_left": (0, 1), "front_right": (2, 3), "rear_left": (4, 5), "rear_right": (6, 7)})
    """Quadrature (A, B) line offsets per wheel. UNVERIFIED: the seed says only 'four quadrature
    wheel encoders on GPIO'; set them from the board's pinout."""


class EStopGpioConfig(Strict):
    chip: str = "/dev/gpiochip0"
    """GPIO chip of the e-stop button."""
    line: int = Field(8, ge=0)
    """Line offset of the e-stop button. UNVERIFIED (polarity too: hw.estop.engaged_level)."""
    pull_up: bool = True
    """Bias the line up. With the default engaged_level 1 that suits a normally-closed e-stop
    switch to ground: 0 while released, 1 when pressed *or when the wire breaks* (fail-safe)."""


class ServoPortConfig(Strict):
    port: str = "/dev/ttyUSB1"
    """Serial device of the Hiwonder TTL bus adapter (UNVERIFIED device name)."""
    baud: int = Field(115200, gt=0)
    """Reference: Hiwonder bus 115200 8N1."""
    echo: bool = False
    """The adapter echoes every sent byte (some one-wire adapters do): read and discard it."""
    timeout_s: float = Field(0.03, gt=0)
    """Reply timeout per transaction; a reply takes < 1 ms of wire time plus the servo's
    turnaround (~0.5 ms), so 30 ms means 'silent', not 'slow'."""
    retries: int = Field(2, ge=0, le=10)
    """Extra attempts for a read that timed out or came back garbled (bounded)."""


class LidarPortConfig(Strict):
    port: str = "/dev/ttyUSB0"
    """Serial device of the RPLidar C1 (USB serial; UNVERIFIED device name)."""
    baud: int = Field(460800, gt=0)
    """Seed: rplidar_c1_launch.py baudrate 460800."""
    timeout_s: float = Field(0.5, gt=0)
    """Reply timeout for info / health / descriptors."""
    spinup_s: float = Field(3.0, gt=0)
    """How long to wait for the first scan bytes after SCAN (reference: ~2 s of silence while
    the C1's motor spins up, unverified)."""
    stale_s: float = Field(0.5, gt=0)
    """A scan older than this is a dropout (5 revolutions at the C1's ~10 Hz)."""
    range_min: float = 0.05
    """Shortest valid return, m (reference: C1 range 0.05-12 m)."""
    range_max: float = 12.0
    """Longest valid return, m (seed: laser_max_range 12 m)."""


class CameraDeviceConfig(Strict):
    device: str
    """V4L2 device path or index for OpenCV capture."""
    width: int = Field(640, gt=0)
    height: int = Field(480, gt=0)
    fps: float = Field(30.0, gt=0)
    """Capture rate; the producer never delivers faster (seed: producer-side camera lesson)."""
    jpeg_quality: int = Field(80, ge=1, le=100)
    """JPEG quality for the link (seed: only JPEG crosses the WiFi, ~50 kB a frame)."""


def _default_cameras() -> dict[str, CameraDeviceConfig]:
    return {
        # seed: Astra Mini Pro colour at 640x480 30 fps (cameras.yaml)
        "front": CameraDeviceConfig(device="/dev/video0", fps=30.0),
        # seed: gripper usb_cam relaunched at low, config-driven fps (value UNVERIFIED)
        "wrist": CameraDeviceConfig(device="/dev/video2", fps=10.0),
    }


class LedSpiConfig(Strict):
    device: str = "/dev/spidev1.0"
    """SPI device whose MOSI drives the WS2812 data line (UNVERIFIED wiring)."""
    spi_hz: int = Field(2_400_000, gt=0)
    """SPI clock: 3 SPI bits per WS2812 bit at 2.4 MHz gives the 1.25 us bit period."""


class DevicesConfig(Strict):
    """Every real device of the robot, for the hardware backend and ``lupin hw``."""

    i2c: I2cBusConfig = I2cBusConfig()
    """The I2C bus of the PCA9685, INA226, MPU9250 and the AS5600 mux."""
    pwm: Pca9685Config = Pca9685Config()
    """Motor PWM (PCA9685) and the H-bridge wiring."""
    power: Ina226Config = Ina226Config()
    """Power monitor (INA226) and the seed's power policy."""
    imu: ImuConfig = ImuConfig()
    """IMU (MPU9250 + AK8963)."""
    arm_encoders: ArmEncodersConfig = ArmEncodersConfig()
    """Joint absolute encoders (AS5600 behind a TCA9548A)."""
    encoders: EncoderGpioConfig = EncoderGpioConfig()
    """Wheel quadrature encoders on GPIO."""
    estop: EStopGpioConfig = EStopGpioConfig()
    """The physical e-stop button on GPIO."""
    servo_bus: ServoPortConfig = ServoPortConfig()
    """The Hiwonder TTL servo bus."""
    lidar: LidarPortConfig = LidarPortConfig()
    """The RPLidar C1."""
    cameras: dict[str, CameraDeviceConfig] = Field(default_factory=_default_cameras)
    """Cameras by HAL name (front: Astra colour; wrist: the gripper camera)."""
    leds: LedSpiConfig = LedSpiConfig()
    """The status LED strip's data line."""
