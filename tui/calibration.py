"""The arm's zero-offset calibration from the console: four entries of the command palette.

The seed's operator ran ``start | commit | cancel | status`` on the robot (``arm.calibration``):
start unloads the servos so the arm can be posed by hand at its zero, commit samples ~2 s and
writes the offsets. It is rare and it limps the arm, so it has no key of its own (nothing to hit
by accident): ``ctrl+p`` then "arm calibration". Each answer (the phase, the note, one line per
joint once committed) goes to the log panel; a refusal (the sim's bus: hardware only) is told
like any refused command.
"""
from __future__ import annotations

from typing import Callable, Iterator

from textual.app import SystemCommand

ACTIONS = {
    "start": "unload the arm's servos: pose it by hand at its zero (every link straight up), then commit",
    "commit": "sample the posed arm for ~2 s and write each joint's zero offset",
    "cancel": "load the servos again, write nothing",
    "status": "where the calibration is, and what the last commit wrote",
}


def lines(answer: dict) -> list[str]:
    """What the log shows of one answer (``Service.arm_calibrate``'s JSON)."""
    out = [f"arm calibration: {answer.get('phase', '?')}: {answer.get('note', '')}"]
    for o in answer.get("outcomes", ()):
        offset = f" {o['offset']:+d} counts" if o.get("offset") is not None else ""
        out.append(f"  {o['joint']}: {o['status']}{offset}{(' (' + o['detail'] + ')') if o.get('detail') else ''}")
    return out


def commands(run: Callable[[str], None]) -> Iterator[SystemCommand]:
    """The palette's entries; ``run(action)`` asks the robot."""
    for action, help_text in ACTIONS.items():
        yield SystemCommand(f"Arm calibration: {action}", help_text, lambda a=action: run(a))
