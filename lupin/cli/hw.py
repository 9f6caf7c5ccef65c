"""`lupin hw ...`: bring-up diagnostics on the real devices (spec/cli.md).

``i2c-scan``, ``servo ping|read|move|offset``, ``lidar info|health|scan``, ``power``, ``imu``,
``encoders``, ``estop``, ``leds``. Serial commands take ``--port`` (and ``--baud``), I2C
commands ``--bus``; defaults come from ``hw.devices`` in the config. Output is human-readable,
or one JSON object with ``--json``. A wrong port, a silent device or a wrong chip id is one line
on stderr and exit 2 (``InputError`` / ``DeviceError``, mapped in ``lupin.cli.main``).

The two boundaries without a device file here, the I2C bus and the GPIO line request, are the
module attributes ``open_i2c`` and ``gpio_request`` (tests point them at the emulators).
"""
from __future__ import annotations

import json
import math
from typing import Optional

import numpy as np
import typer

from hw.drivers.as5600 import As5600Array
from hw.drivers.button import GpioButton
from hw.drivers.gpio import request_inputs
from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.i2c import open_bus
from hw.drivers.ina226 import Ina226
from hw.drivers.led_strip import SpiLedStrip
from hw.drivers.mpu9250 import Mpu9250
from hw.power_policy import PowerPolicy
from hw.drivers.quadrature import QuadratureEncoders
from hw.drivers.rplidar import RplidarC1
from hw.drivers.tca9548a import Tca9548a
from hw.errors import InputError
from hw.interfaces import WHEELS, DeviceError
from hw.leds import PALETTE, to_wire
from hw.wall_clock import WallClock
from lupin.cli.sim import run_config

open_i2c = open_bus
gpio_request = request_inputs

hw_app = typer.Typer(help="Bring-up diagnostics on the real devices.", no_args_is_help=True)
servo_app = typer.Typer(help="The Hiwonder servo bus: ping, read, move, offset.", no_args_is_help=True)
lidar_app = typer.Typer(help="The RPLidar C1: info, health, scan.", no_args_is_help=True)
hw_app.add_typer(servo_app, name="servo")
hw_app.add_typer(lidar_app, name="lidar")

JSON = typer.Option(False, "--json", help="Print one JSON object.")
PORT = typer.Option(None, "--port", help="Serial device (default: from the config).")
BAUD = typer.Option(None, "--baud", help="Baud rate (default: from the config).")
BUS = typer.Option(None, "--bus", help="I2C bus number, /dev/i2c-N (default: from the config).")


def _emit(data: dict, as_json: bool, lines: list[str]) -> None:
    if as_json:
        typer.echo(json.dumps(data))
    else:
        for line in lines:
            typer.echo(line)


def _devices(ctx: typer.Context):
    return run_config(ctx).hw


def _i2c(ctx: typer.Context, bus: Optional[int]):
    hw = _devices(ctx)
    return hw, open_i2c(hw.devices.i2c.bus if bus is None else bus)


# --- I2C ------------------------------------------------------------------------------------
@hw_app.command("i2c-scan")
def i2c_scan(ctx: typer.Context, bus: Optional[int] = BUS, as_json: bool = JSON) -> None:
    """List the addresses that answer, named from the config, and the joint encoders behind the mux."""
    hw, i2c = _i2c(ctx, bus)
    dev = hw.devices
    names = {dev.pwm.address: "PCA9685 motor PWM", dev.power.address: "INA226 power monitor",
             dev.imu.address: "MPU9250 IMU", dev.imu.mag_address: "AK8963 magnetometer",
             dev.arm_encoders.mux_address: "TCA9548A mux"}
    found = []
    for addr in range(0x03, 0x78):
        try:
            i2c.read_byte(addr)
        except OSError:
            continue
        found.append(addr)
    joints = {}
    if dev.arm_encoders.mux_address in found:
        mux = Tca9548a(i2c, dev.arm_encoders.mux_address)
        enc = As5600Array(i2c, mux, dev.arm_encoders.channels, dev.arm_encoders.address)
        for joint in dev.arm_encoders.channels:
            try:
                a = enc.read(joint)
                joints[joint] = {"channel": enc.channels[joint], "degrees": round(a.degrees, 2), "magnet": a.magnet}
            except DeviceError:
                joints[joint] = {"channel": enc.channels[joint], "degrees": None, "magnet": "no answer"}
        mux.release()
    lines = [f"0x{a:02x}  {names.get(a, '?')}" for a in found] or ["no device answered"]
    lines += [f"  AS5600 {j:<14} mux ch {v['channel']}: "
              + (f"{v['degrees']:7.2f} deg, magnet {v['magnet']}" if v["degrees"] is not None else "no answer")
              for j, v in joints.items()]
    _emit({"bus": dev.i2c.bus if bus is None else bus,
           "devices": [{"address": a, "name": names.get(a)} for a in found], "joint_encoders": joints}, as_json, lines)


