"""The real GPIO boundary: a libgpiod v2 line request with both-edge events.

``request_inputs(chip, offsets, pull_up=...)`` is the only place ``gpiod`` is imported (lazily:
it is not a dependency of the project and there is no GPIO chip off the robot). Reference:
``gpiod.request_lines(chip, consumer=..., config={offsets: LineSettings(direction=INPUT,
edge_detection=BOTH, bias=PULL_UP)})``. Drivers only use the request's ``wait_edge_events``,
``read_edge_events``, ``get_value(s)`` and ``release``, which ``hw.emulators.gpio`` emulates.
"""
from __future__ import annotations

import os

from hw.errors import InputError

CONSUMER = "lupin"


def request_inputs(chip: str, offsets, *, pull_up: bool = True, consumer: str = CONSUMER):
    if not os.path.exists(chip):
        raise InputError(f"GPIO chip {chip}: no such device")
    try:
        import gpiod
        from gpiod.line import Bias, Direction, Edge
    except ImportError:
        raise InputError(f"GPIO chip {chip}: the 'gpiod' package (libgpiod v2 bindings) is not installed") from None
    settings = gpiod.LineSettings(direction=Direction.INPUT, edge_detection=Edge.BOTH,
                                  bias=Bias.PULL_UP if pull_up else Bias.AS_IS)
    try:
        return gpiod.request_lines(chip, consumer=consumer, config={tuple(offsets): settings})
    except OSError as exc:
        raise InputError(f"GPIO chip {chip} lines {list(offsets)}: cannot request ({exc.strerror or exc})") from None


def level(value) -> int:
    """A gpiod ``Value`` (or a plain int) as 0/1."""
    return int(getattr(value, "value", value))


def is_rising(event) -> bool:
    return event.event_type.name == "RISING_EDGE"
