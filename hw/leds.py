"""The status LED strip: a palette of robot states, written in the strip's wire colour order.

Seed: Mirte-247264's neopixel strip is wired BRG (byte slot 0 is blue, 1 red, 2 green). The
vendor's documented ``data_order`` fix was a silent no-op in the C++ driver, so Lupin remapped
at the one chokepoint every LED write passes. ``to_wire`` is that chokepoint here: everything
above it speaks RGB, and only this function knows the order (``LedConfig.color_order``,
e.g. 'BRG' or 'GRB'; wire = [{'R': r, 'G': g, 'B': b}[c] for c in order] per pixel).

``LedStatus`` shows one colour per robot state over the whole strip (the seed's light_strip_bridge:
mission palette plus live drive / arm / standby / e-stop activity, and battery-low flips it).
It writes only when the state changes: the strip is a slow serial device shared with nothing
else, and a 10 Hz caller should not flood it with identical frames. A failed write is logged and
retried on the next ``show``.

The palette colours are this project's choice (the seed names the states, not the colours):
red is reserved for the e-stop so it can never be mistaken for anything else.
"""
from __future__ import annotations

import logging
from typing import Sequence

import numpy as np

from hw.config import LedConfig
from hw.interfaces import DeviceError, LedStrip

RGB = tuple[int, int, int]

PALETTE: dict[str, RGB] = {
    "standby": (0, 0, 40),  # dim blue: powered, idle
    "driving": (0, 160, 0),  # green: the base is moving
    "arm_moving": (0, 140, 140),  # cyan: the arm is moving
    "estop": (255, 0, 0),  # red: e-stop engaged (reserved)
    "mission_running": (40, 40, 255),  # bright blue
    "mission_paused": (255, 160, 0),  # amber: waiting for the operator
    "mission_done": (255, 255, 255),  # white
    "mission_failed": (180, 0, 180),  # magenta
    "battery_low": (255, 60, 0),  # orange
}


def to_wire(rgb_pixels: Sequence[Sequence[int]] | np.ndarray, order: str) -> bytes:
    """RGB pixels (N x 3, 0..255) -> the bytes clocked out on the data line, in ``order``."""
    order = order.upper()
    if sorted(order) != ["B", "G", "R"]:
        raise ValueError(f"colour order must be a permutation of 'RGB', got {order!r}")
    px = np.asarray(rgb_pixels)
    if px.size == 0:
        return b""
    px = px.reshape(-1, 3)
    if not np.issubdtype(px.dtype, np.integer) or px.min() < 0 or px.max() > 255:
        raise ValueError("pixels must be integers in 0..255")
    return px[:, ["RGB".index(c) for c in order]].astype(np.uint8).tobytes()


def pick_state(
    *,
    estop: bool = False,
    battery_low: bool = False,
    mission: str | None = None,
    driving: bool = False,
    arm_moving: bool = False,
) -> str:
    """Which palette state to show, most urgent first.

    e-stop > battery low > a paused/done/failed mission (the operator must act or look) >
    live arm / drive activity > a running mission > standby. ``mission`` is one of 'running',
    'paused', 'done', 'failed' or None.
    """
    if estop:
        return "estop"
    if battery_low:
        return "battery_low"
    if mission in ("paused", "done", "failed"):
        return f"mission_{mission}"
    if arm_moving:
        return "arm_moving"
    if driving:
        return "driving"
    if mission == "running":
        return "mission_running"
    if mission is not None:
        raise ValueError(f"unknown mission state {mission!r}")
    return "standby"


class LedStatus:
    def __init__(self, config: LedConfig, strip: LedStrip, log: logging.Logger | None = None):
        self.config = config
        self.strip = strip
        self.log = log if log is not None else logging.getLogger(__name__)
        self.state: str | None = None
        """The state last written successfully to the strip (None before the first write)."""

    def show(self, state: str) -> bool:
        """Show ``state`` on the whole strip; returns True if the strip was written."""
        if state not in PALETTE:
            raise ValueError(f"unknown LED state {state!r} (known: {', '.join(PALETTE)})")
        if state == self.state:
            return False
        wire = to_wire([PALETTE[state]] * self.strip.num_leds, self.config.color_order)
        try:
            self.strip.write(wire)
        except (DeviceError, OSError) as exc:
            self.log.warning("LED strip write failed (%s); will retry", exc)
            return False
        self.state = state
        return True
