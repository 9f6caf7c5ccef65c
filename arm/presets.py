"""Named arm poses (seed: arm_preset_server), radians in joint order.

Joint order everywhere: shoulder_pan, shoulder_lift, elbow, wrist (the gripper is separate).
``home`` is the measured minimum-gravity-load rest pose (the auto-home target); ``inspect`` is
the seed's per-pot stance that pitches the wrist camera down into the pot. ``inspect_plant`` is
Lupin's (issue 30), the one the patrol takes (``mission.patrol.config``): the arm raised and the
wrist bent further, so the camera looks down 47 deg at the middle of the plant from 0.30 m
instead of 53 deg from 0.18 m. ``inspect`` frames the plant's front edge with its back cut off,
and the arm's real sag (0.03-0.04 rad at shoulder_lift and wrist, under the 0.05 rad dead-band
that would correct it) tips the view off the back leaves and a back bloom; ``inspect_plant``
holds the whole plant top in the frame with 40 px to spare on every side even with every joint
0.05 rad off (all 27 combinations of -0.05, 0, +0.05), the plant ~240 px tall, a bloom
still 7,000-10,000 px. Chosen by a grid search over the joint windows with the arm above the plant top;
every joint is well inside its window (wrist -1.30 of -1.57).

A preset is commanded as *one* trajectory of all four joints (seed: "Lupin commands all four
arm joints together as a single trajectory"), clamped through ``arm.limits`` and timed so the
joint with the longest way to go moves at the configured maximum joint speed.
"""
from __future__ import annotations

from hw.errors import InputError

ARM_JOINTS: tuple[str, ...] = ("shoulder_pan", "shoulder_lift", "elbow", "wrist")

PRESETS: dict[str, tuple[float, float, float, float]] = {
    "home": (0.04, -0.01, 0.01, -1.57),
    "zero": (0.0, 0.0, 0.0, 0.0),
    "tuck": (0.0, -1.40, 1.40, 0.0),
    "pick": (0.0, -0.60, 0.80, -0.40),
    "place": (0.0, 0.20, 0.80, -0.40),
    "inspect": (0.0, -0.40, 0.90, -0.80),
    "inspect_plant": (0.0, -0.45, 0.25, -1.30),
}


class UnknownPreset(InputError):
    """An arm preset name that does not exist (an operator's or a mission file's typo)."""


def preset(name: str) -> dict[str, float]:
    """Joint name -> angle for a named preset; ``UnknownPreset`` lists the valid names."""
    try:
        return dict(zip(ARM_JOINTS, PRESETS[name]))
    except KeyError:
        raise UnknownPreset(f"unknown arm preset {name!r}; known: {', '.join(PRESETS)}") from None


def move_duration(start, goal, max_speed: float, min_duration: float) -> float:
    """Seconds for a move from ``start`` to ``goal`` (joint order) with no joint faster than
    ``max_speed`` rad/s, and never shorter than ``min_duration``."""
    span = max((abs(float(g) - float(s)) for s, g in zip(start, goal)), default=0.0)
    return max(span / max_speed, min_duration)
