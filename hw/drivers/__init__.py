"""Drivers for the real MIRTE Master V2 devices, one module per device.

They talk to an smbus2-compatible bus object, a pyserial port, a libgpiod line request or an
OpenCV capture, all opened by ``hw.backend`` from ``hw.devices_config``. Every address, channel,
port and scale comes from that config (../shared/reference/hardware.md: "config wins").
Garbage from a device never escapes a driver's read loop as anything but ``DeviceError``.
"""