@hw_app.command("power")
def power(ctx: typer.Context, bus: Optional[int] = BUS, as_json: bool = JSON) -> None:
    """Pack voltage, current, power and the seed's percentage (INA226)."""
    hw, i2c = _i2c(ctx, bus)
    c = hw.devices.power
    ina = Ina226(i2c, c.address, c.shunt_ohm, c.max_expected_current, c.averaging)
    ina.start()
    s = ina.sample()
    pct = PowerPolicy(c).percentage(s.voltage)
    _emit({"voltage": round(s.voltage, 3), "current": round(s.current, 3), "power": round(s.power, 2),
           "percentage": round(pct, 1)}, as_json,
          [f"voltage {s.voltage:.3f} V  current {s.current:.3f} A  power {s.power:.2f} W  battery {pct:.0f} %"])


@hw_app.command("imu")
def imu(ctx: typer.Context, bus: Optional[int] = BUS, as_json: bool = JSON) -> None:
    """One IMU reading: acceleration, rotation rate, temperature, magnetic field."""
    hw, i2c = _i2c(ctx, bus)
    c = hw.devices.imu
    mpu = Mpu9250(i2c, c.address, c.accel_range_g, c.gyro_range_dps, c.accepted_who_am_i, c.mag_address)
    who = mpu.start()
    accel, temp, gyro = mpu.read_raw()
    mag = mpu.read_mag()
    _emit({"who_am_i": who, "accel": [round(float(x), 4) for x in accel], "gyro": [round(float(x), 5) for x in gyro],
           "temperature_c": round(temp, 2), "mag_ut": None if mag is None else [round(x, 2) for x in mag]}, as_json,
          [f"WHO_AM_I 0x{who:02x}",
           "accel  " + " ".join(f"{x:+8.3f}" for x in accel) + "  m/s^2",
           "gyro   " + " ".join(f"{x:+8.4f}" for x in gyro) + "  rad/s",
           f"temp   {temp:.1f} C",
           "mag    " + ("not found" if mag is None else " ".join(f"{x:+8.2f}" for x in mag) + "  uT")])


# --- servos ---------------------------------------------------------------------------------
def _servo_bus(ctx: typer.Context, port: Optional[str], baud: Optional[int]):
    hw = _devices(ctx)
    sb = hw.devices.servo_bus
    return hw, HiwonderBus.open(port or sb.port, baud or sb.baud, echo=sb.echo, timeout_s=sb.timeout_s,
                                retries=sb.retries)


def _radians(hw, servo_id: int, counts: int) -> float:
    for calib in hw.servos.joints.values():
        if calib.id == servo_id:
            return math.radians((counts * hw.servos.centideg_per_count - calib.home) / 100.0)
    return math.radians((counts - 500) * hw.servos.centideg_per_count / 100.0)


@servo_app.command("ping")
def servo_ping(ctx: typer.Context, port: Optional[str] = PORT, baud: Optional[int] = BAUD,
               ids: Optional[list[int]] = typer.Option(None, "--id", help="Servo id(s) (default: the arm's)."),
               as_json: bool = JSON) -> None:
    """Which servos answer. Exit 2 if none does."""
    hw, bus = _servo_bus(ctx, port, baud)
    ids = ids or [c.id for c in hw.servos.joints.values()]
    alive = {i: bus.ping(i) for i in ids}
    bus.close()
    if not any(alive.values()):
        raise DeviceError(f"servo bus {bus.port.port}: no servo answered (ids {', '.join(map(str, ids))})")
    _emit({"servos": {str(i): a for i, a in alive.items()}}, as_json,
          [f"id {i:3d}  {'ok' if a else 'no answer'}" for i, a in alive.items()])


