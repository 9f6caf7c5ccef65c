"""Named arm poses (seed: arm_preset_server), radians in joint order.

Joint order everywhere: shoulder_pan, shoulder_lift, elbow, wrist (the gripper is separate).
``home`` is the measured minimum-gravity-load rest pose (the auto-home target); ``inspect`` is
the per-pot patrol stance that pitches the wrist camera down into the pot.
"""
from __future__ import annotations

ARM_JOINTS: tuple[str, ...] = ("shoulder_pan", "shoulder_lift", "elbow", "wrist")

PRESETS: dict[str, tuple[float, float, float, float]] = {
    "home": (0.04, -0.01, 0.01, -1.57),
    "zero": (0.0, 0.0, 0.0, 0.0),
    "tuck": (0.0, -1.40, 1.40, 0.0),
    "pick": (0.0, -0.60, 0.80, -0.40),
    "place": (0.0, 0.20, 0.80, -0.40),
    "inspect": (0.0, -0.40, 0.90, -0.80),
}


def preset(name: str) -> dict[str, float]:
    """Joint name -> angle for a named preset; KeyError lists the valid names."""
    try:
        return dict(zip(ARM_JOINTS, PRESETS[name]))
    except KeyError:
        raise KeyError(f"unknown arm preset {name!r}; known: {', '.join(PRESETS)}") from None
