"""The console's keys, in one table (the footer shows them, grouped).

Driving is hold-to-drive on the runtime's ``manual`` source: terminals send no key-up, so every
press and every auto-repeat of a held key sends one twist, and letting go sends nothing; the
twist_mux times the source out 0.5 s later. Arrows: up / down forward and back, left / right
strafe (the mecanum base); q / e turn left / right.

The drive keys and the e-stop are priority bindings: they work on every screen, the clear-map
question included. ``space`` only ever engages the soft e-stop, however often it is pressed (a
panicked double tap must not un-stop the robot); releasing is a different, deliberate key,
``u``, and releasing restarts nothing: ``r`` resumes (ISO 13850: the reset is a separate act).
"""
from __future__ import annotations

from textual.binding import Binding

from arm.presets import PRESETS

SPEED = 0.2
"""m/s, forward and strafe."""
TURN = 0.5
"""rad/s."""
DRIVE: dict[str, tuple[float, float, float]] = {
    "up": (SPEED, 0.0, 0.0), "down": (-SPEED, 0.0, 0.0),
    "left": (0.0, SPEED, 0.0), "right": (0.0, -SPEED, 0.0),  # +y is left (REP-103)
    "q": (0.0, 0.0, TURN), "e": (0.0, 0.0, -TURN),
}
"""Key -> (vx, vy, wz) on the manual source."""
ARM_PRESETS: list[str] = list(PRESETS)[:6]
"""Keys 1..6, in ``arm.presets.PRESETS`` order."""
CAMERAS = {"f": "front", "w": "wrist"}

_drive = Binding.Group("drive", compact=True)
_strafe = Binding.Group("strafe", compact=True)
_turn = Binding.Group("turn")
_arm = Binding.Group("arm", compact=True)
_gripper = Binding.Group("gripper")
_camera = Binding.Group("camera")

BINDINGS: list[Binding] = [
    Binding("up", "drive('up')", "forward", priority=True, group=_drive),
    Binding("down", "drive('down')", "back", priority=True, group=_drive),
    Binding("left", "drive('left')", "strafe left", priority=True, group=_strafe),
    Binding("right", "drive('right')", "strafe right", priority=True, group=_strafe),
    Binding("q", "drive('q')", "turn left", priority=True, group=_turn),
    Binding("e", "drive('e')", "turn right", priority=True, group=_turn),
    Binding("space", "estop(True)", "E-STOP", priority=True),
    Binding("u", "estop(False)", "release e-stop"),
    Binding("r", "send('resume')", "resume"),
    Binding("m", "send('mission_start')", "mission"),
    Binding("p", "send('pause')", "pause"),
    Binding("c", "clear_map", "clear map"),
    *[Binding(str(i + 1), f"preset('{name}')", f"arm to {name}", group=_arm) for i, name in enumerate(ARM_PRESETS)],
    Binding("o", "gripper('open')", "open gripper", group=_gripper),
    Binding("g", "gripper('close')", "close gripper", group=_gripper),
    *[Binding(key, f"snapshot('{camera}')", f"{camera} camera", group=_camera) for key, camera in CAMERAS.items()],
    Binding("ctrl+q", "quit", "quit"),
]