@servo_app.command("read")
def servo_read(ctx: typer.Context, servo_id: int = typer.Option(..., "--id", help="Servo id."),
               port: Optional[str] = PORT, baud: Optional[int] = BAUD, as_json: bool = JSON) -> None:
    """Position (radians and raw counts), voltage, temperature, load and error flags of one servo."""
    hw, bus = _servo_bus(ctx, port, baud)
    st = bus.read_status(servo_id)
    errors = bus.read_errors(servo_id)
    bus.close()
    rad = _radians(hw, servo_id, st.position)
    flags = [n for b, n in ((1, "over-temperature"), (2, "over-voltage"), (4, "stalled")) if errors & b]
    _emit({"id": servo_id, "position_rad": round(rad, 4), "position_counts": st.position, "vin_v": st.vin_mv / 1000,
           "temperature_c": st.temperature_c, "loaded": st.loaded, "errors": flags}, as_json,
          [f"servo {servo_id}: position {rad:+.4f} rad ({st.position} counts)  {st.vin_mv / 1000:.2f} V  "
           f"{st.temperature_c} C  {'loaded' if st.loaded else 'unloaded'}"
           + (f"  errors: {', '.join(flags)}" if flags else "")])


@servo_app.command("move")
def servo_move(ctx: typer.Context, servo_id: int = typer.Option(..., "--id", help="Servo id."),
               position: int = typer.Option(..., "--position", min=0, max=1000, help="Raw counts 0..1000."),
               time_ms: int = typer.Option(1000, "--time", min=0, max=30000, help="Move time, ms."),
               port: Optional[str] = PORT, baud: Optional[int] = BAUD, as_json: bool = JSON) -> None:
    """Move one servo (raw; the running arm controller would re-assert its own setpoint)."""
    _, bus = _servo_bus(ctx, port, baud)
    if not bus.ping(servo_id):
        raise DeviceError(f"servo id {servo_id}: no answer on {bus.port.port}")
    bus.move(servo_id, position, time_ms)
    bus.close()
    _emit({"id": servo_id, "position_counts": position, "time_ms": time_ms}, as_json,
          [f"servo {servo_id}: moving to {position} counts in {time_ms} ms"])


@servo_app.command("offset")
def servo_offset(ctx: typer.Context, servo_id: int = typer.Option(..., "--id", help="Servo id."),
                 set_to: Optional[int] = typer.Option(None, "--set", min=-125, max=125,
                                                      help="Adjust the offset (-125..125 = +-30 deg)."),
                 save: bool = typer.Option(False, "--save", help="Persist the offset in the servo."),
                 port: Optional[str] = PORT, baud: Optional[int] = BAUD, as_json: bool = JSON) -> None:
    """Read, adjust (volatile) and optionally save a servo's angle offset."""
    _, bus = _servo_bus(ctx, port, baud)
    if set_to is not None:
        bus.adjust_offset(servo_id, set_to)
    if save:
        bus.write_offset(servo_id)
    offset = bus.read_offset(servo_id)
    bus.close()
    _emit({"id": servo_id, "offset": offset, "degrees": round(offset * 0.24, 2), "saved": save}, as_json,
          [f"servo {servo_id}: offset {offset} ({offset * 0.24:+.2f} deg){' saved' if save else ''}"])


# --- lidar ----------------------------------------------------------------------------------
def _lidar(ctx: typer.Context, port: Optional[str], baud: Optional[int]) -> RplidarC1:
    ld = _devices(ctx).devices.lidar
    return RplidarC1.open(port or ld.port, baud or ld.baud, timeout_s=ld.timeout_s, spinup_s=ld.spinup_s,
                          stale_s=ld.stale_s, range_min=ld.range_min, range_max=ld.range_max)


@lidar_app.command("info")
def lidar_info(ctx: typer.Context, port: Optional[str] = PORT, baud: Optional[int] = BAUD,
               as_json: bool = JSON) -> None:
    """Model, firmware, hardware and serial number."""
    lidar = _lidar(ctx, port, baud)
    try:
        info = lidar.info()
    finally:
        lidar.port.close()
    _emit({"model": info.model, "firmware": info.firmware, "hardware": info.hardware, "serial": info.serial}, as_json,
          [f"model 0x{info.model:02x}  firmware {info.firmware}  hardware {info.hardware}  serial {info.serial}"])


@lidar_app.command("health")
def lidar_health(ctx: typer.Context, port: Optional[str] = PORT, baud: Optional[int] = BAUD,
                 as_json: bool = JSON) -> None:
    """Health status (good, warning, error) and error code."""
    lidar = _lidar(ctx, port, baud)
    try:
        status, code = lidar.health()
    finally:
        lidar.port.close()
    _emit({"status": status, "error_code": code}, as_json, [f"health {status} (error code {code})"])


@lidar_app.command("scan")
def lidar_scan(ctx: typer.Context, port: Optional[str] = PORT, baud: Optional[int] = BAUD,
               revolutions: int = typer.Option(5, "--revolutions", min=1, help="Revolutions to collect."),
               as_json: bool = JSON) -> None:
    """Points per revolution and the min / median / max range over K revolutions."""
    lidar = _lidar(ctx, port, baud)
    scans = []
    try:
        lidar.start()
        seen = None
        clock = WallClock()
        deadline = clock.now() + lidar.spinup_s + revolutions * 0.5
        while len(scans) < revolutions and clock.now() < deadline:
            s = lidar.wait_for_scan(0.2)
            if s is not None and s is not seen:
                scans.append(s)
                seen = s
            clock.wait_until(clock.now() + 0.01)
    finally:
        lidar.close()
    if not scans:
        raise DeviceError(f"RPLidar on {port or _devices(ctx).devices.lidar.port}: no complete revolution")
    points = [int(s.ranges.size) for s in scans]
    r = np.concatenate([s.ranges[np.isfinite(s.ranges)] for s in scans])
    stats = {k: (round(float(f(r)), 3) if r.size else None)
             for k, f in (("min", np.min), ("median", np.median), ("max", np.max))}
    _emit({"revolutions": len(scans), "points_per_revolution": points, "range_m": stats}, as_json,
          [f"{len(scans)} revolutions, points per revolution {min(points)}..{max(points)}",
           "range min {min} m  median {median} m  max {max} m".format(**stats)])


# --- GPIO and LEDs --------------------------------------------------------------------------
@hw_app.command("encoders")
def encoders(ctx: typer.Context, seconds: float = typer.Option(2.0, "--seconds", min=0.0, help="How long to count."),
             as_json: bool = JSON) -> None:
    """Count wheel encoder ticks for a while (turn the wheels by hand), with lost / illegal counts."""
    c = _devices(ctx).devices.encoders
    req = gpio_request(c.chip, [o for ab in c.lines.values() for o in ab], pull_up=True)
    enc = QuadratureEncoders(req, c.lines)
    clock = WallClock()
    end = clock.now() + seconds
    while clock.now() < end:
        enc.poll()
        clock.wait_until(clock.now() + 0.05)
    ticks = enc.read_ticks()
    enc.close()
    rows = {w: {"ticks": int(t), "lost": int(lo), "illegal": int(il)}
            for w, t, lo, il in zip(WHEELS, ticks, enc.lost, enc.illegal)}
    _emit({"seconds": seconds, "wheels": rows}, as_json,
          [f"{w:<12} {r['ticks']:+7d} ticks  lost {r['lost']}  illegal {r['illegal']}" for w, r in rows.items()])


@hw_app.command("estop")
def estop(ctx: typer.Context, as_json: bool = JSON) -> None:
    """The e-stop pin's level and what it means under the configured polarity (UNVERIFIED)."""
    hw = _devices(ctx)
    c = hw.devices.estop
    button = GpioButton(gpio_request(c.chip, [c.line], pull_up=c.pull_up), c.line, hw.estop.engaged_level)
    lvl = button.read_level()
    button.close()
    engaged = lvl == hw.estop.engaged_level
    _emit({"line": c.line, "level": lvl, "engaged_level": hw.estop.engaged_level, "engaged": engaged}, as_json,
          [f"e-stop line {c.line}: level {lvl} -> {'ENGAGED' if engaged else 'released'} "
           f"(engaged_level {hw.estop.engaged_level}, unverified: press it and check)"])


@hw_app.command("leds")
def leds(ctx: typer.Context, state: str = typer.Option("standby", "--state", help=f"One of: {', '.join(PALETTE)}."),
         as_json: bool = JSON) -> None:
    """Show a palette state on the strip, through the colour-order chokepoint."""
    hw = _devices(ctx)
    if state not in PALETTE:
        raise InputError(f"--state {state!r}: unknown; known: {', '.join(PALETTE)}")
    wire = to_wire([PALETTE[state]] * hw.leds.num_leds, hw.leds.color_order)
    strip = SpiLedStrip(hw.devices.leds.device, hw.leds.num_leds, hw.devices.leds.spi_hz)
    strip.write(wire)
    strip.close()
    _emit({"state": state, "rgb": list(PALETTE[state]), "color_order": hw.leds.color_order, "wire": wire[:3].hex()},
          as_json, [f"LEDs: {state} {PALETTE[state]} sent as {hw.leds.color_order} {wire[:3].hex(' ')}"])
